"""tennislab.trajectory: the flight use case (launch vocabulary, guard rails, result)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core.flight import FlightParams
from tennislab.core.flight import fly_dense as core_fly
from tennislab.errors import InputError
from tennislab.trajectory import MAX_SPEED_MS, MAX_SPIN_RPM, fly, launch_vectors
from tennislab.units import KMH, RPM


@settings(max_examples=200, deadline=None)
@given(
    speed=st.floats(0.5, MAX_SPEED_MS),
    elevation=st.floats(-89, 89),
    heading=st.floats(-180, 180),
    rpm=st.floats(0, MAX_SPIN_RPM),
    axis=st.floats(-180, 180),
)
def test_launch_vocabulary_round_trips(speed, elevation, heading, rpm, axis):
    """Speed, elevation and heading give a velocity of that speed and direction; the spin has the rate asked."""
    v, w = launch_vectors(
        speed_ms=speed, elevation_deg=elevation, heading_deg=heading, spin_rpm=rpm, spin_axis=str(axis)
    )
    assert math.hypot(*v) == pytest.approx(speed, rel=1e-12)
    assert math.degrees(math.asin(v[2] / speed)) == pytest.approx(elevation, abs=1e-6)
    assert math.hypot(*w) == pytest.approx(rpm * RPM, rel=1e-9, abs=1e-12)
    assert abs(float(np.dot(v, w))) <= 1e-9 * max(1.0, speed * rpm * RPM)  # the axis is perpendicular to the path


@settings(max_examples=100, deadline=None)
@given(kmh=st.floats(1, 360))
def test_speed_units_agree(kmh):
    a, _ = launch_vectors(speed_kmh=kmh, elevation_deg=10)
    b, _ = launch_vectors(speed_ms=kmh * KMH, elevation_deg=10)
    c, _ = launch_vectors(speed_mph=kmh * KMH / 0.44704, elevation_deg=10)
    assert a == pytest.approx(b, rel=1e-12) and a == pytest.approx(c, rel=1e-12)


def test_the_workflow_is_the_core_flight():
    p = FlightParams.from_options(aero="cross2014")
    res = fly((-11.885, 0.2, 1.0), (30, -0.5, 6), (0, 150, 0), params=p)
    tr = core_fly((-11.885, 0.2, 1.0), (30, -0.5, 6), (0, 150, 0), p)
    d = res.to_dict()
    assert d["landing"]["x"] == tr.landing.x and d["net"]["clearance"] == tr.net.clearance
    assert d["physics"]["aero"] == "cross2014"


@pytest.mark.parametrize(
    "kw,param",
    [
        (dict(velocity=(1e9, 0, 7)), "velocity"),
        (dict(velocity=(float("inf"), 0, 7)), "velocity[0]"),
        (dict(speed_ms=101, elevation_deg=0), "speed_ms"),
        (dict(speed_kmh=361, elevation_deg=0), "speed_kmh"),
        (dict(speed_mph=224, elevation_deg=0), "speed_mph"),
        (dict(velocity=(30, 0, 5), spin=(0, 1100, 0)), "spin"),
        (dict(velocity=(30, 0, 5), spin_rpm=10001, spin_axis="topspin"), "spin_rpm"),
        (dict(velocity=(30, 0, 5), spin_rpm=100, spin_axis="wobble"), "spin_axis"),
        (dict(speed_ms=30, speed_kmh=30, elevation_deg=0), "speed_ms"),
        (dict(velocity=(30, 0, 5), bounces=-1), "bounces"),
        (dict(velocity=(30, 0, 5), bounces=True), "bounces"),
    ],
)
def test_guard_rails_name_the_parameter(kw, param):
    with pytest.raises(InputError) as e:
        fly((-11.885, 0, 1), **kw)
    msg = str(e.value)
    assert msg.startswith((param + ":", param + " ")), msg
    assert "\n" not in msg


def test_a_ball_below_the_ground_is_refused():
    with pytest.raises(InputError, match=r"^position.*(below the ball radius|outside the allowed range)"):
        fly((-11.885, 0, 0.0), (30, 0, 5))


def test_caveats_for_the_net_and_a_rolling_ball():
    into_net = fly((-11.885, 0, 1), speed_ms=20, elevation_deg=6)
    assert into_net.to_dict()["net"]["result"] == "net" and "hits the net" in into_net.caveats[0]
    clean = fly((-11.885, 0, 1), speed_kmh=120, elevation_deg=6, spin_rpm=2500, spin_axis="topspin")
    assert clean.caveats == [] and clean.to_dict()["caveats"] == []
    rolling = fly((-2, 0, 0.034), (3, 0, -0.04), bounces=6)  # 0.1 m/s down: it rolls after bounce 4
    assert any("rolls" in c for c in rolling.caveats)


def test_the_net_stops_the_ball_by_default():
    """A ball driven into the net ends there (net_contact, no landing); net='through' keeps the seeds' reading."""
    from tennislab.trajectory import fly as fly_workflow

    stopped = fly_workflow((-11.885, 0.0, 1.0), (30.0, 0.0, 1.2)).to_dict()
    assert stopped["landing"] is None and stopped["bounce"] is None
    nc = stopped["net_contact"]
    assert nc["part"] == "mesh" and abs(nc["x"]) == pytest.approx(0.0335, abs=1e-9) and 0 < nc["z"] < 0.914
    assert stopped["net"]["result"] == "net" and "flight ends there" in stopped["caveats"][0]
    through = fly_workflow((-11.885, 0.0, 1.0), (30.0, 0.0, 1.2), net="through").to_dict()
    assert through["net_contact"] is None and through["landing"]["x"] > 0
    clear = fly_workflow((-11.885, 0.0, 1.0), (25.0, 0.0, 6.0), bounces=1).to_dict()
    assert clear["net_contact"] is None and len(clear["bounces"]) == 1
    with pytest.raises(InputError, match="^net: unknown mode"):
        fly_workflow((-11.885, 0.0, 1.0), (25.0, 0.0, 6.0), net="maybe")
