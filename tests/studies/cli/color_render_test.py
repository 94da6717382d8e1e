#!/usr/bin/python3
"""End to end: `vrv render` of RGB scenes (issue 25, colour).

- The reference and a discrete render of an RGB scene write three-channel images (R, G, B) in
  EXR (float), TIFF (double) and PNG.
- An RGB scene whose three channels are a grey scene's transfer function renders, in every
  channel, the grey scene's image bit for bit (reference and discrete; both conventions).
- Errors against a reference are reported per channel: a render whose red and green emission are
  swapped has errors in R and G and none in B.
- A grey reference for an RGB render, a projection of an RGB scene, and the commands that handle
  grey scenes only (verify, gate, export, ray, demo) are refused in one line, exit 2, nothing written.

    color_render_test.py VRV OUT_DIR
"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

vrv, out = sys.argv[1], Path(sys.argv[2])
shutil.rmtree(out, ignore_errors=True)
out.mkdir(parents=True)

HEAD = """[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "grid"
resolution = [9, 8, 7]
source = { kind = "marschner_lobb" }
[camera]
eye = [0.4, 0.7, -3.5]
target = [0.0, 0.1, 0.0]
width = 20
height = 16
"""
GREY_EMISSION = [[0.0, 0.0], [0.4, 0.3], [0.4, 0.9], [1.0, 0.5]]


def points(pts):
    return "[" + ", ".join("[" + ", ".join(repr(float(x)) for x in p) + "]" for p in pts) + "]"


def scene(name, transfer, background=""):
    path = out / name
    path.write_text(HEAD + "[transfer]\n" + transfer + background)
    return path


def run(*args, expect=0):
    r = subprocess.run([vrv, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == expect, f"{args}: exit {r.returncode} (expected {expect}): {r.stderr}"
    return r


def render(scene_path, name, *how):
    r = run("render", "--scene", scene_path, *how, "--quiet", "-o", out / (name + ".exr"))
    return json.loads(r.stdout.splitlines()[-1])


def read(path):
    im = oiio.ImageInput.open(str(path))
    assert im, oiio.geterror()
    spec = im.spec()
    data = np.asarray(im.read_image(oiio.DOUBLE))
    names = tuple(spec.channelnames)
    im.close()
    return data, names


EXTINCTION = "extinction = [[0.0, 0.1], [1.0, 2.0]]\n"
rgb = scene("rgb.toml", "emission = " + points([[0.0, 0.0, 0.2, 0.1], [0.5, 1.0, 0.1, 0.4], [1.0, 0.3, 0.8, 0.0]])
            + "\n" + EXTINCTION, "[background]\ncolor = [0.0, 0.1, 0.2]\n")
swapped = scene("swapped.toml", "emission = " + points([[0.0, 0.2, 0.0, 0.1], [0.5, 0.1, 1.0, 0.4], [1.0, 0.8, 0.3, 0.0]])
                + "\n" + EXTINCTION, "[background]\ncolor = [0.1, 0.0, 0.2]\n")

# Three channels in every file.
render(rgb, "ref", "--reference")
for suffix, kind in ((".exr", "float"), (".f64.tiff", "double"), (".png", "uint8")):
    data, names = read(out / ("ref" + suffix))
    assert names == ("R", "G", "B"), (suffix, names)
    assert data.shape == (16, 20, 3), (suffix, data.shape)
# A swap of red and green (backgrounds too) is an error in R and G only, per channel.
render(swapped, "swapped", "--method", "alpha", "--step", "0.05")
try:
    render(swapped, "swapped_vs", "--method", "alpha", "--step", "0.05", "--error-against", out / "ref.exr")
    raise AssertionError("a render of another scene was compared")
except AssertionError as e:
    assert "another scene" in str(e), e
ref_rgb, _ = read(out / "ref.f64.tiff")
sw, _ = read(out / "swapped.f64.tiff")
d = render(rgb, "discrete", "--method", "alpha", "--step", "0.05", "--error-against", out / "ref.exr")
disc, _ = read(out / "discrete.f64.tiff")
err = disc - ref_rgb
for c, name in enumerate("RGB"):
    assert d["channels"][name]["max_abs_error"] == np.abs(err[:, :, c]).max(), (name, d["channels"][name])
assert d["max_abs_error"] == np.abs(err).max()
assert np.abs(sw[:, :, 2] - disc[:, :, 2]).max() == 0 and np.abs(sw[:, :, 0] - disc[:, :, 1]).max() == 0

# Three equal channels: the grey image in each, bit for bit.
for label, grey_tf, rgb_tf in (
        ("ee", "emission = " + points(GREY_EMISSION) + "\n" + EXTINCTION,
         "emission = " + points([[v, y, y, y] for v, y in GREY_EMISSION]) + "\n" + EXTINCTION),
        ("oc", "opacity = [[0.0, 0.02], [1.0, 0.3]]\ncolor = " + points(GREY_EMISSION) + "\nunit_length = 0.05\n",
         "opacity = [[0.0, 0.02], [1.0, 0.3]]\ncolor = " + points([[v, y, y, y] for v, y in GREY_EMISSION])
         + "\nunit_length = 0.05\n")):
    grey = scene(f"grey_{label}.toml", grey_tf, "[background]\nintensity = 0.25\n")
    same = scene(f"same_{label}.toml", rgb_tf, "[background]\ncolor = [0.25, 0.25, 0.25]\n")
    for how in (("--reference",), ("--method", "alpha", "--step", "0.05"), ("--method", "alpha", "--step", "0.05",
                                                                              "--precision", "float")):
        tag = f"{label}_{how[-1]}"
        render(grey, "grey_" + tag, *how)
        render(same, "same_" + tag, *how)
        g, _ = read(out / f"grey_{tag}.f64.tiff")
        s, _ = read(out / f"same_{tag}.f64.tiff")
        for c in range(3):
            assert np.array_equal(s[:, :, c], g[:, :, 0]), (tag, c, np.abs(s[:, :, c] - g[:, :, 0]).max())

# Refusals: one line, exit 2, nothing written.
grey_ref = out / "grey_ee_--reference.exr"
r = run("render", "--scene", rgb, "--method", "alpha", "--step", "0.05", "-o", out / "x.exr",
        "--error-against", grey_ref, expect=2)
assert "1 channel where the render has 3 (RGB)" in r.stderr, r.stderr
r = run("render", "--scene", rgb, "--reference", "--mode", "mip", "-o", out / "x.exr", expect=2)
assert "the scene is RGB" in r.stderr, r.stderr
assert not (out / "x.exr").exists()
for args in (("verify", "--scene", rgb, out / "discrete.exr"), ("export", "--scene", rgb, "--out", out / "exp"),
             ("ray", "--scene", rgb), ("demo", "--scene", rgb)):
    r = run(*args, expect=2)
    assert r.stderr.count("\n") == 1 and "the scene is RGB" in r.stderr and f"vrv {args[0]}" in r.stderr, r.stderr
assert not (out / "exp").exists()
print("color render: ok")
