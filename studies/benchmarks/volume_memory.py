#!/usr/bin/env python3
"""What a volume scene costs in memory against the volume's own size (issue 27).

    python3 studies/benchmarks/volume_memory.py BUILD_DIR [--copies] SCENE.toml [SCENE.toml ...]

For each scene (a `kind = "volume"` field naming a NIfTI file), runs `vrv scene SCENE` (reads the
scene and its volume into the grid the reference integrates, prints the scene; no image library
loaded) and `vrv scene` of the default scene, and prints a Markdown table: the volume's own size
(its samples in their stored type, from the header as nibabel reads it: an independent reader),
the peak resident memory of each run (GNU time's %M), and the volume run's peak above the
default run's divided by the volume's size.  The goal: at most 1.2.

--copies: also the same samples written here (with nibabel, zlib and base64, in a temporary
folder; not by vrv's own writers) as MetaImage files (raw, zlib, and raw with index axis i
mirrored or with i and j swapped by its TransformMatrix: put in grid order), NRRD files (raw, gzip) and VTK image data (appended raw, appended raw in zlib blocks, appended base64, inline base64), each read
through a copy of the scene naming it.

Needs nibabel (Debian's python3-nibabel) and GNU time (Debian's `time`); writes nothing else.
"""
import base64
import gzip
import re
import struct
import subprocess
import sys
import tempfile
import tomllib
import zlib
from pathlib import Path

VTK_TYPES = {"uint8": "UInt8", "int8": "Int8", "uint16": "UInt16", "int16": "Int16", "uint32": "UInt32",
             "int32": "Int32", "float32": "Float32", "float64": "Float64"}
NRRD_TYPES = {"uint8": "uint8", "int8": "int8", "uint16": "uint16", "int16": "int16", "uint32": "uint32",
              "int32": "int32", "float32": "float", "float64": "double"}
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


def vti_blocks(raw, block=32768):
    """VTK's zlib layout: UInt64 header (blocks, block size, last block's size, each compressed
    size), then the compressed blocks."""
    parts = [zlib.compress(raw[i:i + block], 6) for i in range(0, len(raw), block)]
    last = len(raw) - (len(parts) - 1) * block
    head = struct.pack(f"<{3 + len(parts)}Q", len(parts), block, last, *map(len, parts))
    return head, b"".join(parts)


def vti_file(raw, dtype, dims, spacing, origin, mode):
    """A .vti of one point-data array: mode appended_raw, appended_zlib, appended_base64 or
    inline_base64 (UInt64 headers, little-endian)."""
    zlib_mode = mode == "appended_zlib"
    head = struct.pack("<Q", len(raw))
    extent = " ".join(f"0 {n - 1}" for n in dims)
    fmt = "binary" if mode == "inline_base64" else 'appended" offset="0'
    body = base64.b64encode(head + raw).decode() if mode == "inline_base64" else ""
    xml = ('<?xml version="1.0"?>\n<VTKFile type="ImageData" version="1.0" byte_order="LittleEndian" '
           'header_type="UInt64"' + (' compressor="vtkZLibDataCompressor"' if zlib_mode else "") + '>\n'
           f' <ImageData WholeExtent="{extent}" Origin="{origin}" Spacing="{spacing}">\n  <Piece Extent="{extent}">\n'
           f'   <PointData Scalars="v">\n    <DataArray type="{VTK_TYPES[dtype]}" Name="v" format="{fmt}">{body}'
           '</DataArray>\n   </PointData>\n  </Piece>\n </ImageData>\n').encode()
    if mode == "inline_base64":
        return xml + b"</VTKFile>\n"
    if mode == "appended_base64":
        data, encoding = base64.b64encode(head + raw), "base64"
    else:
        data, encoding = (b"".join(vti_blocks(raw)) if zlib_mode else head + raw), "raw"
    return xml + f' <AppendedData encoding="{encoding}">\n  _'.encode() + data + b"\n </AppendedData>\n</VTKFile>\n"


def file_copies(scene, folder):
    """The scene's samples in other formats, each with a copy of the scene naming it:
    [(label, scene path)].  The samples' own bytes in file order (i fastest), spacing and origin
    from the NIfTI header (the placement does not change what is held)."""
    import nibabel
    image = nibabel.load(str(volume_file(scene)))
    data = image.dataobj.get_unscaled() if hasattr(image.dataobj, "get_unscaled") else image.get_fdata()
    raw = data.tobytes(order="F")
    dtype = str(data.dtype)
    dims = " ".join(map(str, image.shape))
    spacing = " ".join(repr(float(z)) for z in image.header.get_zooms()[:3])
    origin = " ".join(repr(float(x)) for x in image.affine[:3, 3])
    files = []
    # The last two: index axis i mirrored (x runs against it), and index axes i and j along y and
    # x, so the grid's order is not the file's.
    for label, payload, extra in (("raw", raw, ""), ("zlib", zlib.compress(raw, 6), "CompressedData = True\n"),
                                  ("raw, x mirrored,", raw, "TransformMatrix = -1 0 0 0 1 0 0 0 1\n"),
                                  ("raw, axes permuted,", raw, "TransformMatrix = 0 1 0 1 0 0 0 0 1\n")):
        size = f"CompressedDataSize = {len(payload)}\n" if "Compressed" in extra else ""
        header = (f"ObjectType = Image\nNDims = 3\nDimSize = {dims}\nElementSpacing = {spacing}\n"
                  f"Offset = {origin}\nElementType = {MET_TYPES[dtype]}\n{extra}{size}"
                  "ElementDataFile = LOCAL\n")
        stem = label.split(",")[0] + "".join(f"_{w}" for w in ("mirrored", "permuted") if w in label)
        files.append((f"{label} MetaImage", f"{stem}.mha", header.encode() + payload))
    for label, payload in (("raw", raw), ("gzip", gzip.compress(raw, 6, mtime=0))):
        header = (f"NRRD0004\ntype: {NRRD_TYPES[dtype]}\ndimension: 3\nsizes: {dims}\nspacings: {spacing}\n"
                  f"endian: little\nencoding: {label}\n\n")
        files.append((f"{label} NRRD", f"{label}.nrrd", header.encode() + payload))
    for mode in ("appended_raw", "appended_zlib", "appended_base64", "inline_base64"):
        files.append((f"VTI, {mode.replace('_', ' ')}", f"{mode}.vti",
                      vti_file(raw, dtype, image.shape, spacing, origin, mode)))
    out = []
    for label, name, payload in files:
        path = Path(folder) / f"{Path(scene).stem}_{name}"
        path.write_bytes(payload)
        text = re.sub(r'(?m)^file = .*$', f'file = "{path}"', Path(scene).read_text())
        path.with_suffix(".toml").write_text(text)
        out.append((f"{label}, {len(payload) / 2**20:.1f} MiB file", str(path.with_suffix(".toml"))))
        del payload
    return out


def main():
    args = [a for a in sys.argv[1:] if a != "--copies"]
    if len(args) < 2:
        sys.exit(__doc__.split("\n\n")[1])
    copies = "--copies" in sys.argv
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
            if copies:
                runs += [(f"`{name}` as {label}", copy) for label, copy in file_copies(scene, folder)]
            for label, path in runs:
                peak = peak_kib([vrv, "scene", path])
                above = (peak - baseline) * 1024
                print(f"| {label} | {' x '.join(map(str, shape))} {dtype} | {size / 2**20:.1f} MiB | "
                      f"{peak / 1024:.1f} MiB | {above / 2**20:.1f} MiB | {above / size:.2f} |")
    print(f"\nThe default scene's peak (the process without a volume): {baseline / 1024:.1f} MiB.")


if __name__ == "__main__":
    main()
