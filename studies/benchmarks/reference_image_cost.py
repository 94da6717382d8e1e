#!/usr/bin/env python3
"""What a reference image costs against the discrete image it judges (issue 10).

    python3 studies/benchmarks/reference_image_cost.py BUILD_DIR [--before OTHER_BUILD_DIR]
                                                       [--rounds N] [--size N] [--step H]
                                                       [--scene FILE] [--tol T]

Renders the default scene (or FILE, e.g. studies/benchmarks/grid64_opacity.toml, or a real scan:
studies/benchmarks/ch2bet_volume.toml) (SIZE x SIZE pixels, one thread) with the reference
integrator at tol T (default 1e-10) and with the trapezoid rule (inviwo placement, step H, default 0.0062: about 5e-6 off at
most), each ROUNDS times, alternating the builds when --before is given so that both see the same
load, and prints a Markdown table: the median render time each `vrv render` reports (the pixels
only: no start-up, no image writing) and the best (the round least disturbed by other jobs on a
shared machine), the trapezoid image's max |error| against that build's reference, and the ratio
reference / trapezoid of both.  The goals: at most 1 on the default scene, 2 on the grid.

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

TIME = re.compile(r" in ([0-9.]+) s$", re.M)
MAX_ERROR = re.compile(r"max \|e\| ([0-9.eE+-]+)")


def render(vrv, args, out):
    cmd = [vrv, "render", "--threads", "1", "--quiet", "-o", str(out)] + args
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    if run.returncode != 0:
        sys.exit(f"reference_image_cost: {' '.join(cmd)} exited {run.returncode}: {run.stderr.strip()}")
    seconds = TIME.search(run.stderr)
    if not seconds:
        sys.exit(f"reference_image_cost: no render time in the output of {' '.join(cmd)}")
    error = MAX_ERROR.search(run.stderr)
    return float(seconds.group(1)), float(error.group(1)) if error else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("--before", help="another build directory, measured alternately in the same run")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--step", type=float, default=0.0062)
    ap.add_argument("--scene", help="a scene file (default: vrv's default scene)")
    ap.add_argument("--tol", type=float, default=1e-10, help="the reference's tolerance")
    args = ap.parse_args()
    builds = ([("before", args.before)] if args.before else []) + [("this build", args.build_dir)]
    for _, d in builds:
        if not (Path(d) / "vrv").is_file():
            sys.exit(f"reference_image_cost: {d}/vrv: not found")
    size = ["--width", str(args.size), "--height", str(args.size)]
    if args.scene:
        if not Path(args.scene).is_file():
            sys.exit(f"reference_image_cost: --scene {args.scene}: not found")
        size += ["--scene", args.scene]
    times = {name: {"reference": [], "trapezoid": []} for name, _ in builds}
    errors = {}
    with tempfile.TemporaryDirectory() as scratch:
        for _ in range(args.rounds):
            for name, d in builds:
                vrv = str(Path(d) / "vrv")
                ref = Path(scratch) / f"ref_{len(errors)}_{name.replace(' ', '_')}.exr"
                t_ref, _ = render(vrv, ["--reference", "--tol", repr(args.tol)] + size, ref)
                t_trap, err = render(vrv, ["--method", "trapezoid", "--strategy", "inviwo", "--step",
                                           str(args.step), "--error-against", str(ref)] + size,
                                     Path(scratch) / "trap.exr")
                times[name]["reference"].append(t_ref)
                times[name]["trapezoid"].append(t_trap)
                errors[name] = err
    print(f"| build | reference, tol {args.tol:g} (median, best) | trapezoid, inviwo step {args.step} (median, best) | "
          "its max abs error | reference / trapezoid (medians, best) |")
    print("|---|---|---|---|---|")
    for name, d in builds:
        ref, trap = times[name]["reference"], times[name]["trapezoid"]
        r, t = statistics.median(ref), statistics.median(trap)
        print(f"| {name} (`{d}`) | {1e3 * r:.0f}, {1e3 * min(ref):.0f} ms | {1e3 * t:.0f}, {1e3 * min(trap):.0f} ms | "
              f"{errors[name]:.2e} | {r / t:.2f}, {min(ref) / min(trap):.2f} |")
    print(f"\n{args.size}² pixels of {args.scene or 'the default scene'}, one thread, median and best of {args.rounds} rounds "
          "(the time `vrv render` reports for the pixels).")


if __name__ == "__main__":
    main()
