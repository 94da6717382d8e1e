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
