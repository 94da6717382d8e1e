#!/usr/bin/python3
"""Adversarial rays for vrv's reference integrator, with an independent high-precision truth.

Writes adversarial_rays.jsonl next to this script: a header line (mpmath version, dps, seed,
generation time), then one line per ray: its class and tag, the scene (vrv's TOML scene format,
every number written so that it parses to the double used here), the ray's origin and direction
(exact doubles, hex), the truth I to 34 significant digits, and the figures the test needs
(optical depth, length, crossings, the ray's double-precision floor).  Grid scenes also carry
their node values as vrv computes them (the test checks they are the same doubles).

The truth shares no code with vrv (lib/, analytic/): everything is computed here in mpmath
(Debian's python3-mpmath, pure-Python backend), from the definitions:

  I = int_0^L g(f(s)) e^{-Phi(s)} ds + I0 e^{-Phi(L)},   Phi(s) = int_0^s tau(f(u)) du,

- the ray is the line origin + t direction with the direction as given (normalised in mp); it
  is clipped to the closed box in mp (slab test; a zero direction component is a slab test of
  the origin, faces included), s is world length from the entry point;
- f along the ray: Marschner-Lobb from its formula (with analytic first and second derivatives
  in s), a linear ramp, or the trilinear interpolant of the grid's node values (a cubic in s per
  cell, expanded exactly; node planes are structural breaks);
- breaks: every extremum of f along the ray (Marschner-Lobb: f'' and f' scanned at a quarter
  radian of the ray's own frequency bound, inflection points then extrema located by bracketed
  root finding, so a close pair of extrema is not lost; grids: roots of the quadratic f'), then
  on every monotone piece every transfer-function control value crossed (bracketed Illinois /
  bisection to full working precision);
- between breaks g and tau are one affine branch of f (emission/extinction) or
  -log1p(-opacity)/unit_length and colour x tau: smooth.  Each piece is integrated with
  65-point Chebyshev-Lobatto panels, adaptively halved until the last Chebyshev coefficients of
  tau and of g e^{-Phi} are below 1e-33 of the panel's scale; Phi at the nodes is the exact
  integral of tau's interpolant (spectral integration matrix), carried from piece to piece.
  Once e^{-Phi} (max g x remaining length + I0) < 1e-45 the ray stops (nothing behind matters).

Floors (what double precision can reach on a ray, used by the test's "not absurd" check):
  sensitivity = max over +-eta of |I(f + eta) - I(f)|, eta the field's own rounding in double
                on this chord (Marschner-Lobb: eps (4 + 2 pi fM alpha/(1+alpha) + ((pi/2) |z| +
                alpha pi^2 fM r)/(2(1+alpha))), |z| and r their largest on the chord; ramps:
                4 eps (|offset| + sum |g_a| |x_a|); grids: 4 eps max|node| + 2 eps sum slope_a
                (|x_a| + |min_a|)): two more truths (at 22 digits) with the control values
                shifted by -+eta.
  pointwise   = eta int |g'(f) T - tau'(f) R| ds (T = e^{-Phi}, R(s) the light from behind s):
                to first order the most a field wrong by at most eta at every point can change
                I (values rounded independently per sample do not cancel as a uniform shift
                does); at 20 digits (pointwise_floor; --add-pointwise adds it to an existing file).
  rounding    = 8 eps sum over pieces (1 + Phi) |contribution| (+ the background's): the
                relative rounding of e^{-Phi} at depth Phi.
  floor       = the largest of the three.

Self-check (--check): a sample of rays recomputed at dps 50 with panels a third as long (a
different split), asserted to agree to 1e-25; rays recomputed by nested tanh-sinh (mp.quad for
Phi inside mp.quad) where short enough; closed forms for a constant field and for a linear ramp
with a linear transfer function.

Usage:
  /usr/bin/python3 tests/lib/reference_adversarial/make_adversarial.py [--quick] [--jobs 2]
                   [--out FILE] [--check] [--add-pointwise]
Generation time: 332 rays take 1480 s of one core (header "ray_seconds_sum"; the 200-point
transfer functions 45-165 s each, most rays 0.1-15 s), so about 12-13 minutes on two idle cores
(--jobs 2, the default); --quick writes a smaller set (about 100 rays).  A run cut short leaves
FILE.partial with every class represented (the classes are interleaved); --reuse FILE.partial
continues from it.
"""
import argparse
import ctypes
import ctypes.util
import json
import math
import multiprocessing
import os
import random
import sys
import time

import mpmath
from mpmath import mp, mpf

DPS = 40
SENS_DPS = 30  # the floors' shifted truths need only a few digits of I(f + eta) - I(f)
NS = (33, 65)  # Chebyshev-Lobatto points per panel: 33 below a radian of phase, else 65
EPS = 2.0 ** -52
SEED = 20

# --------------------------------------------------------------------------------------------
# Chebyshev machinery (built once per precision).

_cheb_cache = {}


def cheb(dps, N):
    key = (dps, N)
    if key in _cheb_cache:
        return _cheb_cache[key]
    with mp.workdps(dps + 15):
        n = N - 1
        x = [-mp.cos(mp.pi * k / n) for k in range(N)]  # ascending
        # T[k][j] = T_j(x_k), j = 0..N
        T = []
        for k in range(N):
            row = [mpf(1), x[k]]
            for j in range(2, N + 1):
                row.append(2 * x[k] * row[-1] - row[-2])
            T.append(row)
        # a_j = (2/n) sum''_k f_k T_j(x_k), a_0 and a_n halved: C[j][k]
        C = []
        for j in range(N):
            row = []
            for k in range(N):
                w = mpf(1) / n if k in (0, n) else mpf(2) / n
                if j in (0, n):
                    w /= 2
                row.append(w * T[k][j])
            C.append(row)

        # Tint[k][j] = int_{-1}^{x_k} T_j
        def tint(k, j):
            xx = x[k]
            if j == 0:
                return xx + 1
            if j == 1:
                return (xx * xx - 1) / 2
            lo = (mpf(-1) ** (j + 1) / (j + 1) - mpf(-1) ** (j - 1) / (j - 1)) / 2
            return (T[k][j + 1] / (j + 1) - T[k][j - 1] / (j - 1)) / 2 - lo

        Q = []
        for k in range(N):
            ti = [tint(k, j) for j in range(N)]
            Q.append([mp.fdot(ti, [C[j][m] for j in range(N)]) for m in range(N)])
    out = (x, C[-3:], Q)
    _cheb_cache[key] = out
    return out


# --------------------------------------------------------------------------------------------
# Transfer functions (vrv's definition: piecewise linear, constant beyond the ends, two points
# at one value make a jump, right-continuous).


class Curve:
    def __init__(self, pts):
        self.pts = [(mpf(v), mpf(y)) for v, y in pts]

    def line(self, v):
        """(v0, y0, slope) of the piece holding v (right-continuous at a jump)."""
        p = self.pts
        i = 0
        while i < len(p) and p[i][0] <= v:
            i += 1  # first point with value > v
        if i == 0:
            return (p[0][0], p[0][1], mpf(0))
        if i == len(p):
            return (p[-1][0], p[-1][1], mpf(0))
        (a, ya), (b, yb) = p[i - 1], p[i]
        return (a, ya, (yb - ya) / (b - a))


class TF:
    def __init__(self, spec):
        self.spec = spec
        if "emission" in spec:
            self.conv = "ee"
            self.c1, self.c2 = Curve(spec["emission"]), Curve(spec["extinction"])
            self.unit = mpf(1)
        else:
            self.conv = "oc"
            self.c1, self.c2 = Curve(spec["opacity"]), Curve(spec["color"])
            self.unit = mpf(spec.get("unit_length", 1.0))
        keys = ("emission", "extinction") if self.conv == "ee" else ("opacity", "color")
        vals = sorted(set(p[0] for k in keys for p in spec[k]))
        self.levels = [mpf(v) for v in vals]

    def branch(self, v):
        l1, l2 = self.c1.line(v), self.c2.line(v)
        unit, conv = self.unit, self.conv

        def lin(l, u):
            return l[1] + l[2] * (u - l[0])

        if conv == "ee":
            return (lambda u: max(mpf(0), lin(l1, u)), lambda u: max(mpf(0), lin(l2, u)))

        def tau(u):
            return -mp.log1p(-max(mpf(0), lin(l1, u))) / unit

        return (lambda u: max(mpf(0), lin(l2, u)) * tau(u), tau)

    def branch_slopes(self, v):
        """(dg/du, dtau/du) of the branch holding v, as functions of u (0 where a line is clamped)."""
        l1, l2 = self.c1.line(v), self.c2.line(v)
        unit = self.unit

        def lin(l, u):
            return l[1] + l[2] * (u - l[0])

        def slope(l, u):
            return l[2] if lin(l, u) > 0 else mpf(0)

        if self.conv == "ee":
            return (lambda u: slope(l1, u), lambda u: slope(l2, u))

        def tau(u):
            return -mp.log1p(-max(mpf(0), lin(l1, u))) / unit

        def dtau(u):
            return slope(l1, u) / ((1 - max(mpf(0), lin(l1, u))) * unit)

        return (lambda u: slope(l2, u) * tau(u) + max(mpf(0), lin(l2, u)) * dtau(u), dtau)

    def max_slope(self):
        m = mpf(0)
        for c in (self.c1, self.c2):
            for (a, ya), (b, yb) in zip(c.pts, c.pts[1:]):
                if b > a:
                    m = max(m, abs(yb - ya) / (b - a))
        return m * (1 if self.conv == "ee" else 100 / self.unit)

    def tau_scale(self):
        if self.conv == "ee":
            return max(mpf(y) for _, y in self.spec["extinction"])
        return -mp.log1p(-max(mpf(y) for _, y in self.spec["opacity"])) / self.unit

    def max_g(self):
        if self.conv == "ee":
            return max(mpf(y) for _, y in self.spec["emission"])
        a = max(mpf(y) for _, y in self.spec["opacity"])
        return max(mpf(y) for _, y in self.spec["color"]) * -mp.log1p(-a) / self.unit


# --------------------------------------------------------------------------------------------
# The ray: clipped in mp from the doubles given.


def clip(origin, direction, bmin, bmax):
    """(E, d, L): entry point, unit direction and chord length in mp, or None on a miss."""
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
    E = [O[a] + t0 * d[a] for a in range(3)]
    # Coordinates with a zero direction component are exactly the origin's (no rounding in E).
    for a in range(3):
        if D[a] == 0:
            E[a] = O[a]
    return E, d, t1 - t0


# --------------------------------------------------------------------------------------------
# Fields along the ray: f(s), f'(s), f''(s), structural pieces, extrema.

_libm = ctypes.CDLL(ctypes.util.find_library("m"))
for _fn in ("sin", "cos", "hypot"):
    getattr(_libm, _fn).restype = ctypes.c_double
    getattr(_libm, _fn).argtypes = [ctypes.c_double] * (2 if _fn == "hypot" else 1)


def ml_double(fM, alpha, p):
    """Marschner-Lobb in double as vrv's formula states it (same libm calls, same order): only
    for the node values of grids, which the test checks against vrv's own."""
    pi = math.pi
    r = _libm.hypot(p[0], p[1])
    rho = _libm.cos(2 * pi * fM * _libm.cos(pi * r / 2))
    return (1 - _libm.sin(pi * p[2] / 2) + alpha * (1 + rho)) / (2 * (1 + alpha))


def _sinc_q(w):
    """sinc(w) and (sinc'(w))/w = (w cos w - sin w)/w^3, smooth at 0."""
    if abs(w) < mpf("1e-6"):
        w2 = w * w
        return 1 - w2 / 6 + w2 * w2 / 120, -mpf(1) / 3 + w2 / 30 - w2 * w2 / 840
    return mp.sin(w) / w, (w * mp.cos(w) - mp.sin(w)) / w ** 3


class MLRay:
    kind = "ml"

    def __init__(self, fM, alpha, E, d, L):
        self.fM, self.alpha = mpf(fM), mpf(alpha)
        self.E, self.d, self.L = E, d, L
        self.A = 2 * mp.pi * self.fM
        self.k = 1 / (2 * (1 + self.alpha))
        dxy = mp.sqrt(d[0] ** 2 + d[1] ** 2)
        self.omega = mp.pi ** 2 * abs(self.fM) * dxy + mp.pi / 2 * abs(d[2])

    def _parts(self, s):
        x, y, z = (self.E[a] + s * self.d[a] for a in range(3))
        rho = x * x + y * y
        return x, y, z, rho

    def f(self, s):
        x, y, z, rho = self._parts(s)
        u = mp.cos(mp.pi * mp.sqrt(rho) / 2)
        return (1 - mp.sin(mp.pi * z / 2) + self.alpha * (1 + mp.cos(self.A * u))) * self.k

    def derivs(self, s):
        x, y, z, rho = self._parts(s)
        dx, dy, dz = self.d
        r = mp.sqrt(rho)
        w = mp.pi * r / 2
        u = mp.cos(w)
        rp = 2 * (x * dx + y * dy)
        rpp = 2 * (dx * dx + dy * dy)
        sc, q = _sinc_q(w)
        c8 = mp.pi ** 2 / 8
        up = -c8 * sc * rp
        upp = -c8 * (c8 * q * rp * rp + sc * rpp)
        hz = mp.pi / 2
        sA, cA = mp.sin(self.A * u), mp.cos(self.A * u)
        f1 = (-hz * mp.cos(hz * z) * dz - self.alpha * sA * self.A * up) * self.k
        f2 = (hz * hz * mp.sin(hz * z) * dz * dz
              - self.alpha * (cA * self.A ** 2 * up * up + sA * self.A * upp)) * self.k
        return f1, f2

    def pieces(self):
        return [(mpf(0), self.L)]

    def panel_length(self):
        return 20 / self.omega if self.omega > 0 else self.L

    def extrema(self, a, b):
        if b <= a:
            return []
        h = mpf("0.25") / self.omega if self.omega > 0 else b - a
        n = max(1, int(mp.ceil((b - a) / h)))
        grid = [a + (b - a) * i / n for i in range(n + 1)]
        d1 = lambda s: self.derivs(s)[0]
        d2 = lambda s: self.derivs(s)[1]
        vals = [self.derivs(s) for s in grid]
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
                    out.append(bracket_root(d1, p, q, fp, fq, d2))
            # f' exactly 0 on a scan point with f'' not 0 is an extremum there (no sign change
            # brackets it: a ray along z through the axis of Marschner-Lobb's rings lost one).
            if i > 0 and f1u == 0 and f2u != 0:
                out.append(u)
        return sorted(set(out))


class RampRay:
    kind = "ramp"

    def __init__(self, grad, offset, E, d, L):
        self.g = [mpf(c) for c in grad]
        self.off = mpf(offset)
        self.E, self.d, self.L = E, d, L
        self.f0 = self.off + sum(self.g[a] * E[a] for a in range(3))
        self.k = sum(self.g[a] * d[a] for a in range(3))

    def f(self, s):
        return self.f0 + self.k * s

    def derivs(self, s):
        return self.k, mpf(0)

    def pieces(self):
        return [(mpf(0), self.L)]

    def panel_length(self):
        return self.L

    def extrema(self, a, b):
        return []

    def crossing(self, c, a, b):
        return (c - self.f0) / self.k


class GridRay:
    """Trilinear interpolant of node values (node or cell layout, clamped as vrv states it)."""
    kind = "grid"

    def __init__(self, bmin, bmax, res, layout, nodes, E, d, L):
        self.bmin = [mpf(c) for c in bmin]
        self.res = res
        self.off = mpf(0) if layout == "node" else mpf("0.5")
        # The spacing is the double vrv uses: extent / (n - 1) or extent / n, rounded.
        self.h = [mpf((bmax[a] - bmin[a]) / (res[a] - 1 if layout == "node" else res[a]))
                  for a in range(3)]
        self.nodes = nodes  # flat, x fastest, doubles
        self.E, self.d, self.L = E, d, L
        planes = set()
        for a in range(3):
            if d[a] == 0:
                continue
            for i in range(res[a]):
                x = self.bmin[a] + (i + self.off) * self.h[a]
                s = (x - E[a]) / d[a]
                if 0 < s < L:
                    planes.add(s)
        self.cuts = [mpf(0)] + sorted(planes) + [L]
        self._poly = {}

    def node(self, i, j, k):
        return mpf(self.nodes[(k * self.res[1] + j) * self.res[0] + i])

    def _cubic(self, a, b):
        """Coefficients (ascending) of f on the cell piece [a, b]."""
        key = (a, b)
        if key in self._poly:
            return self._poly[key]
        m = (a + b) / 2
        lin, idx = [], []
        for ax in range(3):
            n = self.res[ax]
            u = (self.E[ax] + m * self.d[ax] - self.bmin[ax]) / self.h[ax] - self.off
            if u <= 0 or u >= n - 1:  # clamped: constant along this axis
                i0 = 0 if u <= 0 else n - 2
                w = [mpf(0) if u <= 0 else mpf(1), mpf(0)]
            else:
                i0 = min(int(mp.floor(u)), n - 2)
                # w(s) = (E + s d - min)/h - off - i0
                w = [(self.E[ax] - self.bmin[ax]) / self.h[ax] - self.off - i0,
                     self.d[ax] / self.h[ax]]
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
                    v = self.node(idx[0] + ci, idx[1] + cj, idx[2] + ck)
                    fac = [v]
                    for ax, c in zip(range(3), (ci, cj, ck)):
                        w = lin[ax]
                        fac = mul(fac, w if c else [1 - w[0], -w[1]])
                    for i, x in enumerate(fac):
                        poly[i] += x
        self._poly[key] = (poly, a, b)
        return self._poly[key]

    def _piece_of(self, s):
        for a, b in zip(self.cuts, self.cuts[1:]):
            if a <= s <= b and b > a:
                return a, b
        return self.cuts[-2], self.cuts[-1]

    def f(self, s):
        poly, _, _ = self._cubic(*self._piece_of(s))
        return ((poly[3] * s + poly[2]) * s + poly[1]) * s + poly[0]

    def derivs(self, s):
        poly, _, _ = self._cubic(*self._piece_of(s))
        return (3 * poly[3] * s + 2 * poly[2]) * s + poly[1], 6 * poly[3] * s + 2 * poly[2]

    def pieces(self):
        return [(a, b) for a, b in zip(self.cuts, self.cuts[1:]) if b > a]

    def panel_length(self):
        return self.L

    def extrema(self, a, b):
        poly, _, _ = self._cubic(a, b)
        A, B, C = 3 * poly[3], 2 * poly[2], poly[1]
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


def bracket_root(g, a, b, ga, gb, dg=None):
    """Root of g in [a, b] with g(a) g(b) < 0, to the working precision: Illinois steps (the
    regula falsi with the stale end's value halved), every fourth step a bisection."""
    tol = mpf(2) ** (-mp.prec + 16) * (1 + abs(a) + abs(b))
    side = 0
    for it in range(600):
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


# --------------------------------------------------------------------------------------------
# The integral.


def breaks_of(rf, levels, extrema_cache):
    """Sorted breaks: structural cuts, extrema, and every crossing of a level."""
    cuts = set()
    for a, b in rf.pieces():
        cuts.add(a)
        cuts.add(b)
        key = (a, b)
        if key not in extrema_cache:
            extrema_cache[key] = rf.extrema(a, b)
        ext = extrema_cache[key]
        pts = [a] + ext + [b]
        cuts.update(ext)
        for u, v in zip(pts, pts[1:]):
            if not v > u:
                continue
            fu, fv = rf.f(u), rf.f(v)
            lo, hi = min(fu, fv), max(fu, fv)
            for c in levels:
                if lo < c < hi:
                    if rf.kind == "ramp":
                        cuts.add(rf.crossing(c, u, v))
                    else:
                        cuts.add(bracket_root(lambda s: rf.f(s) - c, u, v, fu - c, fv - c,
                                              lambda s: rf.derivs(s)[0]))
    return sorted(cuts)


class Stats:
    def __init__(self):
        self.panels = 0
        self.evals = 0
        self.unresolved = 0


def integrate(rf, tf, background, shift=mpf(0), extrema_cache=None, panel_scale=1, rtol=None, record=None):
    """Truth for the field f + shift (shift moves the field: control values move by -shift).
    record: a list that receives every accepted panel (its node values, depths, h and the
    emission before it), for pointwise_floor."""
    if extrema_cache is None:
        extrema_cache = {}
    rtol = rtol if rtol is not None else mpf(10) ** (-mp.dps + 7)
    levels = [c - shift for c in tf.levels]
    cuts = breaks_of(rf, levels, extrema_cache)
    gmax = tf.max_g()
    I0 = mpf(background)
    tiny = mpf(10) ** (-mp.dps + 2)
    # f carries ~10^-dps of its size, which a transfer-function slope s turns into s times that
    # in g and tau: tails below that are rounding (a 1e9 slope on a near-constant field).
    fsize = max(abs(rf.f(mpf(0))), abs(rf.f(rf.L)), mpf(1))
    floor_tau = tiny * (max(tf.tau_scale(), mpf(1)) + tf.max_slope() * fsize)
    floor_h = tiny * (max(gmax, mpf(1)) * mpf(10) ** -10 + tf.max_slope() * fsize)
    st = Stats()
    state = {"phi": mpf(0), "I": mpf(0), "rounding": mpf(0), "branch": None}
    crossings = 0

    def panel(a, b, g, tau, depth):
        phase = rf.omega * (b - a) if rf.kind == "ml" else 0
        N = NS[0] if phase < 1 else NS[1]
        x, Ctail, Q = cheb(mp.dps, N)
        half = (b - a) / 2
        mid = (a + b) / 2
        v = [rf.f(mid + half * xk) + shift for xk in x]
        st.evals += N
        tv = [tau(u) for u in v]
        gv = [g(u) for u in v]
        tmax = max(abs(t) for t in tv)
        ttail = max(abs(mp.fdot(row, tv)) for row in Ctail)
        phi0 = state["phi"]
        phis = [phi0 + half * mp.fdot(Q[k], tv) for k in range(N)]
        hv = [gv[k] * mp.exp(-phis[k]) for k in range(N)]
        hmax = max(abs(h) for h in hv)
        htail = max(abs(mp.fdot(row, hv)) for row in Ctail)
        # relative to the panel, with an absolute floor far below anything I can feel (values
        # that are zero up to rounding would otherwise never look resolved)
        ok = ttail <= rtol * tmax + floor_tau and htail <= rtol * hmax + floor_h
        if not ok and depth < 60 and b - a > mpf(10) ** (-mp.dps + 12) * rf.L:
            panel(a, mid, g, tau, depth + 1)
            panel(mid, b, g, tau, depth + 1)
            return
        st.unresolved += not ok  # reported; the main pass must have none (the header counts them)
        st.panels += 1
        e = half * mp.fdot(Q[-1], hv)
        if record is not None:
            record.append({"v": v, "phis": phis, "hv": hv, "half": half, "Q": Q, "before": state["I"],
                           "branch": state["branch"]})
        state["I"] += e
        state["phi"] = phi0 + half * mp.fdot(Q[-1], tv)
        state["rounding"] += (1 + phi0) * abs(e)

    stopped = False
    for a, b in zip(cuts, cuts[1:]):
        if not b > a:
            continue
        crossings += 1
        m = (a + b) / 2
        g, tau = tf.branch(rf.f(m) + shift)
        state["branch"] = rf.f(m) + shift
        h0 = rf.panel_length() * panel_scale
        n = max(1, int(mp.ceil((b - a) / h0)))
        for i in range(n):
            panel(a + (b - a) * i / n, a + (b - a) * (i + 1) / n, g, tau, 0)
        rest = mp.exp(-state["phi"]) * (gmax * (rf.L - b) + I0)
        if rest < mpf(10) ** -45:
            stopped = True
            break
    bg = I0 * mp.exp(-state["phi"])
    total = state["I"] + bg
    rounding = 8 * EPS * (state["rounding"] + (1 + state["phi"]) * bg)
    if record is not None:
        record.append({"total": total})
    return {"I": total, "phi": state["phi"], "stopped": stopped, "pieces": crossings,
            "panels": st.panels, "evals": st.evals, "unresolved": st.unresolved, "rounding": rounding, "cuts": cuts}


def pointwise_floor(tf, record, eta):
    """eta x int |g'(f) T(s) - tau'(f) R(s)| ds: to first order the largest change of I that a
    field wrong by at most eta at every point can make (R(s): the light that reaches the eye from
    behind s, which a change of tau at s scales).  A shift of the whole field by +-eta (the
    sensitivity) is one such change; values rounded independently from point to point, as a
    double computation's are, can be as bad as this, and no estimate from those values can
    promise less.  A few digits suffice: the panels' Clenshaw-Curtis weights on |.|."""
    total = record[-1]["total"]
    acc = mpf(0)
    for p in record[:-1]:
        dg, dtau = tf.branch_slopes(p["branch"])
        Q, half = p["Q"], p["half"]
        for k, u in enumerate(p["v"]):
            R = total - (p["before"] + half * mp.fdot(Q[k], p["hv"]))
            acc += half * Q[-1][k] * abs(dg(u) * mp.exp(-p["phis"][k]) - dtau(u) * R)
    return acc * eta


# --------------------------------------------------------------------------------------------
# Scenes.


def fmt(x):
    """A float as TOML that parses to the same double."""
    x = float(x)
    r = repr(x)
    if "e" in r and "." not in r.split("e")[0]:
        return r  # 1e-13 is valid TOML
    return r


def toml_points(pts):
    return "[" + ", ".join("[%s, %s]" % (fmt(v), fmt(y)) for v, y in pts) + "]"


def scene_toml(sc):
    out = ["[volume]", "min = [%s]" % ", ".join(fmt(c) for c in sc["min"]),
           "max = [%s]" % ", ".join(fmt(c) for c in sc["max"]), "", "[field]"]
    fld = sc["field"]
    if fld["kind"] == "marschner_lobb":
        out += ['kind = "marschner_lobb"', "fM = %s" % fmt(fld["fM"]), "alpha = %s" % fmt(fld["alpha"])]
    elif fld["kind"] == "linear_ramp":
        out += ['kind = "linear_ramp"', "gradient = [%s]" % ", ".join(fmt(c) for c in fld["gradient"]),
                "offset = %s" % fmt(fld["offset"])]
    else:
        out += ['kind = "grid"', "resolution = [%s]" % ", ".join(str(n) for n in fld["resolution"]),
                'layout = "%s"' % fld["layout"], 'interpolation = "trilinear"', "",
                "[field.source]", 'kind = "marschner_lobb"', "fM = %s" % fmt(fld["fM"]),
                "alpha = %s" % fmt(fld["alpha"])]
    out += ["", "[transfer]"]
    for key, val in sc["tf"].items():
        out.append("%s = %s" % (key, fmt(val) if key == "unit_length" else toml_points(val)))
    out += ["", "[background]", "intensity = %s" % fmt(sc.get("background", 0.0)), ""]
    return "\n".join(out)


def grid_nodes(sc):
    fld = sc["field"]
    res, layout = fld["resolution"], fld["layout"]
    off = 0.0 if layout == "node" else 0.5
    sp = [(sc["max"][a] - sc["min"][a]) / (res[a] - 1 if layout == "node" else res[a]) for a in range(3)]
    vals = []
    for k in range(res[2]):
        for j in range(res[1]):
            for i in range(res[0]):
                p = [sc["min"][0] + (i + off) * sp[0], sc["min"][1] + (j + off) * sp[1],
                     sc["min"][2] + (k + off) * sp[2]]
                vals.append(ml_double(fld["fM"], fld["alpha"], p))
    return vals


def ray_field(sc, origin, direction, nodes=None):
    c = clip(origin, direction, sc["min"], sc["max"])
    if c is None:
        return None
    E, d, L = c
    fld = sc["field"]
    if fld["kind"] == "marschner_lobb":
        return MLRay(fld["fM"], fld["alpha"], E, d, L)
    if fld["kind"] == "linear_ramp":
        return RampRay(fld["gradient"], fld["offset"], E, d, L)
    return GridRay(sc["min"], sc["max"], fld["resolution"], fld["layout"], nodes, E, d, L)


def field_noise(sc, rf, nodes=None):
    """eta: the absolute rounding of the field's values in double along this ray (see the module
    comment): the evaluation's own rounding plus the coordinates' (relative eps) times the
    field's sensitivity to them, with the coordinates' largest size on this chord."""
    fld = sc["field"]
    ends = [[float(rf.E[a] + t * rf.d[a]) for a in range(3)] for t in (0, rf.L)]
    P = [max(abs(e[a]) for e in ends) for a in range(3)]
    if fld["kind"] == "linear_ramp":
        return 4 * EPS * (abs(fld["offset"]) + sum(abs(g) * P[a] for a, g in enumerate(fld["gradient"])))
    fM, al = fld["fM"], fld["alpha"]
    if fld["kind"] == "marschner_lobb":
        # sin(pi z / 2) moves by (pi/2) eps |z|; the radial phase by pi^2 fM eps r
        return EPS * (4 + 2 * math.pi * fM * al / (1 + al)
                      + (math.pi / 2 * P[2] + al * math.pi ** 2 * fM * math.hypot(P[0], P[1])) / (2 * (1 + al)))
    res = fld["resolution"]
    off = 0 if fld["layout"] == "node" else 1
    h = [(sc["max"][a] - sc["min"][a]) / (res[a] - 1 + off) for a in range(3)]
    idx = lambda i, j, k: (k * res[1] + j) * res[0] + i
    slope = [0.0, 0.0, 0.0]
    for k in range(res[2]):
        for j in range(res[1]):
            for i in range(res[0]):
                v = nodes[idx(i, j, k)]
                for a, (ii, jj, kk) in enumerate(((i + 1, j, k), (i, j + 1, k), (i, j, k + 1))):
                    if ii < res[0] and jj < res[1] and kk < res[2]:
                        slope[a] = max(slope[a], abs(nodes[idx(ii, jj, kk)] - v) / h[a])
    return 4 * EPS * max(abs(v) for v in nodes) + 2 * EPS * sum(slope[a] * (P[a] + abs(sc["min"][a])) for a in range(3))


# --------------------------------------------------------------------------------------------
# Ray classes.

DEFAULT_TF = {"emission": [[0.0, 0.0], [1.0, 1.0]], "extinction": [[0.0, 0.0], [1.0, 0.5]]}
UNIT = ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])
TALL = ([-1.0, -1.0, -30.0], [1.0, 1.0, 30.0])


def ml(fM, alpha=0.25):
    return {"kind": "marschner_lobb", "fM": float(fM), "alpha": float(alpha)}


def scene(box, field, tf, background=0.0):
    return {"min": list(box[0]), "max": list(box[1]), "field": field, "tf": tf, "background": background}


def random_dir(rng):
    while True:
        v = [rng.uniform(-1, 1) for _ in range(3)]
        n = math.sqrt(sum(c * c for c in v))
        if 0.2 < n <= 1:
            return [c / n for c in v]


def chord(rng, box, min_len=1.0):
    """A random ray from outside the box through it (origin 1.5 extents away)."""
    lo, hi = box
    while True:
        p = [rng.uniform(lo[a] * 0.9, hi[a] * 0.9) for a in range(3)]
        d = random_dir(rng)
        ext = max(hi[a] - lo[a] for a in range(3))
        o = [p[a] - 1.5 * ext * d[a] for a in range(3)]
        c = clip(o, d, lo, hi)
        if c is not None and c[2] >= min_len:
            return o, d


def jump_tf(c, below, above):
    """Emission and extinction jump at c: (g, tau) below and above."""
    return {"emission": [[c, below[0]], [c, above[0]]], "extinction": [[c, below[1]], [c, above[1]]]}


def kink_tf(c, w=0.05):
    """A kink (slope change) at c: tent-shaped emission and extinction peaking at c."""
    return {"emission": [[c - w, 0.0], [c, 2.0], [c + w, 0.1]],
            "extinction": [[c - w, 0.1], [c, 3.0], [c + w, 0.0]]}


def interior_extremum(sc, o, d, rng, margin=0.05):
    """A random interior extremum of f along the ray: (s, f, kind) in mp, or None."""
    rf = ray_field(sc, o, d)
    if rf is None:
        return None
    cands = []
    for a, b in rf.pieces():
        for s in rf.extrema(a, b):
            if margin * rf.L < s < (1 - margin) * rf.L:
                cands.append(s)
    if not cands:
        return None
    s = cands[rng.randrange(len(cands))]
    return s, rf.f(s), ("min" if rf.derivs(s)[1] > 0 else "max")


def make_rays(quick):
    rng = random.Random(SEED)
    rays = []

    def add(cls, tag, sc, o, d, **extra):
        rays.append(dict(cls=cls, tag=tag, scene=sc, origin=[float(c) for c in o],
                         direction=[float(c) for c in d], **extra))

    deltas = [1e-3, 1e-6, 1e-9, 1e-12]
    # -- issue 20's cases --
    axis_o, axis_d = [0.0, 0.0, -31.0], [0.0, 0.0, 1.0]
    rf = ray_field(scene(TALL, ml(24), DEFAULT_TF), axis_o, axis_d)
    fmin = min(rf.f(s) for s in rf.extrema(mpf(0), rf.L))  # f = 0.2 at z = 1 mod 4
    c = float(fmin + mpf("1e-9"))
    add("tall_box", "issue20_axis_fM24_jump_1e-9_above_min", scene(TALL, ml(24), jump_tf(c, (100.0, 5.0), (0.01, 0.08))),
        axis_o, axis_d)
    add("tall_box", "issue20_axis_fM24_default_tf", scene(TALL, ml(24), DEFAULT_TF), axis_o, axis_d)
    far_d = [1.0, 0.3, -0.2]
    q = [-4.0, -0.7, 0.5]  # 3 units before the box (x = -1, y = 0.2, z = -0.1) on the line
    for dist in ([1e6, 1e9, 1e12, 1e15] if quick else [1e3, 1e6, 1e9, 1e12, 1e15]):
        k = dist / math.sqrt(sum(c * c for c in far_d))
        o = [q[a] - k * far_d[a] for a in range(3)]
        add("far_origin", "issue20_far_%.0e_dir_1_0.3_-0.2" % dist, scene(UNIT, ml(6), DEFAULT_TF), o, far_d)
        add("far_origin", "far_%.0e_dir_1_0.3_-0.2_jump" % dist,
            scene(UNIT, ml(6), jump_tf(0.45, (0.2, 0.3), (1.5, 2.0))), o, far_d)
    ramp13 = {"kind": "linear_ramp", "gradient": [1e-13, 0.0, 0.0], "offset": 0.0}
    add("flat", "issue20_ramp_1e-13_jump_at_0", scene(UNIT, ramp13, jump_tf(0.0, (0.5, 0.2), (1.0, 0.7))),
        [-2.0, 0.1, 0.2], [1.0, 0.0, 0.0])
    wall_tf = {"emission": [[0.5, 0.3], [0.5, 1.0]], "extinction": [[0.5, 0.4], [0.5, 1e6]]}
    add("wall", "issue20_wall_1e6_behind_jump", scene(UNIT, {"kind": "linear_ramp", "gradient": [0.5, 0.0, 0.0],
                                                            "offset": 0.25}, wall_tf),
        [-2.0, 0.1, -0.3], [1.0, 0.0, 0.0])
    # Marschner-Lobb fM = 12, alpha = 0.01, grazing ring tops: rays at z = const tangent to the
    # circles where rho_r peaks (12 cos(pi r/2) integer).
    for i, kk in enumerate([11, 10, 9, 7] if not quick else [11, 9]):
        r = 2 / math.pi * math.acos(kk / 12.0)
        z = [0.1, -0.35, 0.6, -0.8][i]
        add("grazing", "issue20_ml12_alpha0.01_ring_%d_tangent" % kk, scene(UNIT, ml(12, 0.01), DEFAULT_TF),
            [-2.0, r, z], [1.0, 0.0, 0.0])
        add("grazing", "ml12_alpha0.01_ring_%d_tilted" % kk, scene(UNIT, ml(12, 0.01), DEFAULT_TF),
            [-2.0, r, z], [1.0, 1e-7, 1e-3])
    # 200-point transfer function at fM = 12.
    for i in range(2 if quick else 4):
        vs = sorted(rng.uniform(0, 1) for _ in range(200))
        tf = {"emission": [[v, rng.uniform(0, 2)] for v in vs], "extinction": [[v, rng.uniform(0, 3)] for v in vs]}
        o, d = chord(rng, UNIT, 1.5)
        add("many_points", ("issue20_" if i == 0 else "") + "tf200_ml12_%d" % i, scene(UNIT, ml(12), tf), o, d)

    # -- jumps and kinks by an extremum --
    n_base = 2 if quick else 5
    for b in range(n_base):
        fM = [6, 12, 24, 6, 12, 24, 2][b]
        alpha = [0.25, 0.25, 0.25, 0.01, 0.5, 0.1, 0.25][b]
        sc0 = scene(UNIT, ml(fM, alpha), DEFAULT_TF)
        while True:
            o, d = chord(rng, UNIT, 1.0)
            e = interior_extremum(sc0, o, d, rng)
            if e is not None:
                break
        s, fe, kind = e
        for delta in deltas:
            for sign in (1, -1):
                c = float(fe + sign * mpf(delta))
                rel = "above" if sign > 0 else "below"
                tag = "fM%d_a%g_%s_%s_%g" % (fM, alpha, kind, rel, delta)
                add("extremum_jump", "jump_" + tag, scene(UNIT, ml(fM, alpha), jump_tf(c, (0.3, 0.8), (4.0, 1.5))), o, d)
                add("extremum_kink", "kink_" + tag, scene(UNIT, ml(fM, alpha), kink_tf(c)), o, d)
    # on a grid (cubic pieces): the extremum of a cell's cubic
    # -- steep transfer functions --
    for i in range(4 if quick else 18):
        slope = 10.0 ** (3 + (i % 6))
        fM = [6, 12][i % 2]
        o, d = chord(rng, UNIT, 1.0)
        v0 = rng.uniform(0.3, 0.7)
        h = rng.choice([1.0, 5.0, 20.0])
        w = h / slope
        tf = {"emission": [[v0, 0.05], [v0 + w, h]], "extinction": [[v0 - w, 0.1], [v0, 0.1 + h / 4]]}
        add("steep", "steep_slope_%.0e_fM%d_%d" % (slope, fM, i), scene(UNIT, ml(fM), tf), o, d)
    for i in range(2 if quick else 3):
        o, d = chord(rng, UNIT, 1.0)
        vs = sorted(rng.uniform(0.1, 0.9) for _ in range(200))
        tf = {"emission": [[v, rng.uniform(0, 1)] for v in vs], "extinction": [[v, rng.uniform(0, 2)] for v in vs]}
        add("many_points", "tf200_ml%d_%d" % ([6, 24][i % 2], i), scene(UNIT, ml([6, 24][i % 2]), tf), o, d)
    # -- late emission behind large optical depth --
    for i, Phi in enumerate([30, 100, 300, 700] if quick else [30, 60, 100, 200, 300, 450, 600, 700]):
        # ramp f = x along x: extinction Phi/1.6 below 0.6, emission e^Phi-ish beyond 0.7
        tf = {"emission": [[0.7, 0.0], [0.8, math.exp(min(Phi, 700))]],
              "extinction": [[0.6, Phi / 1.6], [0.6, 0.0]]}
        add("opaque", "late_emission_phi%d_ramp" % Phi,
            scene(UNIT, {"kind": "linear_ramp", "gradient": [1.0, 0.0, 0.0], "offset": 0.0}, tf),
            [-3.0, 0.2, 0.3], [1.0, 0.0, 0.0])
        # Marschner-Lobb: extinction on low values, emission on the highest values along the ray
        o, d = chord(rng, UNIT, 2.0)
        tf2 = {"emission": [[0.8, 0.0], [0.95, math.exp(min(Phi, 700)) / 50]],
               "extinction": [[0.5, Phi / 1.5], [0.7, 0.0]]}
        add("opaque", "late_emission_phi%d_ml6" % Phi, scene(UNIT, ml(6), tf2, background=1.0), o, d)
    # -- walls of extinction 1e6 behind a jump --
    for i in range(3 if quick else 12):
        c = rng.uniform(0.3, 0.7)
        tau_wall = [1e6, 1e5, 1e7][i % 3]
        tf = {"emission": [[c, rng.uniform(0, 1)], [c, rng.uniform(0, 3)]],
              "extinction": [[c, rng.uniform(0, 1)], [c, tau_wall]]}
        o, d = chord(rng, UNIT, 1.0)
        if i % 2:
            add("wall", "wall_%.0e_ml6_%d" % (tau_wall, i), scene(UNIT, ml(6), tf, background=rng.choice([0.0, 1.0])), o, d)
        else:
            g = [rng.uniform(-1, 1) for _ in range(3)]
            add("wall", "wall_%.0e_ramp_%d" % (tau_wall, i),
                scene(UNIT, {"kind": "linear_ramp", "gradient": g, "offset": 0.5}, tf, background=1.0), o, d)
    # -- long rays through tall boxes --
    tall_rays = [([0.0, 0.0, -31.0], [0.0, 0.0, 1.0]), ([1e-3, 0.0, -31.0], [0.0, 0.0, 1.0]),
                 ([1e-6, 2e-6, -31.0], [0.0, 0.0, 1.0]), ([0.3, -0.2, -31.0], [0.0, 0.0, 1.0]),
                 ([0.0, 0.0, -31.0], [1e-3, 0.0, 1.0]), ([-0.5, 0.1, -31.0], [0.03, 0.0, 1.0]),
                 ([0.0, 0.0, 31.0], [2e-4, -1e-4, -1.0])]
    for fM in ([24] if quick else [6, 12, 24]):
        for j, (o, d) in enumerate(tall_rays[: 3 if quick else 7]):
            add("tall_box", "tall_fM%d_ray%d_default_tf" % (fM, j), scene(TALL, ml(fM), DEFAULT_TF), o, d)
            if j in (0, 1, 4, 5):
                sc0 = scene(TALL, ml(fM), DEFAULT_TF)
                e = interior_extremum(sc0, o, d, rng)
                if e is not None:
                    s, fe, kind = e
                    delta = [1e-6, 1e-9, 1e-12][j % 3]
                    c = float(fe + mpf(delta))
                    add("tall_box", "tall_fM%d_ray%d_jump_%g_above_%s" % (fM, j, delta, kind),
                        scene(TALL, ml(fM), jump_tf(c, (100.0, 5.0), (0.01, 0.08))), o, d)
    # -- far origins with non-unit directions --
    dirs = [[1.0, 0.3, -0.2], [3.0, -2.0, 0.7], [1e-3, 2.5e-4, -3e-4], [1e5, -4e4, 2.5e4], [-0.6, -0.7, 0.3873]]
    tfs = [DEFAULT_TF, jump_tf(0.5, (0.2, 0.3), (1.5, 2.0))]
    for dist in ([1e3, 1e9, 1e15] if quick else [1e3, 1e6, 1e9, 1e12, 1e15]):
        for j, D in enumerate(dirs[: 2 if quick else 5]):
            qn = [rng.uniform(-0.5, 0.5) for _ in range(3)]
            k = dist / math.sqrt(sum(c * c for c in D))
            o = [qn[a] - k * D[a] for a in range(3)]
            fM = [6, 12][j % 2]
            add("far_origin", "far_%.0e_dir%d_fM%d_%s" % (dist, j, fM, "jump" if j % 2 else "default"),
                scene(UNIT, ml(fM), tfs[j % 2]), o, D)
    # -- flat and tiny fields --
    for gmag in ([1e-13, 1e-15] if quick else [1e-8, 1e-10, 1e-13, 1e-15, 1e-300]):
        for off in (0.0, 1e-14, -3e-16):
            ramp = {"kind": "linear_ramp", "gradient": [gmag, 0.0, 0.0], "offset": off}
            add("flat", "ramp_%.0e_offset_%g_jump_at_0" % (gmag, off),
                scene(UNIT, ramp, jump_tf(0.0, (0.5, 0.2), (1.0, 0.7))), [-2.0, 0.1, 0.2], [1.0, 0.3, 0.0])
    for i, (gmag, c) in enumerate([(1e-10, 0.5 + 1e-11), (1e-12, 0.5 - 1e-13), (1e-9, 0.5 + 5e-10), (0.0, 0.5)]):
        ramp = {"kind": "linear_ramp", "gradient": [0.0, gmag, gmag / 2], "offset": 0.5}
        add("flat", "near_constant_%d" % i, scene(UNIT, ramp, kink_tf(c, 1e-9)), [0.3, -2.0, -1.5], [0.1, 1.0, 0.8])
        add("flat", "near_constant_jump_%d" % i, scene(UNIT, ramp, jump_tf(c, (0.2, 3.0), (2.0, 0.1))),
            [0.3, -2.0, -1.5], [0.1, 1.0, 0.8])
    # Marschner-Lobb with alpha 0: f = (1 - sin(pi z/2))/2, flat at z = 1 (its maximum ... minimum)
    add("flat", "ml_alpha0_along_z_top", scene(UNIT, ml(6, 0.0), jump_tf(1e-12, (0.1, 0.2), (1.0, 0.5))),
        [-2.0, 0.3, 1.0], [1.0, 0.2, 0.0])
    # -- faces, edges, corners, grazing --
    face_rays = [
        ("face_z_max", [-2.0, 0.3, 1.0], [1.0, 0.2, 0.0]), ("face_x_min", [-1.0, -2.0, 0.1], [0.0, 1.0, 0.3]),
        ("edge_y1_z1", [-2.0, 1.0, 1.0], [1.0, 0.0, 0.0]), ("edge_x-1_y-1", [-1.0, -1.0, -3.0], [0.0, 0.0, 1.0]),
        ("diagonal_corners", [-3.0, -3.0, -3.0], [1.0, 1.0, 1.0]), ("corner_touch", [2.0, 0.5, 1.0], [-1.0, 0.5, 0.0]),
        ("corner_chord_1e-9", [-1.0 - 1e-9, 1.0 - 2e-9, 0.3], [1.0, 1.0, 0.0]),
        ("grazing_face_1e-9", [-1.5, 0.2, 1.0 - 1e-9], [1.0, 0.1, 1e-9]),
        ("grazing_face_1e-5", [-1.5, -0.4, -1.0 + 1e-5], [1.0, 0.1, -1e-5]),
        ("inside_start", [0.1, 0.2, 0.3], [0.3, -1.0, 0.2]), ("face_y_max_diag", [-2.0, 1.0, -2.0], [1.0, 0.0, 1.0]),
    ]
    for name, o, d in (face_rays[:5] if quick else face_rays):
        add("faces", name + "_ml6", scene(UNIT, ml(6), DEFAULT_TF, background=0.5), o, d)
        add("faces", name + "_ml12_jump", scene(UNIT, ml(12), jump_tf(0.5, (0.2, 0.3), (1.5, 2.0))), o, d)
    # -- grids with anisotropic cells --
    grids = [([5, 9, 61], "node", TALL), ([3, 17, 5], "node", UNIT), ([8, 4, 30], "cell", TALL),
             ([7, 5, 11], "node", UNIT), ([12, 3, 6], "cell", UNIT)]
    for gi, (res, layout, box) in enumerate(grids[: 2 if quick else 5]):
        fld = {"kind": "grid", "resolution": res, "layout": layout, "fM": 6.0, "alpha": 0.25}
        for j in range(2 if quick else 6):
            if box is TALL and j % 2 == 0:
                o, d = [rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9), -31.0], [rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02), 1.0]
            else:
                o, d = chord(rng, box, 1.0)
            sc0 = scene(box, fld, DEFAULT_TF)
            nodes = grid_nodes(sc0)
            rf = ray_field(sc0, o, d, nodes)
            if rf is None:
                continue
            ext = [s for a, b in rf.pieces() for s in rf.extrema(a, b)]
            add("grid", "grid%d_%s_%s_ray%d_default" % (gi, "x".join(map(str, res)), layout, j), sc0, o, d)
            if ext:
                s = ext[rng.randrange(len(ext))]
                delta = deltas[j % 4]
                c = float(rf.f(s) + mpf(delta) * (1 if j % 2 else -1))
                tf = jump_tf(c, (0.3, 0.8), (4.0, 1.5)) if j % 3 else kink_tf(c)
                add("grid", "grid%d_%s_%s_ray%d_%s_%g" % (gi, "x".join(map(str, res)), layout, j,
                                                          "jump" if j % 3 else "kink", delta),
                    scene(box, fld, tf), o, d)
            else:
                add("grid", "grid%d_%s_%s_ray%d_jump_mid" % (gi, "x".join(map(str, res)), layout, j),
                    scene(box, fld, jump_tf(float(rf.f(rf.L / 2)), (0.3, 0.8), (4.0, 1.5))), o, d)
    # opacity/colour convention: a few steep and jump rays
    for i in range(2 if quick else 6):
        o, d = chord(rng, UNIT, 1.0)
        v0 = rng.uniform(0.3, 0.7)
        tf = {"opacity": [[v0, 0.01], [v0, 0.9], [v0 + 1e-6, 0.2]], "color": [[0.0, 1.0], [1.0, 0.2]],
              "unit_length": 0.05}
        add("steep", "opacity_color_jump_%d" % i, scene(UNIT, ml([6, 12][i % 2]), tf), o, d)
    # A jump within ulps of a grid cell's maximum in the ray's last piece (a helper's honesty
    # hunt): no crossing is found there, the band holds the jump, and the ray ends after it.
    o, d = [3.1006335372676284, -2.2928922800354483, 0.610236734093889], \
           [-0.7555947237711041, 0.6500149536977087, -0.08097637543527388]
    fld = {"kind": "grid", "resolution": [7, 5, 11], "layout": "node", "fM": 6.0, "alpha": 0.25}
    sc0 = scene(UNIT, fld, DEFAULT_TF)
    rf = ray_field(sc0, o, d, grid_nodes(sc0))
    last = max(s for a, b in rf.pieces() for s in rf.extrema(a, b))
    assert rf.derivs(last)[1] < 0  # a maximum, as the tags say
    top = float(rf.f(last))
    for ulps in ([-2, 1] if quick else [-4, -2, -1, 0, 1, 2]):
        c = top
        for _ in range(abs(ulps)):
            c = math.nextafter(c, math.copysign(math.inf, ulps))
        add("grid", "grid3_7x5x11_node_last_piece_max_%+dulp" % ulps,
            scene(UNIT, fld, jump_tf(c, (0.3, 0.8), (4.0, 1.5))), o, d)
    # Along x through y = 0.1, z = 0.05: Marschner-Lobb's maximum at x = 0, exactly on a scan
    # point of extrema() (f' is 0 there, no sign change brackets it), above a jump at 0.5.
    add("extremum_jump", "ml6_maximum_on_scan_point_jump_0.5",
        scene(UNIT, ml(6), jump_tf(0.5, (0.2, 0.3), (1.5, 2.0)), background=0.1), [-2.0, 0.1, 0.05], [1.0, 0.0, 0.0])
    return rays


# --------------------------------------------------------------------------------------------
# Truth per ray.


_extrema_cache = {}  # per worker: the rays of one base share a field and a line


def truth_of(job):
    ray, dps = job
    mp.dps = dps if ray["cls"] != "far_origin" else dps + 10
    t_start = time.time()
    sc = ray["scene"]
    nodes = grid_nodes(sc) if sc["field"]["kind"] == "grid" else None
    rf = ray_field(sc, ray["origin"], ray["direction"], nodes)
    tf = TF(sc["tf"])
    out = {"class": ray["cls"], "tag": ray["tag"], "scene": scene_toml(sc),
           "origin": [float(c).hex() for c in ray["origin"]],
           "direction": [float(c).hex() for c in ray["direction"]]}
    if rf is None:
        out.update(truth=mp.nstr(mpf(sc.get("background", 0.0)), 34), hit=False, length=0.0, optical_depth=0.0,
                   pieces=0, floor=0.0, sensitivity=0.0, rounding=0.0, eta=0.0)
    else:
        key = json.dumps([sc["min"], sc["max"], sc["field"], ray["origin"], ray["direction"], mp.dps])
        cache = _extrema_cache.setdefault(key, {})
        r = integrate(rf, tf, sc.get("background", 0.0), extrema_cache=cache)
        eta = field_noise(sc, rf, nodes)
        pointwise = pointwise_of(ray, cache)
        sens = mpf(0)
        for sgn in (1, -1):
            with mp.workdps(SENS_DPS):
                rs = integrate(rf, tf, sc.get("background", 0.0), shift=mpf(sgn * eta), extrema_cache=cache,
                               rtol=mpf(10) ** -19)
            sens = max(sens, abs(rs["I"] - r["I"]))
        out.update(truth=mp.nstr(r["I"], 34),
                   hit=True, length=float(rf.L), optical_depth=float(r["phi"]), stopped=r["stopped"],
                   pieces=r["pieces"], structural=len(rf.pieces()), floor=float(max(sens, r["rounding"], pointwise)),
                   sensitivity=float(sens), rounding=float(r["rounding"]), pointwise=float(pointwise), eta=eta,
                   truth_panels=r["panels"],
                   unresolved_panels=r["unresolved"])
    if nodes is not None:
        out["grid_nodes"] = [v.hex() for v in nodes]
    out["seconds"] = round(time.time() - t_start, 2)
    return out


POINTWISE_DPS = 20  # the pointwise floor needs a few digits


def pointwise_of(ray, extrema_cache=None):
    """The ray's pointwise floor (pointwise_floor), at POINTWISE_DPS digits (+10 far away)."""
    with mp.workdps(POINTWISE_DPS + (10 if ray["cls"] == "far_origin" else 0)):
        sc = ray["scene"]
        nodes = grid_nodes(sc) if sc["field"]["kind"] == "grid" else None
        rf = ray_field(sc, ray["origin"], ray["direction"], nodes)
        if rf is None:
            return mpf(0)
        tf = TF(sc["tf"])
        record = []
        integrate(rf, tf, sc.get("background", 0.0), extrema_cache={}, rtol=mpf(10) ** -12, record=record)
        return pointwise_floor(tf, record, field_noise(sc, rf, nodes))


def add_pointwise_job(ray):
    t = time.time()
    return ray["tag"], float(pointwise_of(ray)), time.time() - t


def add_pointwise(path, rays, jobs):
    """Adds the pointwise floor to an existing data file (its truths unchanged): floor becomes
    the largest of sensitivity, rounding and pointwise."""
    lines = [json.loads(line) for line in open(path)]
    by_tag = {r["tag"]: r for r in rays}
    todo = [by_tag[r["tag"]] for r in lines if "header" not in r and r.get("hit")]
    found = {}
    with multiprocessing.Pool(jobs) as pool:
        for k, (tag, pw, sec) in enumerate(pool.imap_unordered(add_pointwise_job, todo)):
            found[tag] = pw
            print("  [%d/%d] %-50s %.3g %6.1fs" % (k + 1, len(todo), tag, pw, sec), file=sys.stderr)
    for r in lines:
        if "header" in r:
            r["header"]["pointwise_dps"] = POINTWISE_DPS
        elif r.get("hit"):
            r["pointwise"] = found[r["tag"]]
            r["floor"] = max(r["sensitivity"], r["rounding"], r["pointwise"])
    with open(path + ".tmp", "w") as fh:
        for r in lines:
            fh.write(json.dumps(r) + "\n")
    os.replace(path + ".tmp", path)


# --------------------------------------------------------------------------------------------
# Self-check.


def closed_form_checks():
    """Constant field and linear ramp with a linear transfer function against closed forms."""
    mp.dps = DPS
    bad = []
    # constant field (ramp of gradient 0): I = g/tau (1 - e^{-tau L}) + I0 e^{-tau L}
    sc = scene(UNIT, {"kind": "linear_ramp", "gradient": [0.0, 0.0, 0.0], "offset": 0.3},
               {"emission": [[0.0, 0.0], [1.0, 2.0]], "extinction": [[0.0, 0.0], [1.0, 5.0]]}, background=0.7)
    rf = ray_field(sc, [-2.0, 0.1, 0.2], [1.0, 0.2, 0.1])
    r = integrate(rf, TF(sc["tf"]), 0.7)
    g, tau = mpf(0.3) * 2, mpf(0.3) * 5
    exact = g / tau * (1 - mp.exp(-tau * rf.L)) + mpf(0.7) * mp.exp(-tau * rf.L)
    bad.append(("constant", abs(r["I"] - exact)))
    # ramp f = k s + f0 along the ray, g = f, tau = 0: I = int f
    sc = scene(UNIT, {"kind": "linear_ramp", "gradient": [0.25, 0.0, 0.0], "offset": 0.5},
               {"emission": [[0.0, 0.0], [1.0, 1.0]], "extinction": [[0.0, 0.0], [1.0, 0.0]]})
    rf = ray_field(sc, [-2.0, 0.1, 0.2], [1.0, 0.0, 0.0])
    r = integrate(rf, TF(sc["tf"]), 0.0)
    exact = mp.quad(lambda x: mpf(0.5) + mpf(0.25) * x, [-1, 1])
    bad.append(("ramp_no_extinction", abs(r["I"] - exact)))
    # ramp with tau = a f (linear): Phi(s) = a (f0 s + k s^2 / 2), g = b: erf closed form via quad of exp
    sc = scene(UNIT, {"kind": "linear_ramp", "gradient": [0.25, 0.0, 0.0], "offset": 0.5},
               {"emission": [[0.0, 1.5], [1.0, 1.5]], "extinction": [[0.0, 0.0], [1.0, 3.0]]})
    rf = ray_field(sc, [-2.0, 0.1, 0.2], [1.0, 0.0, 0.0])
    r = integrate(rf, TF(sc["tf"]), 0.0)
    f0, k, a = mpf(0.25), mpf(0.25), mpf(3)
    # I = 1.5 int_0^2 exp(-a (f0 s + k s^2/2)) ds = 1.5 sqrt(pi/(2 a k)) e^{a f0^2/(2k)} (erf(..) - erf(..))
    c2 = mp.sqrt(a * k / 2)
    # completing the square: a f0 s + a k s^2/2 = c2^2 (s + f0/k)^2 - a f0^2/(2k)
    u0, u1 = c2 * (f0 / k), c2 * (2 + f0 / k)
    exact = mpf(1.5) * mp.exp(a * f0 ** 2 / (2 * k)) * mp.sqrt(mp.pi) / (2 * c2) * (mp.erf(u1) - mp.erf(u0))
    bad.append(("ramp_linear_tau_erf", abs(r["I"] - exact)))
    return bad


def nested_quad(ray):
    """The truth by nested tanh-sinh (mp.quad of tau inside mp.quad), split at the same breaks."""
    sc = ray["scene"]
    nodes = grid_nodes(sc) if sc["field"]["kind"] == "grid" else None
    rf = ray_field(sc, ray["origin"], ray["direction"], nodes)
    tf = TF(sc["tf"])
    cuts = breaks_of(rf, tf.levels, {})
    phi, total = mpf(0), mpf(0)
    for a, b in zip(cuts, cuts[1:]):
        if not b > a:
            continue
        g, tau = tf.branch(rf.f((a + b) / 2))
        p0 = phi
        total += mp.quad(lambda s: g(rf.f(s)) * mp.exp(-p0 - mp.quad(lambda u: tau(rf.f(u)), [a, s])), [a, b])
        phi += mp.quad(lambda u: tau(rf.f(u)), [a, b])
    return total + mpf(sc.get("background", 0.0)) * mp.exp(-phi)


def self_check(rays, jobs):
    print("closed forms:")
    for name, err in closed_form_checks():
        print("  %-22s |truth - closed form| = %s" % (name, mp.nstr(err, 3)))
        assert err < mpf("1e-28"), name
    rng = random.Random(SEED + 1)
    by_class = {}
    for r in rays:
        by_class.setdefault(r["cls"], []).append(r)
    sample = [rng.choice(v) for v in by_class.values()] + [r for r in rays if r["tag"].startswith("issue20")]
    print("higher dps (50) and a third of the panel length, %d rays:" % len(sample))
    for ray in sample:
        mp.dps = DPS if ray["cls"] != "far_origin" else DPS + 10
        sc = ray["scene"]
        nodes = grid_nodes(sc) if sc["field"]["kind"] == "grid" else None
        rf = ray_field(sc, ray["origin"], ray["direction"], nodes)
        if rf is None:
            continue
        a = integrate(rf, TF(sc["tf"]), sc.get("background", 0.0))["I"]
        mp.dps += 10
        rf = ray_field(sc, ray["origin"], ray["direction"], nodes)
        b = integrate(rf, TF(sc["tf"]), sc.get("background", 0.0), panel_scale=mpf(1) / 3)["I"]
        diff = abs(a - b)
        print("  %-12s %-48s I = %s  diff %s" % (ray["cls"], ray["tag"], mp.nstr(a, 20), mp.nstr(diff, 3)))
        assert diff <= mpf("1e-25") * max(1, abs(a)), ray["tag"]
    print("nested tanh-sinh on short rays:")
    for ray in sample:
        mp.dps = 30
        sc = ray["scene"]
        if sc["field"]["kind"] != "marschner_lobb" or sc["field"]["fM"] > 6 or ray["cls"] in ("opaque", "wall", "tall_box"):
            continue
        t = time.time()
        nodes = None
        rf = ray_field(sc, ray["origin"], ray["direction"], nodes)
        if rf is None:
            continue
        a = integrate(rf, TF(sc["tf"]), sc.get("background", 0.0))["I"]
        b = nested_quad(ray)
        print("  %-48s diff %s (%.0f s)" % (ray["tag"], mp.nstr(abs(a - b), 3), time.time() - t))
        assert abs(a - b) <= mpf("1e-25") * max(1, abs(a)), ray["tag"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="a few dozen rays (about a minute)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "adversarial_rays.jsonl"))
    ap.add_argument("--check", action="store_true", help="self-check the truth instead of writing data")
    ap.add_argument("--only", default="", help="only tags containing this string")
    ap.add_argument("--add-pointwise", action="store_true", help="add the pointwise floor to --out's rays "
                    "(truths unchanged) instead of recomputing them")
    ap.add_argument("--reuse", default="", help="a previous output (or its .partial): rays with the same tag, "
                    "scene and line are taken from it instead of recomputed")
    args = ap.parse_args()
    mp.dps = DPS
    t0 = time.time()
    rays = make_rays(args.quick)
    if args.only:
        rays = [r for r in rays if args.only in r["tag"]]
    print("%d rays (%.0f s to set up)" % (len(rays), time.time() - t0), file=sys.stderr)
    if args.check:
        self_check(rays, args.jobs)
        return
    if args.add_pointwise:
        add_pointwise(args.out, rays, args.jobs)
        return
    jobs = [(r, DPS) for r in rays]
    reused = {}
    if args.reuse:
        for line in open(args.reuse):
            r = json.loads(line)
            if "header" not in r:
                reused[(r["tag"], r["scene"], tuple(r["origin"]), tuple(r["direction"]))] = r
    results = [None] * len(jobs)
    for i, (r, _) in enumerate(jobs):
        key = (r["tag"], scene_toml(r["scene"]), tuple(float(c).hex() for c in r["origin"]),
               tuple(float(c).hex() for c in r["direction"]))
        results[i] = reused.get(key)
    n_reused = sum(r is not None for r in results)  # their seconds are in their own lines
    # Classes interleaved, so that a run cut short (the .partial file) still holds every class.
    by_class = {}
    for i, (r, _) in enumerate(jobs):
        if results[i] is None:
            by_class.setdefault(r["cls"], []).append(i)
    order = []
    while any(by_class.values()):
        for lst in by_class.values():
            if lst:
                order.append(lst.pop(0))
    partial = open(args.out + ".partial", "w")  # rays as they finish, should a run be cut short
    with multiprocessing.Pool(args.jobs) as pool:
        for r in results:
            if r is not None:
                partial.write(json.dumps(r) + "\n")
        for k, res in enumerate(pool.imap(truth_of, [jobs[i] for i in order])):
            results[order[k]] = res
            partial.write(json.dumps(res) + "\n")
            partial.flush()
            print("  [%d/%d] %-10s %-50s %6.1fs" % (k + 1, len(jobs), res["class"], res["tag"], res["seconds"]),
                  file=sys.stderr)
    header = {"header": {"generator": "tests/lib/reference_adversarial/make_adversarial.py",
                         "mpmath": mpmath.__version__, "dps": DPS, "dps_far_origin": DPS + 10,
                         "chebyshev_points": list(NS), "sensitivity_dps": SENS_DPS, "seed": SEED, "quick": args.quick, "rays": len(results),
                         "seconds": round(time.time() - t0, 1), "reused": n_reused, "jobs": args.jobs,
                         "python": sys.version.split()[0], "pointwise_dps": POINTWISE_DPS,
                         "ray_seconds_sum": round(sum(r["seconds"] for r in results), 1)}}
    with open(args.out, "w") as fh:
        fh.write(json.dumps(header) + "\n")
        for r in results:
            fh.write(json.dumps(r) + "\n")
    partial.close()
    os.remove(args.out + ".partial")
    print("wrote %s: %d rays in %.0f s" % (args.out, len(results), time.time() - t0), file=sys.stderr)


if __name__ == "__main__":
    main()
