"""The fixed-step sampler (core.integrators.sweep_positions) against an independent SciPy integration
of the same right-hand side, with drag and lift scales (the track fit's model)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tennislab.core.aero import get_aero_model
from tennislab.core.dynamics import derivative_call
from tennislab.core.flight import FlightParams
from tennislab.core.integrators import sweep_positions


def _sweep(params: FlightParams, y0, t0, times, h, sd=1.0, sl=1.0, decay=0.0):
    k = params.k
    w = params.atmosphere.wind
    out = np.full((times.size, 3), np.nan)
    kern = params.aero.kernel
    for direction, sel in ((1.0, np.nonzero(times >= t0)[0]), (-1.0, np.nonzero(times < t0)[0][::-1])):
        if sel.size:
            sweep_positions(
                np.ascontiguousarray(y0, dtype=float), t0, times, np.ascontiguousarray(sel), sel.size,
                direction * h, kern, params.aero.params, k * sd, k * sl, params.atmosphere.gravity,
                params.ball.radius, w[0], w[1], w[2], decay, out,
            )  # fmt: skip
    return out


def _reference(params: FlightParams, y0, t0, times, sd=1.0, sl=1.0, decay=0.0):
    k = params.k
    w = params.atmosphere.wind
    kern, ap = params.aero.kernel, params.aero.params

    def f(t, y):
        out = np.empty(9)
        derivative_call(np.ascontiguousarray(y), out, kern, ap, k * sd, k * sl, params.atmosphere.gravity,
                        params.ball.radius, w[0], w[1], w[2], decay)  # fmt: skip
        return out

    out = np.empty((times.size, 3))
    for sel in (times >= t0, times < t0):
        ts = times[sel]
        if ts.size:
            end = ts.max() if ts[0] >= t0 else ts.min()
            sol = solve_ivp(f, (t0, end), y0, method="DOP853", rtol=1e-12, atol=1e-13, dense_output=True)
            out[sel] = sol.sol(ts).T[:, :3]
    return out


@pytest.mark.parametrize("model", ["choppin2018", "stepanek1988", "constant"])
@pytest.mark.parametrize("scales", [(1.0, 1.0, 0.0), (1.2, 0.8, 0.3), (0.7, 1.4, 0.0)])
def test_sweep_matches_scipy_with_scales(model, scales):
    """Forward and backward from a mid-flight state, 50 Hz samples, steps of 16 ms: within 1 um of
    DOP853 at rtol 1e-12 on the same equations (the drag and lift scales and a spin decay included)."""
    sd, sl, decay = scales
    params = FlightParams(aero=get_aero_model(model), atmosphere=FlightParams().atmosphere)
    rng = np.random.default_rng(7)
    for _ in range(4):
        v = rng.uniform(10, 50) * np.array([1.0, rng.uniform(-0.15, 0.15), rng.uniform(-0.2, 0.2)])
        w = rng.uniform(-400, 400, 3)
        y0 = np.concatenate([[-2.0, 0.3, 1.5], v, w])
        times = np.round(np.arange(-0.4, 0.5, 0.02), 10) + 0.003
        got = _sweep(params, y0, 0.0, times, 16e-3, sd, sl, decay)
        ref = _reference(params, y0, 0.0, times, sd, sl, decay)
        assert np.max(np.abs(got - ref)) < 1e-6


def test_scales_act_on_the_coefficients():
    """s_D = 1.2 on C_D 0.55 flies exactly as C_D 0.66 (and s_L on C_L likewise): the scales are the
    coefficients' and nothing else."""
    y0 = np.array([-11.0, 0.0, 1.0, 30.0, 1.0, 5.0, 0.0, 200.0, 0.0])
    times = np.linspace(0.0, 0.8, 41)
    a = _sweep(FlightParams(aero=get_aero_model("constant", cd=0.55, cl=0.2)), y0, 0.0, times, 8e-3, 1.2, 1.5)
    b = _sweep(FlightParams(aero=get_aero_model("constant", cd=0.66, cl=0.3)), y0, 0.0, times, 8e-3)
    assert np.max(np.abs(a - b)) < 1e-12
