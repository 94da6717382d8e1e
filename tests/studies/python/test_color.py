"""RGB scenes from Python (docs/color.md): Scene.reference, discrete and render give a trailing axis
of the three channels; three equal channels are the grey scene bit for bit; every channel agrees
with its own grey scene within the two estimates; verify judges each channel and names swapped
channels; projections refuse an RGB scene."""
import numpy as np
import pytest

import vrv

HEAD = """[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[camera]
width = 9
height = 7
"""
EXTINCTION = "extinction = [[0.0, 0.1], [0.45, 1.5], [1.0, 0.4]]\n"
EMISSION = [[0.0, 0.0, 0.3, 0.1], [0.5, 1.0, 0.3, 0.6], [0.5, 0.2, 0.9, 0.6], [1.0, 0.4, 0.0, 1.0]]
BACKGROUND = (0.1, 0.0, 0.25)


def points(pts):
    return "[" + ", ".join("[" + ", ".join(repr(float(x)) for x in p) + "]" for p in pts) + "]"


def rgb_scene(emission=EMISSION, background=BACKGROUND):
    return vrv.Scene.from_toml(HEAD + "[transfer]\nemission = " + points(emission) + "\n" + EXTINCTION +
                               "[background]\ncolor = [%r, %r, %r]\n" % background, "rgb.toml")


def grey_scene(c, emission=EMISSION, background=BACKGROUND):
    return vrv.Scene.from_toml(HEAD + "[transfer]\nemission = " + points([[p[0], p[1 + c]] for p in emission]) +
                               "\n" + EXTINCTION + "[background]\nintensity = %r\n" % background[c], "grey.toml")


def test_rgb_scene_has_three_channels():
    s = rgb_scene()
    assert s.channels == 3 and s.background == BACKGROUND
    assert grey_scene(0).channels == 1 and grey_scene(0).background == BACKGROUND[0]


def test_each_channel_is_its_grey_scene_within_the_estimates():
    s = rgb_scene()
    origins, directions = s.rays()
    r = s.reference(origins, directions, tol=1e-11)
    assert r["value"].shape == (7, 9, 3) and r["error_estimate"].shape == (7, 9, 3)
    assert r["evaluations"].shape == (7, 9) and r["tolerance_met"].all()
    for c in range(3):
        g = grey_scene(c).reference(origins, directions, tol=1e-11)
        assert (np.abs(r["value"][..., c] - g["value"]) <= r["error_estimate"][..., c] + g["error_estimate"]).all()
        d = s.discrete(origins, directions, method="alpha", step=0.05)
        dg = grey_scene(c).discrete(origins, directions, method="alpha", step=0.05)
        assert np.array_equal(d["value"][..., c], dg["value"]), c
    # The camera's own rays, not their (origin, direction) round trip through numpy: equal within
    # the estimates, not bitwise.
    assert (np.abs(s.render(tol=1e-11) - r["value"]) <= 2 * r["error_estimate"] + 1e-15).all()


def test_three_equal_channels_are_the_grey_scene_bitwise():
    same = [[p[0], p[1], p[1], p[1]] for p in EMISSION]
    s = rgb_scene(same, (0.2, 0.2, 0.2))
    g = grey_scene(0, same, (0.2, 0.2, 0.2))
    origins, directions = g.rays()
    for how in ({}, {"method": "trapezoid", "step": 0.04}):
        rgb, grey = s.render(**how), g.render(**how)
        assert rgb.shape == (7, 9, 3) and grey.shape == (7, 9)
        for c in range(3):
            assert np.array_equal(rgb[..., c], grey), (how, c)
    r, rg = s.reference(origins, directions), g.reference(origins, directions)
    for c in range(3):
        assert np.array_equal(r["error_estimate"][..., c], rg["error_estimate"])
    assert np.array_equal(r["evaluations"], rg["evaluations"])


def test_verify_judges_each_channel_and_names_swapped_channels():
    s = rgb_scene()
    steps = [0.08, 0.04, 0.02]
    images = [s.render(method="alpha", step=h) for h in steps]
    report = vrv.verify(s, images, steps)
    assert report["pass"], report["failures"]
    assert [c["channel"] for c in report["images"][:3]] == ["R", "G", "B"]
    assert report["diagnosis_channel"] in ("R", "G", "B")
    assert report["diagnosis"][0]["rms"] < 1e-12, report["diagnosis"][0]
    swapped = vrv.verify(s, [im[..., ::-1].copy() for im in images], steps)
    assert not swapped["pass"]
    assert "swapped channels" in [f["name"] for f in swapped["faults"]], swapped["faults"]
    with pytest.raises(ValueError, match="but the scene is RGB"):
        vrv.verify(s, [im[..., 0].copy() for im in images], steps)


def test_projections_refuse_an_rgb_scene():
    s = rgb_scene()
    origins, directions = s.rays()
    image = s.render()[..., 0]
    with pytest.raises(ValueError, match="the scene is RGB"):
        vrv.verify(s, [image, image], [0.02, 0.01], mode="mip")
    with pytest.raises(ValueError, match="the scene is RGB"):
        s.reference(origins, directions, mode="mip")
    with pytest.raises(ValueError, match="the scene is RGB"):
        s.render(mode="xray")


def test_render_with_alpha():
    """render(alpha=True): A = 1 - e^-Phi last, the colour over nothing (C + I0 (1 - A) is the plain
    render); the discrete A is the same bit for bit in an RGB scene and its grey channel's."""
    s = rgb_scene()
    plain = s.render(method="alpha", step=0.05)
    over = s.render(method="alpha", step=0.05, alpha=True)
    assert over.shape == (7, 9, 4)
    a = over[:, :, 3]
    assert 0 <= a.min() and a.max() <= 1 and a.max() > 0.2
    for c in range(3):
        assert np.abs(over[:, :, c] + BACKGROUND[c] * (1 - a) - plain[:, :, c]).max() <= 1e-15
    grey = grey_scene(1).render(method="alpha", step=0.05, alpha=True)
    assert grey.shape == (7, 9, 2) and np.array_equal(grey[:, :, 1], a)
    ref = s.render(tol=1e-10, alpha=True)
    assert ref.shape == (7, 9, 4) and np.abs(ref[:, :, 3] - a).max() < 0.05
    with pytest.raises(ValueError, match="alpha="):
        grey_scene(0).render(mode="xray", alpha=True)
