"""The aim's search keeps its flights tied to their rows: a row (height, branch) whose heading falls outside
the machine's range is dropped before the search, and the flights it reuses (its parents) must follow the
rows that remain (default physics)."""

import importlib
import math

import numpy as np
import pytest

from tennislab.launcher.aim import aim_all, fly_settings, launcher_params
from tennislab.launcher.machine import DEFAULT_SPEC

_search = importlib.import_module("tennislab.launcher._search")
_aim = importlib.import_module("tennislab.launcher.aim")

#: Machine 5 m right of the centre line; targets at headings 37-40 deg from it: with a 1500 rpm spin
#: some heights' (or a branch's) exact heading passes the range's 40 deg and others do not.
SPEC = DEFAULT_SPEC.with_position(-12.385, -5.0)
EDGE = [(17.0, 37.0, -60.0), (17.0, 40.0, 0.0), (20.0, 37.0, -60.0)]


def _target(dist, heading_deg):
    px, py = SPEC.position
    return (px + dist * math.cos(math.radians(heading_deg)), py + dist * math.sin(math.radians(heading_deg)))


def test_parents_keep_renumbers_the_rows_kept():
    p = _search.Parents(DEFAULT_SPEC)
    ell, info = np.arange(8.0).reshape(4, 2), np.zeros((4, 4))
    p.add(np.array([0, 1, 2, 3]), 100.0, np.array([10.0, 11.0, 12.0, 13.0]), ell, info)
    k = p.keep([True, False, True, False])
    ri, v, a, e, _ = k.arrays()
    assert ri.tolist() == [0, 1] and a.tolist() == [10.0, 12.0] and e.tolist() == [[0, 1], [4, 5]]
    assert not k.new(np.array([1]), 100.0, np.array([12.0])).any()  # row 2 is row 1 now
    assert k.new(np.array([0]), 100.0, np.array([12.0])).all()
    assert len(p) == 4 and len(k) == 2  # the original is left as it was


@pytest.mark.parametrize("dist,heading,axis", EDGE)
def test_rows_outside_the_heading_range_leave_their_parents_behind(monkeypatch, dist, heading, axis):
    seen = {}
    real = _search.search

    def spy(shoot5, spec, ask, rows, flown, need_net, prefs):
        seen.update(rows=list(rows), flown=flown, ask=ask)
        return real(shoot5, spec, ask, rows, flown, need_net, prefs)

    monkeypatch.setattr(_search, "search", spy)
    real_rows = _search.rows_of
    dropped = []

    def rows_spy(*a):
        rows, flown = real_rows(*a)
        dropped.append(sum(not (SPEC.heading.lo <= r.b <= SPEC.heading.hi) for r in rows))
        return rows, flown

    monkeypatch.setattr(_search, "rows_of", rows_spy)
    target = _target(dist, heading)
    sols, reasons = aim_all(target, 100, 1500, axis, None, SPEC)
    assert dropped[0] > 0  # the case does drop rows (else it tests nothing)
    rows, flown, ask = seen["rows"], seen["flown"], seen["ask"]
    ri, v, a, ell, _ = flown.arrays()
    assert ri.max() < len(rows)
    # each parent is the flight of its row's height at the row's heading b0
    pick = np.linspace(0, ri.size - 1, 12).astype(int)
    h = np.array([rows[i].height for i in ri[pick]])
    b0 = np.array([rows[i].b0 for i in ri[pick]])
    shoot = _search.Shooter(SPEC, launcher_params())
    tab = shoot(h, v[pick], a[pick], b0, ask.q_spin_rpm, ask.q_spin_axis_deg, explore=True)
    np.testing.assert_allclose(_search._polar(tab, SPEC.position, b0), ell[pick], atol=1e-9)
    assert set(sols) | set(reasons) == {"low", "high"}  # and the aim answers, or says why not
    for sol in sols.values():
        assert SPEC.heading.lo <= sol.settings.heading_deg <= SPEC.heading.hi
        tr = fly_settings(sol.settings, SPEC, launcher_params())
        assert tr.landing.x == pytest.approx(sol.landing[0], abs=1e-3)
        assert tr.landing.y == pytest.approx(sol.landing[1], abs=1e-3)


def test_spare_flights_are_parents_only_when_asked_for():
    p = _search.Parents(DEFAULT_SPEC)
    ell, info = np.arange(6.0).reshape(3, 2), np.ones((3, 4))
    p.add_spare(np.array([0, 1, 2]), 101.0, np.array([10.0, 11.0, 12.0]), ell, info)
    assert len(p) == 0  # spare: not parents
    have, e, i = p.spare_of(np.array([2, 1, 0, 1]), np.array([101.0, 100.0, 101.0, 101.0]), np.full(4, 12.0))
    assert have.tolist() == [True, False, False, False] and e.tolist() == [[4.0, 5.0]] and i.shape == (1, 4)
    k = p.keep([False, True, True])
    have, e, _ = k.spare_of(np.array([0, 1]), 101.0, np.array([11.0, 12.0]))  # rows 1, 2 are rows 0, 1 now
    assert have.tolist() == [True, True] and e.tolist() == [[2.0, 3.0], [4.0, 5.0]]
    assert not _search.Parents(DEFAULT_SPEC).spare_of(np.array([0]), 100.0, np.array([10.0]))[0].any()


@pytest.mark.parametrize("target,kw", [((8.0, -1.0), {}), ((10.0, 2.0), dict(height_m=1.0)), ((20.0, 1.0), {})])
def test_an_aim_flies_no_setting_twice(flown_settings, target, kw):
    """Every flight of an aim's search is a different launch (the speed's sensitivity flights of stage 1 are
    reused as stage 2's parents, not flown again)."""
    aim_all(target, 100, 1000, 0, spec=DEFAULT_SPEC, **kw)
    every = np.round(np.concatenate(flown_settings), 9)
    assert len(every) > 150
    assert len(np.unique(every, axis=0)) == len(every)


def test_the_search_explores_at_a_looser_tolerance_only_for_smooth_models(monkeypatch):
    """Stages 1-2 fly at EXPLORE_TOL (their landings within 0.1 mm of the model's tolerance: they only guide the
    search); the candidates, the answers, at the model's own; a piecewise-linear model explores at its own."""
    from tennislab.core.flight import FlightParams, fly_batch
    from tennislab.launcher.machine import machine_states

    params = launcher_params()
    assert _search.Shooter(DEFAULT_SPEC, params).explore_tol == _search.EXPLORE_TOL > params.aero.batch_tol
    kinked = FlightParams.from_options(aero="tennislab2026")
    assert _search.Shooter(DEFAULT_SPEC, kinked).explore_tol == kinked.aero.batch_tol
    explored, answered = [], []
    real = _search.Shooter.__call__

    def spy(self, h, v, a, b, w, g, explore=False):
        (explored if explore else answered).append(np.broadcast_arrays(h, v, a, b, w, g))
        return real(self, h, v, a, b, w, g, explore=explore)

    monkeypatch.setattr(_search.Shooter, "__call__", spy)
    sols, _ = aim_all((9.0, 2.0), 100, 1000, 0, spec=DEFAULT_SPEC)
    assert explored and answered
    for cols in explored:
        st = machine_states(DEFAULT_SPEC, *cols)
        loose = fly_batch(st, params, rtol=_search.EXPLORE_TOL, atol=_search.EXPLORE_TOL)
        tight = fly_batch(st, params)
        ok = loose.ok & tight.ok
        assert ok.mean() > 0.9
        d = np.hypot(loose["land_x"] - tight["land_x"], loose["land_y"] - tight["land_y"])[ok]
        assert d.max() < 1e-4
    for sol in sols.values():  # the answer's landing is that of the model's tolerance
        tr = fly_settings(sol.settings, DEFAULT_SPEC, params)
        assert tr.landing.x == pytest.approx(sol.landing[0], abs=1e-5)
        assert tr.landing.y == pytest.approx(sol.landing[1], abs=1e-5)
