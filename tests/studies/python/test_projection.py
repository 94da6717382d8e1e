"""vrv.verify(mode=...), Scene.reference(mode=...), Scene.discrete(mode=...) and Scene.render(mode=...):
projection images from the numpy renderer (numpy_raycaster.project, not vrv's) pass at the mode's
expected order 2, planted faults fail, the discrete projections sample where their placement says,
and a bad mode or keyword is a ValueError naming the keyword."""
import json
import os
import subprocess

import numpy as np
import pytest

import vrv
import numpy_raycaster

VRV = os.environ.get("VRV_EXE", "vrv")
# Marschner-Lobb's rings are resolved from about h = 0.025 on (a MIP's asymptotic range).  A
# sampled MIP's error per pixel is f'' d^2 / 2 with d the distance of the nearest sample from the
# peak, which depends on the sample phase, not only on h: the error falls as h^2 on average over
# many pixels but not monotonically pixel by pixel (the default camera's symmetry repeats each
# pixel eight times).  48 x 48 pixels average that out; at 24 x 24 the finest pair of steps can
# read as a floor (docs/projections.md).
STEPS = [0.025, 0.0125, 0.00625, 0.003125]
SIZE = 48


@pytest.fixture(scope="module")
def scene_and_rays():
    scene = vrv.Scene.default()
    origins, directions = scene.rays(width=SIZE, height=SIZE)
    return scene, origins, directions


@pytest.mark.parametrize("mode", ["mip", "xray"])
def test_numpy_projection_passes_at_order_two(scene_and_rays, mode):
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.project(origins, directions, h, mode) for h in STEPS]
    report = vrv.verify(scene, images, STEPS, mode=mode)
    assert report["pass"], report["verdict_reason"]
    assert report["verdict"] == "converges"
    assert report["expected_order"] == 2
    assert report["mode"] == mode
    assert len(report["notes"]) == 1 and "not run" in report["notes"][0]
    assert report["faults"] == [] and report["conventions"] == []
    assert report["diagnosis"][0]["rule"] in (("max",) if mode == "mip" else ("riemann", "trapezoid", "simpson"))


@pytest.mark.parametrize("mode,planted", [("mip", "first_sample_dropped"), ("xray", "step_not_multiplied")])
def test_planted_projection_faults_fail(scene_and_rays, mode, planted):
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.project(origins, directions, h, mode, planted) for h in STEPS]
    report = vrv.verify(scene, images, STEPS, mode=mode)
    assert not report["pass"]
    assert report["verdict"] != "converges"


def test_reference_and_render_modes_match_vrv_ray(scene_and_rays, tmp_path):
    scene, origins, directions = scene_and_rays
    y, x = SIZE // 2 + 3, SIZE // 2 - 5  # a ray through the box
    r = scene.reference(origins[y:y + 1, x], directions[y:y + 1, x], mode="mip")
    assert r["hit"][0]
    out = subprocess.run([VRV, "ray", "--json", "--mode", "mip", "--origin", ",".join(repr(x) for x in origins[y, x]),
                          "--direction", ",".join(repr(x) for x in directions[y, x])],
                         capture_output=True, text=True, check=True)
    j = json.loads(out.stdout)
    assert r["value"][0] == j["value"]
    assert r["position"][0] == j["position"]
    image = scene.render(width=SIZE, height=SIZE, mode="xray")
    rays = scene.reference(origins, directions, mode="xray")
    # Both are references to 1e-12 (the rays rebuilt from arrays may differ in their last bits).
    assert np.max(np.abs(image - rays["value"])) <= 2e-12
    assert np.max(image) > 0
    assert not np.array_equal(image, scene.render(width=SIZE, height=SIZE))  # not emission-absorption


@pytest.mark.parametrize("call", ["verify", "reference", "render"])
def test_bad_mode_is_a_value_error_naming_the_keyword(scene_and_rays, call):
    scene, origins, directions = scene_and_rays
    with pytest.raises(ValueError, match=r"^mode: unknown value 'MIP'"):
        if call == "verify":
            vrv.verify(scene, [np.zeros((SIZE, SIZE))] * 2, [0.1, 0.05], mode="MIP")
        elif call == "reference":
            scene.reference(origins, directions, mode="MIP")
        else:
            scene.render(width=SIZE, height=SIZE, mode="MIP")


def test_discrete_mip_takes_the_largest_sample_at_the_step_placement(scene_and_rays):
    # `step` places samples at t0 + (k + 1/2) h while inside the box; the largest of the field there,
    # computed here in numpy with the numpy renderer's own clipping and field.
    scene, origins, directions = scene_and_rays
    h = 0.05
    o, d, t0, t1 = numpy_raycaster.clip_to_box(origins, directions)
    r = scene.discrete(o, d, mode="mip", method="max", strategy="step", step=h)
    checked = 0
    for i in range(len(o)):
        if not t1[i] - t0[i] > h:
            continue
        n = int(np.ceil((t1[i] - t0[i]) / h))
        t = t0[i] + (np.arange(n) + 0.5) * h
        t = t[t < t1[i]]
        v = numpy_raycaster.marschner_lobb(o[i] + t[:, None] * d[i])
        assert r["samples"][i] == len(t)
        assert abs(r["value"][i] - v.max()) <= 1e-12
        assert r["position"][i] == pytest.approx(t[np.argmax(v)], abs=1e-12)
        checked += 1
    assert checked >= 100  # 324 of the 48 x 48 default camera rays cross more than one step


def test_discrete_xray_render_converges_to_its_reference(scene_and_rays):
    scene = scene_and_rays[0]
    reference = scene.render(width=SIZE, height=SIZE, mode="xray")
    errors = [np.sqrt(np.mean((scene.render(width=SIZE, height=SIZE, mode="xray", method="trapezoid", strategy="step",
                                            step=h) - reference) ** 2)) for h in (0.02, 0.01, 0.005)]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.75), orders  # the trapezoid: second order
    # vrv's own discrete MIP images: samples at midpoints never reach a maximum on the entry face, so
    # they converge at first order (docs/projections.md) and pass verify when that is what is expected.
    images = [scene.render(width=SIZE, height=SIZE, mode="mip", method="max", strategy="partial", step=h)
              for h in STEPS]
    report = vrv.verify(scene, images, STEPS, mode="mip", expected_order=1)
    assert report["pass"], report["verdict_reason"]
    assert report["diagnosis"][0]["rule"] == "max"


@pytest.mark.parametrize("keywords,message", [
    ({"method": "simpson"}, r"^method: unknown value 'simpson' for mode mip \(max\)"),
    ({"method": "max", "oversample": 2}, r"^oversample: applies to emission-absorption raycasts, not to mode mip"),
    ({"method": "{max}"}, r"^method: unknown value '\{max\}' for mode mip"),
    ({"method": "max", "max_work": -1}, r"^max_work: must be positive"),
])
def test_bad_discrete_projection_keywords_name_the_keyword(scene_and_rays, keywords, message):
    scene, origins, directions = scene_and_rays
    with pytest.raises(ValueError, match=message):
        scene.discrete(origins, directions, mode="mip", strategy="step", step=0.05, **keywords)
    with pytest.raises(ValueError, match=message):
        scene.render(width=SIZE, height=SIZE, mode="mip", strategy="step", step=0.05, **keywords)
