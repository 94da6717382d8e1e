#!/usr/bin/env python3
"""End to end: `vrv export`, then docs/examples/render_export.py (a renderer that has never seen
vrv's code) renders the export, and must equal vrv's own alpha raycast with opacity per unit
distance (the same convention) to rounding, and converge to vrv's reference at second order.

    export_render_test.py VRV SOURCE_DIR SCRATCH_DIR
"""
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

vrv, src, scratch = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
scratch.mkdir(parents=True, exist_ok=True)
sys.path.insert(0, str(src / "docs" / "examples"))
import render_export  # noqa: E402

scene = scratch / "scene.toml"
scene.write_text("""
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "grid"
resolution = [9, 9, 9]
[field.source]
kind = "marschner_lobb"
fM = 2.0
[transfer]
opacity = [[0.0, 0.05], [1.0, 0.4]]
color = [[0.0, 1.0], [1.0, 0.2]]
unit_length = 0.25
[background]
intensity = 0.1
[camera]
projection = "perspective"
eye = [0.3, 0.2, -4.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 35.0
width = 7
height = 5
""")
out = scratch / "export"
subprocess.run([vrv, "export", "--scene", str(scene), "--out", str(out)], check=True, stdout=subprocess.DEVNULL)

rays = np.load(out / "rays.npy")
lines = "".join(json.dumps({"origin": list(r[0]), "direction": list(r[1])}) + "\n" for r in rays.reshape(-1, 2, 3))
(scratch / "rays.jsonl").write_text(lines)


def vrv_values(*options):
    run = subprocess.run([vrv, "ray", "--scene", str(scene), "--rays", str(scratch / "rays.jsonl"), *options],
                         check=True, capture_output=True, text=True)
    return np.array([json.loads(line)["value"] for line in run.stdout.splitlines()]).reshape(rays.shape[:2])


reference = vrv_values("--tol", "1e-12")
steps = (0.08, 0.04, 0.02, 0.01)
# vrv's step strategy leaves the last sample a whole step at the exit: first order (border);
# whole steps (inviwo) have no border error: second order.
for strategy, whole, lo, hi in (("step", False, 0.7, 1.3), ("inviwo", True, 1.7, 2.3)):
    errors = []
    for H in steps:
        numpy_image = render_export.render(out, H, whole)
        vrv_image = vrv_values("--method", "alpha", "--strategy", strategy, "--step", str(H), "--opacity-unit", "distance")
        agree = np.max(np.abs(numpy_image - vrv_image))
        errors.append(np.max(np.abs(numpy_image - reference)))
        print(f"{strategy} H = {H}: numpy renderer vs vrv alpha/distance max |diff| = {agree:.3g}, "
              f"vs reference max |e| = {errors[-1]:.3g}")
        if not agree < 1e-12:
            sys.exit(f"{strategy}: the numpy renderer and vrv's alpha rule with opacity per unit distance differ by {agree}")
    order = np.polyfit(np.log(steps), np.log(errors), 1)[0]  # least-squares slope of log error on log H
    print(f"{strategy}: observed order {order:.3f} (expected in [{lo}, {hi}])")
    if not lo <= order <= hi:
        sys.exit(f"{strategy}: observed order {order:.3f} outside [{lo}, {hi}]")


# The round trip: `vrv export` writes scene.toml, the scene that describes exactly what it wrote
# (an analytic field as the grid of its exported nodes, an emission/extinction transfer function
# as the exported opacity/colour table).  The numpy renderer's images of an export, saved as
# numpy saves them (.npy), verified against that scene, converge at the renderer's order (2 with
# whole steps) with no fault named: the default scene (analytic, emission/extinction; `vrv scene
# --print`, with a small camera so that the Python renderer is quick) and the grid scene above
# (opacity/colour).
default_text = subprocess.run([vrv, "scene", "--print"], check=True, capture_output=True, text=True).stdout
small_camera = "\n[camera]\neye = [0.4, 0.3, -4.5]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov = 30.0\nwidth = 12\nheight = 10\n"
(scratch / "default.toml").write_text(default_text + small_camera)


def verify_passes(label, scene_file, images, steps):
    """`vrv verify` of a correct renderer's images: converges at order 2, no fault named."""
    run = subprocess.run([vrv, "verify", "--scene", str(scene_file), *map(str, images),
                          "--steps", ",".join(map(str, steps)), "--expected-order", "2", "--no-diagnosis",
                          "--cache-dir", str(scratch / "cache"), "--quiet"], capture_output=True, text=True)
    report = json.loads(run.stdout) if run.stdout.strip() else {}
    faults = [f["name"] for f in report.get("faults", [])]
    orders = [round(o["order"], 3) for o in report.get("orders", []) if o.get("kind") == "reference"]
    print(f"{label}: verify exit {run.returncode}, verdict {report.get('verdict')}, order {orders}, faults {faults}")
    if run.returncode != 0 or report.get("verdict") != "converges" or faults:
        sys.exit(f"{label}: a correct renderer of the export does not pass against its scene.toml:\n"
                 f"{run.stdout}\n{run.stderr}")


for name, scene_file in (("default", scratch / "default.toml"), ("grid", scene)):
    exported = scratch / f"roundtrip_{name}"
    subprocess.run([vrv, "export", "--scene", str(scene_file), "--out", str(exported)], check=True,
                   stdout=subprocess.DEVNULL)
    manifest = json.loads((exported / "export.json").read_text())
    if manifest["scene_file"] != "scene.toml" or not (exported / "scene.toml").is_file():
        sys.exit(f"{name}: export.json names no scene file: {manifest}")
    print(f"{name}: export.json grid source: {manifest['grid']['source']}")
    steps = (0.04, 0.02, 0.01, 0.005)
    arrays = [render_export.render(exported, H, True) for H in steps]
    images = [exported / f"image_H{H}.npy" for H in steps]
    for path, array in zip(images, arrays):
        np.save(path, array)
    verify_passes(f"{name} (.npy)", exported / "scene.toml", images, steps)
    if name == "default":
        # Against the analytic scene instead, the grid's interpolation error is a floor: named as
        # a constant floor (whose causes list the export's grid), never as jitter.
        run = subprocess.run([vrv, "verify", "--scene", str(scene_file), *map(str, images), "--steps",
                              ",".join(map(str, steps)), "--no-diagnosis", "--cache-dir", str(scratch / "cache"),
                              "--quiet"], capture_output=True, text=True)
        report = json.loads(run.stdout)
        faults = {f["name"]: f["evidence"] for f in report["faults"]}
        print(f"default against the analytic scene: {report['verdict']}, faults {list(faults)}")
        if report["verdict"] != "stalls at a floor" or "jitter" in faults or \
                "scene.toml" not in faults.get("constant floor", ""):
            sys.exit(f"default against the analytic scene: expected a constant floor naming scene.toml:\n{run.stdout}")

# The numpy -> EXR recipe of docs/verify.md (Debian's python3-openimageio), on the last export.
import OpenImageIO as oiio  # noqa: E402
exrs = [exported / f"image_H{H}.exr" for H in steps]
for path, image in zip(exrs, arrays):
    oiio.ImageBuf(image.astype("float32")).write(str(path))
verify_passes(f"{name} (EXR from numpy)", exported / "scene.toml", exrs, steps)
