"""The answers a line judge gives besides in and out: volley, dead (the point is over), a first contact
on the hitter's own side (out, "lands before the net"); and the bounce placed near the bounce
(local refits, linecall.local_fit) on smooth tracks with model error and on noisy ones."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from tennislab.core.aero import get_aero_model
from tennislab.core.flight import FlightParams
from tennislab.io.hawkeye import parse_points
from tennislab.linecall import CALLS, call_rally, call_track, check_rally, independent_bounces
from tennislab.linecall.answer import OWN_SIDE
from tennislab.linecall.local_fit import runs_z
from tennislab.linecall.rally import DEAD_SPEED
from tennislab.linecall.synth_points import aim, sample_point, simulate_shot, truth_params

TRUTH = truth_params()


def _point(shots, seed=0, sigma=1e-3, rate=50.0, outliers=0):
    doc = sample_point(shots, np.random.default_rng(seed), rate=rate, sigma=sigma, outliers=outliers, dropout=0.0)
    return parse_points(json.dumps([doc]), "answers")


def _serve(target, t0=0.0):
    p0 = np.array([-11.6, 0.4, 2.85])
    v, w = aim(p0, 45.0, (1500.0, 0.0, 0.0), target, TRUTH)
    st = simulate_shot(p0, v, w, t0, TRUTH, max_bounces=2)
    st.serve, st.target = True, "ad-box"  # struck from y > 0 (the ad court) toward the far ad box
    return st


def _return(t0, p0=(11.0, -1.5, 1.0), target=(-8.0, 0.0), speed=22.0):
    p0 = np.asarray(p0, dtype=float)
    v, w = aim(p0, speed, (1800.0, 0.0, 0.0), target, TRUTH)
    return simulate_shot(p0, v, w, t0, TRUTH, max_bounces=2)


def test_the_calls_include_volley_and_dead():
    assert {"volley", "dead"} <= set(CALLS)


def test_after_an_out_serve_the_return_is_dead():
    """The serve lands long of the box (a fault: the point is over); the receiver plays it back anyway,
    as players do: that return is `dead`, not called, however it lands."""
    serve = _serve((8.2, -2.0))  # beyond the service line (6.40 m)
    ret = _return(serve.bounces[0].t + 0.45)
    res = call_rally(_point([serve, ret]))
    calls = [s["call"] for s in res.shots]
    assert calls == ["out", "dead"], [(s["call"], s["reason"]) for s in res.shots]
    assert "the shot before was out" in res.shots[1]["reason"]
    assert res.summary["calls"]["dead"] == 1
    row = res.rows()[1]
    assert row["call"] == "dead"


def test_a_ball_dribbling_after_the_point_is_dead():
    """A "shot" slower than DEAD_SPEED off its hit (the ball rolled back or dribbled) is `dead`."""
    serve = _serve((4.5, -2.0))  # in the ad box
    p0 = np.array([9.0, 3.0, 0.5])
    slow = simulate_shot(p0, (-0.5 * DEAD_SPEED, 0.2, 1.0), (0.0, 0.0, 0.0), serve.bounces[0].t + 0.8, TRUTH)
    res = call_rally(_point([serve, slow]))
    assert res.shots[0]["call"] == "in"
    assert res.shots[1]["call"] == "dead" and "dribbling" in res.shots[1]["reason"]


def test_a_first_contact_on_the_hitters_side_is_out():
    """A ball that comes down before the net is out ("lands before the net"), whatever its mark
    touches; with the tracker's other lines it would be called in."""
    p0 = np.array([-11.0, 0.5, 1.0])
    v, w = aim(p0, 14.0, (500.0, 0.0, 0.0), (-0.6, 0.5), TRUTH)  # just short of the net
    st = simulate_shot(p0, v, w, 0.0, TRUTH, max_bounces=1)
    assert st.bounces[0].x < 0
    t = np.arange(0.0, st.t_end, 1 / 50.0)
    xyz = st.position(t)
    ok = np.all(np.isfinite(xyz), axis=1)
    res = call_track(t[ok], xyz[ok], target="singles")
    d = res.to_dict()
    assert d["call"] == "out" and d["reason"] == OWN_SIDE and d["p_in"] == 0.0


def test_runs_z():
    assert runs_z(np.array([1, -1] * 10)) > 3  # alternating: many runs
    assert runs_z(np.array([1] * 10 + [-1] * 10)) < -3  # two runs: systematic
    assert runs_z(np.array([1, 1, -1])) == 0.0  # too short to judge


def _track(params, rate, sigma, seed=3):
    p0 = np.array([-11.6, 0.3, 2.85])
    v, w = aim(p0, 48.0, (1500.0, -600.0, 300.0), (5.2, 2.0), params)
    st = simulate_shot(p0, v, w, 0.0, params, max_bounces=1)
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, st.bounces[0].t + 0.25, 1.0 / rate) + rng.uniform(0, 1 / rate)
    x = st.position(t)
    ok = np.all(np.isfinite(x), axis=1)
    return st.bounces[0], t[ok], x[ok] + rng.normal(0, sigma, (ok.sum(), 3))


def test_local_windows_follow_the_data():
    """A smooth track flown with another drag shape than the fit's: the bounce comes from a short window
    near it; a noisy track flown with the fit's own physics: from a long one (the intersection of
    confidence intervals chooses; linecall.local_fit)."""
    other = FlightParams(aero=get_aero_model("stepanek1988"))
    b, t, x = _track(other, 50.0, 2e-4)
    smooth = call_track(t, x, target="deuce-box").to_dict()
    b2, t2, x2 = _track(FlightParams(), 340.0, 3e-3)
    noisy = call_track(t2, x2, target="deuce-box").to_dict()
    assert smooth["fit"]["bounce_window_s"] < noisy["fit"]["bounce_window_s"]
    assert math.hypot(smooth["bounce"]["x"] - b.x, smooth["bounce"]["y"] - b.y) < 3e-3
    assert math.hypot(noisy["bounce"]["x"] - b2.x, noisy["bounce"]["y"] - b2.y) < 6e-3
    assert smooth["fit"]["flight_rms_mm"] > 0 and len(smooth["fit"]["bounce_windows"]) >= 1


def test_independent_bounces_and_check_rally():
    """The independent estimate (a quadratic through the last six on-grid samples, z = 0.033 m) lands
    within 3 mm of the true contact on a smooth 50 Hz serve; check_rally compares a rally's calls with it."""
    serve = _serve((4.8, -2.2))  # in
    pts = _point([serve], sigma=2e-4)
    est = independent_bounces(pts[0])
    b = serve.bounces[0]
    assert len(est) >= 1 and math.hypot(est[0].x - b.x, est[0].y - b.y) < 3e-3
    check = check_rally(call_rally(pts), pts).summary
    assert check["bounce_error_mm_all"]["n"] == 1 and check["bounce_error_mm_all"]["median"] < 5.0
    assert set(check["coverage"]) >= {"1sigma", "2sigma", "n"}


@pytest.mark.parametrize("bad", ["volley", "dead"])
def test_new_answers_in_the_csv_rows(bad):
    row_keys = {"call", "reason"}
    serve = _serve((8.2, -2.0))
    res = call_rally(_point([serve, _return(serve.bounces[0].t + 0.45)]))
    assert row_keys <= set(res.rows()[0])
    assert bad in res.summary["calls"]
