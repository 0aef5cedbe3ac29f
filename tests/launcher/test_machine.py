"""Launcher machine spec, settings and launch states (issue 5; seed 002 section 2)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core.flight import FlightParams, fly_batch
from tennislab.errors import InputError
from tennislab.launcher.machine import (
    DEFAULT_SPEC,
    MachineSpec,
    Range,
    Settings,
    machine_states,
    settings_states,
    validate_arrays,
)
from tennislab.units import KMH, RPM

PARAMS = FlightParams.from_options(aero="launcher2015")


def test_seed_ranges_and_steps():
    s = DEFAULT_SPEC
    assert (s.height.hi, s.height.step) == (3.0, 0.1)
    assert (s.speed.lo, s.speed.hi, s.speed.step) == (30, 200, 1)
    assert (s.elevation.lo, s.elevation.hi) == (-20, 80)
    assert (s.heading.lo, s.heading.hi) == (-40, 40)
    assert (s.spin_axis.lo, s.spin_axis.hi) == (-180, 180)
    assert (s.spin.lo, s.spin.hi, s.spin.step) == (0, 2000, 1)
    assert (s.interval.lo, s.interval.hi, s.interval.step) == (1, 15, 1)
    assert (s.roller_radius, s.roller_axis_distance) == (0.1, 0.25)
    assert s.position == (-12.385, 0.0)


@pytest.mark.parametrize(
    "field,value,frag",
    [
        ("speed_kmh", 201, "[30, 200] km/h"),
        ("speed_kmh", 29.9, "[30, 200] km/h"),
        ("elevation_deg", 81, "[-20, 80] deg"),
        ("heading_deg", -41, "[-40, 40] deg"),
        ("spin_rpm", 2001, "[0, 2000] rpm"),
        ("spin_axis_deg", 181, "[-180, 180] deg"),
        ("height_m", 3.1, "[0.1, 3] m"),
        ("speed_kmh", float("nan"), "finite"),
    ],
)
def test_validate_names_field_and_range(field, value, frag):
    kw = dict(height_m=1.0, speed_kmh=80, elevation_deg=5, heading_deg=0, spin_rpm=0, spin_axis_deg=0)
    kw[field] = value
    with pytest.raises(InputError) as e:
        DEFAULT_SPEC.validate(Settings(**kw))
    msg = str(e.value)
    assert msg.startswith(field) and frag in msg and "\n" not in msg


def test_quantise_rounds_to_steps_and_require_steps():
    q = DEFAULT_SPEC.quantise(Settings(1.04, 80.6, 5.2, -0.4, 1500.3, -179.6))
    assert q == Settings(1.0, 81.0, 5.0, 0.0, 1500.0, -180.0)
    assert math.copysign(1, q.heading_deg) == 1.0
    with pytest.raises(InputError, match="not on the machine's 1 km/h steps"):
        DEFAULT_SPEC.validate(Settings(1.0, 80.5, 5, 0), require_steps=True)
    DEFAULT_SPEC.validate(q, require_steps=True)
    with pytest.raises(InputError, match="interval_s.*steps"):
        DEFAULT_SPEC.check_interval(2.5)
    with pytest.raises(InputError, match=r"interval_s: 16 s is outside the allowed range \[1, 15\] s"):
        DEFAULT_SPEC.check_interval(16)


def test_range_neighbours():
    r = Range(-20, 80, 1, "deg")
    assert list(r.neighbours(17.3)) == [16, 17, 18, 19]
    assert list(r.neighbours(79.6)) == [78, 79, 80]
    assert list(r.neighbours(5.0)) == [4, 5, 6]


def test_bad_spec():
    with pytest.raises(InputError, match="roller_axis_distance"):
        MachineSpec(roller_axis_distance=0.15)
    with pytest.raises(InputError, match="position"):
        MachineSpec(position=(1.0, float("nan")))


def test_launch_state_conventions():
    st_ = machine_states(DEFAULT_SPEC, 1.2, 100, 10, 0, 1000, [0, 180, 90, -90])
    v = 100 * KMH
    np.testing.assert_allclose(st_[:, 0:3], [[-12.385, 0, 1.2]] * 4)
    np.testing.assert_allclose(st_[0, 3:6], [v * math.cos(0.17453292519943295), 0, v * math.sin(0.17453292519943295)])
    w = 1000 * RPM
    np.testing.assert_allclose(st_[0, 6:9], [0, w, 0], atol=1e-9)  # topspin: +y for a ball along +x
    np.testing.assert_allclose(st_[1, 6:9], [0, -w, 0], atol=1e-9)  # backspin
    # spin always perpendicular to the velocity, |omega| = spin
    assert np.allclose(np.einsum("ij,ij->i", st_[:, 3:6], st_[:, 6:9]), 0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(st_[:, 6:9], axis=1), w)
    # heading positive toward +y
    s2 = machine_states(DEFAULT_SPEC, 1.0, 80, 0, 30, 0, 0)[0]
    assert s2[4] > 0 and math.degrees(math.atan2(s2[4], s2[3])) == pytest.approx(30)


def test_spin_axis_effects_in_flight():
    """Topspin dips (shorter), backspin floats (longer), +90 curves to +y, -90 to -y."""
    t = fly_batch(
        machine_states(DEFAULT_SPEC, 1.0, 100, 6, 0, [0, 1500, 1500, 1500, 1500], [0, 0, 180, 90, -90]), PARAMS
    )
    x, y = t["land_x"], t["land_y"]
    assert x[1] < x[0] < x[2]
    assert y[3] > 0.3 and y[4] < -0.3 and abs(y[0]) < 1e-9
    assert y[3] == pytest.approx(-y[4], rel=1e-6)


@settings(max_examples=40, deadline=None)
@given(st.floats(-20, 80), st.floats(-40, 40), st.floats(-180, 180), st.floats(30, 200), st.floats(0, 2000))
def test_machine_states_invariants(elev, head, axis, speed, spin):
    s = machine_states(DEFAULT_SPEC, 1.0, speed, elev, head, spin, axis)[0]
    v, w = s[3:6], s[6:9]
    assert np.linalg.norm(v) == pytest.approx(speed * KMH)
    assert np.linalg.norm(w) == pytest.approx(spin * RPM, abs=1e-9)
    assert abs(v @ w) <= 1e-9 * (1 + np.linalg.norm(v) * np.linalg.norm(w))
    assert math.degrees(math.asin(v[2] / np.linalg.norm(v))) == pytest.approx(elev, abs=1e-9)
    # the spin component along the horizontal-left axis is spin cos(axis): topspin share
    h = np.array([-math.sin(math.radians(head)), math.cos(math.radians(head)), 0.0])
    assert w @ h == pytest.approx(spin * RPM * math.cos(math.radians(axis)), abs=1e-6)


def test_broadcast_and_settings_states():
    s = machine_states(DEFAULT_SPEC, [[1.0], [2.0]], [80, 90, 100], 5, 0)
    assert s.shape == (6, 9)
    with pytest.raises(InputError, match="broadcast"):
        machine_states(DEFAULT_SPEC, 1.0, [80, 90], 5, 0, 0, [0, 1, 2])
    one = Settings(1.0, 80, 5, 3, 500, 20)
    np.testing.assert_allclose(
        settings_states(DEFAULT_SPEC, one)[0], machine_states(DEFAULT_SPEC, 1.0, 80, 5, 3, 500, 20)[0]
    )
    with pytest.raises(InputError, match=r"spin_rpm: 2500 rpm is outside"):
        validate_arrays(DEFAULT_SPEC, spin_rpm=[0, 2500])
