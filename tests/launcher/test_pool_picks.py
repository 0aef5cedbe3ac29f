"""The compiled pool selection of the aim's search against a plain NumPy statement of the same rule."""

import numpy as np
import pytest

from tennislab.launcher import _select


def _reference(pred, k, members, tops, ids):
    chosen = []
    for p in range(len(tops)):
        idx = (np.flatnonzero(members[p])[:, None] * k + np.arange(k)).reshape(-1)
        idx = idx[np.isfinite(pred[idx])]
        idx = idx[np.argsort(pred[idx], kind="stable")][: 8 * tops[p]]
        _, first = np.unique(ids[idx], return_index=True)
        chosen.append(idx[np.sort(first)][: tops[p]])
    return np.unique(np.concatenate(chosen))


@pytest.mark.parametrize("seed", range(6))
def test_pool_picks_match_the_numpy_rule(seed):
    rng = np.random.default_rng(seed)
    n, k = 60, 7
    pred = np.round(rng.uniform(0, 1, n * k), 2)  # ties
    pred[rng.uniform(size=pred.size) < 0.1] = np.nan
    members = rng.uniform(size=(4, n)) < 0.6
    tops = np.array([3, 5, 1, 8], np.int64)
    ids = rng.integers(0, 40, n * k).astype(np.int64)  # repeated settings
    cand = np.empty(int((8 * tops).sum()), np.int64)
    ends = np.empty(tops.size + 1, np.int64)
    _select._best_kernel(pred, k, members, 8 * tops, cand, ends)
    some = np.unique(cand[: ends[-1]])
    taken = np.zeros(some.size, bool)
    _select._walk_kernel(np.searchsorted(some, cand[: ends[-1]]), ends, ids[some], tops, taken)
    np.testing.assert_array_equal(some[taken], _reference(pred, k, members, tops, ids))


def _reference_lists(pred, k, members, sizes):
    out = []
    for p in range(len(sizes)):
        idx = (np.flatnonzero(members[p])[:, None] * k + np.arange(k)).reshape(-1)
        idx = idx[np.isfinite(pred[idx])]
        out.append(idx[np.argsort(pred[idx], kind="stable")][: sizes[p]])
    return out


@pytest.mark.parametrize("seed", range(8))
def test_nested_pools_read_off_earlier_lists_are_their_own_best(seed):
    """The search's pools per branch: every entry, those whose parent is acceptable, the reference height's and
    both (each inside an earlier one, sometimes equal): every pool's list is its own best, ties to the first."""
    rng = np.random.default_rng(seed)
    n, k = 80, 9
    pred = np.round(rng.uniform(0, 1, n * k), 2)
    pred[rng.uniform(size=pred.size) < 0.2] = np.inf
    low = rng.uniform(size=n) < 0.5
    good = rng.uniform(size=n) < (1.0 if seed % 2 else 0.7)  # all acceptable: pools equal to earlier ones
    ref = rng.uniform(size=n) < 0.3
    every = np.ones(n, bool)
    members = np.array([mask & on for on in (low, ~low) for mask in (every, good, ref, ref & good)])
    tops = np.array([16, 8, 16, 8] * 2, np.int64) * (1 + seed % 3)
    cand = np.empty(int((8 * tops).sum()), np.int64)
    ends = np.empty(tops.size + 1, np.int64)
    _select._best_kernel(pred, k, members, 8 * tops, cand, ends)
    for p, want in enumerate(_reference_lists(pred, k, members, 8 * tops)):
        np.testing.assert_array_equal(cand[ends[p] : ends[p + 1]], want)


def test_distinct_is_unique_and_its_positions():
    c = np.random.default_rng(1).integers(0, 50, 300)
    some, pos = _select._distinct(c, 50)
    np.testing.assert_array_equal(some, np.unique(c))
    np.testing.assert_array_equal(pos, np.searchsorted(np.unique(c), c))
    some, pos = _select._distinct(np.empty(0, np.int64), 5)
    assert some.size == 0 and pos.size == 0


@pytest.mark.parametrize("seed", range(6))
def test_best_of_pools_is_the_stable_argsort_rule(seed):
    """The prune of the predicted candidates: per pool its ``sizes[p]`` smallest finite values (ties to the first
    index), all pools' once, sorted; as a stable argsort restricted to each pool gives them."""
    rng = np.random.default_rng(seed)
    n = 500
    v = np.round(rng.uniform(0, 1, n), 2)  # ties
    v[rng.uniform(size=n) < 0.1] = np.nan
    low, good, ref = (rng.uniform(size=n) < q for q in (0.5, 0.7, 0.1))
    every = np.ones(n, bool)
    members = np.array([m & on for on in (low, ~low) for m in (every, good, ref, ref & good)])
    sizes = np.array([64, 32, 64, 32] * 2, np.int64)
    order = np.argsort(v, kind="stable")
    order = order[np.isfinite(v[order])]
    want = np.unique(np.concatenate([order[m[order]][:s] for m, s in zip(members, sizes)]))
    np.testing.assert_array_equal(_select.best_of_pools(v, members, sizes), want)
