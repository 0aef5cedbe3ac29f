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
