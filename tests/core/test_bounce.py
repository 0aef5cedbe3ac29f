"""Bounce model, surfaces (CPR), ball mark and multi-bounce flight (issue 4)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core.ball import Ball
from tennislab.core.bounce import bounce, bounce_batch, court_pace_rating
from tennislab.core.flight import FlightParams
from tennislab.core.mark import ball_mark, contact_displacement, depth_in_halfplane, depth_in_rect
from tennislab.core.rally import fly_bounces, fly_bounces_batch
from tennislab.core.surfaces import Surface, cpr_category, cpr_formula, get_surface, surface_names
from tennislab.errors import InputError

BALL = Ball()
R = BALL.radius
ALPHA = BALL.inertia_factor


def test_slide_matches_brody():
    s = Surface("slippery", e=0.8, mu=0.3)
    vin, vz = 30.0, -8.0
    res = bounce((vin, 0, vz), (0, 0, 0), s)
    assert res.mode == "slide"
    assert res.velocity_out[0] == pytest.approx(vin - 0.3 * 1.8 * 8.0, rel=1e-12)
    assert res.velocity_out[2] == pytest.approx(0.8 * 8.0, rel=1e-12)
    # R w2 = mu (1 + e) v_z1 / alpha  (Brody 1984), topspin about +y for a ball moving +x
    assert R * res.spin_out[1] == pytest.approx(0.3 * 1.8 * 8.0 / ALPHA, rel=1e-12)


def test_roll_is_three_fifths_for_thin_shell():
    s = Surface("sticky", e=0.8, mu=2.0)
    res = bounce((10.0, 0, -8.0), (0, 0, 0), s)
    assert res.mode == "roll"
    assert res.velocity_out[0] == pytest.approx(0.6 * 10.0, rel=1e-12)
    assert res.velocity_out[0] == pytest.approx(R * res.spin_out[1], rel=1e-12)  # rolls out


def test_roll_with_spin_brody_formula():
    s = Surface("sticky", e=0.7, mu=2.0)
    vx, w = 12.0, -150.0
    res = bounce((vx, 0, -6.0), (0, w, 0), s)
    assert res.velocity_out[0] == pytest.approx((vx + ALPHA * R * w) / (1 + ALPHA), rel=1e-12)


def test_grip_reverses_slip_by_ex():
    s = Surface("grippy", e=0.8, mu=2.0, e_x=0.2)
    res = bounce((10.0, 1.0, -8.0), (5.0, 20.0, 3.0), s)
    assert res.mode == "grip"
    slip_out = np.array([res.velocity_out[0] - R * res.spin_out[1], res.velocity_out[1] + R * res.spin_out[0]])
    assert np.allclose(slip_out, -0.2 * res.slip_in, rtol=1e-12, atol=1e-12)
    assert res.spin_out[2] == 3.0


def test_bad_input():
    with pytest.raises(InputError, match="velocity_in"):
        bounce((10, 0, 1.0), (0, 0, 0), "hard")
    with pytest.raises(InputError, match="surface"):
        get_surface("ice")
    with pytest.raises(InputError, match="surface mu"):
        Surface("x", e=0.8, mu=-0.1)


vel = st.tuples(st.floats(-60, 60), st.floats(-60, 60), st.floats(-40, -0.05))
spin = st.tuples(st.floats(-600, 600), st.floats(-600, 600), st.floats(-600, 600))
surf = st.builds(
    lambda e, mu, ex: Surface("h", e=e, mu=mu, e_x=ex), st.floats(0.05, 1.0), st.floats(0.0, 1.5), st.floats(0.0, 0.5)
)


@settings(max_examples=200, deadline=None)
@given(vel, spin, surf)
def test_invariants(v, w, s):
    """Angular momentum about the contact point is conserved (all impulses act there),
    energy never increases, v_z,out = e |v_z,in|, the slip never grows."""
    m, I = BALL.mass, BALL.inertia
    res = bounce(v, w, s, BALL)
    vo, wo = res.velocity_out, res.spin_out
    Ly_in, Ly_out = I * w[1] + m * R * v[0], I * wo[1] + m * R * vo[0]
    Lx_in, Lx_out = I * w[0] - m * R * v[1], I * wo[0] - m * R * vo[1]
    scale = m * R * 60 + I * 600
    assert abs(Ly_in - Ly_out) < 1e-12 * scale and abs(Lx_in - Lx_out) < 1e-12 * scale
    e_in = 0.5 * m * np.dot(v, v) + 0.5 * I * np.dot(w, w)
    e_out = 0.5 * m * np.dot(vo, vo) + 0.5 * I * np.dot(wo, wo)
    assert e_out <= e_in * (1 + 1e-12)
    assert vo[2] == pytest.approx(-s.e * v[2], rel=1e-12)
    slip_out = np.hypot(vo[0] - R * wo[1], vo[1] + R * wo[0])
    assert slip_out <= np.hypot(*res.slip_in) * (1 + 1e-12) + 1e-12


@settings(max_examples=50, deadline=None)
@given(vel, spin, st.floats(0, 2 * math.pi))
def test_isotropy(v, w, phi):
    """Rotating the incoming state about the vertical rotates the outcome."""
    c, s_ = math.cos(phi), math.sin(phi)
    Rz = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
    s = get_surface("clay")
    a = bounce(v, w, s)
    b = bounce(Rz @ v, Rz @ w, s)
    assert np.allclose(Rz @ a.velocity_out, b.velocity_out, atol=1e-9)
    assert np.allclose(Rz @ a.spin_out, b.spin_out, atol=1e-7)


def test_batch_equals_scalar():
    rng = np.random.default_rng(1)
    v = np.column_stack([rng.uniform(-40, 40, 50), rng.uniform(-5, 5, 50), rng.uniform(-20, -1, 50)])
    w = rng.uniform(-400, 400, (50, 3))
    vo, wo, modes = bounce_batch(v, w, "hard")
    for i in range(50):
        r = bounce(v[i], w[i], "hard")
        assert np.allclose(r.velocity_out, vo[i], rtol=0, atol=1e-12)
        assert np.allclose(r.spin_out, wo[i], rtol=0, atol=1e-9)


# ---------------------------------------------------------------- surfaces and CPR
def test_cpr_formula():
    assert cpr_formula(0.81, 1.0) == 0.0
    assert cpr_formula(0.75, 0.53) == pytest.approx(56.0)
    assert [cpr_category(c) for c in (10, 29, 29.4, 30, 34, 35, 39, 40, 44, 45, 80)] == [
        "slow",
        "slow",
        "slow",
        "medium-slow",
        "medium-slow",
        "medium",
        "medium",
        "medium-fast",
        "medium-fast",
        "fast",
        "fast",
    ]


@pytest.mark.parametrize("name", ["clay", "grass", "hard", "carpet"])
def test_surfaces_reproduce_their_category(name):
    s = get_surface(name)
    assert s.source and s.category
    res = court_pace_rating(s)
    assert res["category"] == s.category
    assert res["e"] == pytest.approx(s.e, rel=1e-12)
    if res["mode"] == "slide":  # the ITF formula recovers the sliding friction
        assert res["mu"] == pytest.approx(s.mu, rel=1e-12)
    else:  # gripping: apparent friction below mu
        assert res["mu"] < s.mu


def test_clay_grips_at_itf_angle():
    """reference-data.md: at the ITF angle a rigid ball rolls out once mu exceeds ~0.7."""
    assert court_pace_rating("clay")["mode"] == "roll"
    assert court_pace_rating(Surface("x", e=0.9, mu=0.65))["mode"] == "slide"


def test_user_surface_and_registry():
    assert set(["clay", "grass", "hard", "carpet"]) <= set(surface_names())
    s = get_surface("hard", mu=0.5)
    assert s.mu == 0.5 and get_surface("hard").mu != 0.5


# ---------------------------------------------------------------- the mark
def test_mark_vertical_drop_is_round():
    mk = ball_mark((1.0, 2.0), (0.0, 0.0, -7.06), (0.0, 0.0, 5.3), (0, 0, 0), "hard")
    assert mk.length == pytest.approx(mk.width, rel=1e-9)
    dmax = 7.06 * 4.5e-3 / math.pi
    assert mk.compression == pytest.approx(dmax)
    assert mk.width == pytest.approx(2 * math.sqrt(2 * R * dmax - dmax**2), rel=1e-3)
    assert np.allclose(mk.center, (1.0, 2.0))


def test_mark_sliding_displacement_and_size():
    s = get_surface("grass")
    vin = np.array([30.0, 0.0, -8.0])
    res = bounce(vin, (0, 0, 0), s)
    assert res.mode == "slide"
    mk = ball_mark((5.0, 0.0), vin, res.velocity_out, (0, 0, 0), s)
    T = 4.5e-3
    assert mk.displacement[0] == pytest.approx(T * (vin[0] + res.velocity_out[0]) / 2, rel=1e-3)
    d = np.empty(2)
    contact_displacement(vin[0], vin[1], res.velocity_out[0], res.velocity_out[1], vin[2], s.mu, s.e, T, d)
    assert d[0] == pytest.approx(mk.displacement[0], rel=1e-3)
    # the footprint: its travel plus (at most) a patch diameter; never wider than the ball
    assert mk.displacement[0] < mk.length < mk.displacement[0] + 2 * R
    assert mk.width <= 2 * R
    assert mk.skid > 0


def test_contact_displacement_grip_matches_mark():
    s = get_surface("clay")
    vin = np.array([12.0, 3.0, -9.0])
    res = bounce(vin, (0, 0, 0), s)
    assert res.mode == "roll"
    mk = ball_mark((0.0, 0.0), vin, res.velocity_out, (0, 0, 0), s)
    d = np.empty(2)
    contact_displacement(vin[0], vin[1], res.velocity_out[0], res.velocity_out[1], vin[2], s.mu, s.e, 4.5e-3, d)
    assert np.allclose(d, mk.displacement, rtol=2e-3)


def test_depth_functions():
    discs = np.array([[0.0, 0.0, 0.01]])
    rect = (0.02, 1.0, -1.0, 1.0)
    assert depth_in_rect(discs, rect) == pytest.approx(-0.01)
    assert depth_in_rect(discs, (-0.5, 0.005, -1, 1)) == pytest.approx(0.015)
    corner = depth_in_rect(discs, (0.03, 1, 0.04, 1))
    assert corner == pytest.approx(-(0.05 - 0.01))
    assert depth_in_halfplane(discs, 0, 0.02, -1.0) == pytest.approx(0.03)  # inside is x <= 0.02
    off = np.array([[0.0, 0.0], [0.05, 0.0]])
    assert np.allclose(depth_in_halfplane(discs, 0, 0.02, -1.0, off), [0.03, -0.02])


# ---------------------------------------------------------------- multi-bounce flight
def test_fly_bounces_chain_and_batch():
    params = FlightParams()
    pos, v, w = (-11.885, 0.3, 2.8), (48.0, -0.5, -3.0), (0.0, 250.0, 40.0)
    r = fly_bounces(pos, v, w, params, surface="hard", bounces=3)
    assert len(r.bounces) == 3 and len(r.segments) == 4
    ts = [b.t for b in r.bounces]
    assert all(b > a for a, b in zip(ts, ts[1:]))
    # each segment starts where the contact model leaves the ball
    b0 = r.bounces[0]
    y1 = r.segments[1].y[0]
    assert y1[2] == pytest.approx(R, abs=1e-8)
    assert np.allclose(y1[:2], np.array([b0.x, b0.y]) + b0.mark.displacement, atol=1e-12)
    assert r.segments[1].t[0] == pytest.approx(b0.t + 4.5e-3)
    speeds = [np.linalg.norm(b.velocity_in) for b in r.bounces]
    assert speeds[0] > speeds[1] > speeds[2]
    out = fly_bounces_batch(np.array([list(pos) + list(v) + list(w)] * 2), params, surface="hard", bounces=3)
    for j, b in enumerate(r.bounces):
        assert out["x"][0, j] == pytest.approx(b.x, abs=2e-5)
        assert out["y"][0, j] == pytest.approx(b.y, abs=2e-5)
        assert out["t"][0, j] == pytest.approx(b.t, abs=1e-6)
        assert np.allclose(out["vout"][0, j], b.velocity_out, atol=1e-4)


@settings(max_examples=100, deadline=None)
@given(vel, spin, st.sampled_from(["clay", "grass", "hard", "carpet"]))
def test_mark_invariants(v, w, name):
    s = get_surface(name)
    res = bounce(v, w, s)
    mk = ball_mark((1.0, -2.0), v, res.velocity_out, w, s)
    across = mk.discs[:, :2] @ np.array([-mk.direction[1], mk.direction[0]])
    assert 0 <= mk.width <= 2 * R + np.ptp(across) + 1e-12
    assert mk.length >= np.hypot(*mk.displacement) - 1e-12
    assert mk.length >= mk.width - 1e-9 or mk.length > 0.9 * mk.width
    assert mk.skid >= 0 and mk.compression <= R
    # the first-contact point lies inside the mark's footprint (its first disc has radius 0 there)
    assert depth_in_rect(mk.discs, (1.0 - 1e-9, 1.0 + 1e-9, -2.0 - 1e-9, -2.0 + 1e-9)) >= 0


def test_rally_stops_when_rolling():
    s = Surface("dead", e=0.05, mu=0.5)
    r = fly_bounces((-5.0, 0.0, 0.2), (3.0, 0.0, 0.0), (0, 0, 0), surface=s, bounces=10)
    assert len(r.bounces) < 10 and r.bounces[-1].velocity_out[2] < 0.05
    assert len(r.segments) == len(r.bounces)
