#!/usr/bin/env python3
"""Recompute `vrv verify`'s whole-image figures in numpy, independently, and compare them.

    /usr/bin/python3 vtk_figures.py REF.f64.tiff VERIFY_OUT_DIR OUT_PREFIX IMAGE... --steps H1,H2,...
        -> OUT_PREFIX.md, OUT_PREFIX.csv, OUT_PREFIX.json; exit 1 if a figure differs by more than 1 %

REF.f64.tiff is `vrv render --reference` at the images' size (double, row 0 at the top); the
images are read with OpenImageIO (8-bit PNGs become v / 255). Per image, over all pixels, of
e = image - reference: max |e|, mean |e|, RMS, the 99th percentile of |e| (nearest rank:
the ceil(0.99 n)-th smallest). Across images: the least-squares slope of log(RMS) against log(h)
(np.polyfit), and the self-convergence order (Etiene et al.) from d_k = RMS(image_k - image_k+1)
alone: slope of log d_k against log h_k, then log d_k - log(1 - (h_k+1/h_k)^p) refitted until p
settles. These are compared with VERIFY_OUT_DIR/errors.json (region "all") and orders.json.
"""
import json
import math
import sys
from pathlib import Path

import numpy as np
import OpenImageIO as oiio


def read(path, fmt):
    image = oiio.ImageInput.open(str(path))
    if image is None:
        sys.exit(f"vtk_figures.py: {path}: {oiio.geterror()}")
    pixels = image.read_image(fmt)
    image.close()
    return pixels[..., 0].astype(np.float64)


def stats(e):
    a = np.sort(np.abs(e).ravel())
    return {"max": a[-1], "mean": a.mean(), "rms": math.sqrt(np.mean(e * e)),
            "p99": a[math.ceil(0.99 * a.size) - 1]}


def slope(h, y):
    return np.polyfit(np.log(h), np.log(y), 1)[0]


def self_order(h, d):
    r = np.array(h[1:]) / np.array(h[:-1])
    p = slope(h[:-1], d)
    for _ in range(50):
        q = np.polyfit(np.log(h[:-1]), np.log(d) - np.log1p(-r ** p), 1)[0]
        if abs(q - p) <= 1e-12 * max(1.0, abs(p)):
            return q
        p = q
    return p


def main(argv):
    if "--steps" not in argv or len(argv) < 6:
        sys.exit(__doc__)
    i = argv.index("--steps")
    steps = [float(s) for s in argv[i + 1].split(",")]
    del argv[i:i + 2]
    ref_path, verify_dir, prefix, images = Path(argv[0]), Path(argv[1]), Path(argv[2]), argv[3:]
    if len(images) != len(steps):
        sys.exit("vtk_figures.py: --steps: one step per image")
    order = np.argsort(steps)[::-1]  # coarsest first
    steps = [steps[k] for k in order]
    images = [images[k] for k in order]
    ref = read(ref_path, "double")
    pictures = [read(p, "float") for p in images]
    ours = [stats(p - ref) for p in pictures]
    ours_orders = {
        "reference": slope(steps, [s["rms"] for s in ours]),
        "self": self_order(steps, [math.sqrt(np.mean((a - b) ** 2)) for a, b in zip(pictures, pictures[1:])]),
    }

    vrv_errors = json.loads((verify_dir / "errors.json").read_text())
    vrv_orders = {o["kind"]: o["order"] for o in json.loads((verify_dir / "orders.json").read_text())}
    rows, worst = [], 0.0
    for h, name, s in zip(steps, images, ours):
        theirs = next(r for r in vrv_errors if r["step"] == h and r["region"] == "all")
        for key in ("max", "mean", "rms", "p99"):
            rel = abs(theirs[key] - s[key]) / abs(s[key])
            worst = max(worst, rel)
            rows.append({"figure": key, "step": h, "image": Path(name).name, "vrv": theirs[key],
                         "numpy": s[key], "relative_difference": rel})
    for kind, p in ours_orders.items():
        rel = abs(vrv_orders[kind] - p) / abs(p)
        worst = max(worst, rel)
        rows.append({"figure": f"order ({kind}, rms)", "step": "all", "image": "", "vrv": vrv_orders[kind],
                     "numpy": p, "relative_difference": rel})

    lines = ["| figure | step | image | vrv verify | numpy | relative difference |",
             "| :-- | --: | :-- | --: | --: | --: |"]
    lines += [f"| {r['figure']} | {r['step']} | {r['image']} | {r['vrv']:.6g} | {r['numpy']:.6g} | "
              f"{r['relative_difference']:.1e} |" for r in rows]
    lines.append(f"\nLargest relative difference: {worst:.1e} (limit 1e-2).")
    # Not independent: the slopes of vrv's own per-region RMS (errors.json), where the error sits.
    lines.append("\nOrder of vrv's per-region RMS (slope of log RMS against log h, numpy on errors.json):")
    for region in ("silhouette", "interior"):
        rms = [next(r for r in vrv_errors if r["step"] == h and r["region"] == region)["rms"] for h in steps]
        local = [math.log(a / b) / math.log(g / k) for a, b, g, k in zip(rms, rms[1:], steps, steps[1:])]
        lines.append(f"- {region}: RMS {rms[0]:.3g} at h = {steps[0]:g} to {rms[-1]:.3g} at h = {steps[-1]:g}, "
                     f"order {slope(steps, rms):.3f}, local orders " + ", ".join(f"{q:.2f}" for q in local))
    # Where the finest image's error sits, and the orientation check (a flip makes it far worse).
    fine, e = pictures[-1], pictures[-1] - ref
    rms = lambda a: math.sqrt(np.mean((a - ref) ** 2))
    lines.append(f"\nFinest image (h = {steps[-1]:g}): RMS {rms(fine):.3g} as read, {rms(fine[::-1]):.3g} with rows "
                 f"flipped, {rms(fine[:, ::-1]):.3g} with columns flipped.")
    rows_over, counts = np.unique(np.argwhere(np.abs(e) > 0.03)[:, 0], return_counts=True)
    busiest = np.argsort(counts)[::-1][:3]
    lines.append(f"Pixels with |e| > 0.03: {int(counts.sum())}; busiest rows (y: count): "
                 + ", ".join(f"{rows_over[k]}: {counts[k]}" for k in busiest))
    largest = np.argsort(np.abs(e).ravel())[::-1][:5]
    lines.append("Largest |e| (x, y: image / reference): " + "; ".join(
        f"{k % e.shape[1]}, {k // e.shape[1]}: {fine.flat[k]:.3f} / {ref.flat[k]:.3f}" for k in largest))
    prefix.with_suffix(".md").write_text("\n".join(lines) + "\n")
    csv = ["figure,step,image,vrv,numpy,relative_difference"]
    csv += [f"{r['figure']},{r['step']},{r['image']},{r['vrv']!r},{r['numpy']!r},{r['relative_difference']!r}"
            for r in rows]
    prefix.with_suffix(".csv").write_text("\n".join(csv) + "\n")
    prefix.with_suffix(".json").write_text(json.dumps({"rows": rows, "largest_relative_difference": worst},
                                                      indent=1, default=float) + "\n")
    print("\n".join(lines))
    return 0 if worst <= 1e-2 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
