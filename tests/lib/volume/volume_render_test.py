#!/usr/bin/python3
"""End to end: a volume file written from a sampled analytic field (`vrv export`'s float64 NRRD,
VTI, MetaImage and NIfTI of a Marschner-Lobb grid) renders, as a scene's [field] kind = "volume" placed by its
header, the same reference image as the grid scene it came from (`vrv render --reference`),
pixel for pixel in double (node spacings that are exact binary fractions, so that the header's
origin + (n - 1) spacing is the grid's box exactly, in NIfTI-1's float32 too); and the images'
scene hashes differ (they name other fields).  nibabel, an independent reader, reads the exported
NIfTI: its affine is the grid's placement and its data the NRRD's, in the same index order.

    volume_render_test.py VRV OUT_DIR
"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import nibabel
import numpy as np
import OpenImageIO as oiio

vrv, out = sys.argv[1], Path(sys.argv[2])
shutil.rmtree(out, ignore_errors=True)
out.mkdir(parents=True)

TRANSFER = """[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 2.5]]
[camera]
eye = [0.4, 0.7, -3.5]
target = [0.0, 0.1, 0.0]
width = 24
height = 20
"""
(out / "grid.toml").write_text("""[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "grid"
resolution = [17, 9, 5]
source = { kind = "marschner_lobb" }
""" + TRANSFER)


def run(*args):
    r = subprocess.run([vrv, *args], capture_output=True, text=True)
    assert r.returncode == 0, f"{args}: exit {r.returncode}: {r.stderr}"
    return json.loads(r.stdout.splitlines()[-1])


def pixels(path):
    im = oiio.ImageInput.open(str(path))
    assert im, oiio.geterror()
    data = im.read_image(oiio.DOUBLE)
    im.close()
    return np.asarray(data)


run("export", "--scene", str(out / "grid.toml"), "--out", str(out / "export"), "--formats", "nrrd,vti,metaimage,nifti")
grid = run("render", "--scene", str(out / "grid.toml"), "--reference", "--quiet", "-o", str(out / "grid.exr"))
reference = pixels(out / "grid.f64.tiff")
assert reference.max() > 0.1, reference.max()
for name in ["field_f64.nrrd", "field_f64.vti", "field_f64.mha", "field_f64.nii", "field_f32.nii"]:
    stem = name.replace(".", "_")
    (out / f"{stem}.toml").write_text(f'[field]\nkind = "volume"\nfile = "export/{name}"\n' + TRANSFER)
    r = run("render", "--scene", str(out / f"{stem}.toml"), "--reference", "--quiet", "-o", str(out / f"{stem}.exr"))
    image = pixels(out / f"{stem}.f64.tiff")
    assert image.shape == reference.shape
    if "f32" in name:  # float32 nodes: a different field, within their rounding of the reference
        assert np.max(np.abs(image - reference)) < 1e-6, f"{name}: max |diff| {np.max(np.abs(image - reference))}"
        continue
    assert np.array_equal(image, reference), f"{name}: max |diff| {np.max(np.abs(image - reference))}"
    assert r["evaluations"] == grid["evaluations"], (r["evaluations"], grid["evaluations"])
    assert r["scene_camera_hash"] != grid["scene_camera_hash"]
    print(f"{name}: {image.size} pixels identical to the grid scene's reference image")

# nibabel's reading of the exported NIfTI against the NRRD's bytes (i fastest: Fortran order).
nrrd = (out / "export" / "field_f64.nrrd").read_bytes()
header, data = nrrd.split(b"\n\n", 1)
nrrd_values = np.frombuffer(data, dtype="<f8").reshape((17, 9, 5), order="F")
image = nibabel.load(str(out / "export" / "field_f64.nii"))
assert image.shape == (17, 9, 5), image.shape
assert np.array_equal(np.asarray(image.dataobj), nrrd_values)
expected = np.diag([0.125, 0.25, 0.5, 1.0])
expected[:3, 3] = [-1.0, -1.0, -1.0]
assert np.array_equal(image.affine, expected), image.affine
print("nibabel: field_f64.nii has the NRRD's values and the grid's placement")

# A refused volume: exit 2 and one line on stderr naming the file and what is unsupported.
bad = Path(__file__).resolve().parent / "data" / "bad_nifti_4d.nii.gz"
(out / "bad.toml").write_text(f'[field]\nkind = "volume"\nfile = "{bad}"\n' + TRANSFER)
r = subprocess.run([vrv, "render", "--scene", str(out / "bad.toml"), "--reference", "--quiet", "-o",
                    str(out / "bad.exr")], capture_output=True, text=True)
assert r.returncode == 2, r.returncode
lines = r.stderr.strip().splitlines()
assert len(lines) == 1 and f"{bad}: dim[4]: 4-D (time series of 2) not supported" in lines[0], r.stderr
assert not (out / "bad.exr").exists()
print("a 4-D NIfTI: exit 2,", lines[0])

# --max-memory: the volume (765 float64 samples: 6120 bytes, read straight into the samples, in
# the grid's order: no second copy) refused from its header, before its data are read, in one line
# naming the file; and read under a limit just above its size (refused when every reader was
# counted two copies).
r = subprocess.run([vrv, "render", "--scene", str(out / "field_f64_nrrd.toml"), "--reference", "--quiet",
                    "--max-memory", "0.000005", "-o", str(out / "small.exr")], capture_output=True, text=True)
assert r.returncode == 2, (r.returncode, r.stderr)
lines = r.stderr.strip().splitlines()
assert len(lines) == 1 and "field_f64.nrrd: sizes: 17 x 9 x 5 float64 samples take 6120 bytes, more than the 5368 allowed (--max-memory)" in lines[0], r.stderr
assert not (out / "small.exr").exists()
r = subprocess.run([vrv, "render", "--scene", str(out / "field_f64_nrrd.toml"), "--reference", "--quiet", "--width", "4", "--height", "4",
                    "--max-memory", "0.0000058", "-o", str(out / "small.exr")], capture_output=True, text=True)
assert r.returncode == 0 and (out / "small.exr").exists(), (r.returncode, r.stderr)
print("--max-memory:", lines[0])
