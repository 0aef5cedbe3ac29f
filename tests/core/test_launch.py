"""Launch vocabulary (core.launch): the launcher's convention, named axes, round trips."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tennislab.core.launch import (
    SPIN_AXES_DEG,
    describe_spin,
    describe_velocity,
    launch_spin,
    launch_velocity,
    path_spin_basis,
    spin_axis_angle,
    spin_basis,
)
from tennislab.errors import InputError
from tennislab.launcher.machine import DEFAULT_SPEC, machine_states
from tennislab.units import DEG, KMH, RPM


def test_matches_the_launcher_states():
    rng = np.random.default_rng(3)
    n = 50
    v, a, b = rng.uniform(30, 200, n), rng.uniform(-20, 80, n), rng.uniform(-40, 40, n)
    w, g = rng.uniform(0, 2000, n), rng.uniform(-180, 180, n)
    s = machine_states(DEFAULT_SPEC, 1.0, v, a, b, w, g)
    assert np.allclose(launch_velocity(v * KMH, a * DEG, b * DEG), s[:, 3:6], rtol=1e-13, atol=1e-12)
    assert np.allclose(launch_spin(w * RPM, a * DEG, b * DEG, g * DEG), s[:, 6:9], rtol=1e-13, atol=1e-12)


def test_named_axes_give_the_documented_forces():
    v = launch_velocity(20.0, 0.0, 0.0)
    for name, force_dir in (
        ("topspin", (0, 0, -1)),
        ("backspin", (0, 0, 1)),
        ("sidespin-left", (0, 1, 0)),
        ("sidespin-right", (0, -1, 0)),
    ):
        w = launch_spin(100.0, 0.0, 0.0, spin_axis_angle(name))
        f = np.cross(w, v)
        assert np.allclose(f / np.linalg.norm(f), force_dir, atol=1e-12), name
    assert set(SPIN_AXES_DEG) >= {"topspin", "slice", "sidespin"}
    assert spin_axis_angle("45") == pytest.approx(math.pi / 4)
    assert spin_axis_angle(-90) == pytest.approx(-math.pi / 2)


@pytest.mark.parametrize("bad", ["wobble", "nan", "1e9", ""])
def test_bad_axis_names_the_parameter(bad):
    with pytest.raises(InputError, match=r"^spin_axis: "):
        spin_axis_angle(bad)


@given(st.floats(1, 80), st.floats(-1.4, 1.4), st.floats(-3.1, 3.1), st.floats(0, 700), st.floats(-3.1, 3.1))
def test_round_trip(speed, elev, head, rate, g):
    v = launch_velocity(speed, elev, head)
    s, a, b = describe_velocity(v)
    assert (s, a, b) == pytest.approx((speed, elev, head), abs=1e-9)
    d = describe_spin(launch_spin(rate, elev, head, g), v)
    assert d["rate"] == pytest.approx(rate, abs=1e-9)
    assert abs(d["along_path"]) < 1e-9 * max(1.0, rate)
    if rate > 1e-6:
        assert math.cos(d["axis_angle"] - g) == pytest.approx(1.0, abs=1e-9)


@given(st.floats(1, 80), st.floats(-1.5, 1.5), st.floats(-3.1, 3.1))
def test_the_path_basis_is_the_launch_basis(speed, elev, head):
    """``path_spin_basis`` (from the velocity vector, the track identification's axes) is
    ``spin_basis`` of the velocity's elevation and heading to round-off: one basis, perpendicular to
    the path, its first axis the topspin axis (the Magnus force of spin about it points down)."""
    v = launch_velocity(speed, elev, head)
    h, u = path_spin_basis(v)
    h0, u0 = spin_basis(*describe_velocity(v)[1:])
    assert np.abs(np.concatenate([h - h0, u - u0])).max() < 1e-12
    d = v / np.linalg.norm(v)
    assert abs(h @ d) < 1e-12 and abs(u @ d) < 1e-12 and abs(h[2]) < 1e-12
    assert np.cross(h, v)[2] < 0.0
    hv, uv = path_spin_basis([0.0, 0.0, -3.0])  # vertical: a horizontal axis still
    assert np.allclose(hv, [1.0, 0.0, 0.0]) and abs(uv @ [0.0, 0.0, 1.0]) < 1e-12
