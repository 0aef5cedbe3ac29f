"""Inverse aiming of the launcher (issue 5): round trips against the reference integrator."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tennislab.core.flight import fly
from tennislab.errors import InputError
from tennislab.launcher.aim import aim, aim_all, aim_result_dict, fly_settings, launcher_params
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec, Settings, launch_states

PARAMS = launcher_params()


def _fly_exact(sol, spec=DEFAULT_SPEC):
    s = sol.settings
    y0 = launch_states(
        spec, s.height_m, s.speed_kmh, sol.exact_elevation_deg, sol.exact_heading_deg, s.spin_rpm, s.spin_axis_deg
    )[0]
    return fly(y0[0:3], y0[3:6], y0[6:9], PARAMS)


CASES = [
    ((8.0, 2.0), dict(speed_kmh=80, spin_rpm=1500)),
    ((10.0, -3.0), dict(speed_kmh=100, spin_rpm=800, spin_axis_deg=180)),
    ((9.0, 1.0), dict(speed_kmh=90, spin_rpm=1200, spin_axis_deg=70)),
    ((6.0, -2.5), dict(speed_kmh=60, spin_rpm=0, height_m=0.5)),
]


@pytest.mark.parametrize("target,kw", CASES)
def test_aim_round_trip_low_and_high(target, kw):
    sols, reasons = aim_all(target, **kw)
    assert set(sols) == {"low", "high"}, reasons
    lo, hi = sols["low"], sols["high"]
    assert lo.exact_elevation_deg < hi.exact_elevation_deg
    for sol in (lo, hi):
        # the exact (continuous) solution lands on the target (reference DOP853 integrator)
        tr = _fly_exact(sol)
        assert math.hypot(tr.landing.x - target[0], tr.landing.y - target[1]) < 1e-3
        # the quantised settings: on the machine's steps, landing as reported, miss within the bound
        DEFAULT_SPEC.validate(sol.settings, require_steps=True)
        tq = fly_settings(sol.settings, DEFAULT_SPEC, PARAMS)
        assert math.hypot(tq.landing.x - sol.landing[0], tq.landing.y - sol.landing[1]) < 1e-3
        miss = math.hypot(tq.landing.x - target[0], tq.landing.y - target[1]) * 1e3
        assert miss == pytest.approx(sol.miss_mm, abs=1.0)
        assert sol.miss_mm <= 1.05 * sol.quantisation_bound_mm + 1.0
        assert tq.net.result == "over" and tq.net.clearance == pytest.approx(sol.net_clearance_m, abs=1e-3)
        assert abs(sol.settings.elevation_deg - sol.exact_elevation_deg) <= 2
        assert abs(sol.settings.heading_deg - sol.exact_heading_deg) <= 2


def test_quantised_is_best_of_neighbours():
    sol = aim((9.0, 1.5), 85, 1000, 0)
    base = dict(height_m=1.0, speed_kmh=85, spin_rpm=1000, spin_axis_deg=0)
    best = math.inf
    for da in (-1, 0, 1):
        for db in (-1, 0, 1):
            s = Settings(
                elevation_deg=sol.settings.elevation_deg + da, heading_deg=sol.settings.heading_deg + db, **base
            )
            tr = fly_settings(s, DEFAULT_SPEC, PARAMS)
            best = min(best, math.hypot(tr.landing.x - 9.0, tr.landing.y - 1.5) * 1e3)
    assert sol.miss_mm == pytest.approx(best, abs=0.5)


def test_inputs_are_quantised_and_result_dict_keys():
    sol = aim((8.0, 0.0), 80.4, 1499.6, 0.3, 1.04)
    assert (sol.settings.speed_kmh, sol.settings.spin_rpm, sol.settings.spin_axis_deg, sol.settings.height_m) == (
        80,
        1500,
        0,
        1.0,
    )
    d = aim_result_dict(sol)
    for k in ("height_m", "speed_kmh", "elevation_deg", "heading_deg", "spin_rpm", "spin_axis_deg"):
        assert k in d["settings"]
    assert d["rollers"]["rpm1"] < d["rollers"]["rpm2"]  # topspin: roller 2 faster
    assert {"x", "y"} <= set(d["landing"]) and "miss_mm" in d and "net_clearance_m" in d


def test_machine_position_and_sidespin_heading():
    spec = MachineSpec(position=(-12.0, 3.0))
    sol = aim((8.0, -1.0), 90, 1500, 90, spec=spec)  # curves to +y: must aim right of the line
    geometric = math.degrees(math.atan2(-4.0, 20.0))
    assert sol.exact_heading_deg < geometric - 1.0
    tr = fly_settings(sol.settings, spec, PARAMS)
    assert tr.landing.x == pytest.approx(sol.landing[0], abs=1e-3)


def test_same_half_target_needs_no_net():
    sol = aim((-5.0, 0.0), 40, 0, 0)
    assert sol.net_result == "none" and math.isnan(sol.net_clearance_m)


@pytest.mark.parametrize(
    "target,kw,frag",
    [
        ((11.5, 0.0), dict(speed_kmh=30), "beyond its reach"),
        ((-11.0, 0.0), dict(speed_kmh=200, height_m=3.0), "nearer than its shortest flight"),
        (
            (2.0, 14.0),
            dict(speed_kmh=100),
            "heading: the low solution needs 44.22 deg, outside the allowed range [-40, 40] deg",
        ),
        ((4.0, 0.0), dict(speed_kmh=129), "into the net at the machine's 1 deg steps"),
        ((-20.0, 0.0), dict(speed_kmh=100), "heading range"),
        ((3.0, 0.0), dict(speed_kmh=200, height_m=1.0), "into the net"),
        ((8.0, 0.0), dict(speed_kmh=250), "speed_kmh: 250 km/h is outside the allowed range [30, 200] km/h"),
        ((8.0, 0.0), dict(speed_kmh=80, spin_rpm=-5), "spin_rpm"),
        ((8.0, float("nan")), dict(speed_kmh=80), "target"),
    ],
)
def test_unreachable_targets_say_why(target, kw, frag):
    with pytest.raises(InputError) as e:
        aim(target, **kw)
    assert frag in str(e.value) and "\n" not in str(e.value)


def test_high_missing_reason():
    sols, reasons = aim_all((5.0, 0.0), 150, height_m=3.0)
    assert "low" in sols and "high" in reasons and "80 deg" in reasons["high"]
    with pytest.raises(
        InputError,
        match=r"^elevation_deg: no high \(lob\) solution within the allowed range \[-20, 80\] deg"
        r".*\(a low solution exists\)",
    ):
        aim((5.0, 0.0), 150, height_m=3.0, solution="high")


def test_other_aero_model_changes_the_aim():
    a = aim((9.0, 0.0), 90, 1000, 0)
    b = aim((9.0, 0.0), 90, 1000, 0, params=launcher_params(aero="cross2014"))
    assert b.exact_elevation_deg < a.exact_elevation_deg  # less drag -> flatter


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.floats(2.0, 11.5), st.floats(-4.0, 4.0), st.integers(50, 140), st.integers(0, 2000), st.integers(-180, 180))
def test_aim_property_either_error_or_within_bound(x, y, speed, spin, axis):
    try:
        sols, _ = aim_all((x, y), speed, spin, axis)
    except InputError:
        return
    for sol in sols.values():
        assert sol.miss_mm <= 1.05 * sol.quantisation_bound_mm + 1.0
        assert sol.net_clearance_m >= 0
        DEFAULT_SPEC.validate(sol.settings, require_steps=True)
        s = launch_states(
            DEFAULT_SPEC,
            sol.settings.height_m,
            sol.settings.speed_kmh,
            sol.exact_elevation_deg,
            sol.exact_heading_deg,
            spin,
            axis,
        )[0]
        tr = fly(s[0:3], s[3:6], s[6:9], PARAMS, rtol=1e-9, atol=1e-10)
        assert np.hypot(tr.landing.x - x, tr.landing.y - y) < 2e-3
