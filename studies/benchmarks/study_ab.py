#!/usr/bin/env python3
"""Two builds of vrv side by side on the same studies: which is faster, and do they agree?

    /usr/bin/python3 studies/benchmarks/study_ab.py OLD_VRV NEW_VRV [--rounds N]
        [--old-threads N] [--new-threads N] [STUDY ...]

Runs `vrv study --all` (or each STUDY given) with OLD_VRV and NEW_VRV in turn, ROUNDS times
(default 3), so both see the same load on a shared machine, each into its own scratch folder
with --no-plots --quiet.  Prints, per build, the wall seconds and CPU use of each run and the
median wall seconds of each study (meta.json's wall_seconds), their ratio old / new, and the load
average before and after.  --old-threads and --new-threads pass --threads to one side (the
same build twice with 1 and 2 threads measures what the second core gives).  Checks that the two builds wrote the same files with the same bytes,
apart from meta.json and the files that hold measured times (their names are listed in TIMED).

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# Files whose numbers are measured times (docs/studies.md): they differ from run to run.
TIMED = {
    "opacity-correction": {"timing.csv", "timing.md", "timing.tex", "speed_error.csv", "checks.csv", "checks.md",
                           "checks.tex"},
    "speed-vs-error": {"points.csv", "points.md", "points.tex", "targets.csv", "targets.md", "targets.tex",
                       "checks.csv", "checks.md", "checks.tex"},
}


def run(vrv, out, studies, threads):
    """Wall seconds and CPU share of one run of the studies."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    for s in studies or [None]:
        one = [vrv, "study", s if s else "--all", "--out", out, "--no-plots", "--quiet"]
        if threads:
            one += ["--threads", str(threads)]
        proc = subprocess.run(one, capture_output=True, text=True, timeout=7200)
        if proc.returncode != 0:
            sys.exit(f"study_ab: {' '.join(one)} exited {proc.returncode}: {proc.stderr.strip()[:400]}")
    took = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return took, cpu / took


def walls(out):
    return {p.parent.name: json.loads(p.read_text())["wall_seconds"] for p in Path(out).glob("*/meta.json")}


def files(out):
    found = {}
    for p in Path(out).rglob("*"):
        study = p.relative_to(out).parts[0]
        if p.is_file() and p.name != "meta.json" and p.name not in TIMED.get(study, set()):
            found[p.relative_to(out)] = p.read_bytes()
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("old", type=Path)
    ap.add_argument("new", type=Path)
    ap.add_argument("studies", nargs="*")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--old-threads", type=int)
    ap.add_argument("--new-threads", type=int)
    args = ap.parse_args()
    builds = {"old": str(args.old.resolve()), "new": str(args.new.resolve())}
    threads = {"old": args.old_threads, "new": args.new_threads}
    runs = {name: [] for name in builds}
    per_study = {name: {} for name in builds}
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            for name, vrv in builds.items():
                out = f"{tmp}/{name}{r}"
                runs[name].append(run(vrv, out, args.studies, threads[name]))
                for study, w in walls(out).items():
                    per_study[name].setdefault(study, []).append(w)
        if files(f"{tmp}/old0") != files(f"{tmp}/new0"):
            old, new = files(f"{tmp}/old0"), files(f"{tmp}/new0")
            differ = sorted(str(k) for k in set(old) | set(new) if old.get(k) != new.get(k))
            sys.exit(f"study_ab: the builds wrote different results: {differ[:10]}")
    load_after = os.getloadavg()[0]
    print(f"old: {builds['old']} (--threads {threads['old'] or 'all'}), new: {builds['new']} "
          f"(--threads {threads['new'] or 'all'})")
    print(f"{args.rounds} rounds, old then new in each; load average {load_before:.2f} before, "
          f"{load_after:.2f} after; the same files apart from meta.json and measured times\n")
    print("| run | wall s, each round | CPU use, each round | wall s (median) |")
    print("|---|---|---|---|")
    for name, rs in runs.items():
        print(f"| {name} | {', '.join(f'{w:.1f}' for w, _ in rs)} | {', '.join(f'{c:.2f}' for _, c in rs)} | "
              f"{statistics.median(w for w, _ in rs):.1f} |")
    print("\n| study | old s (median) | new s (median) | old / new |")
    print("|---|---|---|---|")
    for study in sorted(per_study["old"]):
        o, n = statistics.median(per_study["old"][study]), statistics.median(per_study["new"][study])
        print(f"| {study} | {o:.2f} | {n:.2f} | {o / n:.2f} |")


if __name__ == "__main__":
    main()
