"""The one serve pipeline: simulate, window and monte_carlo honour every flight setting alike.

Issue 21's lossy-converter bug: the window and the Monte Carlo rebuilt the flight physics from a
few fields and silently flew the default ``t_max``, ``net_obstacle``, ``inertia_factor`` and court.
Each setting is changed here from its default; each workflow must show its effect, and the three
must agree on the same serve (the window's cell = the single serve to round-off; the zero-scatter
Monte Carlo within 0.1 mm: tabulated impacts at 200 steps, flights at 5 x the batch tolerance).
"""

import math

import numpy as np
import pytest

from tennislab.core.court import Court
from tennislab.core.flight import FlightParams
from tennislab.serve import monte_carlo, simulate, window
from tennislab.serve.pipeline import launch, launch_3d, make_setup

ALPHA, BETA = 44.0, 19.0  #: a professional's topspin serve that goes in (2-D and, at azimuth 6, the deuce box)
THREE_D = {"target": "deuce", "server_y": -0.5, "azimuth_deg": 6.0}


def seed(**options) -> FlightParams:
    return FlightParams.from_options(preset="seed000", **options)


def three_ways(flight: FlightParams, alpha=ALPHA, beta=BETA, **kw):
    """(single serve, window cell, zero-scatter Monte Carlo) of the same serve and physics."""
    s = simulate("pro", alpha, beta, flight=flight, advice=False, **kw)
    w = window("pro", alpha_deg=[alpha], beta_deg=[beta], flight=flight, **kw)
    m = monte_carlo("pro", alpha, beta, n=20, sd_angle=0, sd_speed=0, sd_azimuth=0, flight=flight, **kw)
    return s, w, m


def agree(s, w, m, landed=True):
    """The three workflows say the same about the serve."""
    assert bool(w.success[0, 0]) == s.success
    assert m.p_success == (1.0 if s.success else 0.0)
    if landed:
        assert w.landing_x[0, 0] == pytest.approx(s.landing_x, abs=1e-9)
        assert m.landing["mean"][0] == pytest.approx(s.landing["x"], abs=1e-4)
        assert m.landing["mean"][1] == pytest.approx(s.landing["y"], abs=1e-4)
        assert m.n_landed == m.n
    else:
        assert math.isnan(s.landing_x) and math.isnan(w.landing_x[0, 0])
        assert m.n_landed == 0 and m.landing["mean"] == [None, None]


def test_base_serve_goes_in_alike():
    s, w, m = three_ways(seed())
    assert s.success
    agree(s, w, m)
    s3, w3, m3 = three_ways(seed(), **THREE_D)
    assert s3.success
    agree(s3, w3, m3)


def test_wind_is_honoured():
    base = simulate("pro", ALPHA, BETA, flight=seed(), advice=False)
    s, w, m = three_ways(seed(wind=(-6.0, 2.0, 0.0)))  # head wind, blowing to the left
    assert s.landing["x"] < base.landing["x"] - 0.3 and s.landing["y"] > base.landing["y"] + 0.05
    agree(s, w, m)


def test_t_max_is_honoured():
    base = simulate("pro", ALPHA, BETA, flight=seed(), advice=False)
    assert base.landing["t"] > 0.4
    s, w, m = three_ways(seed(t_max=0.4))
    assert not s.success and s.verdict.reason == "no-landing" and "0.4 s" in s.verdict.detail
    agree(s, w, m, landed=False)


def test_net_obstacle_is_honoured():
    """alpha 36, beta 21 passes the net plane 0.1 m below the tape: through it by default, stopped with
    the obstacle (no landing in any workflow)."""
    through = three_ways(seed(), 36.0, 21.0)
    assert through[0].verdict.reason == "net"
    agree(*through)
    s, w, m = three_ways(seed(net_obstacle=True), 36.0, 21.0)
    assert s.verdict.reason == "net" and "stops" in s.verdict.detail
    agree(s, w, m, landed=False)


def test_inertia_factor_is_honoured():
    """The ball's moment of inertia enters the impact through the flight's ball: a solid ball (0.4)
    leaves with more spin than the thin shell (2/3), in every workflow."""
    base = simulate("pro", ALPHA, BETA, flight=seed(), advice=False)
    s, w, m = three_ways(seed(inertia_factor=0.4))
    assert s.spin_rpm > base.spin_rpm * 1.1
    assert w.spin_rpm[0] == pytest.approx(s.spin_rpm, rel=1e-12)
    assert s.landing["x"] != pytest.approx(base.landing["x"], abs=1e-3)
    agree(s, w, m)


def test_court_is_honoured():
    """A higher net (flight events) and a shorter service box (the judgement) of the flight's court."""
    base = simulate("pro", ALPHA, BETA, flight=seed(), advice=False, **THREE_D)
    assert base.success and base.landing["x"] > 4.5
    h = 0.914 + base.net_clearance + 0.05
    high_net = seed(court=Court(net_center_height=h, net_post_height=h + 0.156))
    s, w, m = three_ways(high_net, **THREE_D)
    assert s.verdict.reason == "net" and s.net_clearance < 0
    agree(s, w, m)
    short_box = seed(court=Court(service_line=4.0))
    s, w, m = three_ways(short_box, **THREE_D)
    assert s.verdict.reason == "long" and "4.00 m" in s.verdict.detail
    agree(s, w, m)


def test_launch_stage_is_the_3d_impact_algebra():
    """Stage 2's kernel: velocity v_n n + v_t t and spin omega (t x n) on the face basis of
    core.impact_3d, plus the toss's part outside the impact plane."""
    from tennislab.core.impact_3d import face_basis

    rng = np.random.default_rng(0)
    vn, vt, w = rng.uniform(20, 50, 50), rng.uniform(-5, 15, 50), rng.uniform(-300, 600, 50)
    b, psi = rng.uniform(-0.5, 1.2, 50), rng.uniform(-0.6, 0.6, 50)
    brush, toss = -0.7, -3.0
    setup = make_setup("pro", flight=seed(), target="deuce", brush_deg=math.degrees(brush), toss_vz=toss)
    states = launch(setup, vn, vt, w, b, psi)
    n, tu, tl = face_basis(b, psi)
    t = math.cos(brush) * tu + math.sin(brush) * tl
    up = np.array([0.0, 0.0, toss])
    off = up - (n @ up)[:, None] * n - (t @ up)[:, None] * t
    np.testing.assert_allclose(states[:, 3:6], vn[:, None] * n + vt[:, None] * t + off, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(states[:, 6:9], w[:, None] * np.cross(t, n), rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(states[:, :3], np.tile([-11.885, 0.0, 3.0], (50, 1)))
    vel, spin = launch_3d(vn, vt, w, b, psi, brush)
    np.testing.assert_allclose(vel, vn[:, None] * n + vt[:, None] * t, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(spin, states[:, 6:9], rtol=1e-13, atol=1e-12)


def test_advice_with_a_falling_toss_skips_impacts_the_racket_cannot_make():
    """A falling toss: at alpha near 90 deg the racket no longer approaches the ball; the advice scans skip
    those impacts instead of failing."""
    r = simulate("pro", 36, 18, target="deuce", server_y=-0.5, azimuth_deg=6, brush_deg=-30, toss_vz=-2)
    assert r.verdict.reason == "net" and isinstance(r.verdict.advice, str)


@pytest.mark.parametrize(
    ("kw", "frag"),
    [
        ({"flat_max_rpm": 5000.0, "topspin_min_rpm": 100.0}, "topspin_min_rpm: the topspin band's start 100 rpm"),
        ({"flat_max_rpm": -1.0}, "flat_max_rpm: -1 rpm is outside the allowed range [0, 10000] rpm"),
        ({"topspin_min_rpm": float("nan")}, "topspin_min_rpm: "),
    ],
)
def test_spin_classes_out_of_order_or_range_are_refused_by_the_criteria(kw, frag):
    """The serve's spin classes are checked where they are defined (SeedCriteria), for Python and the CLI."""
    from tennislab.errors import InputError
    from tennislab.serve import SeedCriteria

    with pytest.raises(InputError) as e:
        SeedCriteria(**kw)
    assert str(e.value).startswith(frag) and "\n" not in str(e.value)
    assert SeedCriteria(flat_max_rpm=2000.0, topspin_min_rpm=2000.0).category([1999.0, 2000.0, 2001.0]).tolist() == [
        0,
        2,
        1,
    ]
