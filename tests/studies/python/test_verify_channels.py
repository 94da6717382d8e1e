"""vrv.verify with (height, width, 3 or 4) arrays: RGB and RGBA read as `vrv verify` reads the same
array saved as .npy (one code path, lib/io/image_channels.h), with the same report and the same
one-line errors naming the argument."""
import json
import os
import subprocess

import numpy as np
import pytest

import vrv
import numpy_raycaster

VRV = os.environ.get("VRV_EXE", "vrv")
STEPS = [0.08, 0.04, 0.02, 0.01]


@pytest.fixture(scope="module")
def rgba_images():
    scene = vrv.Scene.default()
    origins, directions = scene.rays(width=16, height=16)
    return scene, [numpy_raycaster.render(origins, directions, h, rgba=True) for h in STEPS]


def channels(report):
    return sorted({c["channel"] for c in report["images"]})


def test_rgba_passes_with_alpha_compared_to_opacity(rgba_images):
    scene, images = rgba_images
    report = vrv.verify(scene, images, STEPS, expected_order=2, diagnose=False)
    assert report["pass"], report["verdict_reason"]
    assert channels(report) == ["A", "B", "G", "R"]
    alpha = [c for c in report["images"] if c["channel"] == "A"]
    assert all(c["alpha"] for c in alpha) and len(alpha) == len(STEPS)
    # The alpha channel is judged: a wrong opacity fails even with the right colour.
    wrong = [np.concatenate([im[..., :3], im[..., 3:] * 0.9], axis=-1) for im in images]
    assert not vrv.verify(scene, wrong, STEPS, expected_order=2, diagnose=False)["pass"]


def test_rgb_is_three_channels_of_the_value(rgba_images):
    scene, images = rgba_images
    report = vrv.verify(scene, [im[..., :3] for im in images], STEPS, expected_order=2, diagnose=False)
    assert report["pass"], report["verdict_reason"]
    assert channels(report) == ["B", "G", "R"]
    grey = vrv.verify(scene, [im[..., 0] for im in images], STEPS, expected_order=2, diagnose=False)
    r = [c["regions"] for c in report["images"] if c["channel"] == "R"]
    assert r == [c["regions"] for c in grey["images"]]


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_same_report_as_vrv_verify_of_the_npy_files(rgba_images, tmp_path, dtype):
    scene, images = rgba_images
    files = []
    for h, im in zip(STEPS, images):
        files.append(str(tmp_path / f"rgba_{h}.npy"))
        np.save(files[-1], im.astype(dtype))
    p = subprocess.run([VRV, "verify", *files, "--steps", ",".join(map(str, STEPS)), "--no-cache", "--quiet",
                        "--expected-order", "2"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    cli = json.loads(p.stdout)
    mine = vrv.verify(scene, [im.astype(dtype) for im in images], STEPS, expected_order=2)
    for key in ("pass", "verdict", "verdict_reason", "orders", "diagnosis", "faults"):
        assert mine[key] == cli[key], key
    strip = ("image",)  # the file name there, "image i (step h)" here
    assert [{k: v for k, v in c.items() if k not in strip} for c in mine["images"]] == \
        [{k: v for k, v in c.items() if k not in strip} for c in cli["images"]]


def test_float32_keeps_its_quantum(rgba_images):
    scene, images = rgba_images
    f32 = vrv.verify(scene, [im.astype(np.float32) for im in images], STEPS, diagnose=False)
    f64 = vrv.verify(scene, images, STEPS, diagnose=False)
    q32 = {c["quantum"] for c in f32["images"]}
    q64 = {c["quantum"] for c in f64["images"]}
    assert min(q32) > 1e-9 > max(q64) > 0, (q32, q64)


def test_bad_shapes_name_the_argument_and_the_image(rgba_images):
    scene, images = rgba_images
    two = STEPS[:2]
    with pytest.raises(ValueError, match=r"^images\[1\]: 5 channels \(1 to 4: grey, grey\+alpha, RGB or RGBA\)$"):
        vrv.verify(scene, [images[0], np.zeros((16, 16, 5))], two)
    with pytest.raises(ValueError, match=r"^images\[0\]: an array of 4 dimensions \(expected \(height, width\) "
                                         r"or \(height, width, channels\)\)$"):
        vrv.verify(scene, [np.zeros((16, 16, 4, 1)), images[1]], two)
    with pytest.raises(ValueError, match=r"^images\[1\]: an array of 1 dimensions"):
        vrv.verify(scene, [images[0], np.zeros(16)], two)
    with pytest.raises(ValueError, match=r"^images\[0\]: 0 channels"):
        vrv.verify(scene, [np.zeros((16, 16, 0)), images[1]], two)
    with pytest.raises(ValueError, match=r"^images\[1\]: 16 x 0 pixels"):
        vrv.verify(scene, [images[0], np.zeros((0, 16, 4))], two)
    with pytest.raises(ValueError, match=r"^image 1 \(step 0.04\): .*channel"):
        vrv.verify(scene, [images[0], images[1][..., :3]], two)


def straight(image):
    """The RGBA image with its colour divided by alpha (straight, not premultiplied); 0 where A = 0."""
    rgb, a = image[..., :3], image[..., 3:]
    return np.concatenate([np.divide(rgb, a, out=np.zeros_like(rgb), where=a > 0), a], axis=-1)


def test_alpha_straight_as_the_cli(rgba_images):
    """alpha= is `vrv verify --alpha`: straight colour passes as straight, fails as premultiplied."""
    scene, images = rgba_images
    unmultiplied = [straight(im) for im in images]
    report = vrv.verify(scene, unmultiplied, STEPS, expected_order=2, diagnose=False, alpha="straight")
    assert report["pass"], report["verdict_reason"]
    assert not vrv.verify(scene, unmultiplied, STEPS, expected_order=2, diagnose=False)["pass"]
    assert not vrv.verify(scene, unmultiplied, STEPS, expected_order=2, diagnose=False,
                          alpha="premultiplied")["pass"]


def test_bad_alpha_gives_the_cli_message(rgba_images, tmp_path):
    scene, images = rgba_images
    files = []
    for h, im in zip(STEPS, images):
        files.append(str(tmp_path / f"rgba_{h}.npy"))
        np.save(files[-1], im)
    p = subprocess.run([VRV, "verify", *files, "--steps", ",".join(map(str, STEPS)), "--no-cache", "--quiet",
                        "--alpha", "linear"], capture_output=True, text=True)
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    with pytest.raises(ValueError) as e:
        vrv.verify(scene, images, STEPS, alpha="linear")
    assert str(e.value) == "alpha: 'linear' is not one of auto, premultiplied, straight"
    assert p.stderr == "vrv: error: --alpha: 'linear' is not one of auto, premultiplied, straight\n"  # the flag
