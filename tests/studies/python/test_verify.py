"""vrv.verify (studies/python/module.cpp): `vrv verify`'s report in-process, as a dict.  The
numpy raycaster (numpy_raycaster.py) passes at second order and its half-step-offset copy is
caught and named; the report is the command line's for the same pixels; bad input raises the
command line's message."""
import json
import os
import subprocess
import warnings

import numpy as np
import pytest

import vrv
import numpy_raycaster

VRV = os.environ.get("VRV_EXE", "vrv")
STEPS = [0.08, 0.04, 0.02, 0.01]


@pytest.fixture(scope="module")
def scene_and_rays():
    scene = vrv.Scene.default()
    origins, directions = scene.rays(width=24, height=24)
    return scene, origins, directions


def test_numpy_raycaster_passes_and_its_files_are_written(scene_and_rays, tmp_path):
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.render(origins, directions, h) for h in STEPS]
    report = vrv.verify(scene, images, STEPS, expected_order=2, out=str(tmp_path / "out"), plots=True)
    assert report["pass"], report["verdict_reason"]
    assert report["verdict"] == "converges"
    reference = [o for o in report["orders"] if o["kind"] == "reference"][0]
    assert abs(reference["order"] - 2) < 0.25, reference
    nearest = report["diagnosis"][0]
    # Its step, rounded up to fit the ray (ceil), is neither vrv's inviwo (round) nor partial
    # placement exactly; the nearest is one of those two midpoint placements (partial since issue 24).
    assert nearest["rule"] == "alpha" and nearest["placement"] in ("inviwo", "partial"), nearest
    assert report["faults"] == [], report["faults"]
    for name in ("errors.csv", "orders.md", "diagnosis.json", "faults.csv", "reference.exr", "meta.json",
                 "plots.json", "error_vs_step.png", "error_vs_step.pdf"):
        assert (tmp_path / "out" / name).is_file(), name
    assert (tmp_path / "out" / "error_vs_step.png").stat().st_size > 0
    assert report["out"] == str(tmp_path / "out")


def test_plot_failure_warns_and_keeps_the_tables(scene_and_rays, tmp_path, monkeypatch):
    """As `vrv verify --out`: a plot that cannot be drawn is one line (a RuntimeWarning), not an
    error; the tables are written.  Without plots=True (`--plots`) nothing is drawn."""
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.render(origins, directions, h) for h in STEPS]
    monkeypatch.setenv("VRV_PYTHON", str(tmp_path / "no-such-python"))
    out = tmp_path / "failed"
    with pytest.warns(RuntimeWarning, match=r"^vrv.verify: .*failed: the plot could not be drawn"):
        report = vrv.verify(scene, images, STEPS, diagnose=False, out=str(out), plots=True)
    assert report["pass"] and (out / "errors.csv").is_file() and (out / "plots.json").is_file()
    assert not (out / "error_vs_step.png").exists()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # not drawn, so nothing to warn about
        vrv.verify(scene, images, STEPS, diagnose=False, out=str(tmp_path / "none"))
    assert (tmp_path / "none" / "plots.json").is_file()
    assert not (tmp_path / "none" / "error_vs_step.png").exists()


def test_planted_half_step_offset_fails_and_is_named(scene_and_rays):
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.render(origins, directions, h, offset=0.0) for h in STEPS]
    report = vrv.verify(scene, images, STEPS, expected_order=2)
    assert not report["pass"]
    assert report["verdict"] == "converges at a lower order", report["verdict_reason"]
    assert "half-step offset" in [f["name"] for f in report["faults"]], report["faults"]


def test_bounds_file_fail_levels_decide_pass(scene_and_rays, tmp_path):
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.render(origins, directions, h) for h in STEPS]
    plain = vrv.verify(scene, images, STEPS, diagnose=False)
    rms = max(c["regions"]["all"]["rms"] for c in plain["images"] if c["step"] == STEPS[-1])
    for factor, passes in ((1.01, True), (0.99, False)):
        path = tmp_path / f"bounds_{factor}.toml"
        path.write_text(f"[defaults]\nrms = {{ fail = {rms * factor!r} }}\n")
        report = vrv.verify(scene, images, STEPS, diagnose=False, bounds=str(path))
        assert report["pass"] is passes, report["bounds"]
        assert [row["bound"] for row in report["bounds"]] == ["rms"]


def test_same_report_as_vrv_verify(tmp_path):
    """vrv's own alpha/vtk images (`vrv render` writes the double pixels as .f64.tiff; scene.render
    gives the same doubles): the command line and the module report the same numbers."""
    scene = vrv.Scene.default()
    files, images = [], []
    for h in STEPS:
        exr = tmp_path / f"vtk_{h}.exr"
        subprocess.run([VRV, "render", "--method", "alpha", "--strategy", "vtk", "--step", str(h),
                        "--width", "16", "--height", "16", "--quiet", "-o", str(exr)], check=True)
        files.append(str(exr).replace(".exr", ".f64.tiff"))
        images.append(scene.render(width=16, height=16, method="alpha", strategy="vtk", step=h))
    p = subprocess.run([VRV, "verify", *files, "--steps", ",".join(map(str, STEPS)), "--no-cache",
                        "--quiet", "--expected-order", "2"], capture_output=True, text=True)
    assert p.returncode == 1, p.stderr
    cli = json.loads(p.stdout)
    mine = vrv.verify(scene, images, STEPS, expected_order=2)
    assert mine["pass"] is cli["pass"] is False
    for key in ("verdict", "verdict_reason", "orders"):
        assert mine[key] == cli[key], key
    assert [c["regions"] for c in mine["images"]] == [c["regions"] for c in cli["images"]]
    assert [(d["name"], d["rms"]) for d in mine["diagnosis"]] == [(d["name"], d["rms"]) for d in cli["diagnosis"]]
    assert [f["name"] for f in mine["faults"]] == [f["name"] for f in cli["faults"]]


def test_bad_input_raises_the_command_lines_message(scene_and_rays, tmp_path):
    scene, _, _ = scene_and_rays
    zeros = [np.zeros((8, 8))] * 4
    with pytest.raises(ValueError, match=r"^--steps: 3 steps for 4 images"):
        vrv.verify(scene, zeros, STEPS[:3])
    with pytest.raises(ValueError, match=r"^images\[1\]: an array of 1 dimensions \(expected \(height, width\) or "):
        vrv.verify(scene, [np.zeros((8, 8)), np.zeros(8)], STEPS[:2])
    with pytest.raises(ValueError, match=r"^image 1 \(step 0.04\): size 4 x 8 differs from image 0"):
        vrv.verify(scene, [np.zeros((8, 8)), np.zeros((8, 4))], STEPS[:2])
    nan = np.zeros((8, 8))
    nan[2, 3] = np.nan
    with pytest.raises(ValueError, match=r"^image 1 \(step 0.04\): pixel \(3, 2\) channel Y is nan$"):
        vrv.verify(scene, [np.zeros((8, 8)), nan], STEPS[:2])
    with pytest.raises(ValueError, match=r"^order_metric: 'median' is not one of"):
        vrv.verify(scene, zeros, STEPS, order_metric="median")
    with pytest.raises(FileNotFoundError, match=r"^no/such/bounds.toml: "):
        vrv.verify(scene, zeros, STEPS, bounds="no/such/bounds.toml")
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match=r"^--out: .*file exists and is not a directory$"):
        vrv.verify(scene, zeros, STEPS, out=str(tmp_path / "file"))
    with pytest.raises(TypeError):
        vrv.verify(scene, zeros, STEPS, expected_ordre=2)
    # A complex image lost its imaginary part (numpy's warning only); booleans became 0 and 1.
    with pytest.raises(ValueError, match=r"^images\[0\]: dtype complex128 is not real numbers"):
        vrv.verify(scene, [z.astype(complex) for z in zeros], STEPS)
    with pytest.raises(ValueError, match=r"^images\[0\]: dtype bool is not real numbers"):
        vrv.verify(scene, [z.astype(bool) for z in zeros], STEPS)
    # The plot goes into out: without it plots=True was accepted and nothing drawn.
    with pytest.raises(ValueError, match=r"^plots: the plot is drawn into out; give out= as well$"):
        vrv.verify(scene, zeros, STEPS, plots=True)


def test_out_is_published_whole(scene_and_rays, tmp_path):
    """As `vrv verify --out` (issue 22): a second run replaces the folder whole, so an earlier
    run's bounds.csv does not stay beside the new tables; a folder vrv did not write is refused
    before any work, its files untouched; no staging folder is left behind."""
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.render(origins, directions, h) for h in STEPS]
    out = tmp_path / "out"
    vrv.verify(scene, images, STEPS, diagnose=False, out=str(out), plots=False)
    (out / "bounds.csv").write_text("an earlier run's table\n")
    vrv.verify(scene, images, STEPS, diagnose=False, out=str(out), plots=False)
    assert (out / "errors.csv").is_file() and not (out / "bounds.csv").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"], list(tmp_path.iterdir())
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    with pytest.raises(ValueError, match=r"^--out: "):
        vrv.verify(scene, images, STEPS, diagnose=False, out=str(mine), plots=False)
    assert [p.name for p in mine.iterdir()] == ["notes.txt"]


def test_report_writes_one_self_contained_page(scene_and_rays, tmp_path):
    """report= (`vrv verify --report`): one HTML page with the verdict and the named fault first,
    every error map inline; a directory is refused before any work (ValueError, nothing written)."""
    scene, origins, directions = scene_and_rays
    images = [numpy_raycaster.render(origins, directions, h, offset=0.0) for h in STEPS]
    page = tmp_path / "r.html"
    report = vrv.verify(scene, images, STEPS, expected_order=2, report=str(page))
    assert report["report"] == str(page)
    text = page.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and text.endswith("</body></html>\n")
    verdict = text.index('<span id="verdict-text">' + report["verdict"])
    assert verdict < text.index("<b>Fault: half-step offset</b>") < text.index('id="convergence-plot"')
    assert text.count('<img class="error-map"') == len(STEPS)
    assert "vrv.verify(scene, images, steps=[0.08, 0.04, 0.02, 0.01], expected_order=2, report=&quot;" in text
    with pytest.raises(ValueError, match=r"^report: .*: is a directory"):
        vrv.verify(scene, images, STEPS, report=str(tmp_path))
