#!/usr/bin/env python3
"""Render a `vrv export` directory the way most volume renderers do, with numpy only.

    python3 render_export.py DIR H [H ...]        ->  DIR/image_H<H>.npy (float64, height x width)
    python3 render_export.py --whole-steps DIR H [H ...]

What it does, per pixel (rays from rays.npy, so the camera is vrv's exactly):
  - clip the ray to the box [box.min, box.max] of export.json (t >= 0);
  - samples at t = entry + (k + 1/2) H while t < exit (vrv's `step` strategy: the last sample
    stands for a whole H even where less is left, a first-order border error), or with
    --whole-steps at the midpoints of n = round(length / H) equal steps (vrv's `inviwo`: no
    border error, second order);
  - the field trilinear between the nodes of field_f64.nrrd (clamped to the grid);
  - opacity a(v) and colour c(v) linear between the points of transfer_function.json,
    constant beyond the ends;
  - opacity per unit distance L corrected to the sample distance: alpha = 1 - (1 - a)^(H / L);
  - front to back: I += T c alpha, T *= 1 - alpha; finally I += T background.
This is `vrv render --method alpha --strategy step (or inviwo) --step H --opacity-unit distance`
on the exported grid (see docs/export.md), so the two agree to rounding.
"""
import json
import math
import sys
from pathlib import Path

import numpy as np


def read_nrrd(path):
    """An attached NRRD written by vrv export: values[k, j, i], origin, spacing."""
    data = Path(path).read_bytes()
    end = data.index(b"\n\n") + 2
    fields = {}
    for line in data[:end].decode().splitlines()[1:]:
        if line and not line.startswith("#"):
            key, value = line.split(": ", 1)
            fields[key] = value
    assert fields["encoding"] == "raw" and fields["endian"] == "little"
    sizes = [int(s) for s in fields["sizes"].split()]
    dtype = {"double": "<f8", "float": "<f4"}[fields["type"]]
    values = np.frombuffer(data[end:], dtype=dtype).astype(np.float64).reshape(sizes[::-1])
    vec = lambda text: np.array([float(x) for x in text.strip("()").split(",")])
    origin = vec(fields["space origin"])
    directions = [vec(d) for d in fields["space directions"].split()]
    spacing = np.array([directions[a][a] for a in range(3)])
    return values, origin, spacing


def trilinear(values, origin, spacing, p):
    """p: (m, 3) world positions -> (m,) values, as vrv's GridField (node layout)."""
    n = np.array(values.shape[::-1])  # (nx, ny, nz)
    u = np.clip((p - origin) / spacing, 0, n - 1)
    i0 = np.minimum(u.astype(int), n - 2)
    w = u - i0
    i, j, k = i0[:, 0], i0[:, 1], i0[:, 2]
    lerp = lambda a, b, t: a + t * (b - a)
    c00 = lerp(values[k, j, i], values[k, j, i + 1], w[:, 0])
    c10 = lerp(values[k, j + 1, i], values[k, j + 1, i + 1], w[:, 0])
    c01 = lerp(values[k + 1, j, i], values[k + 1, j, i + 1], w[:, 0])
    c11 = lerp(values[k + 1, j + 1, i], values[k + 1, j + 1, i + 1], w[:, 0])
    return lerp(lerp(c00, c10, w[:, 1]), lerp(c01, c11, w[:, 1]), w[:, 2])


def clip(origin, direction, lo, hi):
    """Entry and exit parameters (t >= 0) of each ray in the box; nan where it misses."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t_a = (lo - origin) / direction
        t_b = (hi - origin) / direction
    t_near = np.where(direction == 0, np.where((origin >= lo) & (origin <= hi), -np.inf, np.inf), np.minimum(t_a, t_b))
    t_far = np.where(direction == 0, np.where((origin >= lo) & (origin <= hi), np.inf, -np.inf), np.maximum(t_a, t_b))
    t0 = np.maximum(t_near.max(axis=1), 0.0)
    t1 = t_far.min(axis=1)
    hit = t0 <= t1
    return np.where(hit, t0, np.nan), np.where(hit, t1, np.nan)


def render(directory, H, whole_steps=False):
    d = Path(directory)
    manifest = json.loads((d / "export.json").read_text())
    tf = json.loads((d / "transfer_function.json").read_text())
    values, origin, spacing = read_nrrd(d / "field_f64.nrrd")
    rays = np.load(d / "rays.npy")  # (height, width, 2, 3)
    height, width = rays.shape[:2]
    o = rays[:, :, 0, :].reshape(-1, 3)
    u = rays[:, :, 1, :].reshape(-1, 3)
    lo, hi = np.array(manifest["box"]["min"]), np.array(manifest["box"]["max"])
    t0, t1 = clip(o, u, lo, hi)
    op = np.array(tf["opacity"])
    co = np.array(tf["color"])
    L = tf["unit_distance"]
    image = np.full(o.shape[0], float(manifest["background"]))
    for m in range(o.shape[0]):
        if np.isnan(t0[m]):
            continue
        dt = H
        if whole_steps:  # round half away from zero, as C++ std::round
            dt = (t1[m] - t0[m]) / max(1.0, math.floor((t1[m] - t0[m]) / H + 0.5))
        count = 0
        t_first = t0[m] + 0.5 * dt
        while t_first + count * dt < t1[m]:  # vrv's plan: t_k = t_first + k dt, exact count
            count += 1
        t = t_first + np.arange(count) * dt
        v = trilinear(values, origin, spacing, o[m] + t[:, None] * u[m])
        a = np.interp(v, op[:, 0], op[:, 1])
        c = np.interp(v, co[:, 0], co[:, 1])
        alpha = -np.expm1(np.log1p(-a) * (dt / L))
        transmittance = np.concatenate(([1.0], np.cumprod(1 - alpha)))
        image[m] = np.sum(transmittance[:-1] * c * alpha) + transmittance[-1] * manifest["background"]
    return image.reshape(height, width)


if __name__ == "__main__":
    args = sys.argv[1:]
    whole = args[:1] == ["--whole-steps"]
    args = args[1:] if whole else args
    if len(args) < 2:
        sys.exit(__doc__)
    for h in args[1:]:
        out = Path(args[0]) / f"image_H{h}.npy"
        np.save(out, render(args[0], float(h), whole))
        print(out)
