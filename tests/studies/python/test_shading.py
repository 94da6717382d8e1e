"""Shaded scenes ([shading], docs/shading.md) from Python: the reference and the discrete raycast
are `vrv ray`'s bit for bit, gradient= chooses the scheme, and a keyword that would do nothing is
refused by name.  Run by CTest as `python` (test_module.py's set-up)."""
import json
import os
import subprocess

import numpy as np
import pytest

import vrv

VRV = os.environ.get("VRV_EXE", "vrv")

SHADED = """[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 0.5]]
[shading]
light = [0.3, -0.4, 0.87]
two_sided = false
"""

ORIGINS = np.array([[0.1, 0.2, -3.0], [-3.0, 0.2, 0.1]])
DIRECTIONS = np.array([[0.0, 0.05, 1.0], [1.0, 0.1, -0.05]])


def ray_json(scene_path, origin, direction, *args):
    p = subprocess.run([VRV, "ray", "--scene", str(scene_path), "--origin", ",".join(map(str, origin)),
                        "--direction", ",".join(map(str, direction)), "--json", *args], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def test_shaded_reference_and_discrete_are_vrv_ray_bitwise(tmp_path):
    path = tmp_path / "shaded.toml"
    path.write_text(SHADED)
    scene = vrv.Scene.from_toml(SHADED)
    ref = scene.reference(ORIGINS, DIRECTIONS, tol=1e-11)
    disc = scene.discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.01, gradient="analytic")
    for i in range(len(ORIGINS)):
        line = ray_json(path, ORIGINS[i], DIRECTIONS[i], "--tol", "1e-11")
        assert ref["value"][i] == line["value"]
        line = ray_json(path, ORIGINS[i], DIRECTIONS[i], "--method", "trapezoid", "--step", "0.01",
                        "--gradient", "analytic")
        assert disc["value"][i] == line["value"]
    # One-sided: S is continuous, and a finer step is closer (two-sided, S jumps where the normal
    # turns and the error is O(h) with an erratic constant).
    finer = scene.discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.0025, gradient="analytic")
    assert np.all(np.abs(finer["value"] - ref["value"]) < np.abs(disc["value"] - ref["value"]))
    plain = vrv.Scene.from_toml(SHADED.split("[shading]")[0]).reference(ORIGINS, DIRECTIONS, tol=1e-11)
    assert np.all(np.abs(plain["value"] - ref["value"]) > 1e-4)


def shaded_grid():
    return vrv.Scene.from_toml(SHADED.replace('kind = "marschner_lobb"', 'kind = "grid"\nsource = { kind = "marschner_lobb" }\n'
                                              'resolution = [17, 17, 17]'))


def test_shading_at_the_nodes_is_vrv_rays(tmp_path):
    path = tmp_path / "grid.toml"
    scene = shaded_grid()
    path.write_text(SHADED.replace('kind = "marschner_lobb"', 'kind = "grid"\nsource = { kind = "marschner_lobb" }\n'
                                   'resolution = [17, 17, 17]'))
    options = dict(method="trapezoid", step=0.01, classification="pre", gradient="nodes")
    at_nodes = scene.discrete(ORIGINS, DIRECTIONS, shade_at="nodes", **options)
    at_samples = scene.discrete(ORIGINS, DIRECTIONS, **options)
    for i in range(len(ORIGINS)):
        line = ray_json(path, ORIGINS[i], DIRECTIONS[i], "--method", "trapezoid", "--step", "0.01",
                        "--classification", "pre", "--gradient", "nodes", "--shade-at", "nodes")
        assert at_nodes["value"][i] == line["value"]
    assert np.all(at_nodes["value"] != at_samples["value"])


def test_gradient_keywords_are_checked():
    shaded = vrv.Scene.from_toml(SHADED)
    with pytest.raises(ValueError, match="gradient: nodes"):
        shaded.discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.01, gradient="nodes")
    with pytest.raises(ValueError, match="gradient_offset: applies to gradient central only"):
        shaded.discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.01, gradient="analytic", gradient_offset=0.01)
    with pytest.raises(ValueError, match="shade_at: nodes .*needs a grid field"):
        shaded.discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.01, shade_at="nodes")
    with pytest.raises(ValueError, match="shade_at: nodes .*needs classification pre and gradient nodes"):
        shaded_grid().discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.01, shade_at="nodes")
    plain = vrv.Scene.from_toml(SHADED.split("[shading]")[0])
    with pytest.raises(ValueError, match="gradient: applies to a shaded scene only"):
        plain.discrete(ORIGINS, DIRECTIONS, method="trapezoid", step=0.01, gradient="analytic")


# Marschner-Lobb at fM = 1 seen from the side: away from where its gradient nearly vanishes, where
# S is nearly a jump at these steps and the order falls toward 1 (tests/lib/verify/verify_shading_test.cpp).
SIDE = SHADED.replace('kind = "marschner_lobb"', 'kind = "marschner_lobb"\nfM = 1.0') + """[camera]
eye = [-4.0, 0.5, 0.3]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 20.0
width = 10
height = 10
"""


def test_verify_names_the_gradient_scheme():
    s = vrv.Scene.from_toml(SIDE)
    steps = [0.1, 0.05, 0.025]
    exact = [s.render(method="alpha", strategy="inviwo", step=h, gradient="analytic") for h in steps]
    report = vrv.verify(s, exact, steps, expected_order=2)
    assert report["pass"], report["failures"]
    assert report["diagnosis"][0]["gradient"] == "analytic", report["diagnosis"][0]
    assert "gradient floor" not in [f["name"] for f in report["faults"]]
    central = [s.render(method="alpha", strategy="inviwo", step=h, gradient="central") for h in steps]
    report = vrv.verify(s, central, steps, expected_order=2)
    assert report["diagnosis"][0]["gradient"] == "central", report["diagnosis"][0]
    assert "gradient floor" in [f["name"] for f in report["faults"]], report["faults"]
