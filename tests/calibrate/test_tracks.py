"""Calibration on time-stamped free-flight tracks: recovery of known coefficients, bad input."""

import numpy as np
import pytest

from tennislab.calibrate import calibrate_tracks
from tennislab.core.flight import FlightParams, fly_dense
from tennislab.core.launch import launch_spin, launch_velocity
from tennislab.errors import InputError
from tennislab.io.track import Track
from tennislab.units import RPM

TRUTH = FlightParams.from_options(aero="cross2014", cd=0.62, cl=0.45)


def _tracks(n=6, rpm=2500.0, axis_deg=0.0, noise=0.003, seed=1, params=TRUTH):
    """Launcher-like shots flown by SciPy's DOP853 (an independent integrator), sampled at 100 Hz."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        sp = rng.uniform(20, 45)
        a, b = np.radians(rng.uniform(0, 10)), np.radians(rng.uniform(-5, 5))
        tr = fly_dense(
            (-11.5, rng.uniform(-2, 2), 1.0 + rng.uniform(0, 1.0)),
            launch_velocity(sp, a, b),
            launch_spin(rpm * RPM, a, b, np.radians(axis_deg)),
            params,
        )
        t = np.arange(0.0, 0.95 * tr.landing.t, 0.01)
        xyz = tr.sol(t).T[:, :3] + rng.normal(0.0, noise, (t.size, 3))
        out.append(Track(t + 5.0 * i, xyz, np.full(t.size, noise)))
    return out


def test_recovers_cd_and_cl_with_known_spin():
    r = calibrate_tracks(_tracks(), fit="cd,cl", spin_rpm=2500, spin_axis="topspin")
    assert r.values["cd"] == pytest.approx(0.62, abs=4 * r.sd["cd"] + 1e-3)
    assert r.values["cl"] == pytest.approx(0.45, abs=4 * r.sd["cl"] + 3e-3)
    assert r.rms_after_mm < 3.5 < r.rms_before_mm
    assert 0.7 < r.chi2_dof < 1.3
    d = r.to_dict()
    assert d["n_tracks"] == 6 and len(d["tracks"]) == 6 and "cd:cl" in d["correlation"]
    assert r.table_csv().startswith("speed_ms,spin_rpm,cd,cl\n")


def test_drag_alone_without_spin():
    no_spin = FlightParams.from_options(aero="constant", cd=0.58, cl=0.0)
    r = calibrate_tracks(_tracks(n=4, rpm=0.0, params=no_spin), fit="cd")
    assert r.values["cd"] == pytest.approx(0.58, abs=5e-3)


def test_bad_input():
    tr = _tracks(n=1)
    with pytest.raises(InputError, match="^fit: cl and cd_s need"):
        calibrate_tracks(tr, fit="cd,cl")
    with pytest.raises(InputError, match="^fit: unknown parameter"):
        calibrate_tracks(tr, fit="mass")
    with pytest.raises(InputError, match="^tracks: no tracks"):
        calibrate_tracks([])
    with pytest.raises(InputError, match="^spin_rpm"):
        calibrate_tracks(tr, spin_rpm=-5)
    with pytest.raises(InputError, match="^cd:"):
        calibrate_tracks(tr, cd=9.0)
