#!/usr/bin/env python3
"""What `vrv plan`'s choice costs against the cheapest configuration brute force finds (issue 29's
goal: at most 1.5x).

    python3 studies/benchmarks/plan_cost.py BUILD_DIR [--scene FILE ...] [--target T] [--metric max|rms]
                                            [--size N] [--rounds N]

For the default scene and each FILE (e.g. studies/benchmarks/grid24_emission.toml), on the scene
camera at SIZE x SIZE pixels (default 64):
  * the plan: `vrv plan --target T` picks a rule and step before rendering (the cheapest it ranks);
  * brute force, as speed-vs-error searches: every rule (riemann, alpha, trapezoid, exact_linear;
    placement `step`, as the plan's) at the steps 0.4 / 2^k, k = 0..11, each rendered and measured
    against the reference (tol 1e-12); per rule the largest step that meets the target;
  * then the plan's choice and each rule's brute-force choice are rendered ROUNDS times (default 5)
    side by side, one thread, and the median times (the pixels only: `vrv render`'s JSON "seconds")
    compared: the plan's over the fastest brute-force choice's.
Prints a Markdown table per scene and the ratio.  Exits 1 when the plan's choice, rendered, misses
the target.

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ERROR = {"max": "max_abs_error", "rms": "rms_error"}
RULES = ["riemann", "alpha", "trapezoid", "exact_linear"]
LADDER = [0.4 / 2 ** k for k in range(12)]


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    if r.returncode not in (0, 1) or (r.returncode == 1 and "plan" not in cmd):
        sys.exit(f"plan_cost: {' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
    return r


def render(vrv, args, out):
    """(seconds, max error, rms error) of one `vrv render`; the errors when --error-against is given."""
    r = json.loads(run([vrv, "render", "--threads", "1", "--quiet", "-o", str(out)] + args).stdout)
    return r["seconds"], {m: r.get(key) for m, key in ERROR.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("--scene", action="append", default=[], help="a scene file (repeatable); the default scene always")
    ap.add_argument("--target", type=float, default=1e-3)
    ap.add_argument("--metric", choices=["max", "rms"], default="max")
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    vrv = str(Path(a.build_dir) / "vrv")
    if not Path(vrv).is_file():
        sys.exit(f"plan_cost: {vrv}: not found")
    for s in a.scene:
        if not Path(s).is_file():
            sys.exit(f"plan_cost: --scene {s}: not found")
    if a.rounds < 1 or a.size < 1 or not a.target > 0:
        sys.exit("plan_cost: --rounds and --size must be at least 1, --target positive")
    missed = False
    with tempfile.TemporaryDirectory() as scratch:
        for scene in [None] + a.scene:
            where = ["--scene", scene] if scene else []
            size = ["--width", str(a.size), "--height", str(a.size)]
            ref = Path(scratch) / "reference.exr"
            render(vrv, ["--reference", "--tol", "1e-12"] + size + where, ref)
            plan = json.loads(run([vrv, "plan", "--target", repr(a.target), "--metric", a.metric, "--json"] + size +
                                  where).stdout)
            chosen = plan["ranked"][0]
            configs = {"plan": (chosen["rule"], chosen["step"])}
            errors = {}
            for rule in RULES:
                for h in LADDER:
                    _, e = render(vrv, ["--method", rule, "--strategy", "step", "--step", repr(h),
                                        "--error-against", str(ref)] + size + where, Path(scratch) / "d.exr")
                    if e[a.metric] is not None and e[a.metric] <= a.target:
                        configs[rule] = (rule, h)
                        errors[rule] = e[a.metric]
                        break
            times = {k: [] for k in configs}
            for _ in range(a.rounds):
                for k, (rule, h) in configs.items():
                    t, e = render(vrv, ["--method", rule, "--strategy", "step", "--step", repr(h),
                                        "--error-against", str(ref)] + size + where, Path(scratch) / "d.exr")
                    times[k].append(t)
                    errors.setdefault(k, e[a.metric])
            median = {k: statistics.median(v) for k, v in times.items()}
            brute = [k for k in configs if k != "plan"]
            fastest = min(brute, key=lambda k: median[k]) if brute else None
            print(f"\n### {scene or 'the default scene'}: {a.metric} error <= {a.target:g}, {a.size}x{a.size} pixels\n")
            print("| configuration | rule | step | measured error | median seconds (one thread) |")
            print("|---|---|---:|---:|---:|")
            for k, (rule, h) in configs.items():
                label = "vrv plan" if k == "plan" else "brute force" + (" (fastest)" if k == fastest else "")
                print(f"| {label} | {rule} | {h:.4g} | {errors[k]:.3g} | {median[k]:.4f} |")
            if errors["plan"] > a.target:
                missed = True
                print(f"\nthe plan's choice misses the target: {errors['plan']:.3g}")
            if fastest:
                print(f"\nplan / fastest brute force: {median['plan'] / median[fastest]:.2f} (goal: at most 1.5)")
    print(f"\nMedians of {a.rounds} rounds, side by side; the brute-force ladder is 0.4 / 2^k, k = 0..11.")
    sys.exit(1 if missed else 0)


if __name__ == "__main__":
    main()
