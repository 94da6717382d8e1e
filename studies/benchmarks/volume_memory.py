#!/usr/bin/env python3
"""What a volume scene costs in memory against the volume's own size (issue 27).

    python3 studies/benchmarks/volume_memory.py BUILD_DIR SCENE.toml [SCENE.toml ...]

For each scene (a `kind = "volume"` field naming a NIfTI file), runs `vrv scene SCENE` (reads the
scene and its volume into the grid the reference integrates, prints the scene; no image library
loaded) and `vrv scene` of the default scene, and prints a Markdown table: the volume's own size
(its samples in their stored type, from the header as nibabel reads it: an independent reader),
the peak resident memory of each run (GNU time's %M), and the volume run's peak above the
default run's divided by the volume's size.  The goal: at most 1.2.

Needs nibabel (Debian's python3-nibabel) and GNU time (Debian's `time`); writes nothing.
"""
import subprocess
import sys
import tomllib
from pathlib import Path


def peak_kib(cmd):
    """Peak resident set of one run, in KiB, as GNU time reports it.  Not this process's own
    os.wait4: Linux carries the forking process's peak into the child's ru_maxrss across exec,
    so a child of Python would report Python's peak (nibabel and numpy loaded) when larger."""
    run = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        sys.exit(f"volume_memory: {' '.join(cmd)} exited {run.returncode}: {run.stderr.strip()}")
    return int(run.stderr.strip().splitlines()[-1])


def volume_bytes(scene):
    import nibabel
    field = tomllib.loads(Path(scene).read_text())["field"]
    if field.get("kind") != "volume":
        sys.exit(f"volume_memory: {scene}: field.kind is not \"volume\"")
    file = Path(field["file"])
    if not file.is_absolute():
        file = Path(scene).parent / file
    image = nibabel.load(str(file))
    count = 1
    for n in image.shape:
        count *= n
    return file.name, image.shape, image.get_data_dtype(), count * image.get_data_dtype().itemsize


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__.split("\n\n")[1])
    vrv = str(Path(sys.argv[1]) / "vrv")
    for tool in (vrv, "/usr/bin/time"):
        if not Path(tool).is_file():
            sys.exit(f"volume_memory: {tool}: not found")
    baseline = peak_kib([vrv, "scene"])
    print("| volume | samples | own size | peak, `vrv scene` | peak above the default scene's | ÷ own size |")
    print("|---|---|---|---|---|---|")
    for scene in sys.argv[2:]:
        name, shape, dtype, size = volume_bytes(scene)
        peak = peak_kib([vrv, "scene", scene])
        above = (peak - baseline) * 1024
        print(f"| `{name}` | {' x '.join(map(str, shape))} {dtype} | {size / 2**20:.1f} MiB | "
              f"{peak / 1024:.1f} MiB | {above / 2**20:.1f} MiB | {above / size:.2f} |")
    print(f"\nThe default scene's peak (the process without a volume): {baseline / 1024:.1f} MiB.")


if __name__ == "__main__":
    main()
