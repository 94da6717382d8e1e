#!/usr/bin/python3
"""End to end: `vrv render --alpha` (issue 25: A = 1 - e^-Phi in vrv's own images).

- Grey and RGB scenes write Y, A and R, G, B, A in EXR and double TIFF; the PNG preview keeps the
  colour channels only (PNG's alpha is straight, vrv's colour premultiplied).
- The colour is rendered over nothing: a scene with a background renders C with --alpha such that
  C + I0 (1 - A) is the render without --alpha (discrete: to rounding; reference: within tol).
- A white emission (opacity-colour, colour 1) makes I = A: the reference's Y and A agree within
  the tolerance, the discrete alpha rule's to rounding (1 - prod(1 - a_i) = sum a_i T_i).
- A discrete A is the same, bit for bit, in a grey scene and an RGB scene of the same opacity, and
  is the colour's transmittance with transfer-function tables too.
- --error-against with alpha reports the A channel; a reference without alpha is refused, and so
  is --alpha with --mode; one line, exit 2, nothing written.
- vrv verify judges vrv's own RGBA renders (premultiplied, as EXR declares) and passes them.

    alpha_render_test.py VRV OUT_DIR
"""
import json
import sys

import numpy as np

from render_session import RenderSession, read

session = RenderSession(sys.argv[1], sys.argv[2])
out = session.out
scene, run, render = session.scene, session.run, session.render
OPACITY = "opacity = [[0.0, 0.02], [0.5, 0.2], [1.0, 0.3]]\nunit_length = 0.05\n"

grey = scene("grey.toml", OPACITY + "color = [[0.0, 0.2], [0.5, 0.9], [1.0, 0.4]]\n[background]\nintensity = 0.3\n")
rgb = scene("rgb.toml", OPACITY + "color = [[0.0, 0.2, 0.1, 0.0], [0.5, 0.9, 0.3, 0.6], [1.0, 0.4, 0.8, 0.2]]\n"
            "[background]\ncolor = [0.3, 0.1, 0.2]\n")
white = scene("white.toml", OPACITY + "color = [[0.0, 1.0]]\n")
DISCRETE = ("--method", "alpha", "--step", "0.05")

# Channels in every file; the preview without alpha.
for path, label, names in ((grey, "grey", ("Y", "A")), (rgb, "rgb", ("R", "G", "B", "A"))):
    render(path, label + "_ref_a", "--reference", "--alpha", "--tol", "1e-10")
    for suffix in (".exr", ".f64.tiff"):
        data, got = read(out / (label + "_ref_a" + suffix))
        assert got == names, (label, suffix, got)
        assert data.shape == (16, 20, len(names)), (label, suffix, data.shape)
        a = data[:, :, -1]
        assert a.min() >= 0 and a.max() <= 1 and a.max() > 0.3, (label, a.min(), a.max())
    preview, got = read(out / (label + "_ref_a.png"))
    assert preview.shape[2] == len(names) - 1, (label, preview.shape)

# Over nothing: C + I0 (1 - A) is the render without --alpha.
for path, label, background in ((grey, "grey", [0.3]), (rgb, "rgb", [0.3, 0.1, 0.2])):
    for how, tag, close in ((DISCRETE, "disc", 1e-15), (("--reference", "--tol", "1e-10"), "ref", 4e-10)):
        render(path, f"{label}_{tag}", *how)
        render(path, f"{label}_{tag}_a", *how, "--alpha")
        plain, _ = read(out / f"{label}_{tag}.f64.tiff")
        over, _ = read(out / f"{label}_{tag}_a.f64.tiff")
        a = over[:, :, -1]
        for c, i0 in enumerate(background):
            composited = over[:, :, c] + i0 * (1 - a)
            assert np.abs(composited - plain[:, :, c]).max() <= close, (label, tag, c, np.abs(composited - plain[:, :, c]).max())

# Tables over the transfer function's breakpoints: the colour's reach past the opacity's, and the
# alpha channel's table covers the same values (else A is not the colour's transmittance).
wide = scene("wide.toml", "opacity = [[0.1, 0.02], [0.9, 0.3]]\nunit_length = 0.05\n"
             "color = [[-0.2, 0.1, 0.9, 0.3], [1.2, 0.8, 0.2, 0.6]]\n[background]\ncolor = [0.3, 0.1, 0.2]\n")
for size in ("64", "1024"):
    table = (*DISCRETE, "--table-size", size)
    render(wide, f"wide_{size}", *table)
    render(wide, f"wide_{size}_a", *table, "--alpha")
    plain, _ = read(out / f"wide_{size}.f64.tiff")
    over, _ = read(out / f"wide_{size}_a.f64.tiff")
    for c, i0 in enumerate([0.3, 0.1, 0.2]):
        gap = np.abs(over[:, :, c] + i0 * (1 - over[:, :, 3]) - plain[:, :, c]).max()
        assert gap <= 1e-15, (size, c, gap)

# White emission: I = A.
render(white, "white_ref", "--reference", "--alpha", "--tol", "1e-12")
w, _ = read(out / "white_ref.f64.tiff")
assert np.abs(w[:, :, 0] - w[:, :, 1]).max() <= 2e-12, np.abs(w[:, :, 0] - w[:, :, 1]).max()
render(white, "white_disc", *DISCRETE, "--alpha")
w, _ = read(out / "white_disc.f64.tiff")
assert np.abs(w[:, :, 0] - w[:, :, 1]).max() <= 1e-14, np.abs(w[:, :, 0] - w[:, :, 1]).max()
assert w[:, :, 1].max() > 0.3

# The same opacity: the same A, bit for bit.
g, _ = read(out / "grey_disc_a.f64.tiff")
c, _ = read(out / "rgb_disc_a.f64.tiff")
assert np.array_equal(g[:, :, 1], c[:, :, 3])

# Errors per channel, A included; refusals.
d = render(rgb, "rgb_disc_vs", *DISCRETE, "--alpha", "--error-against", out / "rgb_ref_a.exr")
ref, _ = read(out / "rgb_ref_a.f64.tiff")
disc, _ = read(out / "rgb_disc_vs.f64.tiff")
assert d["channels"]["A"]["max_abs_error"] == np.abs(disc[:, :, 3] - ref[:, :, 3]).max(), d["channels"]
assert d["channels"]["A"]["max_abs_error"] > 0
r = run("render", "--scene", rgb, *DISCRETE, "--alpha", "-o", out / "x.exr", "--error-against",
        out / "rgb_ref.exr", expect=2)
assert r.stderr.count("\n") == 1 and "3 channels where the render has 4 (RGBA)" in r.stderr, r.stderr
r = run("render", "--scene", grey, "--reference", "--mode", "xray", "--alpha", "-o", out / "x.exr", expect=2)
assert r.stderr.count("\n") == 1 and "--alpha" in r.stderr, r.stderr
assert not (out / "x.exr").exists()

# vrv verify of vrv's own RGBA renders (premultiplied EXR): passes, each channel judged.
steps = ["0.04", "0.02", "0.01"]
for h in steps:
    render(rgb, f"verify_{h}", "--method", "alpha", "--strategy", "vtk", "--step", h, "--alpha")
r = run("verify", "--scene", rgb, *[out / f"verify_{h}.exr" for h in steps], "--steps", ",".join(steps),
        "--no-diagnosis", "--quiet")
report = json.loads(r.stdout.splitlines()[-1])
assert report["pass"], report
print("alpha render: every check passed")
