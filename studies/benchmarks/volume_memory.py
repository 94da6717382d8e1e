#!/usr/bin/env python3
"""What a volume scene costs in memory against the volume's own size (issue 27).

    python3 studies/benchmarks/volume_memory.py BUILD_DIR [--metaimage] SCENE.toml [SCENE.toml ...]

For each scene (a `kind = "volume"` field naming a NIfTI file), runs `vrv scene SCENE` (reads the
scene and its volume into the grid the reference integrates, prints the scene; no image library
loaded) and `vrv scene` of the default scene, and prints a Markdown table: the volume's own size
(its samples in their stored type, from the header as nibabel reads it: an independent reader),
the peak resident memory of each run (GNU time's %M), and the volume run's peak above the
default run's divided by the volume's size.  The goal: at most 1.2.

--metaimage: also the same samples written here (with nibabel and zlib, in a temporary folder) as
MetaImage files, raw and zlib-compressed, each read through a copy of the scene naming it.

Needs nibabel (Debian's python3-nibabel) and GNU time (Debian's `time`); writes nothing else.
"""
import re
import subprocess
import sys
import tempfile
import tomllib
import zlib
from pathlib import Path

MET_TYPES = {"uint8": "MET_UCHAR", "int8": "MET_CHAR", "uint16": "MET_USHORT", "int16": "MET_SHORT",
             "uint32": "MET_UINT", "int32": "MET_INT", "float32": "MET_FLOAT", "float64": "MET_DOUBLE"}


def peak_kib(cmd):
    """Peak resident set of one run, in KiB, as GNU time reports it.  Not this process's own
    os.wait4: Linux carries the forking process's peak into the child's ru_maxrss across exec,
    so a child of Python would report Python's peak (nibabel and numpy loaded) when larger."""
    run = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True)
    if run.returncode != 0:
        sys.exit(f"volume_memory: {' '.join(cmd)} exited {run.returncode}: {run.stderr.strip()}")
    return int(run.stderr.strip().splitlines()[-1])


def volume_file(scene):
    field = tomllib.loads(Path(scene).read_text())["field"]
    if field.get("kind") != "volume":
        sys.exit(f"volume_memory: {scene}: field.kind is not \"volume\"")
    file = Path(field["file"])
    return file if file.is_absolute() else Path(scene).parent / file


def volume_bytes(scene):
    import nibabel
    file = volume_file(scene)
    image = nibabel.load(str(file))
    count = 1
    for n in image.shape:
        count *= n
    return file.name, image.shape, image.get_data_dtype(), count * image.get_data_dtype().itemsize


def metaimage_copies(scene, folder):
    """The scene's samples as MetaImage files (raw, zlib), each with a copy of the scene naming it:
    [(label, scene path)].  The samples' own bytes in file order (i fastest), spacing and origin
    from the NIfTI header (the placement does not change what is held)."""
    import nibabel
    image = nibabel.load(str(volume_file(scene)))
    data = image.dataobj.get_unscaled() if hasattr(image.dataobj, "get_unscaled") else image.get_fdata()
    raw = data.tobytes(order="F")
    dims = " ".join(map(str, image.shape))
    spacing = " ".join(repr(float(z)) for z in image.header.get_zooms()[:3])
    origin = " ".join(repr(float(x)) for x in image.affine[:3, 3])
    out = []
    for label, payload, extra in (("raw", raw, ""), ("zlib", zlib.compress(raw, 6), "CompressedData = True\n")):
        stem = Path(folder) / f"{Path(scene).stem}_{label}"
        size = f"CompressedDataSize = {len(payload)}\n" if extra else ""
        header = (f"ObjectType = Image\nNDims = 3\nDimSize = {dims}\nElementSpacing = {spacing}\n"
                  f"Offset = {origin}\nElementType = {MET_TYPES[str(data.dtype)]}\n{extra}{size}"
                  "ElementDataFile = LOCAL\n")
        stem.with_suffix(".mha").write_bytes(header.encode() + payload)
        text = re.sub(r'(?m)^file = .*$', f'file = "{stem.with_suffix(".mha")}"', Path(scene).read_text())
        stem.with_suffix(".toml").write_text(text)
        out.append((f"{label} MetaImage, {len(payload) / 2**20:.1f} MiB file", str(stem.with_suffix(".toml"))))
    return out


def main():
    args = [a for a in sys.argv[1:] if a != "--metaimage"]
    if len(args) < 2:
        sys.exit(__doc__.split("\n\n")[1])
    metaimage = "--metaimage" in sys.argv
    vrv = str(Path(args[0]) / "vrv")
    for tool in (vrv, "/usr/bin/time"):
        if not Path(tool).is_file():
            sys.exit(f"volume_memory: {tool}: not found")
    baseline = peak_kib([vrv, "scene"])
    print("| volume | samples | own size | peak, `vrv scene` | peak above the default scene's | ÷ own size |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for scene in args[1:]:
            name, shape, dtype, size = volume_bytes(scene)
            runs = [(f"`{name}`", scene)]
            if metaimage:
                runs += [(f"`{name}` as {label}", copy) for label, copy in metaimage_copies(scene, folder)]
            for label, path in runs:
                peak = peak_kib([vrv, "scene", path])
                above = (peak - baseline) * 1024
                print(f"| {label} | {' x '.join(map(str, shape))} {dtype} | {size / 2**20:.1f} MiB | "
                      f"{peak / 1024:.1f} MiB | {above / 2**20:.1f} MiB | {above / size:.2f} |")
    print(f"\nThe default scene's peak (the process without a volume): {baseline / 1024:.1f} MiB.")


if __name__ == "__main__":
    main()
