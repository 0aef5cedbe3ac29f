"""Identification of a ball's curves from timed flights (calibrate_tracks, the curves fit): synthetic
flights with a drag crisis and spin decay flown by core's reference integrator (SciPy DOP853) are
recovered; point JSON is cut into flights; the held-out report; bad input.  Synthetic truth made with
our own physics proves the code, not the physics."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from tennislab.calibrate import Curves, calibrate_tracks, flights_from_points
from tennislab.calibrate.flights import on_grid, velocity_jump
from tennislab.calibrate.identify import cubic_floor_mm
from tennislab.core.flight import FlightParams, fly_dense
from tennislab.core.launch import launch_spin, launch_velocity
from tennislab.errors import InputError
from tennislab.io.hawkeye import parse_points
from tennislab.io.track import Track
from tennislab.linecall import find_bounces, find_hits
from tennislab.units import RPM

#: the truth: C_D falling from 0.75 at 15 m/s to 0.56 at 50 m/s (a drag crisis), lift 0.6 S then
#: bending over, spin decaying at 0.6 /s
TRUTH = Curves(speed=(15.0, 25.0, 35.0, 50.0), cd=(0.75, 0.66, 0.60, 0.56), s=(0.15, 0.35), cl=(0.09, 0.17), decay=0.6)
KNOTS = {"speed_knots": TRUTH.speed, "s_knots": TRUTH.s}
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _params(curves=TRUTH) -> FlightParams:
    return FlightParams.from_options(aero=curves.model(), spin_decay=curves.decay)


def _shot(rng, params):
    """A serve or a groundstroke with top- or backspin, flown to its landing by SciPy's DOP853."""
    if rng.uniform() < 0.4:
        speed, elev, p0, rpm = rng.uniform(40, 55), rng.uniform(-7, -3), (-11.6, rng.uniform(-3, 3), 2.8), 2500
    else:
        speed, elev, p0, rpm = rng.uniform(18, 35), rng.uniform(3, 12), (-11.0, rng.uniform(-3, 3), 1.0), 3000
    head = np.radians(rng.uniform(-6, 6))
    spin = rng.choice([-1.0, 1.0]) * rng.uniform(0.4, 1.0) * rpm * RPM
    a = np.radians(elev)
    return fly_dense(p0, launch_velocity(speed, a, head), launch_spin(spin, a, head, 0.0), params)


def _flights(n=10, seed=3, hz=50.0, noise=2e-4, params=None):
    rng = np.random.default_rng(seed)
    params = params or _params()
    out = []
    for i in range(n):
        tr = _shot(rng, params)
        t = np.arange(0.02, tr.landing.t - 0.01, 1.0 / hz)
        xyz = tr.sol(t).T[:, :3] + rng.normal(0.0, noise, (t.size, 3))
        out.append(Track(t + 10.0 * i, xyz, np.full(t.size, 1e-3)))
    return out


@pytest.fixture(scope="module")
def identified():
    tracks = _flights(n=8, hz=25.0)
    held = _flights(n=5, seed=11, hz=25.0)
    return calibrate_tracks(tracks, holdout_tracks=held, drag_sigma=0, max_iter=10, **KNOTS)


@pytest.mark.slow
def test_recovers_drag_crisis_and_spin_decay(identified):
    """C_D at every knot within 3 sigma (and 0.02) of the truth, the decay within 3 sigma (and 0.2 /s),
    the lift's shape knot within 0.02."""
    r = identified
    for v, cd in zip(TRUTH.speed, TRUTH.cd):
        name = f"cd@{v:g}"
        assert r.values[name] == pytest.approx(cd, abs=max(3 * r.sd[name], 0.005) + 0.015), name
    assert r.values["decay"] == pytest.approx(TRUTH.decay, abs=3 * r.sd["decay"] + 0.2)
    assert r.values["cl@0.35"] == pytest.approx(TRUTH.cl[1], abs=0.02)
    assert 0 < r.sd["cd@25"] < 0.05


@pytest.mark.slow
def test_held_out_report(identified):
    """The held-out flights fly the identified model to the noise, the baseline (choppin2018) not."""
    d = identified.to_dict()
    assert d["split"] == {"name": "holdout", "n_fit": 8, "n_held_out": 5}
    h = d["held_out"]["all"]
    assert h["n"] == 5 and h["after"]["median_mm"] < 0.6 < h["before"]["median_mm"]
    lo, hi = h["after"]["median_ci95_mm"]
    assert lo <= h["after"]["median_mm"] <= hi
    assert {r["part"] for r in d["tracks"]} == {"fit", "held_out"}
    assert d["tracks"][0]["cubic_floor_mm"] > 0
    assert d["spin_decay_per_s"] == pytest.approx(d["curves"]["spin_decay_per_s"])
    table = identified.table_csv().splitlines()
    assert table[0] == "speed_ms,spin_rpm,cd,cl" and len(table) > 100
    assert "spin_decay = " in identified.config_toml("aero.csv")
    assert d["convergence"]["stopped"] == "converged" and 1 < d["convergence"]["iterations"] < 10


def test_a_fit_cut_short_says_so():
    """``convergence`` tells a fit that ran out of iterations from one that converged."""
    r = calibrate_tracks(_flights(n=4, hz=25.0), drag_sigma=0, max_iter=1, **KNOTS)
    assert r.to_dict()["convergence"] == {"iterations": 1, "stopped": "max_iter"}


def test_cubic_floor_of_a_cubic_is_zero():
    t = np.linspace(0.0, 1.0, 40)
    pos = np.stack([1 + 2 * t - t**3, 3 * t**2, -t], axis=1)
    assert cubic_floor_mm(t, pos) < 1e-9
    pos[:, 0] += 1e-3 * np.sin(12 * t)
    assert 0.1 < cubic_floor_mm(t, pos) < 1.0


def _point(tracks, game, events=True):
    """A tracker point of the given flights: 50 Hz samples, a hit sample at each flight's start and a
    bounce sample at its end (off the grid, as a tracker stores them)."""
    samples = []
    for tr in tracks:
        if events:
            samples.append({"time": float(tr.t[0] - 0.013), "event": "hit", "ball": list(map(float, tr.xyz[0]))})
        samples += [{"time": float(t), "ball": list(map(float, p))} for t, p in zip(tr.t, tr.xyz)]
        if events:
            samples.append({"time": float(tr.t[-1] + 0.007), "event": "bounce", "ball": list(map(float, tr.xyz[-1]))})
    return {"sequences": {"set": 1, "game": game, "point": 1}, "samples": samples}


def test_point_json_is_cut_into_flights():
    tracks = _flights(n=4, seed=5)
    pts = parse_points(json.dumps([_point(tracks[:2], 1), _point(tracks[2:], 2)]))
    fl = flights_from_points(pts, min_samples=8)
    assert [f.game for f in fl] == [1, 1, 2, 2]
    for f, tr in zip(fl, tracks):  # the event samples (off the grid) are left out, the rest kept
        assert len(f) == len(tr) and np.allclose(f.xyz, tr.xyz)
    assert [f.kind for f in fl] == ["serve", "rally", "serve", "rally"]  # a point's first hit from the baseline


def test_point_json_without_events_needs_a_detector():
    """Without hit and bounce events the cut needs detectors; linecall's find the same rally flight as
    the events of the shipped synthetic points (the serves, hit at their first sample, are not found)."""
    tr = _flights(n=1, seed=8)[0]
    with pytest.raises(InputError, match="^points: .* no hit events; pass a hit detector"):
        flights_from_points(parse_points(json.dumps(_point([tr], 1, events=False))))
    doc = json.loads((EXAMPLES / "points" / "synthetic_points.json").read_text())
    bare = [
        {
            "sequences": p.get("sequences", {}),
            "samples": [{k: v for k, v in x.items() if k != "event"} for x in p["samples"]],
        }
        for p in (doc if isinstance(doc, list) else doc.get("points", [doc]))
    ]
    by_events = flights_from_points(parse_points(json.dumps(doc)))
    found = flights_from_points(parse_points(json.dumps(bare)), find_hits=find_hits, find_bounces=find_bounces)
    assert len(by_events) == 3 and len(found) == 1
    same = [f for f in by_events if abs(f.t[0] - found[0].t[0]) < 1e-9]
    assert len(same) == 1 and np.array_equal(same[0].xyz, found[0].xyz)


def test_grid_and_contact_helpers():
    t = np.arange(0.0, 1.0, 0.02)
    mixed = np.sort(np.append(t, [0.371, 0.613]))
    assert (~on_grid(mixed)).sum() == 2
    x = np.stack([30 * t, 0 * t, 2 - 4.9 * t**2], axis=1)
    assert velocity_jump(t, x) is None
    x[25:, 0] = x[24, 0] + 10 * (t[25:] - t[24])  # the ball loses 2/3 of its speed at the net
    assert 20 <= velocity_jump(t, x) <= 24  # within a window of the contact, never after it


@pytest.mark.parametrize(
    "kwargs,msg",
    [
        ({"fit": "mass"}, "^fit: unknown parameter"),
        ({"fit": "cd_v,cl"}, "^fit: cl is a parameter of the family"),
        ({"split": "random"}, "^split: unknown split"),
        ({"drag_sigma": -1}, "^drag_sigma"),
        ({"speed_knots": (20.0, 10.0)}, "^cd: knots must be"),
    ],
)
def test_bad_input(kwargs, msg):
    with pytest.raises(InputError, match=msg):
        calibrate_tracks(_flights(n=2), **kwargs)
    with pytest.raises(InputError, match="^tracks: no tracks"):
        calibrate_tracks([])


def test_a_step_to_curves_core_refuses_is_not_tried():
    """The search's box is core's rule: a drag growth cd_s that turns the drag negative at high spin (which
    curves_model refuses) or lies outside its range is not a valid trial, as a non-finite one is not."""
    from tennislab.calibrate.identify import _valid
    from tennislab.core.aero import CURVES_CD_S_RANGE, CURVES_S_DRAG_MAX, curves_drag_positive
    from tennislab.errors import InputError

    lay = TRUTH.layout()
    ext = TRUTH.ext()
    assert _valid(ext, lay)
    neg = -(min(TRUTH.cd) + 0.01) / CURVES_S_DRAG_MAX  # just enough to turn the least drag negative
    assert not curves_drag_positive(min(TRUTH.cd), neg) and curves_drag_positive(min(TRUTH.cd), 0.0)
    with pytest.raises(InputError, match="^cd_s: drag would turn negative"):
        Curves(speed=TRUTH.speed, cd=TRUTH.cd, s=TRUTH.s, cl=TRUTH.cl, cd_s=neg).model()
    for bad in (neg, CURVES_CD_S_RANGE[1] + 1.0, float("nan")):
        trial = ext.copy()
        trial[lay["cd_s"][0]] = bad
        assert not _valid(trial, lay)
