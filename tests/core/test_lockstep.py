"""The lockstep batch kernel against its reference, the per-shot kernel: the same table to 1e-9 m."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tennislab.core.aero import get_aero_model
from tennislab.core.atmosphere import Atmosphere
from tennislab.core.events import COL, COLUMNS
from tennislab.core.flight import KERNELS, FlightParams, fly_batch
from tennislab.core.lockstep import LANES, lockstep_suits
from tennislab.errors import InputError
from tennislab.units import RPM

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from _shots import mixed_shots  # the shots of bench_flight.py and bench_peers.py


def shot_states(n: int, seed: int = 1) -> np.ndarray:
    return mixed_shots(n, seed=seed)


#: the smooth models the lockstep kernel serves by default; the default model first
SMOOTH = ("choppin2018", "stepanek1988", "launcher2015", "cross2014", "constant")
#: the benchmarks' constant physics (benchmarks/bench_peers.py)
CONSTANT = get_aero_model("constant", cd=0.55, cl=0.25)
#: integer columns, equal exactly; the others to 1e-9 (m, s, m/s)
_EXACT = ("status", "n_steps", "net_status")


def _params(name: str, **kw) -> FlightParams:
    aero = CONSTANT if name == "constant" else get_aero_model(name)
    return FlightParams(aero=aero, **kw)


def assert_same_tables(states, params: FlightParams, **kw):
    a = fly_batch(states, params, kernel="per-shot", **kw).data
    b = fly_batch(states, params, kernel="lockstep", **kw).data
    assert np.array_equal(np.isnan(a), np.isnan(b)), "the kernels disagree on which events happened"
    for name in _EXACT:
        assert np.array_equal(a[:, COL[name]], b[:, COL[name]]), name
    d = np.abs(np.nan_to_num(a - b))
    worst = d.max(axis=0)
    bad = [f"{c} {worst[i]:.2e}" for i, c in enumerate(COLUMNS) if worst[i] > 1e-9]
    assert not bad, "lockstep differs from per-shot: " + ", ".join(bad)


@pytest.mark.slow
@pytest.mark.parametrize("name", SMOOTH)
@pytest.mark.parametrize("obstacle", [False, True])
def test_lockstep_agrees_with_per_shot_on_the_benchmark_shots(name, obstacle):
    # 300 mixed shots (as bench_flight_accuracy.py), a batch that is not a multiple of the lanes
    S = shot_states(301, seed=23)
    assert_same_tables(S, _params(name, net_obstacle=obstacle))


@pytest.mark.slow
def test_lockstep_agrees_with_wind_decay_tolerance_and_one_thread():
    S = shot_states(97, seed=5)
    p = FlightParams(atmosphere=Atmosphere(wind=(-3.0, 1.5, 0.5)), spin_decay=0.2, net_obstacle=True)
    assert_same_tables(S, p, rtol=1e-9, atol=1e-9)
    assert_same_tables(S, p, parallel=False)


def test_rows_that_end_at_the_start_or_never_land():
    """Bad starts, refused launches, a ball on the ground, t_max and the step limit, among good rows."""
    good = shot_states(2 * LANES + 3, seed=2)
    odd = np.array(
        [
            [np.nan, 0, 1, 10, 0, 1, 0, 0, 0],  # not finite
            [-11, 0, 1, 500, 0, 0, 0, 0, 0],  # too fast
            [-11, 0, 0.0, 10, 0, 1, 0, 0, 0],  # below the ground
            [-11, 0, 0.0335, 10, 0, -1, 0, 0, 0],  # on the ground going down: ends at the start
            [-11, 0, 0.0335, 10, 0, 3, 0, 0, 0],  # on the ground going up: a hop
        ]
    )
    S = np.vstack([odd, good[:7], odd[::-1], good[7:]])
    assert_same_tables(S, FlightParams())
    assert_same_tables(S, FlightParams(t_max=0.3, net_obstacle=True))
    assert_same_tables(S[:1], FlightParams())  # a batch of one
    assert fly_batch(np.empty((0, 9)), FlightParams(), kernel="lockstep").data.shape == (0, len(COLUMNS))


_finite = dict(allow_nan=False, allow_infinity=False)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    name=st.sampled_from(SMOOTH),
    obstacle=st.booleans(),
    seed=st.integers(0, 2**31),
    n=st.integers(1, 3 * LANES),
    speed=st.floats(1.0, 70.0, **_finite),
    rpm=st.floats(0.0, 8000.0, **_finite),
)
def test_lockstep_agrees_on_any_launch(name, obstacle, seed, n, speed, rpm):
    """Any launches from either side, at any height and direction, spinning about any axis."""
    rng = np.random.default_rng(seed)
    pos = np.column_stack([rng.uniform(-13, 13, n), rng.uniform(-5, 5, n), rng.uniform(0.0335, 3.5, n)])
    d = rng.normal(size=(n, 3))
    v = d / np.linalg.norm(d, axis=1)[:, None] * speed * rng.uniform(0.2, 1.0, (n, 1))
    a = rng.normal(size=(n, 3))
    w = a / np.linalg.norm(a, axis=1)[:, None] * rpm * RPM
    assert_same_tables(np.hstack([pos, v, w]), _params(name, net_obstacle=obstacle))


def test_auto_takes_lockstep_where_it_is_faster():
    for name in SMOOTH:
        assert lockstep_suits(_params(name).aero.kernel), name
    assert not lockstep_suits(get_aero_model("tennislab2026").kernel)
    assert not lockstep_suits(get_aero_model(lambda v, w: (0.55, 0.1)).kernel)
    S = shot_states(20, seed=3)
    p = FlightParams()
    assert np.array_equal(fly_batch(S, p).data, fly_batch(S, p, kernel="lockstep").data, equal_nan=True)
    assert KERNELS == ("auto", "lockstep", "per-shot")


def test_a_user_kernel_runs_in_either_kernel():
    p = FlightParams(aero=get_aero_model(lambda v, w: (0.55, 0.2)))
    assert_same_tables(shot_states(11, seed=4), p)


def test_unknown_kernel_is_refused():
    with pytest.raises(InputError, match="kernel: unknown flight kernel 'simd'; allowed: auto, lockstep, per-shot"):
        fly_batch(shot_states(1), FlightParams(), kernel="simd")


@pytest.mark.parametrize("name", ["choppin2018", "constant", "stepanek1988"])
@pytest.mark.parametrize("obstacle", [False, True])
def test_a_shot_lands_the_same_whatever_batch_it_is_flown_in(name, obstacle):
    """Only the lanes up to the last busy one are computed (a batch of a few shots pays for those) and a drained
    block moves its flights down to its lowest lanes (``_compact``), yet a shot's row is the same bit for bit
    alone, in a short batch (the lanes of the vector loop's remainder) and in a long one: batches of 1 to
    LANES + 5 shots against the whole batch, both threadings."""
    S = shot_states(3 * LANES + 7, seed=5)
    p = _params(name, net_obstacle=obstacle)
    whole = fly_batch(S, p, kernel="lockstep").data
    for size in (1, 2, 3, 5, 6, 7, 9, 17, LANES - 1, LANES + 1, LANES + 5):
        for parallel in (False, True):
            parts = [
                fly_batch(S[i : i + size], p, kernel="lockstep", parallel=parallel).data for i in range(0, len(S), size)
            ]
            assert np.array_equal(np.vstack(parts), whole, equal_nan=True), (size, parallel)
