"""The spin that lands a candidate nearest the target, within the tolerances, on the machine's steps.

A candidate of the search (:mod:`._search`) is a launch whose landing L0 [m] is known (flown, or
predicted) for a spin vector omega_b (two components about the flight, topspin and sidespin [rpm],
:func:`~.preferences.spin_rpm_components`), with the sensitivity J [m/rpm] of its landing to those
components.  The Magnus force of the seed's model is linear in omega (Wojcicki, Pucilowski & Kulesza
2010, eq 3), so the landing is nearly linear in it::

    L(omega) = L0 + J (omega - omega_b)

The spins allowed (:class:`~.preferences.Tolerances`) are the disc |omega - omega_asked| <= tol
and, with an axis tolerance, the box |w - w_asked| <= tol, |g - g_asked| <= tol_g of rate w and axis
angle g; the machine dials w in 1 rpm and g in 1 deg steps.  :func:`variants` finds, per
candidate, the continuous optimum in the disc (a 2 x 2 trust-region problem, :func:`trust_step`)
and in the box (projected Gauss-Newton in (w, g)), then for the axis steps around each optimum the
best rate on that axis (a 1-D least-squares problem clipped to the allowed interval of rates on it)
rounded both ways, and the rounding of the asked spin: the quantised spins worth flying, with their
predicted misses.

References
----------
Nocedal & Wright (2006), Numerical Optimization, 2nd ed., chapter 4 (the trust-region subproblem).
Wojcicki, Pucilowski & Kulesza (2010), Acta Mech. Autom. 4(4) (seed 002: spin rate and axis steps).
"""

from __future__ import annotations

import functools
import math

import numba as nb
import numpy as np

from tennislab.launcher.machine import Range
from tennislab.launcher.preferences import Tolerances, wrap_deg


def _rate_intervals(g, w0, g0, tol_w, tol_g):
    """Per axis angle g [deg] (any shape), the allowed rates: the disc's interval and the box's
    ([lo, hi], NaN if none)."""
    dg = np.radians(wrap_deg(g - g0))
    c, s = np.cos(dg), np.sin(dg)
    disc = tol_w * tol_w - (w0 * s) ** 2
    root = np.sqrt(np.maximum(disc, 0.0))
    d_lo = np.where(disc >= 0, w0 * c - root, np.nan)
    d_hi = np.where(disc >= 0, w0 * c + root, np.nan)
    in_box = (tol_g > 0) & (w0 > 0) & (np.abs(np.degrees(dg)) <= tol_g + 1e-9)
    b_lo = np.where(in_box, w0 - tol_w, np.nan)
    b_hi = np.where(in_box, w0 + tol_w, np.nan)
    return (d_lo, d_hi), (b_lo, b_hi)


#: More axis steps than this (a disc around a slow asked spin holds every axis): each candidate tries the
#: :data:`NEAR_AXES` steps either side of its continuous optimum's axis instead
MAX_AXES = 41
NEAR_AXES = 4


def _near_axes(J, rx, ry, w0, g0, tol_w, gr: Range) -> np.ndarray:
    """Per candidate (n, 2 NEAR_AXES + 1) axis steps [deg] around the axis of its optimum in the disc
    (the least-squares spin, pulled back onto the disc)."""
    o0 = w0 * np.array([np.cos(np.radians(g0)), np.sin(np.radians(g0))])
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    det = np.where(np.abs(det) > 1e-300, det, 1e-300)
    # omega minimising |r + J omega|: -J^-1 r
    ox = -(J[:, 1, 1] * rx - J[:, 0, 1] * ry) / det
    oy = -(-J[:, 1, 0] * rx + J[:, 0, 0] * ry) / det
    d = np.stack([ox - o0[0], oy - o0[1]], axis=1)
    nd = np.hypot(d[:, 0], d[:, 1])
    d *= np.where(nd > tol_w, tol_w / np.maximum(nd, 1e-300), 1.0)[:, None]
    ang = np.degrees(np.arctan2(o0[1] + d[:, 1], o0[0] + d[:, 0]))
    base = gr.lo + np.round((ang - gr.lo) / gr.step) * gr.step
    return np.round(wrap_deg(base[:, None] + np.arange(-NEAR_AXES, NEAR_AXES + 1)[None, :] * gr.step), 9)


def axis_steps(asked: tuple[float, float], tol: Tolerances, gr: Range) -> np.ndarray:
    """Every axis step [deg] on which some rate is allowed (the disc's and the box's axis ranges)."""
    return _axis_steps(float(asked[0]), float(asked[1]), tol, gr).copy()


@functools.lru_cache(maxsize=64)
def _axis_steps(w0: float, g0: float, tol: Tolerances, gr: Range) -> np.ndarray:
    """:func:`axis_steps`, kept for the last requests (a search asks for the same steps several times)."""
    if tol.spin_rpm == 0 and (tol.spin_axis_deg == 0 or w0 == 0):
        return np.array([gr.quantise(g0)])
    if tol.spin_rpm >= w0:
        half = 180.0  # the disc holds the origin: every axis
    else:
        half = np.degrees(np.arcsin(tol.spin_rpm / w0)) if tol.spin_rpm > 0 else 0.0
        if tol.spin_axis_deg > 0 and w0 > 0:
            half = max(half, tol.spin_axis_deg)
    if half >= 180.0:
        g = gr.lo + np.arange(int(round((gr.hi - gr.lo) / gr.step)) + 1) * gr.step
    else:
        k0 = np.ceil((g0 - half - 1e-9 - gr.lo) / gr.step)
        k1 = np.floor((g0 + half + 1e-9 - gr.lo) / gr.step)
        g = gr.lo + np.arange(k0, k1 + 1) * gr.step
    g = np.unique(np.round(wrap_deg(g), 9))
    return g[(g >= gr.lo - 1e-9) & (g <= gr.hi + 1e-9)]


def variants(L0, J, omega_b, target, asked: tuple[float, float], tol: Tolerances, wr: Range, gr: Range):
    """Quantised spins worth flying for each of n candidates (module docstring).

    ``L0`` (n, 2) [m] landings with the spin ``omega_b`` (n, 2) [rpm components], ``J`` (n, 2, 2)
    [m/rpm]; ``asked`` (rate [rpm], axis [deg]) as asked (not rounded).  For every allowed axis step
    (:func:`axis_steps`) the best rate on it under the linear model, clipped to the rates allowed on
    that axis and rounded down and up to the rate steps, and the rounding of the asked spin.
    Returns (rate (n, k), axis (n, k), predicted miss (n, k) [m]); a variant outside the tolerances
    has miss inf.  One compiled pass (:func:`_variants_kernel`; its NumPy reference is in tests/launcher/test_spin.py).
    """
    L0, J, omega_b = (np.ascontiguousarray(x, dtype=float) for x in (L0, J, omega_b))
    n = L0.shape[0]
    w0, g0 = float(asked[0]), float(asked[1])
    g = _axis_steps(w0, g0, tol, gr)
    if g.size > MAX_AXES:  # the disc holds the origin (a slow asked spin): the axes near each optimum
        tx, ty = float(target[0]), float(target[1])
        r0x = L0[:, 0] - J[:, 0, 0] * omega_b[:, 0] - J[:, 0, 1] * omega_b[:, 1] - tx
        r0y = L0[:, 1] - J[:, 1, 0] * omega_b[:, 0] - J[:, 1, 1] * omega_b[:, 1] - ty
        g = np.ascontiguousarray(_near_axes(J, r0x, r0y, w0, g0, tol.spin_rpm, gr))
    else:
        g = np.ascontiguousarray(g.reshape(1, -1))
    k = 1 + 2 * g.shape[1]
    W, G, miss = np.empty((n, k)), np.empty((n, k)), np.empty((n, k))
    _variants_kernel(
        L0,
        J,
        omega_b,
        float(target[0]),
        float(target[1]),
        w0,
        g0,
        float(tol.spin_rpm),
        float(tol.spin_axis_deg),
        float(wr.lo),
        float(wr.hi),
        float(wr.step),
        _quantised(wr, w0),
        _quantised(gr, g0),
        g,
        W,
        G,
        miss,
    )
    return W, G, miss


@functools.lru_cache(maxsize=64)
def _quantised(rng: Range, value: float) -> float:
    """``rng.quantise(value)`` as a float, kept for the last requests."""
    return float(rng.quantise(value))


_RAD = math.pi / 180.0


@nb.njit(cache=True, error_model="numpy")
def _wrap(x: float) -> float:
    return (x + 180.0) % 360.0 - 180.0


@nb.njit(cache=True, error_model="numpy")
def _round9(x: float) -> float:
    return np.rint(x * 1e9) / 1e9  # NumPy's round(x, 9)


@nb.njit(cache=True, error_model="numpy")
def _intervals(g, w0, g0, tol_w, tol_g, w_lo, w_hi, out):
    """The rates allowed on axis g [deg] (the disc's interval, the box's; clipped to the machine's rates,
    NaN if none), cos g, sin g and whether g is within the axis tolerance into ``out`` (7,)."""
    dg = _wrap(g - g0) * _RAD
    c, s = math.cos(dg), math.sin(dg)
    disc = tol_w * tol_w - (w0 * s) ** 2
    root = math.sqrt(max(disc, 0.0))
    in_box = tol_g > 0 and w0 > 0 and abs(dg * (180.0 / math.pi)) <= tol_g + 1e-9
    out[0], out[1] = (max(w0 * c - root, w_lo), min(w0 * c + root, w_hi)) if disc >= 0 else (np.nan, np.nan)
    out[2], out[3] = (max(w0 - tol_w, w_lo), min(w0 + tol_w, w_hi)) if in_box else (np.nan, np.nan)
    out[4], out[5] = math.cos(g * _RAD), math.sin(g * _RAD)
    out[6] = 1.0 if abs(_wrap(g - g0)) <= tol_g + 1e-9 else 0.0


@nb.njit(cache=True, error_model="numpy")
def _best_rate(w_opt, iv):
    """The allowed rate (intervals ``iv`` of :func:`_intervals`) nearest w_opt, NaN if none."""
    best = np.nan
    for k in (0, 2):
        lo, hi = iv[k], iv[k + 1]
        if math.isnan(lo) or math.isnan(hi):
            continue
        w_c = min(max(w_opt, lo), hi)
        if math.isfinite(w_c) and lo <= hi and (not math.isfinite(best) or abs(w_c - w_opt) < abs(best - w_opt)):
            best = w_c
    return best


@nb.njit(cache=True, error_model="numpy")
def _variants_kernel(L0, J, om, tx, ty, w0, g0, tol_w, tol_g, w_lo, w_hi, w_step, w_q, g_q, axes, W, G, miss):
    """:func:`variants` for n candidates and their axes ((n, m), or (1, m) shared by all): fills W, G, miss
    (n, 1 + 2 m) (no fast-math: the rounding to the steps is NumPy's, bit for bit)."""
    n = L0.shape[0]
    na, m = axes.shape
    iv = np.empty((na, m, 7))
    for r in range(na):
        for j in range(m):
            _intervals(axes[r, j], w0, g0, tol_w, tol_g, w_lo, w_hi, iv[r, j])
    a0x, a0y = w0 * math.cos(g0 * _RAD), w0 * math.sin(g0 * _RAD)
    cq, sq = math.cos(g_q * _RAD), math.sin(g_q * _RAD)
    near_q = abs(_wrap(g_q - g0)) <= tol_g + 1e-9
    box = tol_g > 0 and w0 > 0
    tol2 = (tol_w + 1e-9) ** 2
    for i in range(n):
        r = i if na > 1 else 0
        j00, j01, j10, j11 = J[i, 0, 0], J[i, 0, 1], J[i, 1, 0], J[i, 1, 1]
        r0x = L0[i, 0] - j00 * om[i, 0] - j01 * om[i, 1] - tx
        r0y = L0[i, 1] - j10 * om[i, 0] - j11 * om[i, 1] - ty
        _variant_into(i, 0, w_q, g_q, cq, sq, near_q, r0x, r0y, J, w0, w_q, g_q, cq, sq, near_q, w_lo, w_hi, a0x, a0y,
                      tol2, tol_w, box, W, G, miss)  # fmt: skip
        for jj in range(m):  # each axis step: the best rate on it, rounded down (variant 1 + jj) and up (1 + m + jj)
            g, cg, sg, near = axes[r, jj], iv[r, jj, 4], iv[r, jj, 5], iv[r, jj, 6] > 0.5
            jx, jy = j00 * cg + j01 * sg, j10 * cg + j11 * sg
            w_opt = -(jx * r0x + jy * r0y) / (jx * jx + jy * jy)
            if not math.isfinite(w_opt):
                w_opt = w0
            best = _best_rate(w_opt, iv[r, jj])
            k = math.floor(((best if math.isfinite(best) else w0) - w_lo) / w_step)
            for up in range(2):
                _variant_into(i, 1 + jj + up * m, w_lo + (k + up) * w_step, g, cg, sg, near, r0x, r0y, J, w0, w_q,
                              g_q, cq, sq, near_q, w_lo, w_hi, a0x, a0y, tol2, tol_w, box, W, G, miss)  # fmt: skip


@nb.njit(cache=True, error_model="numpy", inline="always")
def _variant_into(i, j, w, g, cg, sg, near, r0x, r0y, J, w0, w_q, g_q, cq, sq, near_q, w_lo, w_hi, a0x, a0y, tol2,
                  tol_w, box, W, G, miss):  # fmt: skip
    """Variant j of candidate i of :func:`_variants_kernel`: rate ``w`` [rpm] (clipped to the machine's rates and
    rounded as NumPy's round(x, 9)) on axis g [deg] (cos, sin; within the axis tolerance: ``near``), its predicted
    miss (inf outside the tolerances) into W, G, miss."""
    w = _round9(min(max(w, w_lo), w_hi))
    if w == 0.0:
        g, cg, sg, near = g_q, cq, sq, near_q  # zero spin: one axis (the same flight)
    W[i, j], G[i, j] = w, g
    ox, oy = w * cg, w * sg
    ok = (ox - a0x) ** 2 + (oy - a0y) ** 2 <= tol2
    ok = ok or (box and near and abs(w - w0) <= tol_w + 1e-9) or (w == w_q and g == g_q)
    if ok:
        ex, ey = r0x + J[i, 0, 0] * ox + J[i, 0, 1] * oy, r0y + J[i, 1, 0] * ox + J[i, 1, 1] * oy
        miss[i, j] = math.sqrt(ex * ex + ey * ey)
    else:
        miss[i, j] = np.inf


def reach(J: np.ndarray, omega_b, asked: tuple[float, float], tol: Tolerances) -> np.ndarray:
    """Per candidate, an upper bound [m] of how far an allowed spin can move its landing (pruning)."""
    w0, g0 = float(asked[0]), np.radians(float(asked[1]))
    o0 = w0 * np.array([np.cos(g0), np.sin(g0)])
    box = tol.spin_rpm + (w0 + tol.spin_rpm) * np.radians(tol.spin_axis_deg) if w0 > 0 else 0.0
    radius = np.hypot(*(np.asarray(omega_b, dtype=float) - o0).T) + max(tol.spin_rpm, box)
    J = np.asarray(J, dtype=float)
    a = J[:, 0, 0] * J[:, 0, 0] + J[:, 1, 0] * J[:, 1, 0]  # J^T J = [[a, b], [b, c]]
    b = J[:, 0, 0] * J[:, 0, 1] + J[:, 1, 0] * J[:, 1, 1]
    c = J[:, 0, 1] * J[:, 0, 1] + J[:, 1, 1] * J[:, 1, 1]
    tr, det = a + c, a * c - b**2
    sigma = np.sqrt(np.maximum(0.5 * (tr + np.sqrt(np.maximum(tr * tr - 4 * det, 0.0))), 0.0))
    return sigma * radius


__all__ = ["axis_steps", "reach", "variants"]
