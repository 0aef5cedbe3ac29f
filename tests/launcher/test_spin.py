"""The compiled spin variants of the aim's search against their NumPy reference."""

import numpy as np
import pytest

from tennislab.launcher import _spin
from tennislab.launcher.machine import DEFAULT_SPEC, Range
from tennislab.launcher.preferences import Tolerances


def variants_reference(L0, J, omega_b, target, asked: tuple[float, float], tol: Tolerances, wr: Range, gr: Range):
    """:func:`tennislab.launcher._spin.variants` in NumPy, the reference of its compiled kernel.

    ``L0`` (n, 2) [m] landings with the spin ``omega_b`` (n, 2) [rpm components], ``J`` (n, 2, 2)
    [m/rpm]; ``asked`` (rate [rpm], axis [deg]) as asked (not rounded).  For every allowed axis step
    (:func:`axis_steps`) the best rate on it under the linear model, clipped to the rates allowed on
    that axis and rounded down and up to the rate steps, and the rounding of the asked spin.
    Returns (rate (n, k), axis (n, k), predicted miss (n, k) [m]); a variant outside the tolerances
    has miss inf.
    """
    L0, J, omega_b = (np.asarray(x, dtype=float) for x in (L0, J, omega_b))
    n = L0.shape[0]
    w0, g0 = float(asked[0]), float(asked[1])
    j00, j01, j10, j11 = (J[:, i, k][:, None] for i in (0, 1) for k in (0, 1))
    tx, ty = float(target[0]), float(target[1])
    r0x = (L0[:, 0] - J[:, 0, 0] * omega_b[:, 0] - J[:, 0, 1] * omega_b[:, 1] - tx)[
        :, None
    ]  # L(omega) - T = r0 + J omega
    r0y = (L0[:, 1] - J[:, 1, 0] * omega_b[:, 0] - J[:, 1, 1] * omega_b[:, 1] - ty)[:, None]
    g = _spin.axis_steps(asked, tol, gr)
    if g.size > _spin.MAX_AXES:  # the disc holds the origin (a slow asked spin): the axes near each optimum
        g = _spin._near_axes(J, r0x[:, 0], r0y[:, 0], w0, g0, tol.spin_rpm, gr)
    else:
        g = np.broadcast_to(g, (n, g.size))
    cg, sg = np.cos(np.radians(g)), np.sin(np.radians(g))
    jx, jy = j00 * cg + j01 * sg, j10 * cg + j11 * sg  # J e_g (n, m)
    with np.errstate(invalid="ignore", divide="ignore"):
        w_opt = -(jx * r0x + jy * r0y) / (jx * jx + jy * jy)
    w_opt = np.nan_to_num(w_opt, nan=w0, posinf=w0, neginf=w0)
    best = np.full(w_opt.shape, np.nan)
    for lo, hi in _spin._rate_intervals(g, w0, g0, tol.spin_rpm, tol.spin_axis_deg):
        lo, hi = np.maximum(lo, wr.lo), np.minimum(hi, wr.hi)
        with np.errstate(invalid="ignore"):
            w_c = np.clip(w_opt, lo, hi)
            better = np.isfinite(w_c) & (lo <= hi)
            better &= ~np.isfinite(best) | (np.abs(w_c - w_opt) < np.abs(best - w_opt))
        best = np.where(better, w_c, best)
    k = np.floor((np.where(np.isfinite(best), best, w0) - wr.lo) / wr.step)
    w_q, g_q = wr.quantise(w0), gr.quantise(g0)
    W = np.concatenate([np.full((n, 1), w_q), wr.lo + k * wr.step, wr.lo + (k + 1) * wr.step], axis=1)
    G = np.concatenate([np.full((n, 1), g_q), g, g], axis=1)
    W = np.round(np.clip(W, wr.lo, wr.hi), 9)
    G = np.where(W == 0.0, g_q, G)  # zero spin: one axis (the same flight)
    gg = np.radians(G)
    ox, oy = W * np.cos(gg), W * np.sin(gg)
    miss = np.hypot(r0x + j00 * ox + j01 * oy, r0y + j10 * ox + j11 * oy)
    ok = tol.allows(W, G, w0, g0) | ((W == w_q) & (G == g_q))
    return W, G, np.where(ok, miss, np.inf)


@pytest.mark.parametrize(
    "asked,tol",
    [
        ((1000.0, 0.0), Tolerances()),
        ((300.4, 12.6), Tolerances()),
        ((40.0, 180.0), Tolerances()),  # a slow spin: the disc holds every axis (the axes near each optimum)
        ((0.0, 0.0), Tolerances(3.0, 100.0, 0.0)),
        ((1500.0, -45.0), Tolerances(3.0, 0.0, 10.0)),
        ((1995.0, 170.0), Tolerances(3.0, 250.0, 30.0)),  # the rate's upper bound, the axis wrapping
        ((500.0, 0.0), Tolerances(0.0, 0.0, 0.0)),
    ],
)
def test_compiled_variants_are_the_reference(asked, tol):
    rng = np.random.default_rng(3)
    n = 200
    L0 = np.column_stack([rng.uniform(5, 12, n), rng.uniform(-4, 4, n)])
    J = rng.normal(0.0, 2e-4, (n, 2, 2))
    J[:5] = 0.0  # no sensitivity: the asked rate
    om = np.column_stack([rng.uniform(-2000, 2000, n), rng.uniform(-500, 500, n)])
    T = (8.7, 1.3)
    got = _spin.variants(L0, J, om, T, asked, tol, DEFAULT_SPEC.spin, DEFAULT_SPEC.spin_axis)
    ref = variants_reference(L0, J, om, T, asked, tol, DEFAULT_SPEC.spin, DEFAULT_SPEC.spin_axis)
    assert np.array_equal(got[0], ref[0]) and np.array_equal(got[1], ref[1])
    assert np.array_equal(np.isinf(got[2]), np.isinf(ref[2]))
    fin = np.isfinite(ref[2])
    assert fin.any() and np.allclose(got[2][fin], ref[2][fin], rtol=1e-12, atol=1e-12)
