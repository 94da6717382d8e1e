#!/usr/bin/python3
"""End to end: `vrv render` of RGB scenes (issue 25, colour).

- The reference and a discrete render of an RGB scene write three-channel images (R, G, B) in
  EXR (float), TIFF (double) and PNG.
- An RGB scene whose three channels are a grey scene's transfer function renders, in every
  channel, the grey scene's image bit for bit (reference and discrete; both conventions).
- Errors against a reference are reported per channel: a render whose red and green emission are
  swapped has errors in R and G and none in B.
- A grey reference for an RGB render, a projection of an RGB scene, and the commands that handle
  grey scenes only (demo) and projections are refused in one line, exit 2, nothing written.
- vrv ray gives each channel's value, estimate and optical depth; each matches its grey scene.
- vrv export of an RGB scene writes one table whose channel columns are each channel's grey export.
- vrv verify and vrv gate judge each channel against its own: vrv's RGB renders pass, the same
  files with red and blue exchanged fail naming the swap, a one-channel image is refused; an RGBA
  PNG (straight colour, as PNG declares) is read straight by default (`--alpha auto`).

    color_render_test.py VRV OUT_DIR
"""
import json
import sys

import numpy as np
import OpenImageIO as oiio

from render_session import RenderSession, points, read

session = RenderSession(sys.argv[1], sys.argv[2])
vrv, out = session.vrv, session.out
scene, run, render = session.scene, session.run, session.render
GREY_EMISSION = [[0.0, 0.0], [0.4, 0.3], [0.4, 0.9], [1.0, 0.5]]


EXTINCTION = "extinction = [[0.0, 0.1], [1.0, 2.0]]\n"
RGB_TF = "emission = " + points([[0.0, 0.0, 0.2, 0.1], [0.5, 1.0, 0.1, 0.4], [1.0, 0.3, 0.8, 0.0]]) + "\n" + EXTINCTION
rgb = scene("rgb.toml", RGB_TF, "[background]\ncolor = [0.0, 0.1, 0.2]\n")
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
for args in (("demo", "--scene", rgb),):
    r = run(*args, expect=2)
    assert r.stderr.count("\n") == 1 and "the scene is RGB" in r.stderr and f"vrv {args[0]}" in r.stderr, r.stderr

# vrv ray on an RGB scene: a value, estimate and optical depth per channel, each channel within the
# two estimates of its own grey scene's reference and its discrete cast bit for bit; a rays file
# the same per line; a projection refused.
ray = ("--origin", "0.3,-0.2,-3", "--direction", "-0.1,0.05,1")
one = json.loads(run("ray", "--scene", rgb, *ray, "--json").stdout)
disc = json.loads(run("ray", "--scene", rgb, *ray, "--json", "--method", "alpha", "--step", "0.05").stdout)
assert len(one["value"]) == 3 and len(one["error_estimate"]) == 3 and one["tolerance_met"], one
for c, name in enumerate("RGB"):
    grey_c = scene(f"ray_{name}.toml", "emission = " + points([[p[0], p[1 + c]] for p in
                   [[0.0, 0.0, 0.2, 0.1], [0.5, 1.0, 0.1, 0.4], [1.0, 0.3, 0.8, 0.0]]]) + "\n" + EXTINCTION,
                   f"[background]\nintensity = {[0.0, 0.1, 0.2][c]}\n")
    g = json.loads(run("ray", "--scene", grey_c, *ray, "--json").stdout)
    assert abs(one["value"][c] - g["value"]) <= one["error_estimate"][c] + g["error_estimate"], (name, one, g)
    gd = json.loads(run("ray", "--scene", grey_c, *ray, "--json", "--method", "alpha", "--step", "0.05").stdout)
    assert disc["value"][c] == gd["value"], (name, disc, gd)
text = run("ray", "--scene", rgb, *ray).stdout
assert text.splitlines()[0].split()[1:] == [f"{v:.17g}" for v in one["value"]], text
rays_file = out / "rays.jsonl"
rays_file.write_text('{"origin": [0.3, -0.2, -3], "direction": [-0.1, 0.05, 1], "id": 7}\n')
line = json.loads(run("ray", "--scene", rgb, "--rays", rays_file, "--quiet").stdout)
assert line["id"] == 7 and line["value"] == one["value"], line
r = run("ray", "--scene", rgb, *ray, "--mode", "mip", expect=2)
assert "the scene is RGB" in r.stderr and "vrv ray --mode" in r.stderr, r.stderr

# vrv export of an RGB scene: one table for the three channels, each channel's columns (repeats
# aside) exactly what exporting that channel as a grey scene writes; colour points [v, r, g, b] in the JSON and in
# the scene.toml it writes, which reads back as an RGB scene.
run("export", "--scene", rgb, "--out", out / "exp", "--table-points", "4")
lines = (out / "exp" / "transfer_function.csv").read_text().splitlines()
assert lines[0] == "value,emission_r,emission_g,emission_b,extinction,opacity,color_r,color_g,color_b", lines[0]
table = [line.split(",") for line in lines[1:]]
emission = [[0.0, 0.0, 0.2, 0.1], [0.5, 1.0, 0.1, 0.4], [1.0, 0.3, 0.8, 0.0]]
for c, name in enumerate("RGB"):
    one = scene(f"channel_{name}.toml", "emission = " + points([[p[0], p[1 + c]] for p in emission]) + "\n" + EXTINCTION,
                f"[background]\nintensity = {[0.0, 0.1, 0.2][c]}\n")
    run("export", "--scene", one, "--out", out / f"exp_{name}", "--table-points", "4")
    grey_rows = [line.split(",") for line in (out / f"exp_{name}" / "transfer_function.csv").read_text().splitlines()[1:]]
    # A row is where any channel changes: a channel's own columns may repeat a row there.
    columns = [(r[0], r[1 + c], r[4], r[5], r[6 + c]) for r in table]
    columns = [row for i, row in enumerate(columns) if i == 0 or row != columns[i - 1]]
    assert columns == [tuple(r) for r in grey_rows], name
exported = json.loads((out / "exp" / "transfer_function.json").read_text())
assert exported["channels"] == ["R", "G", "B"] and not exported["exact"], exported.keys()
assert all(len(p) == 4 for p in exported["color"]) and len(exported["color"]) == len(table)
manifest = json.loads((out / "exp" / "export.json").read_text())
assert manifest["background"] == [0.0, 0.1, 0.2], manifest["background"]
# An opacity/colour RGB scene's own points, exactly.
oc_colour = [[0.0, 0.1, 0.2, 0.3], [0.4, 0.9, 0.5, 0.0], [1.0, 0.2, 0.7, 1.0]]
oc = scene("rgb_oc.toml", "opacity = [[0.0, 0.02], [1.0, 0.3]]\ncolor = " + points(oc_colour) + "\nunit_length = 0.05\n",
           "[background]\ncolor = [0.0, 0.1, 0.2]\n")
run("export", "--scene", oc, "--out", out / "exp_oc")
exported_oc = json.loads((out / "exp_oc" / "transfer_function.json").read_text())
assert exported_oc["exact"] and exported_oc["color"] == oc_colour, exported_oc["color"]
assert exported_oc["opacity"] == [[0.0, 0.02], [1.0, 0.3]] and exported_oc["unit_distance"] == 0.05

# The exported RGB scene is each channel's exported grey scene: a discrete render bit for bit.
render(out / "exp" / "scene.toml", "exp_rgb", "--method", "alpha", "--step", "0.05")
exp_rgb, _ = read(out / "exp_rgb.f64.tiff")
for c, name in enumerate("RGB"):
    render(out / f"exp_{name}" / "scene.toml", f"exp_{name}", "--method", "alpha", "--step", "0.05")
    exp_grey, _ = read(out / f"exp_{name}.f64.tiff")
    assert np.array_equal(exp_rgb[:, :, c], exp_grey[:, :, 0]), name

# vrv verify and vrv gate judge each channel against its own reference: vrv's own alpha renders
# (EXR, steps from their provenance) pass; the same files with red and blue exchanged
# fail naming the swap; a one-channel image of the RGB scene is refused in one line.
steps = (0.1, 0.05, 0.025)
rendered = []
for h in steps:
    render(rgb, f"v_{h}", "--method", "alpha", "--step", str(h))
    rendered.append(out / f"v_{h}.exr")
r = run("verify", "--scene", rgb, *rendered, "--quiet", "--out", out / "verify_rgb", "--report", out / "rgb.html")
report = json.loads(r.stdout.splitlines()[-1])
# The reference written and shown in colour (the page's reference once overran a grey buffer).
ref_written, ref_names = read(out / "verify_rgb" / "reference.exr")
assert ref_names == ("R", "G", "B") and ref_written.shape == (16, 20, 3), (ref_names, ref_written.shape)
page = (out / "rgb.html").read_text()
assert "<b>The reference</b>, each channel from" in page and "swapped channels" not in page
assert report["pass"] and report["diagnosis_channel"] in ("R", "G", "B"), report
assert [c["channel"] for c in report["images"][:3]] == ["R", "G", "B"], report["images"][:3]
# The three channels' references come from the cache the second time, the report otherwise equal.
cached = []
for _ in range(2):
    cached.append(json.loads(run("verify", "--scene", rgb, *rendered, "--quiet", "--cache-dir",
                                 out / "cache").stdout.splitlines()[-1]))
assert not cached[0]["reference"]["from_cache"] and cached[1]["reference"]["from_cache"]
assert len(list((out / "cache").iterdir())) == 3
for c in cached:
    del c["reference"]["from_cache"], c["reference"]["cache_file"]
assert cached[0] == cached[1]
bgr = []
for h, path in zip(steps, rendered):
    data, _ = read(path)
    spec = oiio.ImageSpec(20, 16, 3, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B")
    bgr.append(out / f"bgr_{h}.exr")
    o = oiio.ImageOutput.create(str(bgr[-1]))
    assert o.open(str(bgr[-1]), spec) and o.write_image(np.ascontiguousarray(data[:, :, ::-1], dtype=np.float32))
    o.close()
r = run("verify", "--scene", rgb, *bgr, "--steps", ",".join(map(str, steps)), "--quiet", expect=1)
report = json.loads(r.stdout.splitlines()[-1])
assert "swapped channels" in [f["name"] for f in report["faults"]], report["faults"]
assert any(f.startswith("swapped channels: ") for f in report["failures"]), report["failures"]
grey = out / "grey_one.exr"
render(scene("grey_one.toml", "emission = " + points(GREY_EMISSION) + "\n" + EXTINCTION), "grey_one",
       "--method", "alpha", "--step", "0.05")
r = run("verify", "--scene", rgb, grey, grey, "--steps", "0.1,0.05", expect=2)
assert r.stderr.count("\n") == 1 and "but the scene is RGB" in r.stderr, r.stderr
# RGBA in a PNG, which stores colour straight (and says so): colour over nothing and alpha from
# renders over black and white (C = I0, A = 1 - (I1 - I0)), written as C / A in 16 bits.  `--alpha
# auto` (the default) takes the file's word and matches the EXR renders' errors, as `--alpha
# straight` does; the same pixels declared premultiplied are far off.
def finest_rms(report):
    finest = min(c["step"] for c in report["images"])
    return max(c["regions"]["all"]["rms"] for c in report["images"] if c["step"] == finest and not c["alpha"])


exr_rms = finest_rms(json.loads(run("verify", "--scene", rgb, *rendered, "--quiet").stdout.splitlines()[-1]))
black = scene("black.toml", RGB_TF, "[background]\ncolor = [0.0, 0.0, 0.0]\n")
white = scene("white.toml", RGB_TF, "[background]\ncolor = [1.0, 1.0, 1.0]\n")
pngs = []
for h in steps:
    render(black, f"black_{h}", "--method", "alpha", "--step", str(h))
    render(white, f"white_{h}", "--method", "alpha", "--step", str(h))
    c, _ = read(out / f"black_{h}.f64.tiff")
    w, _ = read(out / f"white_{h}.f64.tiff")
    a = 1 - (w[:, :, :1] - c[:, :, :1])
    rgba = np.concatenate([np.where(a > 0, c / np.maximum(a, 1e-300), 0), a], axis=2)
    spec = oiio.ImageSpec(20, 16, 4, oiio.UINT16)
    spec.attribute("oiio:UnassociatedAlpha", 1)  # write the straight values as given
    pngs.append(out / f"straight_{h}.png")
    o = oiio.ImageOutput.create(str(pngs[-1]))
    assert o.open(str(pngs[-1]), spec) and o.write_image(np.ascontiguousarray(np.clip(rgba, 0, 1), dtype=np.float32))
    o.close()
as_png = {}
for alpha in ("auto", "straight", "premultiplied"):
    r = run("verify", "--scene", rgb, *pngs, "--steps", ",".join(map(str, steps)), "--alpha", alpha, "--quiet")
    as_png[alpha] = json.loads(r.stdout.splitlines()[-1])
assert [c["channel"] for c in as_png["auto"]["images"][:4]] == ["R", "G", "B", "A"], as_png["auto"]["images"][:4]
assert finest_rms(as_png["auto"]) < exr_rms + 1e-4, (finest_rms(as_png["auto"]), exr_rms)
# Declared straight, the pixels are read as stored (OpenImageIO would premultiply them on reading,
# and `--alpha straight` then multiplied by alpha twice).
assert finest_rms(as_png["straight"]) == finest_rms(as_png["auto"]), (finest_rms(as_png["straight"]),
                                                                      finest_rms(as_png["auto"]))
assert finest_rms(as_png["premultiplied"]) > 10 * finest_rms(as_png["auto"]), (finest_rms(as_png["premultiplied"]),
                                                                              finest_rms(as_png["auto"]))
bounds = out / "rgb_bounds.toml"
bounds.write_text(f"""[[case]]
name = "rgb_alpha"
scene = "{rgb.name}"
steps = [0.1, 0.05, 0.025]
render = {{ method = "alpha" }}
rms = {{ fail = 0.05 }}
min_order = {{ fail = 0.75 }}
""")
r = run("gate", "--bounds", bounds, "--out", out / "gate")
rows = (out / "gate" / "bounds.csv").read_text()
assert "rgb_alpha" in rows and any(f"({c})" in rows for c in "RGB"), rows
print("color render: ok")
