#!/usr/bin/env python3
"""Draws a study's plots from its CSV tables, as its plots.json describes them.

    python3 studies/engine/plot_study.py DIR          # DIR = OUT/NAME, written by `vrv study`

`vrv study` runs this after writing the tables (Debian's /usr/bin/python3 with python3-matplotlib,
or $VRV_PYTHON).  Each entry of plots.json's "plots" list becomes DIR/<name>.png and DIR/<name>.pdf,
written to a temporary file first and renamed, so an interruption never leaves half a plot.

An entry:
  name      output file stem (required)
  csv       the table to read, relative to DIR (required)
  style     "lines" (one line per group, markers), "points" (scatter), "heatmap" (x, y, z on a
            grid: a colour map with a colour bar) -- default "lines"
  x, y      column names (required); z for heatmaps
  group     a column whose values make one series each (optional)
  where     {"column": "value", ...}: keep only rows whose text matches (optional)
  xscale, yscale   "linear" (default) or "log" (points at or below zero are left out)
  fit       true: least-squares slope of log y against log x per series, shown in the legend
  front     true: draw the Pareto front (the points no other point beats in both x and y)
  diagonal  true: draw the line y = x (a prediction against what it predicts)
  hlines    [numbers]: dashed horizontal reference lines (e.g. error targets)
  xlabel, ylabel, zlabel, title   text
  reference {"column": ..., "value": ...}: the series whose group equals value is drawn as a
            thick black line (e.g. the continuous solution among discrete curves)

Exit status: 0 when every plot was drawn; 1 with a one-line message naming the file and key for
a bad plots.json or a missing column; 2 when matplotlib is missing.
"""
import csv
import json
import math
import os
import sys


def fail(msg, code=1):
    print(f"plot_study: {msg}", file=sys.stderr)
    sys.exit(code)


def read_rows(path, where):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: cannot read: {e.strerror}")
    for key, value in (where or {}).items():
        rows = [r for r in rows if r.get(key) == str(value)]
    return rows


def number(row, column, where):
    text = row.get(column)
    if text is None:
        fail(f"{where}: no column '{column}'")
    try:
        return float(text) if text != "" else math.nan
    except ValueError:
        fail(f"{where}: column '{column}' has non-numeric value '{text}'")


def series(rows, spec, where):
    group = spec.get("group")
    out = {}
    for r in rows:
        key = r.get(group, "") if group else ""
        if group and group not in r:
            fail(f"{where}: no column '{group}'")
        x, y = number(r, spec["x"], where), number(r, spec["y"], where)
        # A log axis has no place for zero or below: such points are left out, not warned about.
        if spec.get("xscale") == "log" and not x > 0 or spec.get("yscale") == "log" and not y > 0:
            continue
        if math.isfinite(x) and math.isfinite(y):
            out.setdefault(key, []).append((x, y))
    return out


def log_slope(points):
    pts = [(math.log(x), math.log(y)) for x, y in points if x > 0 and y > 0]
    if len(pts) < 2:
        return math.nan
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    if sxx == 0:
        return math.nan
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def pareto(points):
    front, best = [], math.inf
    for x, y in sorted(points):
        if y < best:
            front.append((x, y))
            best = y
    return front


def heatmap(ax, fig, rows, spec, where):
    xs = sorted({number(r, spec["x"], where) for r in rows})
    ys = sorted({number(r, spec["y"], where) for r in rows})
    if not xs or not ys:
        fail(f"{where}: no rows to plot")
    ix = {v: i for i, v in enumerate(xs)}
    iy = {v: i for i, v in enumerate(ys)}
    grid = [[math.nan] * len(xs) for _ in ys]
    for r in rows:
        grid[iy[number(r, spec["y"], where)]][ix[number(r, spec["x"], where)]] = number(r, spec["z"], where)
    im = ax.imshow(grid, origin="lower", aspect="auto", cmap=spec.get("cmap", "viridis"),
                   extent=[xs[0], xs[-1], ys[0], ys[-1]])
    bar = fig.colorbar(im, ax=ax)
    bar.set_label(spec.get("zlabel", spec["z"]))


def draw(fig, ax, rows, spec, where):
    style = spec.get("style", "lines")
    if style == "heatmap":
        if "z" not in spec:
            fail(f"{where}: heatmap needs 'z'")
        heatmap(ax, fig, rows, spec, where)
        return
    if style not in ("lines", "points"):
        fail(f"{where}: style: unknown '{style}' (lines, points, heatmap)")
    data = series(rows, spec, where)
    if not data:
        fail(f"{where}: no rows to plot")
    ref = spec.get("reference", {})
    everything = []
    for key, pts in data.items():
        pts.sort()
        everything += pts
        label = key or spec["y"]
        if spec.get("fit"):
            label += f" (slope {log_slope(pts):.2f})"
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        if ref and key == str(ref.get("value")):
            ax.plot(xs, ys, "k-", lw=2.2, label=label, zorder=5)
        elif style == "lines":
            ax.plot(xs, ys, marker="o" if len(pts) <= 40 else None, ms=3, lw=1.2, label=label)
        else:
            many = len(pts) > 200
            ax.plot(xs, ys, ls="none", marker="o", ms=1.5 if many else 4, alpha=0.4 if many else 1, label=label)
    if spec.get("front"):
        f = pareto(everything)
        ax.step([p[0] for p in f], [p[1] for p in f], "k--", where="post", lw=1, label="Pareto front")
    if spec.get("diagonal"):
        positive = [v for p in everything for v in p if v > 0]
        if positive:
            lo, hi = min(positive), max(positive)
            ax.plot([lo, hi], [lo, hi], "k--", lw=1, label="y = x")
    for h in spec.get("hlines", []):
        ax.axhline(h, color="grey", ls=":", lw=1)
    if len(data) > 1 or spec.get("fit") or spec.get("front"):
        ax.legend(fontsize=7)


def main():
    if len(sys.argv) != 2:
        fail("usage: plot_study.py DIR")
    out = sys.argv[1]
    spec_path = os.path.join(out, "plots.json")
    try:
        with open(spec_path) as f:
            plots = json.load(f)["plots"]
    except (OSError, ValueError, KeyError) as e:
        fail(f"{spec_path}: plots: cannot read ({e})")
    # The figure and its Agg canvas directly: pyplot's import (its backend machinery, a third of
    # the script's cost, which every `vrv verify --out` pays) draws nothing these files need.
    try:
        import matplotlib
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError:
        fail("matplotlib is missing (Debian: apt-get install python3-matplotlib)", 2)
    # Reproducible files: no creation date in the PDF, fixed hash salt in the SVG backend.
    matplotlib.rcParams["svg.hashsalt"] = "vrv"
    for i, spec in enumerate(plots):
        where = f"{spec_path}: plots[{i}]"
        for key in ("name", "csv", "x", "y"):
            if key not in spec:
                fail(f"{where}.{key}: missing")
        rows = read_rows(os.path.join(out, spec["csv"]), spec.get("where"))
        fig = Figure(figsize=(6, 4.2))
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
        draw(fig, ax, rows, spec, where)
        ax.set_xscale(spec.get("xscale", "linear"))
        ax.set_yscale(spec.get("yscale", "linear"))
        ax.set_xlabel(spec.get("xlabel", spec["x"]))
        ax.set_ylabel(spec.get("ylabel", spec["y"]))
        if "title" in spec:
            ax.set_title(spec["title"], fontsize=10)
        ax.grid(True, which="both", alpha=0.25)
        fig.tight_layout()
        for ext in ("png", "pdf"):
            target = os.path.join(out, f"{spec['name']}.{ext}")
            tmp = f"{target}.tmp.{os.getpid()}.{ext}"
            meta = {"CreationDate": None} if ext == "pdf" else {"Software": None}
            fig.savefig(tmp, dpi=150, metadata=meta)
            os.replace(tmp, target)


if __name__ == "__main__":
    main()
