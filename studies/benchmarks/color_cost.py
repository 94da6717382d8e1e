#!/usr/bin/env python3
"""What an RGB reference ray costs against the same rays in grey (issue 25's goal: at most 1.3x).

    python3 studies/benchmarks/color_cost.py BUILD_DIR [--rounds N]

Runs BUILD_DIR/bench_reference's BM_Color_* benchmarks ROUNDS times (default 5): in each run the
same 256 rays at tol 1e-12 are integrated with each channel alone (grey, /0../2), with all three
(RGB, /3) and in grey with one emission holding every channel's breakpoints (/4, the grey ray of
the RGB ray's structure: where the channels' breakpoints differ, the RGB panels must resolve all of
them).  Prints per field the field evaluations of the RGB ray over its costliest channel's and over
the union grey's, and the medians over the runs of RGB time over the costliest grey channel's, over
the union grey's and over the three channels' sum.

Python 3 standard library only.
"""
import argparse
import collections
import json
import statistics
import subprocess
import sys
from pathlib import Path


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--rounds", type=int, default=5)
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("color_cost: --rounds: must be at least 1")
    exe = Path(a.build) / "bench_reference"
    times = collections.defaultdict(lambda: collections.defaultdict(list))
    evals = {}
    for _ in range(a.rounds):
        r = subprocess.run([str(exe), "--benchmark_filter=Color", "--benchmark_format=json"], capture_output=True,
                           text=True, timeout=3600)
        if r.returncode != 0:
            sys.exit(f"color_cost: {exe} exited {r.returncode}: {r.stderr.strip()}")
        per = collections.defaultdict(dict)
        for b in json.loads(r.stdout)["benchmarks"]:
            field, arg = b["name"].split("/")
            per[field][int(arg)] = b["real_time"]
            evals[(field, int(arg))] = b["evals_per_ray"]
        for field, t in per.items():
            grey = [t[c] for c in range(3)]
            times[field]["max"].append(t[3] / max(grey))
            times[field]["union"].append(t[3] / t[4])
            times[field]["sum"].append(t[3] / sum(grey))
            times[field]["grey"].append(max(grey))
            times[field]["rgb"].append(t[3])
    print(f"bench_reference BM_Color_*, {a.rounds} runs (medians)\n")
    print("| field | evaluations, RGB ÷ costliest channel | time, RGB ÷ costliest channel | evaluations, RGB ÷ union grey | "
          "time, RGB ÷ union grey | RGB ÷ sum of channels | costliest channel, RGB (ms) |")
    print("|---|---|---|---|---|---|---|")
    for field, t in times.items():
        ev = evals[(field, 3)] / max(evals[(field, c)] for c in range(3))
        ev_union = evals[(field, 3)] / evals[(field, 4)]
        print(f"| {field.removeprefix('BM_Color_')} | {ev:.3f} | {statistics.median(t['max']):.2f} | "
              f"{ev_union:.3f} | {statistics.median(t['union']):.2f} | "
              f"{statistics.median(t['sum']):.2f} | {statistics.median(t['grey']):.1f}, {statistics.median(t['rgb']):.1f} |")


if __name__ == "__main__":
    main()
