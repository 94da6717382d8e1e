#!/usr/bin/env python3
"""What `vrv verify` costs with its reference cached (issue 23: <= 3 CPU s on the 64^3 grid scene,
<= 2 CPU s on the default scene, 5 images at 256^2).

    python3 studies/benchmarks/verify_speed.py BUILD_DIR [--before OTHER_BUILD_DIR]
                                               [--rounds N] [--size N] [--keep DIR]
                                               [--images N] [--first-run] [--threads T]
                                               [--scenes default,grid] [--no-plot-rows] [--floor]

For each scene (the embedded default, and a 64^3 trilinear grid of the Marschner-Lobb field with
an opacity/colour transfer function whose opacity is per unit distance) it renders 5 images with
BUILD_DIR's own `vrv render --method alpha --strategy inviwo --step H` (the grid's with
`--opacity-unit distance`), warms the reference cache with each build, then times
`vrv verify --out` on them ROUNDS times, alternating the builds when --before is given so that
both see the same load, with and without the plot (`--plots`; `--no-plots` for builds before it).  It prints a Markdown table of
the median CPU seconds (user + system of vrv and its children, as /usr/bin/time counts them) and
wall seconds, each build's nearest model and the faults it names.  --keep DIR keeps every build's last --out folder
(DIR/<build>/<scene>/) for diffing.  --images N takes the N coarsest of 0.04, 0.02, ..., 0.00125
(default 5); --first-run times verify with an empty reference cache (the reference computed in the
timed run, as a user's first verify); --threads T passes `--threads T` to verify (default: all
cores); --scenes picks scenes; --no-plot-rows times only the runs without the plot; --floor
renders the images with the field of view 2 % wider than the scene's camera (issue 24's floor: the
fitted fault catalogue runs, and names "field of view 2.0 % wider"; the default scene only).

Python 3 standard library only; writes nothing but a scratch directory it removes.
"""
import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ALL_STEPS = [0.04, 0.02, 0.01, 0.005, 0.0025, 0.00125]
STEPS = ALL_STEPS[:5]

GRID_SCENE = """[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "grid"
resolution = [64, 64, 64]
[field.source]
kind = "marschner_lobb"
[transfer]
opacity = [[0.0, 0.0], [0.3, 0.05], [1.0, 0.6]]
color = [[0.0, 0.2], [0.55, 1.0], [1.0, 0.5]]
unit_length = 0.25
[background]
intensity = 0.1
"""

SCENES = {
    "default": {"key": "default", "file": None, "render": []},
    "grid 64^3": {"key": "grid", "file": "grid.toml", "render": ["--opacity-unit", "distance"]},
}


def run(cmd, what):
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=3600)
    if proc.returncode not in (0, 1):  # verify: 1 is a failed check, still a measurement
        sys.exit(f"verify_speed: {what}: {' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()}")
    return proc


def timed(cmd, what):
    """CPU seconds (user + system of the child and everything it waited for) and wall seconds."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    proc = run(cmd, what)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall, proc


# The default camera (lib/camera.cpp default_camera: the box's centre seen from 2.5 box diagonals
# down -z) with the field of view 2 % wider than its 40 degrees: a step-independent floor.
def floor_scene(vrv, size):
    text = subprocess.run([vrv, "scene"], capture_output=True, text=True, check=True).stdout
    return text + (f"\n[camera]\neye = [0.0, 0.0, {-2.5 * 12 ** 0.5!r}]\ntarget = [0.0, 0.0, 0.0]\n"
                   f"up = [0.0, 1.0, 0.0]\nfov = 40.8\nwidth = {size}\nheight = {size}\n")


def make_images(vrv, scene_args, render_args, size, folder):
    images = []
    for h in STEPS:
        out = folder / f"alpha_{h}.exr"
        run([vrv, "render", *scene_args, "--method", "alpha", "--strategy", "inviwo", "--step", str(h),
             *render_args, "--width", str(size), "--height", str(size), "--quiet", "-o", str(out)], "render")
        images.append(str(out))
    return images


def plot_flags(vrv, plots):
    """Builds since issue 23 draw the plot only with --plots; older ones unless --no-plots."""
    opt_in = "--plots" in subprocess.run([str(vrv), "verify", "--help"], capture_output=True, text=True).stdout
    if opt_in:
        return ["--plots"] if plots else []
    return [] if plots else ["--no-plots"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("--before", help="another build directory, measured alternately in the same run")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--keep", help="keep each build's last --out folder here")
    ap.add_argument("--images", type=int, default=5, choices=range(2, len(ALL_STEPS) + 1))
    ap.add_argument("--first-run", action="store_true", help="an empty reference cache in every timed run")
    ap.add_argument("--threads", type=int, help="verify's --threads (default: all cores)")
    ap.add_argument("--scenes", default="default,grid", help="comma-separated: default, grid")
    ap.add_argument("--no-plot-rows", action="store_true", help="time only the runs without the plot")
    ap.add_argument("--floor", action="store_true", help="images with the field of view 2 %% wide (default scene)")
    args = ap.parse_args()
    global STEPS
    STEPS = ALL_STEPS[:args.images]
    wanted = set(args.scenes.split(","))
    if args.floor:
        wanted = {"default"}
    if not wanted <= {spec["key"] for spec in SCENES.values()}:
        sys.exit(f"verify_speed: --scenes: unknown scene in {args.scenes!r} (default, grid)")
    plot_rows = (False,) if args.no_plot_rows else (True, False)
    thread_args = ["--threads", str(args.threads)] if args.threads is not None else []
    builds = ([("before", args.before)] if args.before else []) + [("this build", args.build_dir)]
    for _, d in builds:
        if not (Path(d) / "vrv").is_file():
            sys.exit(f"verify_speed: {d}/vrv: not found")
    steps = ",".join(str(h) for h in STEPS)
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        (scratch / "grid.toml").write_text(GRID_SCENE)
        cache = scratch / "cache"
        for scene, spec in SCENES.items():
            if spec["key"] not in wanted:
                continue
            scene_args = ["--scene", str(scratch / spec["file"])] if spec["file"] else []
            folder = scratch / scene.replace(" ", "_").replace("^", "")
            folder.mkdir()
            render_args = spec["render"]
            if args.floor:
                (scratch / "floor.toml").write_text(floor_scene(str(Path(args.build_dir) / "vrv"), args.size))
                render_args = render_args + ["--scene", str(scratch / "floor.toml")]
            images = make_images(str(Path(args.build_dir) / "vrv"), scene_args, render_args, args.size, folder)
            results = {(name, plots): [] for name, _ in builds for plots in plot_rows}
            nearest, named = {}, {}
            for name, d in builds if not args.first_run else []:  # warm the cache (shared: same key)
                run([str(Path(d) / "vrv"), "verify", *scene_args, *images, "--steps", steps,
                     "--cache-dir", str(cache), "--quiet", "--no-diagnosis"], "warm the cache")
            for _ in range(args.rounds):
                for name, d in builds:
                    for plots in plot_rows:
                        if args.first_run:
                            shutil.rmtree(cache, ignore_errors=True)
                        out = folder / f"out_{name.replace(' ', '_')}_{plots}"
                        shutil.rmtree(out, ignore_errors=True)
                        cmd = [str(Path(d) / "vrv"), "verify", *scene_args, *images, "--steps", steps,
                               "--cache-dir", str(cache), "--quiet", "--out", str(out), *thread_args]
                        cpu, wall, proc = timed(cmd + plot_flags(Path(d) / "vrv", plots), "verify")
                        if plots and not (out / "error_vs_step.png").is_file():
                            sys.exit(f"verify_speed: {name}: no plot drawn ({proc.stderr.strip()})")
                        report = json.loads(proc.stdout)
                        if report["reference"]["from_cache"] == args.first_run:
                            sys.exit(f"verify_speed: {name}: the reference was "
                                     f"{'read from' if args.first_run else 'not read from'} the cache")
                        results[(name, plots)].append((cpu, wall))
                        nearest[name] = report["diagnosis"][0]["name"] if report["diagnosis"] else "none"
                        named[name] = "; ".join(f.get("behaves_like") or f["name"]
                                                for f in report.get("faults", [])) or "none"
                        if args.keep and not plots:
                            keep = Path(args.keep) / name.replace(" ", "_") / folder.name
                            shutil.rmtree(keep, ignore_errors=True)
                            shutil.copytree(out, keep)
            for (name, plots), times in results.items():
                cpu = statistics.median(t[0] for t in times)
                wall = statistics.median(t[1] for t in times)
                rows.append((scene, name, "yes" if plots else "no", cpu, wall, nearest[name], named[name]))
    cached = "computed in each run (first run)" if args.first_run else "cached"
    floor = ", rendered with the field of view 2 % wide (a floor)" if args.floor else ""
    print(f"`vrv verify`, {len(STEPS)} images of {args.size}²{floor} (alpha, inviwo, steps {steps}), the reference "
          f"{cached}, median of {args.rounds} rounds; CPU = user + system of vrv and its children.\n")
    print("| scene | build | plot | CPU s | wall s | nearest model | faults named |")
    print("|---|---|---|---|---|---|---|")
    for scene, name, plots, cpu, wall, near, faults in rows:
        print(f"| {scene} | {name} | {plots} | {cpu:.2f} | {wall:.2f} | {near} | {faults} |")
    if args.before:
        print()
        for scene in sorted({r[0] for r in rows}):
            for plots in sorted({r[2] for r in rows}, reverse=True):
                cpu = {r[1]: r[3] for r in rows if r[0] == scene and r[2] == plots}
                print(f"- {scene}, plot {plots}: this build / before = {cpu['this build'] / cpu['before']:.2f}")
    threads = f"{args.threads}" if args.threads is not None else f"all ({os.cpu_count()} cores)"
    print(f"\nThreads: {threads}; `python3 studies/benchmarks/verify_speed.py "
          f"{' '.join(sys.argv[1:])}`")


if __name__ == "__main__":
    main()
