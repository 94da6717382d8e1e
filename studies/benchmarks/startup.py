#!/usr/bin/env python3
"""Start-up cost of vrv: wall and CPU time of short commands against a do-nothing baseline.

    python3 studies/benchmarks/startup.py BUILD_DIR [--runs N] [--timer hyperfine|python]
                                          [--before OTHER_BUILD_DIR]

Runs each command N times (after warm-up runs) with hyperfine when it is installed (Debian's
`apt-get install hyperfine`), otherwise with a Python timer (os.wait4: wall and user+system CPU
per run), side by side with `/bin/true`, and prints a Markdown table: median and minimum wall
time, mean CPU time, and the ratio of the median to the baseline's.  The goal (issue 10) is
`vrv --help` and `vrv ray` on one ray under 50 ms wall on an idle machine; the last column says
whether the median meets it.  --before adds the same `--help` and `ray` rows for another
build (e.g. one from before the image module), measured in the same run.  It also counts the shared libraries each binary loads at start
(ldd), which is what the image module (lib/io/image_module.h) keeps out of vrv.

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import json
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

GOAL_MS = 50.0


def ray_argv(vrv):
    return [vrv, "ray", "--origin", "-3,0.5,0", "--direction", "1,0,0", "--json"]


def commands(vrv, scratch, before):
    ray = ray_argv(vrv)
    extra = []
    if before:
        extra = [("before: vrv --help", [before, "--help"], True),
                 ("before: vrv ray (reference, one ray)", ray_argv(before), True)]
    return [
        ("baseline: /bin/true", ["/bin/true"], False),
        ("vrv --help", [vrv, "--help"], True),
        ("vrv ray (reference, one ray)", ray, True),
        ("vrv ray --method riemann (one ray)", ray + ["--method", "riemann"], False),
        ("vrv render 1x1 --reference (loads the image module)",
         [vrv, "render", "--reference", "--width", "1", "--height", "1", "--quiet",
          "-o", str(Path(scratch) / "one.exr")], False),
    ] + extra


def time_python(argv, runs, warmup):
    walls, cpus = [], []
    for i in range(warmup + runs):
        start = time.perf_counter()
        proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        if os.waitstatus_to_exitcode(status) != 0:
            sys.exit(f"startup.py: {' '.join(argv)} exited with {os.waitstatus_to_exitcode(status)}")
        if i >= warmup:
            walls.append(wall)
            cpus.append(usage.ru_utime + usage.ru_stime)
    return walls, statistics.mean(cpus)


def time_hyperfine(argv, runs, warmup, scratch):
    out = Path(scratch) / "hyperfine.json"
    subprocess.run(["hyperfine", "--style", "none", "--shell=none", "--warmup", str(warmup),
                    "--runs", str(runs), "--export-json", str(out),
                    shlex.join(argv)],
                   check=True, stdout=subprocess.DEVNULL)
    result = json.loads(out.read_text())["results"][0]
    return result["times"], result["user"] + result["system"]


def shared_libraries(path):
    try:
        out = subprocess.run(["ldd", str(path)], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    return sum(1 for line in out.splitlines() if "=>" in line or line.strip().startswith("/"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", type=Path)
    parser.add_argument("--runs", type=int, default=30)
    parser.add_argument("--warmup", type=int, default=3)
    parser.add_argument("--before", type=Path, help="another build directory to compare with")
    parser.add_argument("--timer", choices=["hyperfine", "python"],
                        default="hyperfine" if shutil.which("hyperfine") else "python")
    args = parser.parse_args()
    vrv = (args.build_dir / "vrv").resolve()
    if not vrv.is_file():
        sys.exit(f"startup.py: {vrv}: not built")
    if args.runs < 1:
        sys.exit("startup.py: --runs: must be at least 1")

    before = None
    if args.before:
        before = (args.before / "vrv").resolve()
        if not before.is_file():
            sys.exit(f"startup.py: {before}: not built")
    scratch = tempfile.mkdtemp(prefix="vrv_startup_")
    try:
        rows = []
        for name, argv, has_goal in commands(str(vrv), scratch, str(before) if before else None):
            if args.timer == "hyperfine":
                walls, cpu = time_hyperfine(argv, args.runs, args.warmup, scratch)
            else:
                walls, cpu = time_python(argv, args.runs, args.warmup)
            rows.append((name, statistics.median(walls), min(walls), cpu, has_goal))
    finally:
        shutil.rmtree(scratch, ignore_errors=True)

    load = os.getloadavg()
    print(f"timer: {args.timer}, {args.runs} runs after {args.warmup} warm-up runs; "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} cores")
    module = args.build_dir / "libvrv_image.so"
    print(f"shared libraries loaded at start (ldd): vrv {shared_libraries(vrv)}, "
          f"image module {shared_libraries(module) if module.exists() else 'n/a'}"
          + (f", before: vrv {shared_libraries(before)}" if before else ""))
    print()
    print("| command | median wall (ms) | min wall (ms) | mean CPU (ms) | median / baseline | "
          f"goal < {GOAL_MS:g} ms |")
    print("|---|---|---|---|---|---|")
    base = rows[0][1]
    for name, median, minimum, cpu, has_goal in rows:
        verdict = ""
        if has_goal:
            verdict = "met" if median * 1e3 < GOAL_MS else "missed"
        print(f"| `{name}` | {median * 1e3:.1f} | {minimum * 1e3:.1f} | {cpu * 1e3:.1f} | "
              f"{median / base:.1f} | {verdict} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
