#!/usr/bin/env python3
"""Strong scaling of `vrv render --reference` over MPI ranks on one machine (issue 28,
docs/distributed.md), beside the same render's threads.

    python3 studies/benchmarks/mpi_scaling.py BUILD_DIR [--rounds N] [--size N] [--verify]

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
        ways = {
            "1 rank x 1 thread": ["mpirun", "-np", "1"] + verify + ["--threads", "1"],
            "2 ranks x 1 thread": ["mpirun", "-np", "2"] + verify + ["--threads", "1"],
            "1 process x 2 threads": verify + ["--threads", "2"],
        }
        load_before = os.getloadavg()[0]
        times = {name: [] for name in ways}
        lines = {}
        for _ in range(rounds):
            for name, cmd in ways.items():
                took, proc = run_timed(cmd)
                times[name].append(took)
                lines[name] = proc.stdout
        load_after = os.getloadavg()[0]
    if len(set(lines.values())) != 1:
        sys.exit(f"mpi_scaling: the verifications printed different results: {lines}")
    print(f"vrv verify, {SCENE.name}, 5 alpha images at {size}^2, reference cached, {rounds} rounds; "
          f"load average {load_before:.2f} before, {load_after:.2f} after; the same JSON line each way\n")
    print("| run | wall s (median) | wall s (best) | speed-up, best |")
    print("|---|---|---|---|")
    base = min(times["1 rank x 1 thread"])
    for name, t in times.items():
        print(f"| {name} | {statistics.median(t):.2f} | {min(t):.2f} | {base / min(t):.2f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir", type=Path)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--size", type=int)
    ap.add_argument("--verify", action="store_true", help="time vrv verify of five images instead")
    args = ap.parse_args()
    vrv = str(args.build_dir.resolve() / "vrv")
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
