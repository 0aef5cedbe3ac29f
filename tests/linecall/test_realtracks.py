"""Real 50 Hz tracker output (set 1 of a professional match: ../shared/realdata/match50hz-set1, or the
folder in $TENNISLAB_MATCH50HZ): every shot called, checked against the tracker with the data's
independent bounce estimate (tennislab.linecall.check_rally).  Skipped when the data are absent."""

from __future__ import annotations

import glob
import os
from pathlib import Path

import pytest

from tennislab.io.hawkeye import read_points
from tennislab.linecall import call_rally, check_rally


def _folder() -> Path | None:
    if os.environ.get("TENNISLAB_MATCH50HZ"):
        return Path(os.environ["TENNISLAB_MATCH50HZ"])
    here = Path(__file__).resolve()
    for up in here.parents:
        cand = up / "shared" / "realdata" / "match50hz-set1"
        if cand.is_dir():
            return cand
    return None


FOLDER = _folder()
pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(FOLDER is None or not FOLDER.is_dir(), reason="no real 50 Hz tracker data"),
]


@pytest.fixture(scope="module")
def called():
    points = [p for f in sorted(glob.glob(str(FOLDER / "*.json"))) for p in read_points(f)]
    rally = call_rally(points, workers=2)
    return points, rally, check_rally(rally, points).summary


def test_bounces_agree_with_the_independent_estimate(called):
    _, _, s = called
    b = s["bounce_error_mm_all"]
    assert b["n"] > 150
    assert b["median"] <= 3.0 and b["p90"] <= 8.0, b


def test_every_call_agrees_with_the_tracker(called):
    _, _, s = called
    assert s["tracker_calls_compared"] > 150
    assert s["tracker_calls_agree"] == s["tracker_calls_compared"]


def test_no_review_for_a_volley_and_no_in_on_the_hitters_side(called):
    _, rally, _ = called
    for shot in rally.shots:
        reason = shot["reason"] or ""
        assert not (shot["call"] == "review" and "volley" in reason)
        if shot["call"] == "in" and shot["bounce"]["x"] is not None:
            assert shot["bounce"]["x"] * shot["hit"][0] < 0, shot["point"]  # lands beyond the net
    assert rally.summary["calls"]["volley"] > 0 and rally.summary["calls"]["dead"] > 0
    assert rally.summary["calls"]["review"] <= 0.05 * rally.summary["n_shots"]


def test_the_bounce_sigmas_are_borne_out(called):
    """The reported 1-sigma / 2-sigma ellipses hold about 68 / 95 % of the independent estimates."""
    _, _, s = called
    cov = s["coverage"]
    assert 0.5 < cov["1sigma"] < 0.85 and 0.85 < cov["2sigma"] <= 1.0, cov


def test_rally_spin_matches_the_trackers(called):
    _, _, s = called
    sp = s["spin"]
    assert sp["rally_n"] > 50 and abs(sp["rally_median_ratio"] - 1.0) <= 0.10, sp
