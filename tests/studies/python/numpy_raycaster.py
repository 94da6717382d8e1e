"""A renderer written in numpy, knowing nothing of vrv: the default scene (Marschner-Lobb,
fM = 6, alpha = 0.25, emission v, extinction v / 2, values clamped to [0, 1], box [-1, 1]^3,
black background), each clipped ray cut into equal segments no longer than `step`, sampled at
their midpoints (second order).  `offset=0.0` plants the classic off-by-half-step error.
`rgba=True` returns (..., 4) instead: the value in R, G and B and the opacity 1 - T in A."""
import numpy as np


def marschner_lobb(p, fM=6.0, alpha=0.25):
    rho = np.cos(2 * np.pi * fM * np.cos(np.pi * np.hypot(p[..., 0], p[..., 1]) / 2))
    return (1 - np.sin(np.pi * p[..., 2] / 2) + alpha * (1 + rho)) / (2 * (1 + alpha))


def clip_to_box(origins, directions):
    """Flat origins, unit directions, and each ray's entry and exit parameters on the box [-1, 1]^3
    by the slab method (t0 >= t1 where a ray misses)."""
    o, d = origins.reshape(-1, 3), directions.reshape(-1, 3)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (-1.0 - o) / d, (1.0 - o) / d
    t0 = np.maximum(np.nanmax(np.minimum(a, b), axis=1), 0.0)
    t1 = np.nanmin(np.maximum(a, b), axis=1)
    return o, d, t0, t1


def render(origins, directions, step, offset=0.5, rgba=False):
    o, d, t0, t1 = clip_to_box(origins, directions)
    hit = t1 > t0
    n = np.where(hit, np.ceil((t1 - t0) / step), 0)
    h = np.where(hit, (t1 - t0) / np.maximum(n, 1), 0.0)
    color, transmittance = np.zeros(len(o)), np.ones(len(o))
    for i in range(int(n.max())):
        t = t0 + (i + offset) * h
        v = np.clip(marschner_lobb(o + t[:, None] * d), 0.0, 1.0)
        g, tau = v, 0.5 * v
        alpha = np.where(i < n, -np.expm1(-tau * h), 0.0)
        color += transmittance * np.divide(g * alpha, tau, out=g * h * (i < n), where=tau > 0)
        transmittance *= 1 - alpha
    if rgba:
        return np.stack([color, color, color, 1 - transmittance], axis=-1).reshape(origins.shape[:-1] + (4,))
    return color.reshape(origins.shape[:-1])


def project(origins, directions, step, mode, planted=None):
    """The default scene's field projected along each ray (no transfer function): `mode` "mip"
    (the largest sample) or "xray" (the trapezoid rule), on n = ceil(L / step) equal steps whose
    n + 1 nodes include entry and exit (second order for both).  Planted faults:
    "first_sample_dropped" (MIP without the entry node: first order at maxima on the entry face),
    "step_not_multiplied" (X-ray summing samples without the step: no convergence)."""
    o, d, t0, t1 = clip_to_box(origins, directions)
    hit = t1 > t0
    n = np.where(hit, np.maximum(np.ceil((t1 - t0) / step), 1), 0)
    h = np.where(hit, (t1 - t0) / np.maximum(n, 1), 0.0)
    best, total = np.full(len(o), -np.inf), np.zeros(len(o))
    for i in range(1 if planted == "first_sample_dropped" else 0, int(n.max()) + 1):
        inside = hit & (i <= n)
        v = marschner_lobb(o + (t0 + i * h)[:, None] * d)
        best = np.where(inside, np.maximum(best, v), best)
        weight = np.where((i == 0) | (i == n), 0.5, 1.0) * (1.0 if planted == "step_not_multiplied" else h)
        total += np.where(inside, weight * v, 0.0)
    value = np.where(hit, best, 0.0) if mode == "mip" else total
    return value.reshape(origins.shape[:-1])
