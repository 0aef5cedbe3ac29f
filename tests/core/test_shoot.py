"""The aiming primitive core.shoot against an independent reference: its own equations of motion
(seed 002 eqs 1, 3: constant c_d, Magnus 1/2 c_l pi r^3 rho omega x v), SciPy solve_ivp (DOP853,
rtol 1e-11) with a landing / net-plane event, and scipy.optimize.root on the two angles."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import root

from tennislab.core import shoot as S
from tennislab.core.flight import FlightParams
from tennislab.core.launch import frame
from tennislab.errors import InputError
from tennislab.units import KMH, RPM

PARAMS = FlightParams.from_options(preset="seed002")  # launcher2015: c_d 0.55, c_l 0.6
RHO, G = PARAMS.atmosphere.density, PARAMS.atmosphere.gravity
R, M = PARAMS.ball.radius, PARAMS.ball.mass
K = 0.5 * RHO * math.pi * R * R / M
CD, CL = 0.55, 0.6


def _rhs(t, y):
    v, w = y[3:6], y[6:9]
    s = math.sqrt(v @ v)
    acc = -K * CD * s * v + K * CL * R * np.cross(w, v)
    acc[2] -= G
    return np.concatenate([v, acc, np.zeros(3)])


def _reference(p, speed, comps, a, b, at):
    """Landing (x, y) or net-plane crossing (y, z) of one launch by the independent reference."""
    d, h, u = frame(a, b)
    y0 = np.concatenate([p, speed * d, comps[0] * h + comps[1] * u + comps[2] * d])

    def land(t, y):
        return y[2] - R

    def net(t, y):
        return y[0]

    land.terminal, land.direction = True, -1
    net.terminal = True
    ev = land if at == "landing" else net
    sol = solve_ivp(_rhs, (0, 20), y0, method="DOP853", rtol=1e-11, atol=1e-12, events=[ev])
    ye = sol.y_events[0][0]
    return ye[0:2] if at == "landing" else ye[1:3]


def _reference_aim(p, speed, comps, target, start, at="landing"):
    sol = root(lambda x: _reference(p, speed, comps, x[0], x[1], at) - target, start, tol=1e-10)
    assert np.hypot(*sol.fun) < 1e-8, sol.message
    return sol.x


SHOTS = [  # position, speed [m/s], spin components (top, side, along) [rpm], landing target
    ((-12.385, 0.0, 1.0), 90 * KMH, (1000.0, 0.0, 0.0), (9.0, 0.0)),
    ((-12.385, 0.5, 2.0), 110 * KMH, (-600.0, 400.0, 0.0), (8.0, -2.5)),
    ((-11.0, -1.0, 0.4), 70 * KMH, (0.0, 0.0, 0.0), (5.0, 3.0)),
]


@pytest.mark.slow
@pytest.mark.parametrize("branch", ["low", "high"])
def test_both_branches_match_the_independent_reference(branch):
    p = np.array([s[0] for s in SHOTS])
    v = np.array([s[1] for s in SHOTS])
    w = np.array([s[2] for s in SHOTS]) * RPM
    tgt = np.array([s[3] for s in SHOTS])
    res = S.shoot(p, v, tgt, PARAMS, spin=w, branch=branch)
    assert res.converged.all(), res.reason
    for i in range(len(SHOTS)):
        a, b = _reference_aim(p[i], v[i], w[i], tgt[i], [res.elevation[i], res.heading[i]])
        assert res.elevation[i] == pytest.approx(a, abs=2e-6)
        assert res.heading[i] == pytest.approx(b, abs=2e-6)
        assert np.hypot(*(_reference(p[i], v[i], w[i], res.elevation[i], res.heading[i], "landing") - tgt[i])) < 1e-4
    split = res.scan.split
    assert np.all(res.elevation < split) if branch == "low" else np.all(res.elevation > split)


def test_net_targets_match_the_reference_and_a_batch_is_its_rows():
    p = np.array([[-11.6, 0.3, 2.8], [11.5, -0.8, 2.9]])
    v = np.array([50.0, 44.0])
    w = np.array([[1500.0, -800.0, 300.0], [900.0, 500.0, 0.0]]) * RPM
    tgt = np.array([[-1.5, 1.1], [2.0, 1.05]])
    res = S.shoot(p, v, tgt, PARAMS, spin=w, at="net")
    assert res.converged.all() and np.all(res.miss < 1e-4)
    for i in range(2):
        a, b = _reference_aim(p[i], v[i], w[i], tgt[i], [res.elevation[i], res.heading[i]], at="net")
        assert res.elevation[i] == pytest.approx(a, abs=2e-6) and res.heading[i] == pytest.approx(b, abs=2e-6)
        one = S.shoot(p[i], v[i], tgt[i], PARAMS, spin=w[i], at="net")
        assert one.elevation[0] == pytest.approx(res.elevation[i], abs=1e-9)


def test_on_steps_is_the_nearest_neighbour_of_the_reference():
    p, v, w, tgt = (np.array(x, float) for x in SHOTS[0])
    w = w * RPM
    steps = (np.radians(np.arange(-20, 81)), np.radians(np.arange(-40, 41)))
    res = S.shoot(p, v, tgt, PARAMS, spin=w, steps=steps, step_extra=(1, 1))
    on = res.on_steps
    assert on.valid[0].sum() == 16  # floor-1 .. ceil+1 of both angles
    ref = [
        np.hypot(*(_reference(p, v, w, a, b, "landing") - tgt))
        for a, b in zip(on.elevation[0][on.valid[0]], on.heading[0][on.valid[0]])
    ]
    assert np.nanmin(on.miss[0]) == pytest.approx(min(ref), abs=1e-4)
    k = on.best[0]
    assert on.miss[0, k] == pytest.approx(min(ref), abs=1e-4)
    assert math.degrees(on.elevation[0, k]) == round(math.degrees(on.elevation[0, k]))  # on a step
    assert 0.1 < on.miss[0, k] < 0.5  # rounding the angles alone misses by decimetres (docs/launcher.md)


def test_no_solution_says_why():
    p = np.array([[-12.385, 0.0, 1.0]] * 3)
    v = np.array([30 * KMH, 200 * KMH, 150 * KMH])
    tgt = np.array([[11.5, 0.0], [-11.0, 0.0], [-7.0, 0.0]])
    res = S.shoot(p, v, tgt, PARAMS, branch="high")
    assert [S.REASONS[r] for r in res.reason] == [
        "beyond the reach",
        "nearer than the shortest flight",
        "no such branch",
    ]
    assert not res.converged.any()
    assert res.scan.reach[0, 1] < 23.885  # the longest flight at 30 km/h falls short of the target
    with pytest.raises(InputError, match="^branch: 'middle' is not one of low, high"):
        S.shoot(p, v, tgt, PARAMS, branch="middle")
    with pytest.raises(InputError, match="^position: a launch point lies on the net plane"):
        S.shoot([0.0, 0.0, 1.0], 20.0, (0.0, 1.0), PARAMS, at="net")


def test_a_start_and_bounds_skip_the_scan():
    p, v, w, tgt = (np.array(x, float) for x in SHOTS[1])
    w = w * RPM
    scanned = S.shoot(p, v, tgt, PARAMS, spin=w)
    started = S.shoot(p, v, tgt, PARAMS, spin=w, start=(scanned.elevation + 0.02, scanned.heading - 0.01))
    assert started.scan is None and started.flights < 30 < scanned.flights
    assert started.elevation[0] == pytest.approx(scanned.elevation[0], abs=1e-6)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.floats(2.0, 11.5),
    st.floats(-4.0, 4.0),
    st.floats(60.0, 160.0),
    st.floats(-2000.0, 2000.0),
    st.floats(-2000.0, 2000.0),
    st.floats(0.3, 3.0),
    st.sampled_from(["low", "high"]),
)
def test_property_converged_shots_land_on_their_branch(x, y, kmh, top, side, height, branch):
    p = np.array([-12.385, 0.0, height])
    res = S.shoot(p, kmh * KMH, (x, y), PARAMS, spin=np.array([top, side, 0.0]) * RPM, branch=branch)
    if not res.converged[0]:
        assert res.reason[0] != S.OK
        return
    assert res.miss[0] < 10 * S.TOL
    assert np.hypot(res.table["land_x"][0] - x, res.table["land_y"][0] - y) < 10 * S.TOL
    split = res.scan.split[0]
    assert res.elevation[0] <= split + math.radians(3.0) if branch == "low" else res.elevation[0] >= split - 0.06
