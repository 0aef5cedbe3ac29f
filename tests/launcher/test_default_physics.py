"""The launcher's aim with its default physics, every command's ``standard`` preset (choppin2018 aero, ITF
ball, sea-level air): the exact solutions land on the target under the reference integrator, the chosen
settings are on the machine's steps and within the tolerances, and land where the answer says.  (The
cases of test_aim.py fly the paper's physics, preset seed002, for which they were chosen.)"""

import math

import pytest

from tennislab.core.flight import FlightParams, fly_dense
from tennislab.launcher.aim import aim_all, fly_settings, launcher_params
from tennislab.launcher.machine import DEFAULT_SPEC
from tennislab.launcher.preferences import Tolerances

CASES = [
    ((8.0, 2.0), dict(speed_kmh=80, spin_rpm=1500)),
    ((10.0, -3.0), dict(speed_kmh=100, spin_rpm=800, spin_axis_deg=180)),
    ((6.0, -2.5), dict(speed_kmh=60, spin_rpm=0, height_m=0.5)),
]


def test_the_default_is_the_standard_preset():
    p = launcher_params()
    assert p == FlightParams.from_options(preset="standard") and p.aero.name == "choppin2018"
    assert p is launcher_params() is launcher_params(preset="standard")  # one object: its reach map's key at once
    assert launcher_params(preset="seed002").aero.name == "launcher2015"


@pytest.mark.parametrize("target,kw", CASES)
def test_default_physics_aim_round_trip(target, kw):
    params = launcher_params()
    sols, reasons = aim_all(target, **kw)
    assert set(sols) == {"low", "high"}, reasons
    tol = Tolerances()
    for sol in sols.values():
        assert sol.to_dict(DEFAULT_SPEC, params)["physics"] == params.to_dict()
        y0 = sol.exact_state(DEFAULT_SPEC)
        exact = fly_dense(y0[0:3], y0[3:6], y0[6:9], params).landing
        assert math.hypot(exact.x - target[0], exact.y - target[1]) < 1e-3
        s, a = sol.settings, sol.asked
        DEFAULT_SPEC.validate(s, require_steps=True)
        assert abs(s.speed_kmh - a.speed_kmh) <= tol.speed_kmh + 1e-9
        assert tol.allows(s.spin_rpm, s.spin_axis_deg, a.spin_rpm, a.spin_axis_deg)
        tq = fly_settings(s, DEFAULT_SPEC, params)
        assert math.hypot(tq.landing.x - sol.landing[0], tq.landing.y - sol.landing[1]) < 1e-3
        assert math.hypot(tq.landing.x - target[0], tq.landing.y - target[1]) * 1e3 == pytest.approx(
            sol.miss_mm, abs=1.0
        )
        assert tq.net.result == "over" and sol.miss_mm <= 1.05 * sol.quantisation_bound_mm + 1.0
