"""Rollers (seed 002 eqs 8-17) and power (eqs 18-31, corrected): closed forms and the seed's figures."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core.ball import Ball
from tennislab.errors import InputError
from tennislab.launcher.machine import MachineSpec
from tennislab.launcher.power import power_report
from tennislab.launcher.rollers import ball_from_rollers, roller_geometry, roller_report, roller_speeds
from tennislab.units import KMH, RPM

V200 = 200 * KMH


def test_geometry_closed_form():
    g = roller_geometry()
    assert g.gap == pytest.approx(0.05) and g.deformed_radius == pytest.approx(0.025)
    assert g.deformation == pytest.approx(2 * 0.0335 - 0.05)
    assert math.cos(g.grab_angle) == pytest.approx(0.125 / (0.1 + 0.0335))
    assert math.degrees(g.grab_angle) == pytest.approx(20.556, abs=1e-3)
    with pytest.raises(InputError, match="cannot grip"):
        roller_geometry(MachineSpec(roller_axis_distance=0.3))


def test_seed_roller_speeds():
    """Seed 002 section 6: ~5300 rpm for 200 km/h without spin; 5800 / 4800 rpm with 2000 rpm."""
    r = roller_report(V200, 0.0)
    assert r.rpm1 == pytest.approx(5300, rel=0.005) and r.rpm2 == r.rpm1
    r = roller_report(V200, 2000 * RPM)
    assert r.rpm1 == pytest.approx(4800, rel=0.002)  # eq 16 (the seed's text swaps 1 and 2)
    assert r.rpm2 == pytest.approx(5800, rel=0.002)


@settings(max_examples=60, deadline=None)
@given(st.floats(30 * KMH, 200 * KMH), st.floats(-2000 * RPM, 2000 * RPM))
def test_roller_speeds_invert_eqs_14_15(v, w):
    w1, w2 = roller_speeds(v, w, 0.1, 0.025)
    v_back, w_back = ball_from_rollers(w1, w2, 0.1, 0.025)
    assert v_back == pytest.approx(v, rel=1e-12)
    assert w_back == pytest.approx(w, abs=1e-9)


def test_pull_in_and_throw_conditions():
    r = roller_report(100 * KMH, 0.0)
    assert r.pulls_in and math.degrees(r.friction_angle) == pytest.approx(64.0, abs=0.01)
    # friction below tan(grab angle) = 0.375: the ball is not pulled in (eq 9)
    assert not roller_report(100 * KMH, 0.0, friction=0.3).pulls_in
    assert roller_report(100 * KMH, 0.0, friction=0.4).pulls_in
    # eq 13: N = E s dl / 2r; no slip iff 2 mu N >= m V^2 / (2 L)
    n = 4.2e6 * 2.12e-4 * 0.017 / 0.067
    assert r.normal_force == pytest.approx(n)
    vmax = r.max_no_slip_speed
    assert roller_report(0.99 * vmax, 0.0).throws and not roller_report(1.01 * vmax, 0.0).throws
    assert 130 < vmax / KMH < 150  # with the seed's E, mu and implied s: slips above ~140 km/h


def test_power_reproduces_seed_figures():
    """Seed 002 section 7: ~45 W for a 1 s throw; 35 s start-up at 45 W (roller mass 2 kg implied)."""
    p = power_report(V200, 0.0)
    assert p.throw_power == pytest.approx(45, rel=0.02)
    assert p.startup_time == pytest.approx(35, rel=0.02)


@settings(max_examples=40, deadline=None)
@given(st.floats(30 * KMH, 200 * KMH), st.floats(-2000 * RPM, 2000 * RPM), st.floats(0.5, 10), st.booleans())
def test_power_energy_conservation(v, w, mass, slip):
    ball = Ball()
    p = power_report(v, w, roller_mass=mass, slip=slip)
    e_ball = 0.5 * ball.mass * v**2 + 0.5 * ball.inertia * w**2
    assert p.ball_energy == pytest.approx(e_ball)
    assert p.energy_per_throw == pytest.approx(e_ball * (2 if slip else 1), rel=1e-9)
    # each roller loses exactly its work: 1/2 I_r (w0^2 - w^2) = W_i
    for w0, w1, work in zip(p.omega0, p.omega, p.work):
        assert 0.5 * p.roller_inertia * (w0**2 - w1**2) == pytest.approx(work, rel=1e-9, abs=1e-9)
    # momentum and angular momentum of the ball
    assert p.impulse[0] + p.impulse[1] == pytest.approx(ball.mass * v)
    assert (p.impulse[1] - p.impulse[0]) * 0.025 == pytest.approx(ball.inertia * w, abs=1e-12)


def test_startup_scales_with_roller_mass_and_power():
    a = power_report(V200, 0.0, roller_mass=2.0, motor_power=45)
    b = power_report(V200, 0.0, roller_mass=4.0, motor_power=45)
    c = power_report(V200, 0.0, roller_mass=2.0, motor_power=90)
    assert c.startup_time == pytest.approx(a.startup_time / 2)
    # doubling the roller mass doubles the flywheel energy, the ball's share stays
    assert b.startup_time == pytest.approx(2 * a.startup_time - a.work[0] / 45, rel=1e-3)
    with pytest.raises(InputError, match="roller_mass"):
        power_report(V200, 0.0, roller_mass=0)
