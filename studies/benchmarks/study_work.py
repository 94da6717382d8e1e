#!/usr/bin/env python3
"""A study's estimated work against the time it takes: what calibrates `vrv study --max-work`.

    python3 studies/benchmarks/study_work.py BUILD_DIR [--quick] [--threads N]

Runs every shipped study (`vrv study NAME --no-plots --quiet`, full unless --quick) one after
another into a scratch directory and prints a Markdown table from each run's meta.json: the field
evaluations its file was estimated at before it ran (`work_estimate`, studies/engine/study_work.h),
the largest part, the wall time, and the estimate per second of wall time.  The default limit,
1e10 evaluations, is then that many seconds' work (docs/robustness.md, "Work limits").

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


def studies(vrv):
    out = subprocess.run([vrv, "study", "--list"], capture_output=True, text=True, check=True).stdout
    return [line.split("\t")[0] for line in out.splitlines() if line.strip()]


def run(vrv, name, scratch, quick, threads):
    argv = [vrv, "study", name, "--no-plots", "--quiet", "--out", str(scratch)]
    if quick:
        argv.append("--quick")
    if threads:
        argv += ["--threads", str(threads)]
    done = subprocess.run(argv, capture_output=True, text=True)
    if done.returncode not in (0, 1):  # 1: a check failed; the timing still stands
        sys.exit(f"study_work: {' '.join(argv)} exited {done.returncode}: {done.stderr.strip()}")
    meta = json.loads((scratch / name / "meta.json").read_text())
    work = meta["work_estimate"]
    largest = max(work["parts"], key=lambda p: p["evaluations"])
    return [name, f"{work['evaluations']:.2g}", largest["what"], f"{meta['wall_seconds']:.2f}",
            f"{work['per_second']:.2g}"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("--quick", action="store_true", help="the --quick variants")
    ap.add_argument("--threads", type=int, default=0, help="vrv study --threads (default: all cores)")
    args = ap.parse_args()
    vrv = str(Path(args.build_dir) / "vrv")
    if not os.access(vrv, os.X_OK):
        sys.exit(f"study_work: {vrv}: not an executable")
    scratch = Path(tempfile.mkdtemp(prefix="vrv-study-work-"))
    try:
        rows = [run(vrv, name, scratch, args.quick, args.threads) for name in studies(vrv)]
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    header = ["study", "estimated evaluations", "largest part", "wall seconds", "evaluations per second"]
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print(f"\n{os.cpu_count()} cores; load average at the end: {open('/proc/loadavg').read().split()[0]}")


if __name__ == "__main__":
    main()
