"""The flight engine against closed-form solutions (issue 2)."""

import math

import numpy as np
import pytest

from tennislab.core.aero import get_aero_model
from tennislab.core.atmosphere import Atmosphere
from tennislab.core.ball import Ball
from tennislab.core.flight import FlightParams, fly_batch, fly_dense, initial_state

BALL = Ball(mass=0.057, radius=0.0335)


def params(cd=0.0, cl=0.0, rho=1.2, g=9.81):
    return FlightParams(
        ball=BALL,
        atmosphere=Atmosphere(density=rho, gravity=g),
        aero=get_aero_model("constant", cd=cd, cl=cl),
        t_max=60.0,
    )


@pytest.mark.parametrize("v", [(20.0, 3.0, 8.0), (50.0, -1.0, -2.0), (5.0, 0.0, 25.0)])
def test_vacuum_parabola_exact(v):
    p = params(rho=0.0)
    x0 = np.array([-11.0, 0.5, 2.5])
    g, r = 9.81, BALL.radius
    vz = v[2]
    t_land = (vz + math.sqrt(vz * vz + 2 * g * (x0[2] - r))) / g
    exp_x = x0[0] + v[0] * t_land
    exp_y = x0[1] + v[1] * t_land
    tr = fly_dense(x0, v, (0, 0, 0), p)
    assert tr.landing.t == pytest.approx(t_land, abs=1e-12)
    assert tr.landing.x == pytest.approx(exp_x, abs=1e-9)
    assert tr.landing.y == pytest.approx(exp_y, abs=1e-9)
    tb = fly_batch(initial_state(x0, v), p)
    assert tb["land_x"][0] == pytest.approx(exp_x, abs=1e-8)
    assert tb["land_t"][0] == pytest.approx(t_land, abs=1e-10)
    # apex of a parabola: z0 + vz^2 / 2g
    if vz > 0:
        assert tr.apex.z == pytest.approx(x0[2] + vz * vz / (2 * g), abs=1e-9)
        assert tb["apex_z"][0] == pytest.approx(x0[2] + vz * vz / (2 * g), abs=1e-8)


def test_vertical_fall_quadratic_drag_tanh():
    cd, rho, g = 0.55, 1.2, 9.81
    p = params(cd=cd, rho=rho, g=g)
    k = 0.5 * rho * BALL.area * cd / BALL.mass
    vt = math.sqrt(g / k)  # terminal velocity
    z0, r = 30.0, BALL.radius
    # z(t) = z0 - vt^2/g ln cosh(g t / vt);  v(t) = -vt tanh(g t / vt)
    t_land = vt / g * math.acosh(math.exp((z0 - r) * g / vt**2))
    v_land = -vt * math.tanh(g * t_land / vt)
    tr = fly_dense((0.0, 0.0, z0), (0.0, 0.0, 0.0), (0, 0, 0), p)
    assert tr.landing.t == pytest.approx(t_land, rel=1e-9)
    assert tr.landing.velocity[2] == pytest.approx(v_land, rel=1e-8)
    tb = fly_batch(initial_state((0.0, 0.0, z0), (0, 0, 0)), p)
    assert tb["land_t"][0] == pytest.approx(t_land, rel=1e-6)  # batch tolerance 2e-7
    assert tb["land_vz"][0] == pytest.approx(v_land, rel=1e-6)


def test_terminal_velocity_reached():
    p = params(cd=0.55)
    k = 0.5 * 1.2 * BALL.area * 0.55 / BALL.mass
    vt = math.sqrt(9.81 / k)
    tb = fly_batch(initial_state((0.0, 0.0, 500.0), (0, 0, 0)), p)
    assert -tb["land_vz"][0] == pytest.approx(vt, rel=1e-4)
    assert -tb["land_vz"][0] < vt * (1 + 5e-6)  # never faster than terminal (to solver tolerance)


def test_horizontal_drag_only_seed001_eqs_4_5():
    """Seed 001 eqs 4-5: v = m v0 / (m + k v0 t), x = m/k ln(1 + k v0 t / m), k = 1/2 c rho A."""
    cd, rho = 0.6, 1.2
    p = FlightParams(
        ball=BALL, atmosphere=Atmosphere(density=rho, gravity=0.0), aero=get_aero_model("constant", cd=cd), t_max=2.0
    )
    kk = 0.5 * cd * rho * BALL.area
    m, v0 = BALL.mass, 40.0
    tr = fly_dense((-10.0, 0.0, 1.0), (v0, 0.0, 0.0), (0, 0, 0), p)
    assert tr.landing is None
    for t in (0.1, 0.5, 1.0, 1.9):
        st = tr.sol(t)
        assert st[0] + 10.0 == pytest.approx(m / kk * math.log(1 + kk * v0 * t / m), rel=1e-9)
        assert st[3] == pytest.approx(m * v0 / (m + kk * v0 * t), rel=1e-9)
    # the net plane is reached when x = 10 m: t = m (exp(10 k / m) - 1) / (k v0)
    t_net = m * (math.exp(10 * kk / m) - 1) / (kk * v0)
    assert tr.net.t == pytest.approx(t_net, rel=1e-9)
    tb = fly_batch(initial_state((-10.0, 0.0, 1.0), (v0, 0, 0)), p)
    assert tb["net_t"][0] == pytest.approx(t_net, rel=1e-7)  # 0.1 um at 35 m/s
    assert tb["status"][0] == 1  # no landing without gravity


def test_pure_magnus_circle():
    """No gravity, no drag, constant C_L: a circle of radius m v / F = 1 / (k C_L)."""
    cl, rho = 0.3, 1.2
    p = FlightParams(
        ball=BALL,
        atmosphere=Atmosphere(density=rho, gravity=0.0),
        aero=get_aero_model("constant", cd=0.0, cl=cl),
        t_max=3.0,
    )
    k = 0.5 * rho * BALL.area / BALL.mass
    R = 1.0 / (k * cl)
    v0 = 30.0
    # spin along +z, velocity along +x: omega x v = +y, so the centre is at (x0, y0 + R)
    tr = fly_dense((-5.0, 0.0, 1.0), (v0, 0.0, 0.0), (0.0, 0.0, 100.0), p)
    ts = np.linspace(0, 3.0, 50)
    st = tr.sol(ts)
    dist = np.hypot(st[0] + 5.0, st[1] - R)
    assert np.allclose(dist, R, rtol=1e-9)
    assert np.allclose(np.hypot(st[3], st[4]), v0, rtol=1e-7)  # dense-output error, long steps
    assert np.allclose(st[2], 1.0, atol=1e-12)


@pytest.mark.parametrize("vz", [0.01, 0.06, 0.5, 3.0, 12.0])
def test_flight_starting_on_the_ground_lands_after_its_hop(vz):
    """A flight starting at z = r going up (a segment after a bounce) lands at 2 vz / g, not at t0.

    SciPy sees the ground event's sign change from 0 at the start, and the batch kernel skipped
    contacts in a step starting at z = r; both are handled (low hops fit inside the first step).
    """
    p = params(rho=0.0)
    r, g = BALL.radius, 9.81
    x0, v = np.array([-5.0, 0.2, r]), np.array([15.0, 1.0, vz])
    t_land = 2 * vz / g
    tr = fly_dense(x0, v, (0, 0, 0), p)
    tb = fly_batch(initial_state(x0, v), p)
    assert tr.landing.t == pytest.approx(t_land, rel=1e-9)
    assert tb["status"][0] == 0
    assert tb["land_t"][0] == pytest.approx(t_land, rel=1e-6)
    assert tb["land_x"][0] == pytest.approx(x0[0] + v[0] * t_land, abs=1e-6)


@pytest.mark.parametrize("vz", [0.0, -2.0])
def test_flight_starting_on_the_ground_not_going_up_lands_at_once(vz):
    p = params(rho=0.0)
    x0, v = np.array([-5.0, 0.0, BALL.radius]), np.array([10.0, 0.0, vz])
    assert fly_dense(x0, v, (0, 0, 0), p).landing.t == pytest.approx(0.0, abs=1e-12)
    tb = fly_batch(initial_state(x0, v), p)
    assert tb["status"][0] == 0 and tb["land_t"][0] == 0.0 and tb["land_x"][0] == -5.0
