#!/usr/bin/python3
"""RGB rays for vrv's colour reference (lib/reference_channels.h), with an independent truth.

Writes color_rays.jsonl next to this script: a header line, then one line per ray: its class and
tag, the scene (vrv's TOML, RGB: [value, r, g, b] emission or colour points, an RGB background),
the ray's origin and direction (exact doubles, hex), and per channel the truth I_c to 34
significant digits and its double-precision floor.

The truth is the adversarial generator's mpmath integrator (../reference_adversarial/
make_adversarial.py: Debian's python3-mpmath, its own root finding and Chebyshev quadrature,
no code shared with vrv), applied to each channel on its own: channel c of an RGB scene is the
grey scene with emission (or colour) c and the shared extinction (or opacity), so
  I_c = int_0^L g_c(f(s)) e^{-Phi(s)} ds + I0_c e^{-Phi(L)},   Phi(s) = int_0^s tau(f(u)) du,
with each channel's own breaks (its control values and the extinction's).  Nothing here shares
vrv's panels or the union of the channels' breakpoints, so a crossing one channel needs and the
shared panels miss shows up as an error in that channel.  Floor per channel: the largest of the
sensitivity to the field's rounding eta (two truths with the control values shifted by -+eta) and
8 eps sum (1 + Phi) |contribution| (the generator's definitions).

Classes (each aimed at what sharing the panels could get wrong):
  channel_jumps   jumps at different values per channel over Marschner-Lobb
  extremum_jump   a jump in one channel just above or below an extremum of f along the ray
  opacity_color   the renderer's convention: one opacity, three colour curves
  thick           optical depth 30..300 with different late emission per channel
  dark_channel    a channel without emission and an RGB background
  grid            a trilinear grid of anisotropic cells
  miss            a ray that misses the box: the background colour

Usage: /usr/bin/python3 tests/lib/reference_color/make_color_truth.py [--out FILE]
(about a minute on one core).
"""
import argparse
import json
import math
import os
import random
import sys
import time

import mpmath
from mpmath import mp, mpf

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "reference_adversarial"))
import make_adversarial as adv  # noqa: E402  (the independent mpmath integrator)

SEED = 25
UNIT = ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])


def channel_tf(tf, c):
    """The grey transfer function of channel c: the c-th of r, g, b beside the shared curve."""
    key = "emission" if "emission" in tf else "color"
    out = dict(tf)
    out[key] = [[p[0], p[1 + c]] for p in tf[key]]
    return out


def points_toml(pts):
    return "[" + ", ".join("[" + ", ".join(adv.fmt(x) for x in p) + "]" for p in pts) + "]"


def scene_toml(sc):
    grey = dict(sc, background=0.0, tf={k: v for k, v in sc["tf"].items() if k in ("extinction", "opacity", "unit_length")})
    grey["tf"].update({"emission" if "emission" in sc["tf"] else "color": [[0.0, 0.0]]})
    text = adv.scene_toml(grey)
    head = text[: text.index("[transfer]")]
    out = [head + "[transfer]"]
    for key, val in sc["tf"].items():
        out.append("%s = %s" % (key, adv.fmt(val) if key == "unit_length" else points_toml(val)))
    out += ["", "[background]", "color = [%s]" % ", ".join(adv.fmt(b) for b in sc["background"]), ""]
    return "\n".join(out)


def rgb_scene(box, field, tf, background=(0.0, 0.0, 0.0)):
    return {"min": list(box[0]), "max": list(box[1]), "field": field, "tf": tf, "background": list(background)}


def make_rays():
    rng = random.Random(SEED)
    rays = []

    def add(cls, tag, sc, o, d):
        rays.append({"cls": cls, "tag": tag, "scene": sc, "origin": list(o), "direction": list(d)})

    ramp_ext = [[0.0, 0.2], [1.0, 1.4]]
    for i in range(6):
        fM = [6, 12][i % 2]
        cuts = sorted(rng.uniform(0.2, 0.8) for _ in range(3))
        emission = []
        lo = [0.1, 0.2, 0.3]
        for c, v in enumerate(cuts):  # channel c jumps at v; the others are flat there
            hi = list(lo)
            hi[c] = 2.0 + c
            emission += [[v] + lo, [v] + hi]  # only channel c jumps at v
            lo = hi  # and stays high beyond it
        tf = {"emission": emission, "extinction": ramp_ext}
        o, d = adv.chord(rng, UNIT, 1.0)
        add("channel_jumps", "jumps_fM%d_%d" % (fM, i), rgb_scene(UNIT, adv.ml(fM), tf), o, d)
    n = 0
    while n < 6:
        fM, alpha = [(6, 0.25), (12, 0.05)][n % 2]
        sc0 = rgb_scene(UNIT, adv.ml(fM, alpha), {})
        o, d = adv.chord(rng, UNIT, 1.0)
        ext = adv.interior_extremum(sc0, o, d, rng)
        if ext is None:
            continue
        s, f, kind = ext
        delta = [1e-9, 1e-6, 1e-3][n % 3] * (1 if kind == "max" else -1) * (1 if n < 3 else -1)
        c = float(f) - delta  # just inside (n < 3) or just outside the extremum's reach
        ch = n % 3
        before, after = [0.2, 0.3, 0.4], [0.2, 0.3, 0.4]
        after[ch] = 5.0
        tf = {"emission": [[c] + before, [c] + after], "extinction": [[c, 0.5], [c, 1.5]]}
        add("extremum_jump", "jump_ch%d_%s_%.0e_%d" % (ch, kind, abs(delta), n),
            rgb_scene(UNIT, adv.ml(fM, alpha), tf), o, d)
        n += 1
    for i in range(4):
        tf = {"opacity": [[0.0, 0.0], [0.4, 0.05], [0.6, 0.6], [1.0, 0.2]],
              "color": [[0.0, 1.0, 0.0, 0.2], [0.5, 0.1, 1.0, 0.3], [0.5, 0.8, 0.2, 0.9], [1.0, 0.0, 0.5, 1.0]],
              "unit_length": [0.05, 0.01][i % 2]}
        o, d = adv.chord(rng, UNIT, 1.0)
        add("opacity_color", "opacity_color_%d" % i, rgb_scene(UNIT, adv.ml(6), tf, (0.05, 0.1, 0.0)), o, d)
    for i, Phi in enumerate([30, 100, 300]):
        tf = {"emission": [[0.7, 0.0, 0.0, 0.0], [0.8, math.exp(Phi), 0.0, 1.0]],
              "extinction": [[0.6, Phi / 1.6], [0.6, 0.0]]}
        add("thick", "late_emission_phi%d" % Phi,
            rgb_scene(UNIT, {"kind": "linear_ramp", "gradient": [1.0, 0.0, 0.0], "offset": 0.0}, tf, (1.0, 0.5, 0.25)),
            [-3.0, 0.2, 0.3], [1.0, 0.0, 0.0])
    for i in range(3):
        tf = {"emission": [[0.0, 0.0, 0.0, 0.5], [0.5, 0.0, 2.0, 0.1], [1.0, 0.0, 0.3, 1.0]],
              "extinction": [[0.0, 0.1], [0.5, 2.0], [1.0, 0.4]]}
        o, d = adv.chord(rng, UNIT, 1.0)
        add("dark_channel", "dark_red_%d" % i, rgb_scene(UNIT, adv.ml(6), tf, (0.3, 0.0, 0.6)), o, d)
    box = ([-1.0, -0.5, -1.5], [1.0, 0.5, 1.5])
    for i in range(4):
        field = {"kind": "grid", "resolution": [9, 7, 5], "layout": ["node", "cell"][i % 2], "fM": 6.0, "alpha": 0.25}
        tf = {"emission": [[0.2, 0.0, 1.0, 0.2], [0.5, 1.0, 0.0, 0.2], [0.5, 1.0, 0.0, 2.0], [0.8, 0.3, 0.6, 0.0]],
              "extinction": [[0.2, 0.0], [0.6, 3.0]]}
        o, d = adv.chord(rng, box, 0.5)
        add("grid", "grid_%s_%d" % (field["layout"], i), rgb_scene(box, field, tf), o, d)
    tf = {"emission": [[0.0, 1.0, 2.0, 3.0]], "extinction": [[0.0, 1.0]]}
    add("miss", "miss", rgb_scene(UNIT, adv.ml(6), tf, (0.1, 0.2, 0.3)), [5.0, 5.0, 5.0], [1.0, 0.0, 0.0])
    return rays


def channel_truth(sc, rf, nodes, c):
    tf = adv.TF(channel_tf(sc["tf"], c))
    bg = sc["background"][c]
    if rf is None:
        return {"truth": mp.nstr(mpf(bg), 34), "floor": 0.0, "optical_depth": 0.0}
    r = adv.integrate(rf, tf, bg, extrema_cache={})
    eta = adv.field_noise(sc, rf, nodes)
    sens = mpf(0)
    for sgn in (1, -1):
        with mp.workdps(adv.SENS_DPS):
            rs = adv.integrate(rf, tf, bg, shift=mpf(sgn * eta), extrema_cache={}, rtol=mpf(10) ** -19)
        sens = max(sens, abs(rs["I"] - r["I"]))
    return {"truth": mp.nstr(r["I"], 34), "floor": float(max(sens, r["rounding"])),
            "optical_depth": float(r["phi"])}


def truth_of(ray):
    mp.dps = adv.DPS
    start = time.time()
    sc = ray["scene"]
    nodes = adv.grid_nodes(sc) if sc["field"]["kind"] == "grid" else None
    rf = adv.ray_field(sc, ray["origin"], ray["direction"], nodes)
    out = {"class": ray["cls"], "tag": ray["tag"], "scene": scene_toml(sc),
           "origin": [float(x).hex() for x in ray["origin"]],
           "direction": [float(x).hex() for x in ray["direction"]],
           "hit": rf is not None,
           "channels": [channel_truth(sc, rf, nodes, c) for c in range(3)]}
    if nodes is not None:
        out["grid_nodes"] = [v.hex() for v in nodes]
    out["seconds"] = round(time.time() - start, 2)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(HERE, "color_rays.jsonl"))
    args = ap.parse_args()
    t0 = time.time()
    results = [truth_of(r) for r in make_rays()]
    header = {"header": {"generator": "make_color_truth.py", "mpmath": mpmath.__version__, "dps": adv.DPS,
                         "seed": SEED, "rays": len(results),
                         "ray_seconds_sum": round(sum(r["seconds"] for r in results), 1)}}
    with open(args.out + ".partial", "w") as f:
        for line in [header] + results:
            f.write(json.dumps(line) + "\n")
    os.replace(args.out + ".partial", args.out)
    print("wrote %s: %d rays in %.0f s" % (args.out, len(results), time.time() - t0), file=sys.stderr)


if __name__ == "__main__":
    main()
