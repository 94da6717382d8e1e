#!/usr/bin/env python3
"""Thread scaling of `vrv render --reference` and a cached `vrv verify` (issue 23: >= 1.8x from 1 to
2 threads on an idle machine, serial parts named).

    python3 studies/benchmarks/thread_scaling.py BUILD_DIR [--rounds N] [--size N]

Renders the 64^3 grid scene's reference image (studies/benchmarks/grid64_opacity.toml, tol 1e-10)
at SIZE^2 with --threads 1 and 2, alternately, ROUNDS times (default 5), and times `vrv verify` of
5 alpha images of 256^2 (reference cached, no plot) the same way.  Prints the median and the best
wall seconds (the best is the run least disturbed by other jobs: on this shared machine a 2-thread
run takes 0.55 s or 0.71 s depending on the host), both speed-ups, and the load average before
and after, since a busy machine cannot show a speed-up.
Each render run gives its whole wall time, its pixels alone (the time `vrv render` prints) and
its CPU seconds (user + system), so that the serial part (start-up, the image module, the grid, the
image files) is named; the image module (OpenImageIO and its libraries) loads on a thread of its
own beside the pixels, so a 1-thread run uses more than one core, and a 2-thread run shares its two
cores with that load.  The same render at twice the size (--size-large, default 2 SIZE) shows the
pixel loop's scaling with those fixed costs diluted, and a 1x1 render their cost alone.  For
verify it also times the run with --no-diagnosis, so that the part that is not the diagnosis
(reading images, the reference from the cache, statistics, writing) is named with its share.

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCENE = REPO / "studies" / "benchmarks" / "grid64_opacity.toml"
STEPS = [0.04, 0.02, 0.01, 0.005, 0.0025]


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def wall(cmd):
    """The command's wall seconds, what it printed (stdout, then stderr) and its CPU seconds."""
    cpu0 = children_cpu()
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    took = time.perf_counter() - start
    if proc.returncode not in (0, 1):
        sys.exit(f"thread_scaling: {' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()}")
    return took, proc.stdout + proc.stderr, children_cpu() - cpu0


def pixel_seconds(printed):
    """The pixels' time `vrv render` prints on stderr ("vrv render: N pixels (...) in S s")."""
    m = re.search(r"^vrv render: .* in ([0-9.]+) s$", printed, re.M)
    if not m:
        sys.exit(f"thread_scaling: no pixel time in vrv render's output: {printed.strip()[:200]}")
    return float(m.group(1))


def runs_by_threads(make_cmd, rounds):
    """Every round's wall() at 1 and 2 threads, alternately (so both see the same load)."""
    runs = {1: [], 2: []}
    for _ in range(rounds):
        for threads in (1, 2):
            runs[threads].append(wall(make_cmd(threads)))
    return runs


def pick(runs, measure):
    return {t: [measure(*r) for r in rs] for t, rs in runs.items()}


def wall_of(took, printed, cpu):
    return took


def cpu_of(took, printed, cpu):
    return cpu


def pixels_of(took, printed, cpu):
    return pixel_seconds(printed)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--size-large", type=int, default=0, help="the diluted render's size (default 2 SIZE)")
    args = ap.parse_args()
    vrv = str(Path(args.build_dir) / "vrv")
    if not Path(vrv).is_file():
        sys.exit(f"thread_scaling: {vrv}: not found")
    load_before = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        scene = ["--scene", str(SCENE)]
        render_cmd = lambda side: lambda t: [vrv, "render", *scene, "--reference", "--tol", "1e-10", "--width",
                                             str(side), "--height", str(side), "--quiet", "--threads", str(t),
                                             "-o", str(scratch / f"ref{t}.exr")]
        large = args.size_large or 2 * args.size
        for side in (args.size, large):
            render = runs_by_threads(render_cmd(side), args.rounds)
            rows.append((f"render --reference, grid 64³, {side}²", pick(render, wall_of)))
            rows.append(("the same, its pixels alone (the time `vrv render` reports)", pick(render, pixels_of)))
            rows.append(("the same, CPU seconds (user + system)", pick(render, cpu_of)))
        fixed = runs_by_threads(render_cmd(1), args.rounds)
        images = []
        for h in STEPS:
            out = scratch / f"alpha_{h}.exr"
            subprocess.run([vrv, "render", *scene, "--method", "alpha", "--strategy", "inviwo", "--step", str(h),
                            "--opacity-unit", "distance", "--width", "256", "--height", "256", "--quiet", "-o",
                            str(out)], check=True, capture_output=True)
            images.append(str(out))
        cache = scratch / "cache"
        verify = [vrv, "verify", *scene, *images, "--steps", ",".join(map(str, STEPS)), "--cache-dir", str(cache),
                  "--quiet"]
        subprocess.run(verify + ["--no-diagnosis"], capture_output=True)  # warm the cache
        full = runs_by_threads(lambda t: verify + ["--threads", str(t), "--out", str(scratch / f"v{t}")], args.rounds)
        rows.append(("verify, 5 images of 256², reference cached", pick(full, wall_of)))
        bare = runs_by_threads(lambda t: verify + ["--no-diagnosis", "--threads", str(t), "--out",
                                                    str(scratch / f"n{t}")], args.rounds)
        rows.append(("verify --no-diagnosis (the part that is not the diagnosis)", pick(bare, wall_of)))
    load_after = os.getloadavg()
    print(f"Wall seconds of {args.rounds} rounds, 1 and 2 threads alternately, their median and the best "
          f"(the least disturbed by other jobs on a shared machine) ({os.cpu_count()} cores; load average before "
          f"{load_before[0]:.2f}, after {load_after[0]:.2f}).\n")
    print("| run | 1 thread s (median, best) | 2 threads s (median, best) | speed-up of the medians | "
          "speed-up of the best |")
    print("|---|---|---|---|---|")
    med = [{k: statistics.median(v) for k, v in t.items()} for _, t in rows]
    best = [{k: min(v) for k, v in t.items()} for _, t in rows]
    for (name, _), m, b in zip(rows, med, best):
        print(f"| {name} | {m[1]:.3f}, {b[1]:.3f} | {m[2]:.3f}, {b[2]:.3f} | {m[1] / m[2]:.2f}× | {b[1] / b[2]:.2f}× |")
    serial = best[0][2] - best[1][2]
    share = best[-1][2] / best[-2][2]
    fixed_wall = statistics.median(pick(fixed, wall_of)[1])
    fixed_cpu = statistics.median(pick(fixed, cpu_of)[1])
    print(f"\nThe render's serial part (start-up, loading the image module, building the grid, writing the EXR, "
          f"PNG and double TIFF) is {serial:.3f} s of its best 2-thread wall time at {args.size}² "
          f"({serial / best[0][2]:.0%}); a 1×1 render, those fixed costs alone, takes {fixed_wall:.3f} s wall and "
          f"{fixed_cpu:.3f} CPU s (median). The image module loads on its own thread beside the pixels: at one thread "
          f"it has the second core to itself (CPU seconds above wall seconds), at two it takes a share of the pixel "
          f"loop's cores, so the pixels' speed-up grows with the image ({args.size}² against {large}²). "
          f"The part of verify that is not the diagnosis is {share:.0%} of its best 2-thread wall time. "
          f"`python3 studies/benchmarks/thread_scaling.py {' '.join(sys.argv[1:])}`")


if __name__ == "__main__":
    main()
