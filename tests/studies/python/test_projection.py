"""vrv.verify(mode=...), Scene.reference(mode=...) and Scene.render(mode=...): projection images
from the numpy renderer (numpy_raycaster.project, not vrv's) pass at the mode's expected order 2,
planted faults fail, and a bad mode is a ValueError naming the keyword."""
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
