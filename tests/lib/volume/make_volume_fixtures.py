#!/usr/bin/python3
"""Writes the volume readers' fixtures and what they must read back (tests/lib/volume/).

The independent side of tests/lib/volume/*_test.cpp: every file is written here, by numpy and
nibabel (NIfTI) or by hand from each format's specification (NRRD, MetaImage, VTK XML), with
known values and geometry; expected.json holds them as this script meant them (values as exact
doubles, the 3x3 matrix of index-axis steps and the first sample's position).  A second part
reads the NIfTI files nibabel ships as its own test data with nibabel and writes what nibabel
sees (nibabel_expected.json): affine, shape, type and values (a CRC-32 of the float64 values,
the sum of those not NaN, the count of NaN and every 97th value).

    /usr/bin/python3 tests/lib/volume/make_volume_fixtures.py   # rewrites data/ and the JSON

Deterministic: the same files and JSON on every run (gzip without a time stamp).
"""
import base64
import gzip
import json
import os
import zlib
from pathlib import Path

import numpy as np
import nibabel as nib

HERE = Path(__file__).resolve().parent
DATA = HERE / "data"
SHAPE = (5, 4, 3)  # nx, ny, nz: index i fastest in every file
TYPES = ["u8", "i8", "u16", "i16", "u32", "i32", "f32", "f64"]
NP = {"u8": np.uint8, "i8": np.int8, "u16": np.uint16, "i16": np.int16, "u32": np.uint32,
      "i32": np.int32, "f32": np.float32, "f64": np.float64}
NAME = {"u8": "uint8", "i8": "int8", "u16": "uint16", "i16": "int16", "u32": "uint32",
        "i32": "int32", "f32": "float32", "f64": "float64"}

cases = []  # what the C++ test reads back
bad = []    # files that must be refused, with the message's tail after "<path>: "


def values(t):
    """60 values of type t in i-fastest order: the type's extremes, signs, and (floats) tiny,
    huge, subnormal and negative zero values."""
    n = np.arange(SHAPE[0] * SHAPE[1] * SHAPE[2])
    dt = NP[t]
    if np.issubdtype(dt, np.integer):
        info = np.iinfo(dt)
        v = (n * 37) % 200 - (100 if info.min < 0 else 0)
        v = v.astype(np.int64)
        v[0], v[-1] = info.min, info.max
        return v.astype(dt)
    v = ((n - 30) * 0.37).astype(dt)
    if dt == np.float32:
        v[1], v[2], v[3], v[4] = 3.0e38, -1.0e-30, 1.0e-40, -0.0
    else:
        v[1], v[2], v[3], v[4] = 1.0e300, -1.0e-300, 5.0e-320, -0.0
    return v


def add_case(name, t, vals, steps, origin, rescale=None):
    """steps: 3x3, column a is index axis a's step in world coordinates."""
    steps = np.asarray(steps, dtype=float)
    case = {"file": name, "type": NAME[t], "dims": list(SHAPE),
            "steps": [[float(x) for x in row] for row in steps],
            "origin": [float(x) for x in origin],
            "values": [float(x) for x in np.asarray(vals).astype(np.float64).ravel()]}
    if rescale is not None:
        case["slope"], case["intercept"] = rescale
    cases.append(case)


def write(name, data):
    (DATA / name).write_bytes(data)


def gz(data):
    return gzip.compress(data, mtime=0)


# ---------------------------------------------------------------- NRRD (teem.github.io/nrrd)
NRRD_TYPE = {"u8": "uint8", "i8": "int8", "u16": "uint16", "i16": "int16", "u32": "uint32",
             "i32": "int32", "f32": "float", "f64": "double"}


def nrrd_header(t, endian, encoding, directions=None, origin=None, extra=""):
    h = f"NRRD0004\ntype: {NRRD_TYPE[t]}\ndimension: 3\nsizes: {SHAPE[0]} {SHAPE[1]} {SHAPE[2]}\n"
    if directions is not None:
        cols = " ".join("(" + ",".join(repr(float(x)) for x in np.asarray(directions)[:, a]) + ")"
                        for a in range(3))
        h += "space: right-anterior-superior\n"
        h += f"space directions: {cols}\n"
        h += "space origin: (" + ",".join(repr(float(x)) for x in origin) + ")\n"
    if np.dtype(NP[t]).itemsize > 1:
        h += f"endian: {endian}\n"
    h += f"encoding: {encoding}\n" + extra
    return h


def nrrd_cases():
    steps = np.diag([0.5, 1.25, 2.0])
    origin = [10.0, -20.0, 30.5]
    for t in TYPES:
        v = values(t)
        for endian in (["little", "big"] if np.dtype(NP[t]).itemsize > 1 else ["little"]):
            name = f"nrrd_{t}_{endian}.nrrd"
            raw = v.astype(np.dtype(NP[t]).newbyteorder("<" if endian == "little" else ">")).tobytes()
            write(name, (nrrd_header(t, endian, "raw", steps, origin) + "\n").encode() + raw)
            add_case(name, t, v, steps, origin)
    # gzip, a mirrored and permuted placement: index axes along -y, +z, -x.
    perm = np.array([[0.0, 0.0, -3.0], [-1.5, 0.0, 0.0], [0.0, 2.0, 0.0]])
    for t in ["i16", "f32"]:
        v = values(t)
        name = f"nrrd_{t}_gzip.nrrd"
        raw = v.astype(np.dtype(NP[t]).newbyteorder("<")).tobytes()
        write(name, (nrrd_header(t, "little", "gzip", perm, [1.0, 2.0, 3.0]) + "\n").encode() + gz(raw))
        add_case(name, t, v, perm, [1.0, 2.0, 3.0])
    # Detached header and data; no space: spacings only, the first sample at 0.
    v = values("u16")
    write("nrrd_u16_detached.raw", v.astype(">u2").tobytes())
    write("nrrd_u16_detached.nhdr", (nrrd_header("u16", "big", "raw", extra="spacings: 2 3 4\n"
                                                 "data file: nrrd_u16_detached.raw\n")).encode())
    add_case("nrrd_u16_detached.nhdr", "u16", v, np.diag([2.0, 3.0, 4.0]), [0, 0, 0])
    # Refused.
    raw = values("i16").astype("<i2").tobytes()
    write("bad_nrrd_truncated.nrrd", (nrrd_header("i16", "little", "raw", steps, origin) + "\n").encode() + raw[:-7])
    bad.append({"file": "bad_nrrd_truncated.nrrd", "starts": "(data): "})
    oblique = np.array([[0.8, 0.6, 0.0], [-0.6, 0.8, 0.0], [0.0, 0.0, 1.0]])
    write("bad_nrrd_oblique.nrrd", (nrrd_header("i16", "little", "raw", oblique, origin) + "\n").encode() + raw)
    bad.append({"file": "bad_nrrd_oblique.nrrd",
                "message": "space directions: oblique direction [0.8, -0.6, 0] of index axis 0 not supported "
                           "(only axis-aligned volumes)"})
    h = (f"NRRD0004\ntype: int16\ndimension: 4\nsizes: 2 {SHAPE[0]} {SHAPE[1]} {SHAPE[2]}\n"
         "kinds: 2-vector domain domain domain\nendian: little\nencoding: raw\n\n")
    write("bad_nrrd_4d.nrrd", h.encode() + raw + raw)
    bad.append({"file": "bad_nrrd_4d.nrrd",
                "message": "dimension: 4 axes not supported (a 3-D scalar volume only; several components or a "
                           "time series are refused) axis 0 is 2-vector (multi-component)"})
    write("bad_nrrd_gzip_truncated.nrrd",
          (nrrd_header("i16", "little", "gzip", steps, origin) + "\n").encode() + gz(raw)[:-20])
    bad.append({"file": "bad_nrrd_gzip_truncated.nrrd", "starts": "(data): "})


# ---------------------------------------------------------------- NIfTI (nibabel writes)
def nifti_cases():
    for t in TYPES:
        v = values(t)
        data = v.reshape(SHAPE[::-1]).transpose(2, 1, 0)  # [i, j, k]
        for endian in (["<", ">"] if np.dtype(NP[t]).itemsize > 1 else ["<"]):
            hdr = nib.Nifti1Header(endianness=endian)
            hdr.set_data_dtype(NP[t])
            affine = np.array([[0.5, 0, 0, -10.0], [0, 1.25, 0, 20.0], [0, 0, 2.0, 3.5], [0, 0, 0, 1]])
            img = nib.Nifti1Image(data, affine, hdr)
            img.header.set_slope_inter(1.0, 0.0)
            name = f"nifti_{t}_{'little' if endian == '<' else 'big'}.nii"
            nib.save(img, str(DATA / name))
            back = nib.load(str(DATA / name))
            add_case(name, t, np.asarray(back.dataobj).transpose(2, 1, 0).ravel(), back.affine[:3, :3],
                     back.affine[:3, 3], rescale=(1.0, 0.0))
    # qform only with qfac = -1 (pixdim[0]): a reader that ignores qfac mirrors the third axis.
    v = values("i16")
    data = v.reshape(SHAPE[::-1]).transpose(2, 1, 0)
    affine = np.array([[-2.0, 0, 0, 32.0], [0, 2.0, 0, -40.0], [0, 0, 3.0, -16.0], [0, 0, 0, 1]])
    img = nib.Nifti1Image(data, None)
    img.set_qform(affine, code=1)
    img.set_sform(None, code=0)
    nib.save(img, str(DATA / "nifti_qfac.nii"))
    # nibabel's writer sets the scaling it needs itself (none for int16 data): scl_slope and
    # scl_inter (bytes 112 and 116) are patched in, then the file is gzipped.
    raw = bytearray((DATA / "nifti_qfac.nii").read_bytes())
    raw[112:120] = np.array([2.5, -10.0], "<f4").tobytes()
    (DATA / "nifti_qfac.nii").unlink()
    write("nifti_qfac.nii.gz", gz(bytes(raw)))
    back = nib.load(str(DATA / "nifti_qfac.nii.gz"))
    assert back.header["pixdim"][0] == -1 and back.header["sform_code"] == 0
    add_case("nifti_qfac.nii.gz", "i16", back.dataobj.get_unscaled().transpose(2, 1, 0).ravel(),
             back.affine[:3, :3], back.affine[:3, 3],
             # a loaded image's header drops the scaling, which its data proxy applies
             rescale=(float(back.dataobj.slope), float(back.dataobj.inter)))
    assert back.dataobj.slope == 2.5
    # sform (wins over the qform) permuting and mirroring the axes.
    v = values("f32")
    data = v.reshape(SHAPE[::-1]).transpose(2, 1, 0)
    affine = np.array([[0, 0, -3.0, 5.0], [1.5, 0, 0, -6.0], [0, -0.75, 0, 7.0], [0, 0, 0, 1]])
    img = nib.Nifti1Image(data, affine)
    img.set_qform(np.eye(4), code=1)
    img.header.set_slope_inter(1.0, 0.0)
    nib.save(img, str(DATA / "nifti_sform.nii"))
    back = nib.load(str(DATA / "nifti_sform.nii"))
    add_case("nifti_sform.nii", "f32", np.asarray(back.dataobj).transpose(2, 1, 0).ravel(), back.affine[:3, :3],
             back.affine[:3, 3], rescale=(1.0, 0.0))
    # Refused.
    obl = np.array([[0.8, -0.6, 0, 0], [0.6, 0.8, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    img = nib.Nifti1Image(values("i16").reshape(SHAPE[::-1]).transpose(2, 1, 0), obl)
    nib.save(img, str(DATA / "bad_nifti_oblique.nii"))
    bad.append({"file": "bad_nifti_oblique.nii", "starts": "sform: oblique direction ["})  # float32 or normalised: digits vary
    img = nib.Nifti1Image(np.zeros(SHAPE + (2,), np.int16), np.eye(4))
    nib.save(img, str(DATA / "bad_nifti_4d.nii.gz"))
    bad.append({"file": "bad_nifti_4d.nii.gz",
                "message": "dim[4]: 4-D (time series of 2) not supported (a 3-D scalar volume only)"})
    whole = (DATA / "nifti_i16_little.nii").read_bytes()
    write("bad_nifti_truncated.nii", whole[:-5])
    bad.append({"file": "bad_nifti_truncated.nii",
                "message": f"(data): truncated: 120 bytes of data from offset 352 need 472 bytes, the file has {len(whole) - 5}"})


# ---------------------------------------------------------------- MetaImage (MetaIO's keys)
MET = {"u8": "MET_UCHAR", "i8": "MET_CHAR", "u16": "MET_USHORT", "i16": "MET_SHORT", "u32": "MET_UINT",
       "i32": "MET_INT", "f32": "MET_FLOAT", "f64": "MET_DOUBLE"}


def mha_header(t, msb, compressed, steps, origin, data_file="LOCAL", extra="", ndims=3, dims=SHAPE):
    """steps: 3x3 with column a = index axis a's step; TransformMatrix triple a is its direction."""
    steps = np.asarray(steps, dtype=float)
    spacing = np.linalg.norm(steps, axis=0)
    matrix = " ".join(repr(float(x)) for a in range(3) for x in steps[:, a] / spacing[a])
    h = ("ObjectType = Image\n" f"NDims = {ndims}\n" "BinaryData = True\n"
         f"BinaryDataByteOrderMSB = {'True' if msb else 'False'}\n"
         f"CompressedData = {'True' if compressed else 'False'}\n" + extra +
         f"TransformMatrix = {matrix}\n" "Offset = " + " ".join(repr(float(x)) for x in origin) + "\n"
         "ElementSpacing = " + " ".join(repr(float(x)) for x in spacing) + "\n"
         "DimSize = " + " ".join(str(d) for d in dims) + "\n"
         f"ElementType = {MET[t]}\n" f"ElementDataFile = {data_file}\n")
    return h


def metaimage_cases():
    steps = np.diag([0.5, 1.25, 2.0])
    origin = [-1.0, 2.0, -3.5]
    for t in TYPES:
        v = values(t)
        for msb in ([False, True] if np.dtype(NP[t]).itemsize > 1 else [False]):
            raw = v.astype(np.dtype(NP[t]).newbyteorder(">" if msb else "<")).tobytes()
            name = f"mha_{t}_{'big' if msb else 'little'}.mha"
            write(name, mha_header(t, msb, False, steps, origin).encode() + raw)
            add_case(name, t, v, steps, origin)
    perm = np.array([[0.0, 0.0, -3.0], [-1.5, 0.0, 0.0], [0.0, 2.0, 0.0]])
    for t in ["i16", "f64"]:
        v = values(t)
        raw = zlib.compress(v.astype(np.dtype(NP[t]).newbyteorder("<")).tobytes())
        name = f"mha_{t}_zlib.mha"
        write(name, mha_header(t, False, True, perm, [4.0, 5.0, 6.0], extra=f"CompressedDataSize = {len(raw)}\n").encode() + raw)
        add_case(name, t, v, perm, [4.0, 5.0, 6.0])
    v = values("u16")
    write("mhd_u16.raw", v.astype("<u2").tobytes())
    write("mhd_u16.mhd", mha_header("u16", False, False, steps, origin, "mhd_u16.raw").encode())
    add_case("mhd_u16.mhd", "u16", v, steps, origin)
    raw = values("i16").astype("<i2").tobytes()
    write("bad_mha_truncated.mha", mha_header("i16", False, False, steps, origin).encode() + raw[:-3])
    bad.append({"file": "bad_mha_truncated.mha",
                "message": "(data): truncated: 117 bytes of data where 60 int16 samples need 120"})
    obl = np.array([[0.8, -0.6, 0], [0.6, 0.8, 0], [0, 0, 1.0]])
    write("bad_mha_oblique.mha", mha_header("i16", False, False, obl, origin).encode() + raw)
    bad.append({"file": "bad_mha_oblique.mha", "starts": "TransformMatrix: oblique direction ["})  # float32 or normalised: digits vary
    write("bad_mha_4d.mha", mha_header("i16", False, False, steps, origin, ndims=4).encode() + raw)
    bad.append({"file": "bad_mha_4d.mha",
                "message": "NDims: 4 not supported (a 3-D scalar volume only; a time series is refused)"})
    write("bad_mha_channels.mha", mha_header("i16", False, False, steps, origin,
                                             extra="ElementNumberOfChannels = 3\n").encode() + raw * 3)
    bad.append({"file": "bad_mha_channels.mha",
                "message": "ElementNumberOfChannels: 3 components not supported (one only)"})
    write("bad_mha_zlib_damaged.mha", mha_header("i16", False, True, steps, origin).encode()
          + zlib.compress(raw)[:-9])
    bad.append({"file": "bad_mha_zlib_damaged.mha",
                "starts": "CompressedData: compressed data end after"})


# ---------------------------------------------------------------- VTK XML ImageData (VTK's file formats page)
VTK = {"u8": "UInt8", "i8": "Int8", "u16": "UInt16", "i16": "Int16", "u32": "UInt32", "i32": "Int32",
       "f32": "Float32", "f64": "Float64"}


def vtk_block(raw, endian, header, compressed, block_size):
    """The bytes VTK writes for one array: a header of byte counts, then the data (zlib blocks)."""
    ht = "<" if endian == "LittleEndian" else ">"
    ht += "I" if header == "UInt32" else "Q"
    if not compressed:
        return np.array([len(raw)], ht).tobytes(), raw
    blocks = [raw[i:i + block_size] for i in range(0, len(raw), block_size)]
    comp = [zlib.compress(b) for b in blocks]
    last = len(blocks[-1]) if len(blocks[-1]) != block_size else 0
    head = np.array([len(blocks), block_size, last] + [len(c) for c in comp], ht).tobytes()
    return head, b"".join(comp)


def vti(t, v, steps, origin, extent0, fmt, endian="LittleEndian", header="UInt32", compressed=False,
        block_size=32, extra_array="", components=1, point_data=True):
    steps = np.asarray(steps, dtype=float)
    spacing = np.linalg.norm(steps, axis=0)
    direction = steps / spacing  # column a: index axis a's direction
    ext = []
    for a in range(3):
        ext += [extent0[a], extent0[a] + SHAPE[a] - 1]
    # VTK's Origin is index (0, 0, 0)'s position: the first sample (extent0) sits at `origin`.
    vtk_origin = np.asarray(origin, float) - steps @ np.asarray(extent0, float)
    e = " ".join(str(x) for x in ext)
    raw = v.astype(np.dtype(NP[t]).newbyteorder("<" if endian == "LittleEndian" else ">")).tobytes()
    appended = b""
    if fmt == "ascii":
        body = " ".join(repr(x) if isinstance(x, float) else str(x) for x in v.tolist())
        attrs = 'format="ascii"'
    elif fmt == "binary":
        head, data = vtk_block(raw, endian, header, compressed, block_size)
        # VTK encodes a compressed array's header apart from its blocks, an uncompressed one whole.
        body = (base64.b64encode(head) + base64.b64encode(data) if compressed
                else base64.b64encode(head + data)).decode()
        attrs = 'format="binary"'
    else:
        head, data = vtk_block(raw, endian, header, compressed, block_size)
        appended = head + data
        attrs = 'format="appended" offset="0"'
    where = "PointData" if point_data else "CellData"
    x = (f'<?xml version="1.0"?>\n<VTKFile type="ImageData" version="1.0" byte_order="{endian}" '
         f'header_type="{header}"' + (' compressor="vtkZLibDataCompressor"' if compressed else "") + ">\n"
         f'  <ImageData WholeExtent="{e}" Origin="' + " ".join(repr(float(o)) for o in vtk_origin) + '" Spacing="'
         + " ".join(repr(float(s)) for s in spacing) + '" Direction="'
         + " ".join(repr(float(d)) for d in direction.ravel()) + '">\n'
         f'    <Piece Extent="{e}">\n      <{where} Scalars="density">\n' + extra_array +
         f'        <DataArray type="{VTK[t]}" Name="density" NumberOfComponents="{components}" {attrs}>\n'
         f'          {"" if fmt == "appended" else body}\n        </DataArray>\n      </{where}>\n'
         '    </Piece>\n  </ImageData>\n')
    out = x.encode()
    if fmt == "appended":
        out += b'  <AppendedData encoding="raw">\n   _' + appended + b"\n  </AppendedData>\n"
    return out + b"</VTKFile>\n"


def vti_cases():
    steps = np.diag([0.5, 1.25, 2.0])
    origin = [1.0, -2.0, 3.0]
    perm = np.array([[0.0, 0.0, -3.0], [-1.5, 0.0, 0.0], [0.0, 2.0, 0.0]])
    configs = [  # name, type, format, endian, header, compressed, steps, extent0
        ("ascii", "i32", "ascii", "LittleEndian", "UInt32", False, steps, (0, 0, 0)),
        ("ascii", "f64", "ascii", "LittleEndian", "UInt32", False, steps, (0, 0, 0)),
        ("ascii", "i8", "ascii", "LittleEndian", "UInt32", False, perm, (2, -3, 7)),
        ("binary", "u8", "binary", "LittleEndian", "UInt32", False, steps, (0, 0, 0)),
        ("binary", "f32", "binary", "BigEndian", "UInt64", False, perm, (1, 2, 3)),
        ("binary_zlib", "i16", "binary", "LittleEndian", "UInt32", True, steps, (0, 0, 0)),
        ("binary_zlib", "u32", "binary", "BigEndian", "UInt64", True, perm, (0, 0, 0)),
        ("appended", "u16", "appended", "BigEndian", "UInt32", False, steps, (0, 0, 0)),
        ("appended", "i32", "appended", "LittleEndian", "UInt64", False, steps, (-1, 0, 4)),
        ("appended_zlib", "f64", "appended", "LittleEndian", "UInt64", True, perm, (0, 0, 0)),
        ("appended_zlib", "u8", "appended", "BigEndian", "UInt32", True, steps, (0, 0, 0)),
    ]
    for label, t, fmt, endian, header, comp, st, e0 in configs:
        v = values(t)
        name = f"vti_{t}_{label}_{endian[0].lower()}.vti"
        write(name, vti(t, v, st, origin, e0, fmt, endian, header, comp))
        add_case(name, t, v, st, origin)
    v = values("i16")
    write("bad_vti_components.vti", vti("i16", np.repeat(v, 2), steps, origin, (0, 0, 0), "ascii", components=2))
    bad.append({"file": "bad_vti_components.vti", "message": "NumberOfComponents: 2 components not supported (one only)"})
    write("bad_vti_celldata.vti", vti("i16", v, steps, origin, (0, 0, 0), "ascii", point_data=False))
    bad.append({"file": "bad_vti_celldata.vti", "message": "CellData: cell data not supported (point data only)"})
    obl = np.array([[0.8, -0.6, 0], [0.6, 0.8, 0], [0, 0, 1.0]])
    write("bad_vti_oblique.vti", vti("i16", v, obl, origin, (0, 0, 0), "ascii"))
    bad.append({"file": "bad_vti_oblique.vti", "starts": "Direction: oblique direction ["})  # float32 or normalised: digits vary
    whole = vti("i16", v, steps, origin, (0, 0, 0), "appended")
    cut = whole.index(b"\n  </AppendedData>") - 10
    write("bad_vti_truncated.vti", whole[:cut] + b"\n  </AppendedData>\n</VTKFile>\n")
    # 117 bytes: 114 of the array and the line break and indent before the closing tag.
    bad.append({"file": "bad_vti_truncated.vti", "message": "DataArray: truncated: 117 bytes, the array's header needs 124"})
    write("bad_vti_ascii_short.vti", vti("i16", v[:-1], steps, origin, (0, 0, 0), "ascii"))
    bad.append({"file": "bad_vti_ascii_short.vti", "message": "DataArray: 59 ascii values, the extent needs 60"})


# ---------------------------------------------------------------- nibabel's own test data
NIBABEL_DATA = Path(nib.__file__).parent / "tests" / "data"
NIBABEL_FILES = ["anatomical.nii", "reoriented_anat_moved.nii", "resampled_anat_moved.nii", "standard.nii.gz"]
NIBABEL_REFUSED = {"example4d.nii.gz": "dim[4]: 4-D (time series of 2) not supported (a 3-D scalar volume only)",
                   "functional.nii": "dim[4]: 4-D (time series of 20) not supported (a 3-D scalar volume only)"}


def nibabel_expected():
    out = {"files": [], "refused": []}
    for f in NIBABEL_FILES:
        img = nib.load(str(NIBABEL_DATA / f))
        stored = np.asarray(img.dataobj.get_unscaled() if hasattr(img.dataobj, "get_unscaled") else img.dataobj)
        flat = stored.astype(np.float64).transpose(2, 1, 0).ravel()  # i fastest
        slope, inter = img.dataobj.slope, img.dataobj.inter  # the header's, as the proxy applies them
        out["files"].append({
            "file": f, "type": str(img.header.get_data_dtype().newbyteorder("=")), "dims": list(stored.shape),
            "steps": [[float(x) for x in row] for row in img.affine[:3, :3]],
            "origin": [float(x) for x in img.affine[:3, 3]],
            "slope": float(slope), "intercept": float(inter),
            # NaN samples (the resampled files have some) are counted; JSON has no NaN: null.
            "crc32": zlib.crc32(flat.astype("<f8").tobytes()), "sum": float(np.nansum(flat)),
            "nans": int(np.count_nonzero(np.isnan(flat))),
            "every97": [None if np.isnan(x) else float(x) for x in flat[::97]]})
    for f, msg in NIBABEL_REFUSED.items():
        assert len(nib.load(str(NIBABEL_DATA / f)).shape) == 4
        out["refused"].append({"file": f, "message": msg})
    return out


def main():
    DATA.mkdir(exist_ok=True)
    for p in DATA.iterdir():
        p.unlink()
    nrrd_cases()
    nifti_cases()
    metaimage_cases()
    vti_cases()
    (HERE / "expected.json").write_text(json.dumps({"cases": cases, "bad": bad}, indent=1) + "\n")
    (HERE / "nibabel_expected.json").write_text(json.dumps(nibabel_expected(), indent=1) + "\n")
    print(f"{len(cases)} fixtures, {len(bad)} refused files in {DATA}")


if __name__ == "__main__":
    main()
