"""The net as an obstacle (issue 13): a ball meeting the net stops there, in both integration paths."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core.events import (
    COL,
    COLUMNS,
    FLIGHT_EVENTS,
    OBSTACLE_EVENTS,
    STATUS_BAD_START,
    STATUS_NET,
    STATUS_OK,
    event_array,
)
from tennislab.core.flight import FlightParams, fly_batch, fly_dense, initial_state
from tennislab.errors import InputError
from tennislab.units import RPM

PASS = FlightParams()
STOP = FlightParams(net_obstacle=True)
R = PASS.ball.radius
COURT = PASS.court


def _state(pos, vel, spin=(0.0, 0.0, 0.0)):
    return initial_state(pos, vel, spin)


def test_default_is_pass_through_and_the_option_round_trips():
    assert PASS.net_obstacle is False and PASS.events() == FLIGHT_EVENTS
    assert STOP.events() == OBSTACLE_EVENTS
    assert FlightParams.from_options(net_obstacle=True).net_obstacle
    assert FlightParams.from_dict(STOP.to_dict()) == STOP
    with pytest.raises(InputError, match="net_obstacle"):
        FlightParams(net_obstacle="yes")  # type: ignore[arg-type]


@pytest.mark.parametrize("x0,vx,y0", [(-11.885, 30.0, 0.0), (11.885, -30.0, 2.0), (-8.0, 25.0, -5.0)])
def test_ball_into_the_net_stops_at_the_net(x0, vx, y0):
    s = _state((x0, y0, 1.0), (vx, 0.0, 1.0), (0.0, 30.0, 0.0))
    side = math.copysign(1.0, x0)
    tr = fly_dense(s[:3], s[3:6], s[6:], STOP)
    tb = fly_batch(s, STOP)
    c = tr.net_contact
    assert tr.landing is None and c is not None
    assert c.position[0] == pytest.approx(side * R, abs=1e-9)  # the ball's surface on the plane x = 0
    assert c.z <= COURT.net_height(c.y) and c.part == "mesh"  # below the tape
    assert tr.net.result == "net" and tr.net.t == c.t and tr.net.clearance < 0
    assert tr.t[-1] == c.t and np.array_equal(tr.y[-1], np.concatenate([c.position, c.velocity, c.spin]))
    assert tb["status"][0] == STATUS_NET and tb.net_result[0] == "net" and not tb.ok[0]
    assert np.isnan(tb["land_x"][0])
    for k, want in (("net_hit_t", c.t), ("net_hit_x", c.position[0]), ("net_hit_y", c.y), ("net_hit_z", c.z)):
        assert tb[k][0] == pytest.approx(want, abs=2e-6), k
    assert tb["net_hit_vx"][0] == pytest.approx(c.velocity[0], abs=1e-5)
    assert tb["net_t"][0] == tb["net_hit_t"][0] and tb["net_z"][0] == tb["net_hit_z"][0]
    # without the obstacle the same ball flies through (the crossing says "net") and lands
    assert fly_dense(s[:3], s[3:6], s[6:], PASS).landing is not None
    assert fly_batch(s, PASS)["status"][0] == STATUS_OK


def test_ball_clearing_the_net_is_unchanged():
    s = _state((-11.885, 0.5, 1.0), (30.0, 0.0, 5.0), (0.0, 150.0, 0.0))
    a, b = fly_batch(s, PASS).data, fly_batch(s, STOP).data
    assert np.array_equal(a, b, equal_nan=True)  # same steps, same events: bit for bit
    ta, tb = fly_dense(s[:3], s[3:6], s[6:], PASS), fly_dense(s[:3], s[3:6], s[6:], STOP)
    assert ta.landing.t == tb.landing.t and np.array_equal(ta.landing.position, tb.landing.position)
    assert tb.net_contact is None and tb.net.result == "over"


@pytest.mark.parametrize("dz", [0.5, 0.9])
def test_ball_on_the_tape_stops_at_the_crossing(dz):
    """A ball whose surface reaches the net plane above the cord but whose centre crosses x = 0 less
    than r above it touches the tape: it stops at the crossing (the pass-through net says ``net``)."""
    h = COURT.net_height(0.0)
    s = _state((-0.5, 0.0, h + dz * R), (20.0, 0.0, 9.81 * 0.025 / 2))  # level at the net, 0.025 s later
    tr = fly_dense(s[:3], s[3:6], s[6:], STOP)
    tb = fly_batch(s, STOP)
    c = tr.net_contact
    assert c is not None and c.part == "tape" and tr.landing is None
    assert c.position[0] == pytest.approx(0.0, abs=1e-9) and h < c.z < h + R
    assert tr.net.result == "net" and -R < tr.net.clearance < 0
    assert tb["status"][0] == STATUS_NET and tb["net_hit_x"][0] == pytest.approx(0.0, abs=1e-9)
    assert tb["net_hit_z"][0] == pytest.approx(c.z, abs=1e-6)
    ok = fly_dense(s[:3], s[3:6], s[6:], PASS)
    assert ok.landing is not None and ok.net.result == "net"  # without the obstacle: flies on, flagged net
    above = _state((-0.5, 0.0, h + 1.2 * R), s[3:6])
    assert fly_dense(above[:3], above[3:6], above[6:], STOP).net_contact is None  # clears the tape


def test_beyond_the_posts_there_is_no_net():
    y = COURT.y_post + 0.5
    s = _state((-11.0, y, 0.5), (25.0, 0.0, 2.0))
    tr = fly_dense(s[:3], s[3:6], s[6:], STOP)
    assert tr.net_contact is None and tr.landing is not None and tr.net.result == "over"
    assert fly_batch(s, STOP)["status"][0] == STATUS_OK


def test_ball_starting_inside_the_net_is_refused():
    s = _state((-0.01, 0.0, 0.5), (10.0, 0.0, 0.0))
    with pytest.raises(InputError, match="^position: .*overlaps the net"):
        fly_dense(s[:3], s[3:6], s[6:], STOP)
    assert fly_batch(s, STOP)["status"][0] == STATUS_BAD_START
    assert fly_dense(s[:3], s[3:6], s[6:], PASS).landing is not None  # without the obstacle: allowed


def test_obstacle_columns_are_documented_and_nan_without_contact():
    assert {f"net_hit_{c}" for c in ("t", "x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")} <= set(COLUMNS)
    ev = event_array(OBSTACLE_EVENTS)
    assert ev.shape[0] == 5 and ev.flags.writeable
    tb = fly_batch(_state((-11.885, 0.0, 1.0), (30.0, 0.0, 5.0)), STOP)
    assert np.isnan(tb.data[0, COL["net_hit_t"] :]).all()


@settings(max_examples=60, deadline=None)
@given(
    speed=st.floats(8.0, 60.0),
    elev=st.floats(-8.0, 25.0),
    head=st.floats(-20.0, 20.0),
    z0=st.floats(0.2, 3.0),
    y0=st.floats(-6.0, 6.0),
    spin_rpm=st.floats(0.0, 4000.0),
    ax=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)),
    far=st.booleans(),
)
def test_obstacle_property_batch_equals_scipy(speed, elev, head, z0, y0, spin_rpm, ax, far):
    """Every flight either meets the net (the mesh: surface at x = -+r at or below the cord; the tape:
    centre crossing x = 0 less than r above it; between the posts) -- exactly the flights the
    pass-through net calls ``net`` -- or is exactly the pass-through flight; both paths agree."""
    e, h = math.radians(elev), math.radians(head)
    sgn = -1.0 if far else 1.0
    v = speed * np.array([sgn * math.cos(e) * math.cos(h), math.cos(e) * math.sin(h), math.sin(e)])
    a = np.array(ax)
    w = np.zeros(3) if np.linalg.norm(a) < 1e-6 else a / np.linalg.norm(a) * spin_rpm * RPM
    s = _state((-sgn * 11.885, y0, z0), v, w)
    tb, tp = fly_batch(s, STOP), fly_batch(s, PASS)
    tr = fly_dense(s[:3], s[3:6], s[6:], STOP)
    if tb["status"][0] == STATUS_NET:
        c = tr.net_contact
        assert c is not None and tr.landing is None
        h = COURT.net_height(c.y)
        assert abs(c.y) <= COURT.y_post
        if c.part == "mesh":
            assert abs(c.position[0]) == pytest.approx(R, abs=1e-9) and c.z <= h + 1e-9
        else:  # the centre crosses x = 0 less than r above the cord -- or below it, when the ball came
            # down onto the cord after its leading surface had passed above it at x = -+r
            assert c.position[0] == pytest.approx(0.0, abs=1e-9) and c.z <= h + R + 1e-9
            assert tp["net_z"][0] == pytest.approx(c.z, abs=1e-5)  # where the pass-through flight crosses
        assert tb["net_hit_y"][0] == pytest.approx(c.y, abs=1e-5)
        assert tb["net_hit_z"][0] == pytest.approx(c.z, abs=1e-5)
        if tp.net_result[0] != "net":  # the pass-through flight agrees that it hit the net, or it lands
            # with its centre less than r before the net plane: the ball's surface touched the mesh first
            assert tp.net_result[0] == "none" and tp.ok[0] and abs(tp["land_x"][0]) < R and c.part == "mesh"
    else:
        assert tr.net_contact is None and tp.net_result[0] != "net"
        assert np.array_equal(tb.data[:, : COL["status"] + 1], tp.data[:, : COL["status"] + 1], equal_nan=True)
        if tr.landing is not None and tb.ok[0]:
            assert tb["land_x"][0] == pytest.approx(tr.landing.x, abs=1e-5)


def test_ball_landing_just_before_the_net_touches_the_mesh():
    """Hypothesis found it: a slow ball that lands with its centre less than r before the net plane
    meets the mesh with its surface first (the pass-through flight never crosses: ``none``)."""
    e, h = math.radians(21.25), math.radians(15.5)
    v = 12.5625 * np.array([math.cos(e) * math.cos(h), math.cos(e) * math.sin(h), math.sin(e)])
    s = _state((-11.885, 0.0, 1.84375), v)
    tp, tb = fly_batch(s, PASS), fly_batch(s, STOP)
    assert tp.net_result[0] == "none" and -R < tp["land_x"][0] < 0
    c = fly_dense(s[:3], s[3:6], s[6:], STOP).net_contact
    assert tb["status"][0] == STATUS_NET and c is not None and c.part == "mesh" and c.z < COURT.net_height(c.y)
