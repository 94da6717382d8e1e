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
The render is timed twice: its whole wall time, and its pixels alone (the time `vrv render`
prints), so that the serial part (start-up, the image module, the grid, the image files) is named.
For verify it also times the run with --no-diagnosis, so that the part that is not the diagnosis
(reading images, the reference from the cache, statistics, writing) is named with its share.

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
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
STEPS = [0.04, 0.02, 0.01, 0.005, 0.0025]


def wall(cmd):
    """The command's wall seconds and what it printed (stdout, then stderr)."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    took = time.perf_counter() - start
    if proc.returncode not in (0, 1):
        sys.exit(f"thread_scaling: {' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()}")
    return took, proc.stdout + proc.stderr


def pixel_seconds(printed):
    """The pixels' time `vrv render` prints on stderr ("vrv render: N pixels (...) in S s")."""
    m = re.search(r"^vrv render: .* in ([0-9.]+) s$", printed, re.M)
    if not m:
        sys.exit(f"thread_scaling: no pixel time in vrv render's output: {printed.strip()[:200]}")
    return float(m.group(1))


def times_by_threads(make_cmd, rounds, measure=lambda took, printed: took):
    """Every round's time at 1 and 2 threads, alternately (so both see the same load)."""
    times = {1: [], 2: []}
    for _ in range(rounds):
        for threads in (1, 2):
            times[threads].append(measure(*wall(make_cmd(threads))))
    return times


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--size", type=int, default=512)
    args = ap.parse_args()
    vrv = str(Path(args.build_dir) / "vrv")
    if not Path(vrv).is_file():
        sys.exit(f"thread_scaling: {vrv}: not found")
    load_before = os.getloadavg()
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        scene = ["--scene", str(SCENE)]
        size = ["--width", str(args.size), "--height", str(args.size)]
        render_cmd = lambda t: [vrv, "render", *scene, "--reference", "--tol", "1e-10", *size, "--quiet",
                                "--threads", str(t), "-o", str(scratch / f"ref{t}.exr")]
        render = times_by_threads(render_cmd, args.rounds)
        rows.append((f"render --reference, grid 64³, {args.size}²", render))
        pixels = times_by_threads(render_cmd, args.rounds, lambda took, printed: pixel_seconds(printed))
        rows.append(("the same, its pixels alone (the time `vrv render` reports)", pixels))
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
        full = times_by_threads(lambda t: verify + ["--threads", str(t), "--out", str(scratch / f"v{t}")],
                                 args.rounds)
        rows.append(("verify, 5 images of 256², reference cached", full))
        bare = times_by_threads(lambda t: verify + ["--no-diagnosis", "--threads", str(t), "--out",
                                                     str(scratch / f"n{t}")], args.rounds)
        rows.append(("verify --no-diagnosis (the part that is not the diagnosis)", bare))
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
    share = best[3][2] / best[2][2]
    print(f"\nThe render's serial part (start-up, loading the image module, building the grid, writing the EXR, "
          f"PNG and double TIFF) is {serial:.3f} s of its best 2-thread wall time ({serial / best[0][2]:.0%}); "
          f"the part of verify that is not the diagnosis is {share:.0%} of its best 2-thread wall time. "
          f"`python3 studies/benchmarks/thread_scaling.py {' '.join(sys.argv[1:])}`")


if __name__ == "__main__":
    main()
