"""The line-call fit flies core's kernel: checked against a SciPy reference of the same model.

The reference here is written out independently of tennislab (gravity, drag -k s_D C_D |u| u, Magnus
lift k s_L C_L |u| (w_hat x u), spin decay -lambda w; seed 000 eqs 1-2 with the fit's drag and lift
scales) and integrated by SciPy's DOP853 at rtol 1e-12, so a slip in the fit's right-hand side, its
scales, its spin decay or its integrator shows here.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from tennislab.core.aero import constant
from tennislab.core.flight import FlightParams
from tennislab.core.rally import fly_bounces
from tennislab.core.surfaces import get_surface
from tennislab.linecall import model as M
from tennislab.linecall.fit import fit_track
from tennislab.linecall.synth import synthetic_track

CD, CL = 0.55, 0.25


def _reference_rhs(params: FlightParams, s_d: float, s_l: float):
    k, g, lam = params.k, params.atmosphere.gravity, params.spin_decay

    def rhs(_t, y):
        u, w = y[3:6], y[6:9]
        su, sw = np.linalg.norm(u), np.linalg.norm(w)
        a = -k * s_d * CD * su * u - np.array([0.0, 0.0, g])
        if sw > 0 and su > 0:
            a = a + k * s_l * CL * su * np.cross(w / sw, u)
        return np.r_[u, a, -lam * w]

    return rhs


@pytest.mark.parametrize(("s_d", "s_l", "decay"), [(1.0, 1.0, 0.0), (1.2, 0.7, 0.0), (0.9, 1.3, 0.5)])
def test_fit_model_matches_scipy_reference(s_d, s_l, decay):
    """Pre-bounce positions of the fit's model (parametrised at the bounce, flown backward by
    core.integrators.sweep_positions at the fit's 16 ms step) within 20 um of the reference over 1 s."""
    params = FlightParams.from_options(aero=constant(CD, CL), spin_decay=decay)
    xb, yb, tb = 10.0, 1.2, 1.0
    v_in, w_in = np.array([22.0, -1.5, -6.0]), np.array([30.0, -250.0, 40.0])
    p = M.default_params()
    p[[M.P_XB, M.P_YB, M.P_TB]] = xb, yb, tb
    p[M.P_VIN], p[M.P_WIN] = v_in, w_in
    p[M.P_DRAG], p[M.P_LIFT] = s_d, s_l
    ts = np.linspace(0.0, tb - 1e-3, 60)
    seg = np.zeros(ts.size, dtype=np.int64)
    pos = M.positions(p, ts, seg, params, get_surface("hard"), 0.0045, step=16e-3)
    y0 = np.r_[xb, yb, params.ball.radius, v_in, w_in]
    ref = solve_ivp(_reference_rhs(params, s_d, s_l), (tb, 0.0), y0, method="DOP853", rtol=1e-12, atol=1e-12,
                    dense_output=True)  # fmt: skip
    err = np.linalg.norm(pos - ref.sol(ts)[:3].T, axis=1)
    assert err.max() < 2e-5
    # and the scales matter at this size: the unscaled model is far off when they are not 1
    if (s_d, s_l) != (1.0, 1.0):
        p1 = p.copy()
        p1[M.P_DRAG] = p1[M.P_LIFT] = 1.0
        pos1 = M.positions(p1, ts, seg, params, get_surface("hard"), 0.0045, step=16e-3)
        assert np.linalg.norm(pos1 - ref.sol(ts)[:3].T, axis=1).max() > 0.05


def test_fit_recovers_drag_and_lift_scales_of_a_reference_flight():
    """A noise-free track of a ball whose C_D and C_L are 1.2x and 0.7x the model's (flown by SciPy
    DOP853 through the bounce) is fitted with the free scales at their true values and the bounce
    within 1 mm."""
    truth = FlightParams.from_options(aero=constant(CD * 1.2, CL * 0.7))
    model = FlightParams.from_options(aero=constant(CD, CL))
    pos, vel, spin = (-11.0, 0.8, 1.0), (24.0, 0.5, 5.0), (0.0, 250.0, 0.0)
    tr = synthetic_track(pos, vel, spin, truth, rate=50.0, sigma=1e-4, seed=3)
    f = fit_track(tr.t, tr.xyz, np.full(tr.t.size, 1e-4), model, "hard", drag="free", lift="free")
    assert f.drag_scale == pytest.approx(1.2, abs=0.01)
    assert f.lift_scale == pytest.approx(0.7, abs=0.01)
    assert np.hypot(f.p[0] - tr.bounce.x, f.p[1] - tr.bounce.y) < 1e-3
    # the same ball flown by core with the scales folded into the coefficients lands where the fit says
    b = fly_bounces(pos, vel, spin, truth, surface="hard", bounces=1).bounces[0]
    assert f.t_bounce == pytest.approx(b.t, abs=1e-3)
