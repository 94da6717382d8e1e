#!/usr/bin/python3
"""Shaded rays for vrv's reference (lib/shading.h, lib/shading_weight.h), with an independent truth.

Writes shading_rays.jsonl next to this script: a header line, then one line per ray: its class and
tag, the scene (vrv's TOML with a [shading] table), the ray's origin and direction (exact doubles,
hex), the truth I to 34 significant digits and its double-precision floor.

The truth is computed here in mpmath (Debian's python3-mpmath), from the definitions:

  I = int_0^L g(f(s)) S(s) e^{-Phi(s)} ds + I0 e^{-Phi(L)},   Phi(s) = int_0^s tau(f(u)) du,
  S = ambient + diffuse max(0, n.l) + specular max(0, n.h)^p          (Blinn-Phong)
  S = ambient + diffuse max(0, n.l) + specular max(0, r.v)^p          (Phong, r = 2 (n.l) n - l)

with n = +-grad f / |grad f| (the sign from `normal`), turned to face the eye (n.v >= 0) when
two-sided, v = -direction, l the light (or v: the headlight), h = (l + v) / |l + v|; S = ambient
where the gradient vanishes.  The field along the ray, its extrema and the transfer function's
crossings are the adversarial generator's (../reference_adversarial/make_adversarial.py: f from
its formula in mp, grids as the exact cubic per cell); the gradient is computed here in mp from the
field's definition (Marschner-Lobb's formula, checked against mpmath's numerical derivative by
--check; a ramp's vector; the trilinear interpolant's partial derivatives in the cell of the piece).
Breaks: structural cuts, extrema of f along the ray (where a two-sided normal flips: n.v = 0 is
f' = 0), every crossing of a control value, and the kinks of the diffuse and specular terms (sign
changes of g.l and of g.h or r.v |g|^2, scanned at 1/16 radian of the ray's frequency bound, or 16
points per grid piece, then located by bracketed root finding).  Between breaks the piece is
integrated with 65-point Chebyshev-Lobatto panels halved until the last coefficients of tau and of
g S e^{-Phi} are below 1e-33 of the panel's scale (S evaluated with max(0, .) at every node, so a
kink that the scan missed slows convergence, never biases it); Phi at the nodes is the spectral
integral of tau's interpolant, carried from piece to piece.

Floor (what double precision can reach, for the test's "not absurd" bound): the larger of a
first-order bound on what the field's rounding eta (the generator's) can do, eta max|dg/dv, dtau/dv|
L (S_max + max g S_max L), and 8 eps sum (1 + Phi) |contribution|.

Classes:
  blinn        Marschner-Lobb, Blinn-Phong, a directional light, two-sided
  phong        Marschner-Lobb, Phong, one-sided, normal = gradient
  headlight    Marschner-Lobb with the headlight
  highlight    shininess 128: narrow highlights, a peak placed at a chosen sample of the ray
  grazing      rays that graze a face of the box
  far          an origin 1e5 away
  grid         trilinear grids (node and cell layout), directional light
  flat         a ramp without gradient (ambient alone), and Marschner-Lobb's axis, where the
               gradient vanishes at isolated points
  thick        optical depth 30..300 on a tilted ramp
  opacity      the renderer's opacity/colour convention, shaded
  miss         a ray that misses the box

Usage: /usr/bin/python3 tests/lib/reference_shading/make_shading_truth.py [--out FILE] [--check] [--jobs 2]
(the header's ray_seconds_sum is the one-core time).
"""
import argparse
import json
import math
import multiprocessing
import os
import random
import sys
import time

import mpmath
from mpmath import mp, mpf

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "reference_adversarial"))
import make_adversarial as adv  # noqa: E402  (fields along rays, transfer functions, root finding)

SEED = 31
# 30 digits: panels resolved to 1e-23 of their scale, seven orders below double precision (the
# generator's 40 digits cost this integrand, with the gradient and S at every node, minutes a ray).
DPS = 30
UNIT = ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])
EPS = 2.0 ** -52


# ------------------------------------------------------------------------------------------------
# Gradients in mp.

def grad_ml(fld, P):
    fM, al = mpf(fld["fM"]), mpf(fld["alpha"])
    x, y, z = P
    r = mp.sqrt(x * x + y * y)
    A = 2 * mp.pi * fM
    w = mp.pi * r / 2
    k = 1 / (2 * (1 + al))
    sinc = mp.sin(w) / w if w != 0 else mpf(1)
    # d/dx of al k cos(A cos(pi r / 2)) = al k A sin(A cos w) sin(w) (pi/2) x / r
    rad = al * k * A * mp.sin(A * mp.cos(w)) * (mp.pi / 2) ** 2 * sinc
    return [rad * x, rad * y, -(mp.pi / 2) * mp.cos(mp.pi * z / 2) * k]


def f_ml(fld, P):
    fM, al = mpf(fld["fM"]), mpf(fld["alpha"])
    x, y, z = P
    r = mp.sqrt(x * x + y * y)
    return (1 - mp.sin(mp.pi * z / 2) + al * (1 + mp.cos(2 * mp.pi * fM * mp.cos(mp.pi * r / 2)))) / (2 * (1 + al))


class GridGradient:
    """Partial derivatives of the trilinear interpolant, in the cell that holds a piece's middle."""

    def __init__(self, sc, nodes):
        fld = sc["field"]
        self.res = fld["resolution"]
        self.off = mpf(0) if fld["layout"] == "node" else mpf("0.5")
        self.bmin = [mpf(c) for c in sc["min"]]
        self.h = [mpf((sc["max"][a] - sc["min"][a]) / (self.res[a] - 1 if fld["layout"] == "node" else self.res[a]))
                  for a in range(3)]
        self.nodes = nodes

    def node(self, i, j, k):
        return mpf(self.nodes[(k * self.res[1] + j) * self.res[0] + i])

    def at(self, P, inside):
        i0, w, free = [], [], []
        for a in range(3):
            n = self.res[a]
            u_in = (inside[a] - self.bmin[a]) / self.h[a] - self.off
            u_p = (P[a] - self.bmin[a]) / self.h[a] - self.off
            is_free = n > 1 and 0 <= u_in <= n - 1
            if is_free:
                i = min(int(mp.floor(u_in)), n - 2)
                i0.append(i)
                w.append(u_p - i)
            else:
                i0.append(0 if (u_in < 0 or n == 1) else n - 2)
                w.append(mpf(0) if (u_in < 0 or n == 1) else mpf(1))
            free.append(is_free)

        def c(di, dj, dk):
            return self.node(min(i0[0] + di, self.res[0] - 1), min(i0[1] + dj, self.res[1] - 1),
                             min(i0[2] + dk, self.res[2] - 1))

        g = [mpf(0)] * 3
        for dj in (0, 1):
            for dk in (0, 1):
                g[0] += (c(1, dj, dk) - c(0, dj, dk)) * (w[1] if dj else 1 - w[1]) * (w[2] if dk else 1 - w[2])
        for di in (0, 1):
            for dk in (0, 1):
                g[1] += (c(di, 1, dk) - c(di, 0, dk)) * (w[0] if di else 1 - w[0]) * (w[2] if dk else 1 - w[2])
        for di in (0, 1):
            for dj in (0, 1):
                g[2] += (c(di, dj, 1) - c(di, dj, 0)) * (w[0] if di else 1 - w[0]) * (w[1] if dj else 1 - w[1])
        return [g[a] / self.h[a] if free[a] else mpf(0) for a in range(3)]


def gradient_along(sc, rf, nodes):
    """grad(s, piece_mid): the gradient at rf's point s, of the piece holding piece_mid."""
    fld = sc["field"]
    point = lambda s: [rf.E[a] + s * rf.d[a] for a in range(3)]
    if fld["kind"] == "marschner_lobb":
        return lambda s, m: grad_ml(fld, point(s))
    if fld["kind"] == "linear_ramp":
        g = [mpf(c) for c in fld["gradient"]]
        return lambda s, m: g
    gg = GridGradient(sc, nodes)
    return lambda s, m: gg.at(point(s), point(m))


# ------------------------------------------------------------------------------------------------
# The shading factor.

def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def unit(a):
    n = mp.sqrt(dot(a, a))
    return [x / n for x in a]


class Shade:
    def __init__(self, spec, d):
        self.s = spec
        self.v = [-c for c in d]
        headlit = spec.get("light", "headlight") == "headlight"
        self.l = self.v if headlit else unit([mpf(c) for c in spec["light"]])
        hv = [a + b for a, b in zip(self.l, self.v)]
        self.h = unit(hv) if dot(hv, hv) > 0 else [mpf(0)] * 3
        self.sign = mpf(1) if spec.get("normal", "negative_gradient") == "gradient" else mpf(-1)
        self.phong = spec.get("model", "blinn_phong") == "phong"
        self.two_sided = spec.get("two_sided", True)
        self.ka, self.kd, self.ks = (mpf(spec.get(k, dflt)) for k, dflt in
                                     (("ambient", 0.2), ("diffuse", 0.7), ("specular", 0.1)))
        self.p = mpf(spec.get("shininess", 16))

    def flip(self, g):
        """-1 where a two-sided normal turns (n.v < 0), else 1: decided once per piece."""
        n = [self.sign * c for c in g]
        return -1 if self.two_sided and dot(n, self.v) < 0 else 1

    def value(self, g, flip):
        norm = mp.sqrt(dot(g, g))
        if norm == 0:
            return self.ka
        n = [flip * self.sign * c / norm for c in g]
        nl = dot(n, self.l)
        if self.phong:
            base = 2 * nl * dot(n, self.v) - dot(self.l, self.v)
        else:
            base = dot(n, self.h)
        return self.ka + self.kd * max(mpf(0), nl) + self.ks * max(mpf(0), base) ** self.p

    def kink_functions(self):
        out = []
        if self.kd > 0:
            out.append(lambda g: dot(g, self.l))
        if self.ks > 0:
            if self.phong:
                out.append(lambda g: 2 * dot(g, self.l) * dot(g, self.v) - dot(self.l, self.v) * dot(g, g))
            else:
                out.append(lambda g: dot(g, self.h))
        return out


def kinks(rf, shade, grad, a, b):
    """Sign changes of the kink functions on [a, b], located to the working precision."""
    if rf.kind == "ml":
        n = max(16, int(mp.ceil((b - a) * rf.omega * 16)))
    else:
        n = 16
    m = (a + b) / 2
    xs = [a + (b - a) * i / n for i in range(n + 1)]
    out = []
    for q in shade.kink_functions():
        fun = lambda s: q(grad(s, m))
        vals = [fun(x) for x in xs]
        for i in range(n):
            if vals[i] == 0 and 0 < i:
                out.append(xs[i])
            elif vals[i] * vals[i + 1] < 0:
                out.append(adv.bracket_root(fun, xs[i], xs[i + 1], vals[i], vals[i + 1]))
    return [s for s in out if a < s < b]


# ------------------------------------------------------------------------------------------------
# The integral.

def integrate(rf, tf, background, shade, grad, shift=mpf(0), cache=None):
    cache = {} if cache is None else cache
    rtol = mpf(10) ** (-mp.dps + 7)
    levels = [c - shift for c in tf.levels]
    key = ("cuts", shift)
    if key not in cache:
        cuts = set(adv.breaks_of(rf, levels, cache.setdefault("extrema", {})))
        for a, b in rf.pieces():
            cuts.update(kinks(rf, shade, grad, a, b))
        cache[key] = sorted(cuts)
    cuts = cache[key]
    pieces = rf.pieces()
    gmax = tf.max_g() * (shade.ka + shade.kd + shade.ks)
    I0 = mpf(background)
    tiny = mpf(10) ** (-mp.dps + 2)
    fsize = max(abs(rf.f(mpf(0))), abs(rf.f(rf.L)), mpf(1))
    floor_tau = tiny * (max(tf.tau_scale(), mpf(1)) + tf.max_slope() * fsize)
    floor_h = tiny * (max(gmax, mpf(1)) * mpf(10) ** -10 + tf.max_slope() * fsize)
    state = {"phi": mpf(0), "I": mpf(0), "rounding": mpf(0), "unresolved": 0}

    def structural_mid(s):
        for a, b in pieces:
            if a <= s <= b:
                return (a + b) / 2
        return s

    def panel(a, b, g, tau, flip, sm, piece, depth):
        phase = rf.omega * (b - a) if rf.kind == "ml" else 0
        N = 33 if phase < 1 else 65
        x, Ctail, Q = adv.cheb(mp.dps, N)
        half, mid = (b - a) / 2, (a + b) / 2
        ss = [mid + half * xk for xk in x]
        v = [rf.f(s) + shift for s in ss]
        tv = [tau(u) for u in v]
        # S at a node on the piece's end is its limit from inside the piece: where the piece ends at
        # a zero of the gradient, or on a kink, the end itself may round to the other side.  The
        # nudge (1e-27 of the piece) stays far below the panels' 1e-23 resolution.
        lo, hi = piece[0] + piece[2], piece[1] - piece[2]
        sv = [shade.value(grad(min(max(s, lo), hi), sm), flip) for s in ss]
        gv = [g(u) * w for u, w in zip(v, sv)]
        tmax = max(abs(t) for t in tv)
        ttail = max(abs(mp.fdot(row, tv)) for row in Ctail)
        phi0 = state["phi"]
        phis = [phi0 + half * mp.fdot(Q[k], tv) for k in range(N)]
        hv = [gv[k] * mp.exp(-phis[k]) for k in range(N)]
        hmax = max(abs(h) for h in hv)
        htail = max(abs(mp.fdot(row, hv)) for row in Ctail)
        ok = ttail <= rtol * tmax + floor_tau and htail <= rtol * hmax + floor_h
        if not ok and depth < 60 and b - a > mpf(10) ** (-mp.dps + 12) * rf.L:
            panel(a, mid, g, tau, flip, sm, piece, depth + 1)
            panel(mid, b, g, tau, flip, sm, piece, depth + 1)
            return
        state["unresolved"] += not ok
        e = half * mp.fdot(Q[-1], hv)
        state["I"] += e
        state["phi"] = phi0 + half * mp.fdot(Q[-1], tv)
        state["rounding"] += (1 + phi0) * abs(e)

    for a, b in zip(cuts, cuts[1:]):
        if not b > a:
            continue
        m = (a + b) / 2
        g, tau = tf.branch(rf.f(m) + shift)
        sm = structural_mid(m)
        flip = shade.flip(grad(m, sm))
        h0 = rf.panel_length()
        n = max(1, int(mp.ceil((b - a) / h0)))
        for i in range(n):
            panel(a + (b - a) * i / n, a + (b - a) * (i + 1) / n, g, tau, flip, sm, (a, b, (b - a) * mpf(10) ** -27), 0)
        if mp.exp(-state["phi"]) * (gmax * (rf.L - b) + I0) < mpf(10) ** -45:
            break
    bg = I0 * mp.exp(-state["phi"])
    total = state["I"] + bg
    return {"I": total, "phi": state["phi"], "unresolved": state["unresolved"],
            "rounding": 8 * EPS * (state["rounding"] + (1 + state["phi"]) * bg), "cuts": len(cuts)}


# ------------------------------------------------------------------------------------------------
# Scenes and rays.

def shading_toml(spec):
    out = ["", "[shading]"]
    for k, v in spec.items():
        if isinstance(v, bool):
            out.append("%s = %s" % (k, "true" if v else "false"))
        elif isinstance(v, str):
            out.append('%s = "%s"' % (k, v))
        elif isinstance(v, list):
            out.append("%s = [%s]" % (k, ", ".join(adv.fmt(c) for c in v)))
        else:
            out.append("%s = %s" % (k, adv.fmt(v)))
    return "\n".join(out) + "\n"


def make_rays():
    rng = random.Random(SEED)
    rays = []
    tf_ml = {"emission": [[0.0, 0.0], [0.3, 0.2], [0.6, 1.5], [1.0, 0.4]],
             "extinction": [[0.0, 0.0], [0.5, 1.2], [1.0, 0.6]]}

    def add(cls, tag, sc, spec, o, d):
        rays.append({"cls": cls, "tag": tag, "scene": sc, "shading": spec,
                     "origin": [float(c) for c in o], "direction": [float(c) for c in d]})

    def light():
        return [round(c, 6) for c in adv.random_dir(rng)]

    for i in range(6):
        o, d = adv.chord(rng, UNIT, 1.0)
        spec = {"model": "blinn_phong", "ambient": 0.15, "diffuse": 0.6, "specular": 0.25,
                "shininess": [8.0, 20.0, 3.5][i % 3], "light": light(), "two_sided": True}
        add("blinn", "blinn_%d" % i, adv.scene(UNIT, adv.ml([6, 3][i % 2]), tf_ml), spec, o, d)
    for i in range(4):
        o, d = adv.chord(rng, UNIT, 1.0)
        spec = {"model": "phong", "ambient": 0.1, "diffuse": 0.5, "specular": 0.4, "shininess": 12.0,
                "light": light(), "normal": "gradient", "two_sided": False}
        add("phong", "phong_%d" % i, adv.scene(UNIT, adv.ml(6), tf_ml), spec, o, d)
    for i in range(3):
        o, d = adv.chord(rng, UNIT, 1.0)
        spec = {"model": ["blinn_phong", "phong"][i % 2], "light": "headlight"}
        add("headlight", "headlight_%d" % i, adv.scene(UNIT, adv.ml(6), tf_ml), spec, o, d)
    # A highlight peak at a chosen point of the ray: the light is the mirror of the view about the
    # normal there, so n.h = 1 (Blinn-Phong) at that point.
    for i in range(3):
        o, d = adv.chord(rng, UNIT, 1.2)
        sc = adv.scene(UNIT, adv.ml(3), tf_ml)
        rf = adv.ray_field(sc, o, d)
        s = rf.L * mpf([0.3, 0.5, 0.71][i])
        P = [rf.E[a] + s * rf.d[a] for a in range(3)]
        n = unit([-c for c in grad_ml(sc["field"], P)])
        v = [-c for c in rf.d]
        if dot(n, v) < 0:
            n = [-c for c in n]
        l = [2 * dot(n, v) * nc - vc for nc, vc in zip(n, v)]  # reflect v about n: h = n there
        spec = {"model": "blinn_phong", "ambient": 0.05, "diffuse": 0.3, "specular": 1.0, "shininess": 128.0,
                "light": [float(c) for c in l], "two_sided": True}
        add("highlight", "highlight_%d" % i, sc, spec, o, d)
    # Grazing: nearly parallel to the face x = 1, inside it by 1e-3 .. 1e-9.
    for i, inset in enumerate([1e-3, 1e-6, 1e-9]):
        o = [1.0 - inset, -3.0, 0.1 * i]
        d = [1e-12 * i, 1.0, 0.05]
        spec = {"light": light()}
        add("grazing", "grazing_%.0e" % inset, adv.scene(UNIT, adv.ml(6), tf_ml), spec, o, d)
    o = [1e5, 3.0e4, -2.0e4]
    target = [0.1, -0.2, 0.3]
    d = [t - c for t, c in zip(target, o)]
    add("far", "far_1e5", adv.scene(UNIT, adv.ml(6), tf_ml), {"light": [0.0, 0.6, 0.8]}, o, d)
    box = ([-1.0, -0.5, -1.5], [1.0, 0.5, 1.5])
    tf_grid = {"emission": [[0.2, 0.0], [0.5, 1.0], [0.5, 1.8], [0.8, 0.3]], "extinction": [[0.2, 0.0], [0.6, 3.0]]}
    for i in range(4):
        field = {"kind": "grid", "resolution": [9, 7, 5], "layout": ["node", "cell"][i % 2], "fM": 6.0, "alpha": 0.25}
        o, d = adv.chord(rng, box, 0.5)
        spec = {"model": ["blinn_phong", "phong"][i // 2], "light": light(), "specular": 0.3, "shininess": 10.0}
        add("grid", "grid_%s_%d" % (field["layout"], i), adv.scene(box, field, tf_grid), spec, o, d)
    # Flat: a ramp with no gradient (S = ambient everywhere); the axis of Marschner-Lobb in a tall
    # box, where the gradient is (0, 0, -(pi/4) cos(pi z / 2) / (1 + alpha)) and vanishes at every
    # odd z: a one-sided normal turns there (S jumps), a two-sided headlit one does not.
    add("flat", "zero_ramp", adv.scene(UNIT, {"kind": "linear_ramp", "gradient": [0.0, 0.0, 0.0], "offset": 0.5}, tf_ml),
        {"ambient": 0.3, "light": [0.0, 0.0, 1.0]}, [-3.0, 0.1, 0.2], [1.0, 0.05, 0.02])
    tall = ([-1.0, -1.0, -6.0], [1.0, 1.0, 6.0])
    add("flat", "axis_one_sided", adv.scene(tall, adv.ml(6), tf_ml),
        {"light": [0.3, 0.0, 0.95], "two_sided": False}, [0.0, 0.0, -7.0], [0.0, 0.0, 1.0])
    add("flat", "axis_headlight", adv.scene(tall, adv.ml(6), tf_ml),
        {"light": "headlight", "model": "phong"}, [0.0, 0.0, -7.0], [0.0, 0.0, 1.0])
    for Phi in (30, 300):
        tf = {"emission": [[0.0, 0.0], [1.0, 2.0]], "extinction": [[0.0, Phi / 2.0], [1.0, Phi / 2.0]]}
        add("thick", "ramp_phi%d" % Phi,
            adv.scene(UNIT, {"kind": "linear_ramp", "gradient": [0.3, 0.2, -0.1], "offset": 0.5}, tf),
            {"light": [0.2, 0.5, 0.8]}, [-3.0, 0.1, 0.2], [1.0, 0.05, 0.02])
    for i in range(2):
        tf = {"opacity": [[0.0, 0.0], [0.4, 0.05], [0.6, 0.6], [1.0, 0.2]],
              "color": [[0.0, 1.0], [0.5, 0.1], [0.5, 0.8], [1.0, 0.0]], "unit_length": 0.05}
        o, d = adv.chord(rng, UNIT, 1.0)
        add("opacity", "opacity_%d" % i, adv.scene(UNIT, adv.ml(6), tf), {"light": light()}, o, d)
    add("miss", "miss", adv.scene(UNIT, adv.ml(6), tf_ml, 0.25), {"light": [0.0, 0.0, 1.0]}, [5.0, 5.0, 5.0], [1.0, 0.0, 0.0])
    return rays


def truth_of(ray):
    mp.dps = DPS
    start = time.time()
    sc = ray["scene"]
    nodes = adv.grid_nodes(sc) if sc["field"]["kind"] == "grid" else None
    rf = adv.ray_field(sc, ray["origin"], ray["direction"], nodes)
    out = {"class": ray["cls"], "tag": ray["tag"], "scene": adv.scene_toml(sc) + shading_toml(ray["shading"]),
           "origin": [float(x).hex() for x in ray["origin"]],
           "direction": [float(x).hex() for x in ray["direction"]], "hit": rf is not None}
    if rf is None:
        out.update(truth=mp.nstr(mpf(sc.get("background", 0.0)), 34), floor=0.0, optical_depth=0.0)
    else:
        tf = adv.TF(sc["tf"])
        shade = Shade(ray["shading"], rf.d)
        grad = gradient_along(sc, rf, nodes)
        r = integrate(rf, tf, sc.get("background", 0.0), shade, grad)
        # A field wrong by eta changes g by |dg/dv| eta (times S <= S_max) and tau by |dtau/dv| eta,
        # which reaches at most max g S_max L of light behind: a first-order bound on the floor.
        eta = mpf(adv.field_noise(sc, rf, nodes))
        smax = shade.ka + shade.kd + shade.ks
        sens = eta * tf.max_slope() * rf.L * (smax + tf.max_g() * smax * rf.L)
        out.update(truth=mp.nstr(r["I"], 34), floor=float(max(sens, r["rounding"])), optical_depth=float(r["phi"]),
                   breaks=r["cuts"], unresolved=r["unresolved"])
    if nodes is not None:
        out["grid_nodes"] = [v.hex() for v in nodes]
    out["seconds"] = round(time.time() - start, 2)
    return out


def check():
    """Marschner-Lobb's gradient against mpmath's numerical derivative of its formula."""
    mp.dps = 30
    fld = {"fM": 6.0, "alpha": 0.25}
    for P in ([mpf("0.3"), mpf("-0.2"), mpf("0.7")], [mpf(0), mpf(0), mpf("0.1")], [mpf("1e-7"), mpf("2e-7"), mpf(-1)]):
        g = grad_ml(fld, P)
        for a in range(3):
            def f1(t, a=a):
                Q = list(P)
                Q[a] = t
                return f_ml(fld, Q)
            num = mp.diff(f1, P[a])
            assert abs(num - g[a]) < mpf(10) ** -20, (P, a, num, g[a])
    print("check: Marschner-Lobb's gradient matches mp.diff at 3 points", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(HERE, "shading_rays.jsonl"))
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    if args.check:
        check()
    t0 = time.time()
    with multiprocessing.Pool(args.jobs) as pool:
        results = []
        for r in pool.imap(truth_of, make_rays()):
            results.append(r)
            print("%-24s %6.1f s" % (r["tag"], r["seconds"]), file=sys.stderr)
    header = {"header": {"generator": "make_shading_truth.py", "mpmath": mpmath.__version__, "dps": DPS,
                         "seed": SEED, "rays": len(results),
                         "unresolved_panels": sum(r.get("unresolved", 0) for r in results),
                         "ray_seconds_sum": round(sum(r["seconds"] for r in results), 1)}}
    with open(args.out + ".partial", "w") as f:
        for line in [header] + results:
            f.write(json.dumps(line) + "\n")
    os.replace(args.out + ".partial", args.out)
    print("wrote %s: %d rays in %.0f s" % (args.out, len(results), time.time() - t0), file=sys.stderr)


if __name__ == "__main__":
    main()
