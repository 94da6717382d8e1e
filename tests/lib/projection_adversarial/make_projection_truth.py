#!/usr/bin/python3
"""Adversarial rays for vrv's projection references (X-ray and MIP), with an independent truth.

Writes projection_truth.jsonl next to this script: a header line, then one line per ray: its class
and tag, the field (Marschner-Lobb parameters, a linear ramp, or a grid with its node values given
explicitly as hex doubles), the box, the transfer function's extinction curve (classified modes),
the ray (hex doubles), and the truths to 30 significant digits:

  xray             int_0^L f(s) ds
  xray_classified  int_0^L tau(f(s)) ds
  mip              max f(s) over [0, L], mip_position the first t (from the ray origin, along the
                   unit direction) where it is reached, mip_curvature |f''| there (0 at an end
                   or a kink: the position is then fixed to first order), mip_second the value of
                   the best maximum separated from the first by a dip (for the tie classes)
  mip_classified   sup tau(f(s)) over [0, L]

None of it uses vrv code (lib/, analytic/): everything is computed here in mpmath from the
definitions, with its own clipping, field evaluation, root finding and quadrature:
- the ray: origin + t direction with the direction normalised in mp, clipped to the closed box by
  the slab test (a zero direction component tests the origin, faces included); s = t - t_entry;
- f along the chord: Marschner-Lobb from its formula, with analytic f' and f''; a linear ramp; or
  the trilinear interpolant of the node values, a cubic in s on every cell (node planes are breaks),
  or for nearest interpolation a constant between the half-way planes;
- extrema: Marschner-Lobb f' and f'' scanned at a quarter radian of the ray's frequency bound,
  inflection points then extrema located by bracketed Illinois/bisection root finding (so a close
  pair is not lost); grid cells: the roots of the quadratic f' in closed form; ramps: none;
- the maximum: the largest f over the chord's ends, the breaks and the extrema, the first within
  1e-25 of it (ties and plateaus: the first);
- X-ray: mp.quad (tanh-sinh) on every piece between breaks, extrema and (classified) crossings of
  the transfer function's control values, pieces no longer than a radian of the frequency bound;
  polynomial pieces (ramps, cells) integrated in closed form from their coefficients;
- classified maximum: tau is piecewise linear in v, so its supremum over a piece is at the ends of
  the piece's value range or at a control value inside it (both sides of a jump).

Floors (what double precision can reach): eta, the field's own rounding in double on the chord
(as make_adversarial.py states it), times the chord length (X-ray) or alone (MIP), times tau's
largest slope for the classified modes; for those also their sensitivity, the largest change of the
classified truth when the field moves by -+eta (recomputed at 20 digits): a field at a jump's level
moves it by the jump.

Usage: /usr/bin/python3 tests/lib/projection_adversarial/make_projection_truth.py [--out FILE]
About a minute on one core.
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

DPS = 34
EPS = 2.0 ** -52
SEED = 26


def hexd(x):
    return float(x).hex()


# ------------------------------------------------------------------------------------------------
# The transfer function's extinction: piecewise linear, constant beyond the ends, a repeated value
# a jump, right-continuous.

class Curve:
    def __init__(self, pts):
        self.pts = [(mpf(v), mpf(y)) for v, y in pts]

    def __call__(self, v):
        p = self.pts
        i = 0
        while i < len(p) and p[i][0] <= v:
            i += 1
        if i == 0:
            return p[0][1]
        if i == len(p):
            return p[-1][1]
        (a, ya), (b, yb) = p[i - 1], p[i]
        return max(mpf(0), ya + (yb - ya) * (v - a) / (b - a))

    def levels(self):
        return sorted(set(v for v, _ in self.pts))

    def sup(self, lo, hi):
        """sup over values in [lo, hi] (every value in between reached)."""
        y = max(self(lo), self(hi))
        for v, yy in self.pts:
            if lo < v <= hi:
                y = max(y, yy)
        return y

    def shifted(self, shift):
        """The same curve of f + shift: control values move by -shift."""
        c = Curve([])
        c.pts = [(v - shift, y) for v, y in self.pts]
        return c

    def max_slope(self):
        m = 0.0
        for (a, ya), (b, yb) in zip(self.pts, self.pts[1:]):
            if b > a:
                m = max(m, float(abs(yb - ya) / (b - a)))
        return m


# ------------------------------------------------------------------------------------------------
# Clipping.

def clip(origin, direction, bmin, bmax):
    O = [mpf(c) for c in origin]
    D = [mpf(c) for c in direction]
    nrm = mp.sqrt(sum(c * c for c in D))
    d = [c / nrm for c in D]
    t0, t1 = mpf(0), mp.inf
    for a in range(3):
        lo, hi = mpf(bmin[a]), mpf(bmax[a])
        if D[a] == 0:
            if O[a] < lo or O[a] > hi:
                return None
            continue
        n_, f_ = (lo - O[a]) / d[a], (hi - O[a]) / d[a]
        if n_ > f_:
            n_, f_ = f_, n_
        t0, t1 = max(t0, n_), min(t1, f_)
    if not t0 <= t1:
        return None
    E = [O[a] + t0 * d[a] if D[a] != 0 else O[a] for a in range(3)]
    return E, d, t0, t1


# ------------------------------------------------------------------------------------------------
# Fields along the chord.

def bracket_root(g, a, b, ga, gb):
    """Root of g in [a, b], g(a) g(b) < 0: Illinois steps, every fourth a bisection."""
    tol = mpf(2) ** (-mp.prec + 12) * (1 + abs(a) + abs(b))
    side = 0
    for it in range(400):
        if b - a <= tol:
            break
        m = (a * gb - b * ga) / (gb - ga)
        if it % 4 == 3 or not (a < m < b):
            m = (a + b) / 2
        gm = g(m)
        if gm == 0:
            return m
        if (gm > 0) == (ga > 0):
            a, ga = m, gm
            if side == -1:
                gb /= 2
            side = -1
        else:
            b, gb = m, gm
            if side == 1:
                ga /= 2
            side = 1
    return (a + b) / 2


class MLRay:
    def __init__(self, fM, alpha, E, d, L):
        self.fM, self.alpha = mpf(fM), mpf(alpha)
        self.E, self.d, self.L = E, d, L
        self.A = 2 * mp.pi * self.fM
        self.k = 1 / (2 * (1 + self.alpha))
        self.omega = mp.pi ** 2 * abs(self.fM) * mp.sqrt(d[0] ** 2 + d[1] ** 2) + mp.pi / 2 * abs(d[2])

    def f(self, s):
        x, y, z = (self.E[a] + s * self.d[a] for a in range(3))
        u = mp.cos(mp.pi * mp.sqrt(x * x + y * y) / 2)
        return (1 - mp.sin(mp.pi * z / 2) + self.alpha * (1 + mp.cos(self.A * u))) * self.k

    def derivs(self, s):
        """f'(s), f''(s) by mp.diff (high-order finite differences at working precision)."""
        return mp.diff(self.f, s, 1), mp.diff(self.f, s, 2)

    def breaks(self):
        return [mpf(0), self.L]

    def extrema(self, a, b):
        if not b > a:
            return []
        h = mpf("0.25") / self.omega if self.omega > 0 else b - a
        n = max(2, int(mp.ceil((b - a) / h)))
        grid = [a + (b - a) * i / n for i in range(n + 1)]
        d1 = lambda s: mp.diff(self.f, s, 1)
        d2 = lambda s: mp.diff(self.f, s, 2)
        vals = [(d1(s), d2(s)) for s in grid]
        out = []
        for i in range(n):
            u, v = grid[i], grid[i + 1]
            (f1u, f2u), (f1v, f2v) = vals[i], vals[i + 1]
            pts = [(u, f1u)]
            if f2u * f2v < 0:
                si = bracket_root(d2, u, v, f2u, f2v)
                pts.append((si, d1(si)))
            pts.append((v, f1v))
            for (p, fp), (q, fq) in zip(pts, pts[1:]):
                if fp * fq < 0:
                    out.append(bracket_root(d1, p, q, fp, fq))
                elif fq == 0 and a < q < b:
                    out.append(q)
        return sorted(set(out))

    def pieces(self):
        n = max(1, int(mp.ceil(self.omega * self.L)))
        return [(self.L * i / n, self.L * (i + 1) / n) for i in range(n)]

    def integral(self, a, b, g=None):
        fn = self.f if g is None else (lambda s: g(self.f(s)))
        return mp.quad(fn, [a, b])


class RampRay:
    def __init__(self, grad, offset, E, d, L):
        g = [mpf(c) for c in grad]
        self.f0 = mpf(offset) + sum(g[a] * E[a] for a in range(3))
        self.k = sum(g[a] * d[a] for a in range(3))
        self.L = L
        self.omega = 0

    def f(self, s):
        return self.f0 + self.k * s

    def derivs(self, s):
        return self.k, mpf(0)

    def breaks(self):
        return [mpf(0), self.L]

    def extrema(self, a, b):
        return []

    def pieces(self):
        return [(mpf(0), self.L)]

    def integral(self, a, b, g=None):
        if g is None:
            return self.f0 * (b - a) + self.k * (b * b - a * a) / 2
        return mp.quad(lambda s: g(self.f(s)), [a, b])


class GridRay:
    """Trilinear (a cubic per cell) or nearest (constant between half-way planes) interpolation of
    node values on a node-layout grid, clamped at the box as vrv states it."""

    def __init__(self, bmin, bmax, res, interp, nodes, E, d, L):
        self.bmin = [mpf(c) for c in bmin]
        self.res = res
        self.h = [mpf((bmax[a] - bmin[a]) / (res[a] - 1)) for a in range(3)]
        self.nodes = nodes
        self.interp = interp
        self.E, self.d, self.L = E, d, L
        self.omega = 0
        shift = mpf("0.5") if interp == "nearest" else mpf(0)
        planes = set()
        for a in range(3):
            if d[a] == 0:
                continue
            for i in range(res[a]):
                s = (self.bmin[a] + (i + shift) * self.h[a] - E[a]) / d[a]
                if 0 < s < L:
                    planes.add(s)
        self.cuts = [mpf(0)] + sorted(planes) + [L]
        self._poly = {}

    def node(self, i, j, k):
        return mpf(self.nodes[(k * self.res[1] + j) * self.res[0] + i])

    def _coord(self, ax, s):
        n = self.res[ax]
        u = (self.E[ax] + s * self.d[ax] - self.bmin[ax]) / self.h[ax]
        return min(max(u, mpf(0)), mpf(n - 1))

    def poly(self, a, b):
        """Ascending coefficients of f on the piece [a, b] (cubic; constant for nearest)."""
        key = (a, b)
        if key in self._poly:
            return self._poly[key]
        m = (a + b) / 2
        if self.interp == "nearest":
            idx = [int(mp.nint(self._coord(ax, m))) for ax in range(3)]
            p = [self.node(*idx)]
            self._poly[key] = p
            return p
        lin, idx = [], []
        for ax in range(3):
            n = self.res[ax]
            u = (self.E[ax] + m * self.d[ax] - self.bmin[ax]) / self.h[ax]
            if u <= 0 or u >= n - 1:
                i0 = 0 if u <= 0 else n - 2
                w = [mpf(0) if u <= 0 else mpf(1), mpf(0)]
            else:
                i0 = min(int(mp.floor(u)), n - 2)
                w = [(self.E[ax] - self.bmin[ax]) / self.h[ax] - i0, self.d[ax] / self.h[ax]]
            lin.append(w)
            idx.append(i0)

        def mul(p, q):
            r = [mpf(0)] * (len(p) + len(q) - 1)
            for i, x in enumerate(p):
                for j, y in enumerate(q):
                    r[i + j] += x * y
            return r

        poly = [mpf(0)] * 4
        for ci in (0, 1):
            for cj in (0, 1):
                for ck in (0, 1):
                    fac = [self.node(idx[0] + ci, idx[1] + cj, idx[2] + ck)]
                    for ax, c in zip(range(3), (ci, cj, ck)):
                        w = lin[ax]
                        fac = mul(fac, w if c else [1 - w[0], -w[1]])
                    for i, x in enumerate(fac):
                        poly[i] += x
        self._poly[key] = poly
        return poly

    def _piece_of(self, s):
        for a, b in zip(self.cuts, self.cuts[1:]):
            if a <= s <= b and b > a:
                return a, b
        return self.cuts[-2], self.cuts[-1]

    def f_on(self, a, b, s):
        p = self.poly(a, b)
        return sum(c * s ** i for i, c in enumerate(p))

    def f(self, s):
        return self.f_on(*self._piece_of(s), s)

    def derivs(self, s):
        p = self.poly(*self._piece_of(s)) + [mpf(0)] * 3
        return p[1] + 2 * p[2] * s + 3 * p[3] * s * s, 2 * p[2] + 6 * p[3] * s

    def breaks(self):
        return list(self.cuts)

    def extrema(self, a, b):
        p = self.poly(a, b) + [mpf(0)] * 3
        A, B, C = 3 * p[3], 2 * p[2], p[1]
        out = []
        if A == 0:
            if B != 0:
                out = [-C / B]
        else:
            disc = B * B - 4 * A * C
            if disc > 0:
                sq = mp.sqrt(disc)
                q = -(B + (sq if B >= 0 else -sq)) / 2
                out = [q / A] + ([C / q] if q != 0 else [])
        return sorted(s for s in out if a < s < b)

    def pieces(self):
        return [(a, b) for a, b in zip(self.cuts, self.cuts[1:]) if b > a]

    def integral(self, a, b, g=None):
        if g is None:
            p = self.poly(*self._piece_of((a + b) / 2))
            return sum(c * (b ** (i + 1) - a ** (i + 1)) / (i + 1) for i, c in enumerate(p))
        return mp.quad(lambda s: g(self.f_on(*self._piece_of((a + b) / 2), s)), [a, b])


# ------------------------------------------------------------------------------------------------
# Truths.

def all_points(rf):
    """Sorted: piece ends (structural breaks) and every extremum inside a piece."""
    pts = set()
    for a, b in rf.pieces():
        pts.add(a)
        pts.add(b)
        pts.update(rf.extrema(a, b))
    pts.update(rf.breaks())
    return sorted(pts)


def value_at(rf, s, side):
    """f at s from the piece on the given side (-1 left, +1 right; grids are continuous, nearest not)."""
    if isinstance(rf, GridRay):
        for a, b in zip(rf.cuts, rf.cuts[1:]):
            if b > a and ((side < 0 and a < s <= b) or (side > 0 and a <= s < b)):
                return rf.f_on(a, b, s)
    return rf.f(s)


def mip_truth(rf, pts, curve):
    vals = []  # (s, f) at every candidate, both sides of a break
    for s in pts:
        for side in (-1, 1):
            if (side < 0 and s == 0) or (side > 0 and s == rf.L):
                continue
            vals.append((s, value_at(rf, s, side)))
    if rf.L == 0:
        vals = [(mpf(0), rf.f(mpf(0)))]
    best = max(v for _, v in vals)
    tie = mpf(10) ** -25
    pos = min(s for s, v in vals if v >= best - tie)
    # the best maximum separated from the first by a dip deeper than 1e-20
    second = None
    ordered = sorted(vals)
    i0 = min(i for i, (s, v) in enumerate(ordered) if v >= best - tie)
    low = mp.inf
    for s, v in ordered[i0 + 1:]:
        low = min(low, v)
        if low < v - mpf(10) ** -20 and (second is None or v > second):
            second = v
    # curvature at the maximum: |f''| where f' = 0 inside a piece, else 0 (an end or a kink)
    curv = mpf(0)
    if 0 < pos < rf.L and not isinstance(rf, RampRay):
        f1, f2 = rf.derivs(pos)
        if abs(f1) < mpf(10) ** -10:
            curv = abs(f2)
    # classified: the sup of tau over every piece's value range (f continuous on a piece)
    csup = mpf(-1)
    segs = [(a, b) for a, b in zip(pts, pts[1:]) if b > a] or [(mpf(0), mpf(0))]
    for a, b in segs:
        fa, fb = value_at(rf, a, 1) if b > a else rf.f(a), value_at(rf, b, -1) if b > a else rf.f(a)
        csup = max(csup, curve.sup(min(fa, fb), max(fa, fb)))
    return best, pos, curv, second, csup


def xray_truth(rf, pts, curve):
    total, classified = mpf(0), mpf(0)
    if rf.L == 0:
        return total, classified
    cuts = set(pts)
    for a, b in rf.pieces():
        cuts.add(a)
        cuts.add(b)
    cuts = sorted(cuts)
    levels = curve.levels()
    for a, b in zip(cuts, cuts[1:]):
        if not b > a:
            continue
        total += rf.integral(a, b)
        # classified: cut where f crosses a control value (f is monotone between extrema)
        fa, fb = value_at(rf, a, 1), value_at(rf, b, -1)
        sub = [a]
        for c in levels:
            if min(fa, fb) < c < max(fa, fb):
                if isinstance(rf, GridRay):
                    g = lambda s: rf.f_on(a, b, s) - c
                else:
                    g = lambda s: rf.f(s) - c
                sub.append(bracket_root(g, a, b, fa - c, fb - c))
        sub = sorted(sub) + [b]
        for u, w in zip(sub, sub[1:]):
            if w > u:
                classified += rf.integral(u, w, curve)
    return total, classified


def eta_of(field, E, d, L, bmin):
    """The field's own rounding in double on this chord (as make_adversarial.py)."""
    ends = [[float(E[a] + s * d[a]) for a in range(3)] for s in (mpf(0), L)]
    big = [max(abs(p[a]) for p in ends) for a in range(3)]
    if field["kind"] == "ml":
        fM, al = field["fM"], field["alpha"]
        r = math.hypot(big[0], big[1])
        return EPS * (4 + 2 * math.pi * fM * al / (1 + al) + ((math.pi / 2) * big[2] + al * math.pi ** 2 * fM * r) / (2 * (1 + al)))
    if field["kind"] == "ramp":
        g = [float.fromhex(c) for c in field["gradient"]]
        return 4 * EPS * (abs(float.fromhex(field["offset"])) + sum(abs(g[a]) * big[a] for a in range(3)))
    nodes = [float.fromhex(v) for v in field["nodes"]]
    return 8 * EPS * max(abs(v) for v in nodes) * 3


def make_ray(field, box, curve_pts, origin, direction):
    bmin, bmax = box
    c = clip(origin, direction, bmin, bmax)
    out = {"origin": [hexd(x) for x in origin], "direction": [hexd(x) for x in direction],
           "box": {"min": list(bmin), "max": list(bmax)}, "field": field, "extinction": curve_pts}
    curve = Curve(curve_pts)
    if c is None:
        out.update(hit=False)
        return out
    E, d, t0, t1 = c
    L = t1 - t0
    if field["kind"] == "ml":
        rf = MLRay(field["fM"], field["alpha"], E, d, L)
    elif field["kind"] == "ramp":
        rf = RampRay([float.fromhex(x) for x in field["gradient"]], float.fromhex(field["offset"]), E, d, L)
    else:
        rf = GridRay(bmin, bmax, field["resolution"], field["interpolation"],
                     [float.fromhex(v) for v in field["nodes"]], E, d, L)
    pts = all_points(rf)
    best, pos, curv, second, csup = mip_truth(rf, pts, curve)
    xr, xc = xray_truth(rf, pts, curve)
    eta = eta_of(field, E, d, L, bmin)
    # The classified truths' sensitivity to the field's rounding (a field at a jump's level moves
    # the whole integral by the jump): recomputed with the field moved by -+eta, at fewer digits.
    sens_x, sens_m = 0.0, 0.0
    with mp.workdps(20):
        for shift in (-eta, eta):
            sc = curve.shifted(mpf(shift))
            _, _, _, _, cs = mip_truth(rf, pts, sc)
            _, xs = xray_truth(rf, pts, sc)
            sens_x = max(sens_x, float(abs(xs - xc)))
            sens_m = max(sens_m, float(abs(cs - csup)))
    s = lambda x: mpmath.nstr(x, 30)
    out.update(hit=True, t_entry=s(t0), t_exit=s(t1), length=float(L),
               xray=s(xr), xray_classified=s(xc), mip=s(best), mip_position=s(t0 + pos),
               mip_curvature=float(curv), mip_second=(s(second) if second is not None else None),
               mip_classified=s(csup), eta=eta, tau_slope=curve.max_slope(),
               xray_classified_sensitivity=sens_x, mip_classified_sensitivity=sens_m)
    return out


# ------------------------------------------------------------------------------------------------
# The classes.

TF = [[0.0, 0.0], [0.3, 1.0], [0.5, 0.2], [0.5, 0.8], [1.0, 0.5]]  # kinks and a jump at 0.5
BOX = ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])


def ml(fM=6.0, alpha=0.25):
    return {"kind": "ml", "fM": fM, "alpha": alpha}


def ramp(g, off=0.0):
    return {"kind": "ramp", "gradient": [hexd(c) for c in g], "offset": hexd(off)}


def grid(res, nodes, interp="trilinear"):
    return {"kind": "grid", "resolution": res, "interpolation": interp, "nodes": [hexd(v) for v in nodes]}


def cases(rng):
    out = []
    add = lambda cls, tag, field, o, d, box=BOX: out.append((cls, tag, field, box, o, d))
    # smooth interior maxima of Marschner-Lobb, random chords
    for i in range(6):
        o = [rng.uniform(-0.9, 0.9) for _ in range(3)]
        d = [rng.gauss(0, 1) for _ in range(3)]
        o = [o[a] - 3 * d[a] for a in range(3)]
        add("smooth_interior", "ml_random_%d" % i, ml(), o, d)
    add("smooth_interior", "ml_fM2_diag", ml(2.0, 0.5), [-2.0, -1.7, -1.9], [1.0, 0.9, 1.1])
    # the maximum on a face or an edge
    add("face_edge", "ramp_max_at_exit", ramp([0.3, -0.2, 0.7], 0.1), [-2.0, 0.1, -0.3], [1.0, 0.05, 0.2])
    add("face_edge", "ramp_max_at_entry", ramp([-0.5, 0.0, 0.0]), [-2.0, 0.2, 0.3], [1.0, 0.0, 0.0])
    add("face_edge", "ramp_along_edge", ramp([0.1, 0.2, 0.9], 0.0), [1.0, 1.0, -3.0], [0.0, 0.0, 1.0])
    add("face_edge", "ml_max_on_entry_face", ml(), [0.3, 0.2, -2.0], [0.1, 0.05, 1.0])
    add("face_edge", "ml_along_face_y1", ml(), [-2.0, 1.0, 0.3], [1.0, 0.0, 0.1])
    # two peaks tied to 1e-14: Marschner-Lobb is even in x at y = 0, so a ray along x has mirror
    # peaks; a tilt in z of 1e-14 / ((pi/2) cos(pi z / 2) dx) separates them by about 1e-14
    z0 = 0.3
    for sign, tag in ((1, "second_higher"), (-1, "first_higher")):
        dz = sign * 1e-14 / (math.pi / 2 * math.cos(math.pi * z0 / 2)) / 1.0
        add("two_peaks", "ml_mirror_" + tag, ml(6.0, 0.25), [-2.0, 0.0, z0 + 2 * dz], [1.0, 0.0, -dz])
    add("two_peaks", "ml_mirror_exact", ml(6.0, 0.25), [-2.0, 0.0, z0], [1.0, 0.0, 0.0])
    # grid: two node peaks 1e-14 apart along a ray through node lines
    res = [9, 3, 3]
    base = [0.2 + 0.01 * ((i * 7 + j * 3 + k * 5) % 11) for k in range(3) for j in range(3) for i in range(9)]
    for delta, tag in ((1e-14, "second_higher"), (-1e-14, "first_higher"), (0.0, "exact")):
        nodes = list(base)
        nodes[(1 * 3 + 1) * 9 + 2] = 0.9
        nodes[(1 * 3 + 1) * 9 + 6] = 0.9 + delta
        add("two_peaks", "grid_nodes_" + tag, grid(res, nodes), [-2.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    # plateaus
    add("plateau", "ramp_perpendicular", ramp([0.0, 0.4, 0.0], 0.2), [-2.0, 0.3, 0.1], [1.0, 0.0, 0.0])
    flat = [0.5] * 27
    flat[13] = 0.5  # all equal
    add("plateau", "grid_constant", grid([3, 3, 3], flat), [-2.0, 0.1, -0.2], [1.0, 0.2, 0.1])
    steps = [0.1 * ((i + j + k) % 3) for k in range(5) for j in range(5) for i in range(5)]
    add("plateau", "grid_nearest", grid([5, 5, 5], steps, "nearest"), [-2.0, 0.05, 0.3], [1.0, 0.1, 0.03])
    # a maximum exactly where a discrete plan samples: a node peak at x = 0.25 (vtk step 0.25/m)
    nodes = [0.1 * ((i + 2 * j + k) % 4) for k in range(3) for j in range(3) for i in range(9)]
    nodes[(1 * 3 + 1) * 9 + 5] = 1.0
    add("at_sample", "grid_node_peak_x0.25", grid([9, 3, 3], nodes), [-2.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    # grazing rays: through a corner (a chord of ~1e-9), along an edge of a grid
    add("grazing", "ml_corner_1e-9", ml(), [-1.0 - 5e-10, -3.0, 0.2], [1.0, 1.0, 0.0])
    add("grazing", "ml_tangent_face", ml(), [-3.0, -1.0, 0.2], [1.0, 0.0, 0.05])
    gn = [rng.uniform(0, 1) for _ in range(4 * 4 * 4)]
    add("grazing", "grid_along_edge", grid([4, 4, 4], gn), [-1.0, -1.0, -3.0], [0.0, 0.0, 1.0])
    # empty rays
    add("empty", "ml_miss", ml(), [-3.0, 1.5, 0.0], [1.0, 0.0, 0.0])
    add("empty", "ramp_behind", ramp([1.0, 0.0, 0.0]), [2.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    # far origins
    for dist in (1e3, 1e6):
        d = [1.0, 0.31, -0.17]
        o = [0.1 - dist * d[0], -0.2 - dist * d[1], 0.05 - dist * d[2]]
        add("far_origin", "ml_far_%g" % dist, ml(), o, d)
        add("far_origin", "ramp_far_%g" % dist, ramp([0.2, -0.7, 0.4], 0.3), o, d)
    # grid kinks: random trilinear grids, diagonal chords (maxima on cell faces or inside cells)
    for i in range(5):
        n = [rng.randint(3, 7) for _ in range(3)]
        nodes = [rng.uniform(-1, 2) for _ in range(n[0] * n[1] * n[2])]
        o = [rng.uniform(-0.8, 0.8) for _ in range(3)]
        d = [rng.gauss(0, 1) for _ in range(3)]
        o = [o[a] - 3 * d[a] for a in range(3)]
        add("grid_kinks", "grid_random_%d_%dx%dx%d" % (i, *n), grid(n, nodes), o, d)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "projection_truth.jsonl"))
    args = ap.parse_args()
    mp.dps = DPS
    rng = random.Random(SEED)
    start = time.time()
    lines = []
    for cls, tag, field, box, o, d in cases(rng):
        t = time.time()
        rec = make_ray(field, box, TF, o, d)
        rec = {"class": cls, "tag": tag, **rec, "seconds": round(time.time() - t, 2)}
        lines.append(json.dumps(rec))
        print("%-16s %-28s %6.2fs" % (cls, tag, time.time() - t), file=sys.stderr)
    header = {"header": {"generator": "tests/lib/projection_adversarial/make_projection_truth.py",
                         "mpmath": mpmath.__version__, "dps": DPS, "seed": SEED, "rays": len(lines),
                         "seconds": round(time.time() - start, 1), "python": sys.version.split()[0]}}
    with open(args.out, "w") as f:
        f.write(json.dumps(header) + "\n")
        for line in lines:
            f.write(line + "\n")


if __name__ == "__main__":
    main()
