#!/usr/bin/env python3
"""Strong scaling of `vrv render --reference` over MPI ranks on one machine (issue 28,
docs/distributed.md), beside the same render's threads.

    python3 studies/benchmarks/mpi_scaling.py BUILD_DIR [--rounds N] [--size N] [--verify | --study NAME]

BUILD_DIR holds a vrv built with -DVRV_WITH_MPI=ON.  Renders the 64^3 grid scene's reference image
(studies/benchmarks/grid64_opacity.toml, tol 1e-10) at SIZE^2 (default 1024) three ways, one after
another in each of ROUNDS rounds (default 5), so all three see the same load: one process with one
thread (mpirun -np 1 --threads 1), two ranks of one thread each (mpirun -np 2 --threads 1), and one
process of two threads (--threads 2, no mpirun).  Prints the median and best wall seconds and the
pixels' own seconds (what vrv render prints; for two ranks, rank 0's, which includes the wait for
the other rank and the exchange), the speed-ups over one thread, and the load average before and
after, since a busy machine cannot show a speed-up.  Checks that the three images are the same
bytes.

With --verify it times `vrv verify` instead: five images of the same scene at SIZE^2 (default
256 then) made by vrv's alpha rule at steps 0.04 ... 0.0025, their reference cached first, so the
timed part is the diagnosis and the fault fits (the model casts dealt to the ranks), and checks
that the three verifications print the same JSON line.

With --study NAME it times `vrv study NAME --no-plots` the three ways, each into its own folder,
and checks that every file but meta.json is the same bytes.

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import filecmp
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "studies" / "benchmarks" / "grid64_opacity.toml"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_btl_vader_single_copy_mechanism="none")


def run_timed(cmd):
    """Wall seconds and the finished process; exits on a failure."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600, env=ENV)
    took = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"mpi_scaling: {' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()[:400]}")
    return took, proc


def timed(cmd):
    """Wall seconds and the pixels' seconds vrv render prints."""
    took, proc = run_timed(cmd)
    m = re.search(r"^vrv render: .* in ([0-9.]+) s$", proc.stderr, re.M)
    if not m:
        sys.exit(f"mpi_scaling: no pixel time in vrv render's output: {proc.stderr.strip()[:200]}")
    return took, float(m.group(1))


def time_ways(ways, rounds):
    """Each way's wall seconds over ROUNDS rounds (the ways in turn, so all see the same load), its
    last standard output, and the load average before and after."""
    load_before = os.getloadavg()[0]
    times = {name: [] for name in ways}
    lines = {}
    for _ in range(rounds):
        for name, cmd in ways.items():
            took, proc = run_timed(cmd)
            times[name].append(took)
            lines[name] = proc.stdout
    return times, lines, load_before, os.getloadavg()[0]


def print_walls(times):
    print("| run | wall s (median) | wall s (best) | speed-up, best |")
    print("|---|---|---|---|")
    base = min(times["1 rank x 1 thread"])
    for name, t in times.items():
        print(f"| {name} | {statistics.median(t):.2f} | {min(t):.2f} | {base / min(t):.2f} |")


def three_ways(cmd):
    """One rank of one thread, two ranks of one thread, one process of two threads."""
    return {
        "1 rank x 1 thread": ["mpirun", "-np", "1"] + cmd + ["--threads", "1"],
        "2 ranks x 1 thread": ["mpirun", "-np", "2"] + cmd + ["--threads", "1"],
        "1 process x 2 threads": cmd + ["--threads", "2"],
    }


def verify_scaling(vrv, rounds, size):
    """vrv verify of five images, reference cached, three ways (see the module's docstring)."""
    steps = [0.04, 0.02, 0.01, 0.005, 0.0025]
    with tempfile.TemporaryDirectory() as tmp:
        images = []
        for h in steps:
            images.append(f"{tmp}/alpha_{h}.exr")
            subprocess.run([vrv, "render", "--scene", str(SCENE), "--method", "alpha", "--strategy", "inviwo",
                            "--opacity-unit", "distance", "--step", str(h), "--width", str(size), "--height",
                            str(size), "--quiet", "-o", images[-1]], check=True, capture_output=True)
        verify = [vrv, "verify", "--scene", str(SCENE), *images, "--cache-dir", f"{tmp}/cache", "--quiet"]
        subprocess.run(verify, capture_output=True, env=ENV)  # the reference, cached
        times, lines, load_before, load_after = time_ways(three_ways(verify), rounds)
    if len(set(lines.values())) != 1:
        sys.exit(f"mpi_scaling: the verifications printed different results: {lines}")
    print(f"vrv verify, {SCENE.name}, 5 alpha images at {size}^2, reference cached, {rounds} rounds; "
          f"load average {load_before:.2f} before, {load_after:.2f} after; the same JSON line each way\n")
    print_walls(times)


def study_files(folder):
    """Every file of a study's folder but meta.json (its date and times), as bytes."""
    return {p.relative_to(folder): p.read_bytes() for p in Path(folder).rglob("*")
            if p.is_file() and p.name != "meta.json"}


def study_scaling(vrv, rounds, study):
    """vrv study STUDY (no plots), three ways, each into its own folder; the folders compared."""
    with tempfile.TemporaryDirectory() as tmp:
        ways = {name: cmd + ["--out", f"{tmp}/{i}"]
                for i, (name, cmd) in enumerate(three_ways([vrv, "study", study, "--no-plots", "--quiet"]).items())}
        times, _, load_before, load_after = time_ways(ways, rounds)
        folders = [study_files(f"{tmp}/{i}/{study}") for i in range(len(ways))]
    if any(f != folders[0] for f in folders[1:]) or len(folders[0]) < 3:
        sys.exit(f"mpi_scaling: the study's files differ between the ways (or are missing)")
    print(f"vrv study {study} --no-plots, {rounds} rounds; load average {load_before:.2f} before, "
          f"{load_after:.2f} after; every file but meta.json the same each way\n")
    print_walls(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir", type=Path)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--size", type=int)
    ap.add_argument("--verify", action="store_true", help="time vrv verify of five images instead")
    ap.add_argument("--study", help="time vrv study STUDY instead")
    args = ap.parse_args()
    vrv = str(args.build_dir.resolve() / "vrv")
    if args.study:
        return study_scaling(vrv, args.rounds, args.study)
    if args.verify:
        return verify_scaling(vrv, args.rounds, args.size or 256)
    args.size = args.size or 1024
    with tempfile.TemporaryDirectory() as tmp:
        def render(name, threads):
            return [vrv, "render", "--scene", str(SCENE), "--reference", "--width", str(args.size), "--height",
                    str(args.size), "--threads", str(threads), "--quiet", "-o", f"{tmp}/{name}.exr"]
        ways = {
            "1 rank x 1 thread": ["mpirun", "-np", "1"] + render("one", 1),
            "2 ranks x 1 thread": ["mpirun", "-np", "2"] + render("ranks", 1),
            "1 process x 2 threads": render("threads", 2),
        }
        load_before = os.getloadavg()[0]
        times = {name: [] for name in ways}
        for _ in range(args.rounds):
            for name, cmd in ways.items():
                times[name].append(timed(cmd))
        load_after = os.getloadavg()[0]
        for other in ("ranks", "threads"):
            for ext in ("exr", "f64.tiff"):
                if not filecmp.cmp(f"{tmp}/one.{ext}", f"{tmp}/{other}.{ext}", shallow=False):
                    sys.exit(f"mpi_scaling: the {other} render's .{ext} differs from one process's")
    base = times["1 rank x 1 thread"]
    print(f"vrv render --reference, {SCENE.name}, {args.size}^2, {args.rounds} rounds; "
          f"load average {load_before:.2f} before, {load_after:.2f} after; images bitwise equal\n")
    print("| run | wall s (median) | wall s (best) | pixels s (median) | pixels s (best) | speed-up, wall best | speed-up, pixels best |")
    print("|---|---|---|---|---|---|---|")
    for name, t in times.items():
        wall = [w for w, _ in t]
        pix = [p for _, p in t]
        print(f"| {name} | {statistics.median(wall):.2f} | {min(wall):.2f} | {statistics.median(pix):.2f} | "
              f"{min(pix):.2f} | {min(w for w, _ in base) / min(wall):.2f} | {min(p for _, p in base) / min(pix):.2f} |")


if __name__ == "__main__":
    main()
