#!/usr/bin/env python3
"""One Google Benchmark program of two builds, side by side.

    python3 studies/benchmarks/bench_compare.py BUILD_DIR --before OTHER_BUILD_DIR
                                                [--program bench_reference] [--filter REGEX] [--rounds N]

Runs BUILD_DIR/PROGRAM and OTHER_BUILD_DIR/PROGRAM alternately, ROUNDS times each (default 7), so
that both see the same load, and prints a Markdown table per benchmark: the median time of each
build and the median of the per-round ratios new / before (with their range), and whether the
benchmark's counters (evaluations per ray, largest estimate, ...) are equal in both, which for a
change meant to keep every value says it did.

Python 3 standard library only.
"""
import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path


def run(build, program, pattern):
    exe = Path(build) / program
    cmd = [str(exe), f"--benchmark_filter={pattern}", "--benchmark_format=json"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    if r.returncode != 0:
        sys.exit(f"bench_compare: {' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
    return {b["name"]: b for b in json.loads(r.stdout)["benchmarks"]}


def counters(b):
    skip = {"name", "run_name", "run_type", "repetitions", "repetition_index", "threads", "iterations",
            "real_time", "cpu_time", "time_unit", "family_index", "per_family_instance_index", "label"}
    return {k: v for k, v in b.items() if k not in skip and not k.endswith("_per_s") and k != "rays_per_s"}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--before", required=True)
    ap.add_argument("--program", default="bench_reference")
    ap.add_argument("--filter", default=".")
    ap.add_argument("--rounds", type=int, default=7)
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("bench_compare: --rounds: must be at least 1")
    new, old = [], []
    for _ in range(a.rounds):
        old.append(run(a.before, a.program, a.filter))
        new.append(run(a.build, a.program, a.filter))
    print(f"{a.program}, {a.rounds} rounds alternating, times in ms (medians)\n")
    print("| benchmark | before | new | new / before (range) | counters equal |")
    print("|---|---|---|---|---|")
    for name in new[0]:
        if name not in old[0]:
            continue
        ratios = [n[name]["real_time"] / o[name]["real_time"] for n, o in zip(new, old)]
        same = counters(new[0][name]) == counters(old[0][name])
        print(f"| {name} | {statistics.median(o[name]['real_time'] for o in old):.2f} | "
              f"{statistics.median(n[name]['real_time'] for n in new):.2f} | {statistics.median(ratios):.3f} "
              f"({min(ratios):.2f}–{max(ratios):.2f}) | {'yes' if same else 'no'} |")


if __name__ == "__main__":
    main()
