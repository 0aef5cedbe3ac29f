"""Settings keys and the choice of the candidates to fly, for :mod:`._search` (compiled: the ~10^4 predicted
candidates of an aim are ranked and deduplicated here without NumPy sorts).

A settings key numbers one combination of the machine's steps (height, speed, elevation, heading, spin rate and
axis: Wojcicki, Pucilowski & Kulesza 2010, section 2), so that the search flies no combination twice.
"""

from __future__ import annotations

import functools
import math

import numba as nb
import numpy as np

from tennislab.launcher.machine import MachineSpec, settings_columns

KEY_FIELDS = ("height", "speed", "elevation", "heading", "spin", "spin_axis")


@functools.lru_cache(maxsize=16)
def _key_radix(spec: MachineSpec) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Per machine (cached): the lowest value, step and number of indices of each setting of :func:`settings_key`
    and whether their product fits an int64."""
    ranges = [getattr(spec, f) for f in KEY_FIELDS]
    sizes = [int(round((r.hi - r.lo) / r.step)) + 2 for r in ranges]
    lo = np.array([r.lo for r in ranges], float)
    step = np.array([r.step for r in ranges], float)
    return lo, step, np.array(sizes, np.int64), math.prod(sizes) < 2**62


def settings_key(spec: MachineSpec, h, v, a, b, w, g) -> np.ndarray:
    """One int64 per setting combination (the step index of each setting, in mixed radix), or, for a machine
    with more steps than 2^62 combinations, one bytes-like key per row."""
    lo, step, sizes, fits = _key_radix(spec)
    grid = settings_columns(h, v, a, b, w, g)
    shape, cols = grid.shape[1:], grid.reshape(len(grid), -1)
    if fits:
        out = np.empty(cols.shape[1], np.int64)
        _key_kernel(cols, lo, step, sizes, out)
        return out.reshape(shape)
    idx = [np.rint((c - lo[i]) / step[i]).astype(np.int64) + 1 for i, c in enumerate(cols)]
    arr = np.ascontiguousarray(np.stack(idx, axis=-1))
    return arr.view(np.dtype((np.void, 8 * len(cols)))).reshape(shape)


@nb.njit(cache=True, error_model="numpy")
def _key_kernel(cols, lo, step, sizes, out):
    """:func:`settings_key` in mixed radix: each setting's step index (rounded half to even, as NumPy's rint), + 1,
    clipped to [0, size - 1]."""
    for j in range(cols.shape[1]):
        key = 0
        for i in range(cols.shape[0]):
            k = np.int64(np.rint((cols[i, j] - lo[i]) / step[i])) + 1
            key = key * sizes[i] + min(max(k, 0), sizes[i] - 1)
        out[j] = key


def pool_picks(spec: MachineSpec, pr, members: np.ndarray, tops: np.ndarray, cols) -> tuple:
    """The candidates of :func:`._search.search` to fly (``pr``: its :class:`._search.Predicted`): per pool p
    (``members[p]``: its entries), the ``8 * tops[p]`` best predicted (ties to the first), then in that order the
    first ``tops[p]`` of distinct settings; all pools' picks once (sorted indices) and their settings keys
    (:func:`settings_key`).  Compiled: the selection (:func:`_best_kernel`, a bounded heap: no sort of the ~10^4
    candidates; a pool inside an earlier one read off that one's list, :func:`_from_earlier`), the distinct
    picks (:func:`_distinct`) and the walk (:func:`_walk_kernel`)."""
    some, pos, ends = _best_lists(pr.pred, pr.k, members, 8 * tops)
    sub = settings_key(spec, *(pr.at(c, some) for c in cols))
    if sub.dtype == np.int64:
        ids = sub
    else:  # a machine of more than 2^62 settings: the distinct keys numbered
        ids = np.unique(sub, return_inverse=True)[1].astype(np.int64).reshape(-1)
    taken = np.zeros(some.size, bool)
    _walk_kernel(pos, ends, ids, tops, taken)
    return some[taken], sub[taken]


def best_of_pools(values: np.ndarray, members: np.ndarray, sizes) -> np.ndarray:
    """The union (sorted indices) over pools p of the ``sizes[p]`` entries of smallest (value, index) among the
    finite ``values`` of the pool (``members[p]``: a mask over the entries), as a stable argsort restricted to
    each pool would give them (non-finite values left out).  Compiled: :func:`_best_kernel`, :func:`_distinct`."""
    return _best_lists(np.ascontiguousarray(values, dtype=float), 1, members, sizes)[0]


def _best_lists(pred: np.ndarray, k: int, members: np.ndarray, sizes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_best_kernel`'s lists of every pool: the distinct candidates of all lists (sorted), each list
    element's position among them, and the lists' ends."""
    sizes = np.asarray(sizes, np.int64)
    cand = np.empty(int(sizes.sum()), np.int64)
    ends = np.empty(sizes.size + 1, np.int64)
    _best_kernel(pred, k, members, sizes, cand, ends)
    some, pos = _distinct(cand[: ends[-1]], pred.size)
    return some, pos, ends


#: Variants per entry from which :func:`_best_kernel` visits the entries best first (below it, in their order)
ORDERED_FROM = 4


@nb.njit(cache=True, error_model="numpy")
def _best_kernel(pred, k, members, sizes, cand, ends):
    """Per pool p, the (up to) ``sizes[p]`` candidates j of smallest (pred[j], j) among the finite ones of its
    entries (``members[p, j // k]``), in that order: into ``cand[ends[p]:ends[p + 1]]`` (``ends[0]`` = 0).

    A bounded max-heap of (value, index) per pool.  With :data:`ORDERED_FROM` or more variants per entry the
    entries are visited in the order of their best variant, and a pool stops at the first entry whose best is
    worse than its full heap's worst: the same candidates (the heap orders ties by index), a fraction of the
    comparisons (the unpredictable branches of a scan of every candidate cost ~25 ns each)."""
    ne = members.shape[1]
    best = np.full(ne, np.inf)
    if k >= ORDERED_FROM:
        for e in range(ne):
            mn = np.inf
            for j in range(e * k, e * k + k):
                if pred[j] < mn:  # NaN never
                    mn = pred[j]
            best[e] = mn
        visit = np.argsort(best, kind="mergesort")
    else:
        visit = np.arange(ne)
    ends[0] = 0
    for p in range(members.shape[0]):
        if _from_earlier(p, k, members, sizes, cand, ends):
            continue
        m = sizes[p]
        hv = np.empty(m)
        hi = np.empty(m, np.int64)
        n = 0
        for ee in range(ne):
            e = visit[ee]
            if not members[p, e]:
                continue
            if k >= ORDERED_FROM and (best[e] == np.inf or (n == m and best[e] > hv[0])):
                break  # no later entry holds a candidate the heap takes
            for j in range(e * k, e * k + k):
                v = pred[j]
                if not np.isfinite(v):
                    continue
                if n < m:  # a max-heap of (value, index): sift up
                    c = n
                    n += 1
                    while c > 0:
                        q = (c - 1) // 2
                        if hv[q] > v or (hv[q] == v and hi[q] > j):
                            break
                        hv[c], hi[c] = hv[q], hi[q]
                        c = q
                    hv[c], hi[c] = v, j
                elif v < hv[0] or (v == hv[0] and j < hi[0]):  # replaces the worst kept: sift down
                    c = 0
                    while True:
                        a = 2 * c + 1
                        if a >= n:
                            break
                        if a + 1 < n and (hv[a + 1] > hv[a] or (hv[a + 1] == hv[a] and hi[a + 1] > hi[a])):
                            a += 1
                        if hv[a] < v or (hv[a] == v and hi[a] < j):
                            break
                        hv[c], hi[c] = hv[a], hi[a]
                        c = a
                    hv[c], hi[c] = v, j
        idx = hi[:n].copy()
        idx.sort()
        order = np.argsort(pred[idx], kind="mergesort")  # by value, ties by index
        s = ends[p]
        for i in range(n):
            cand[s + i] = idx[order[i]]
        ends[p + 1] = s + n


@nb.njit(cache=True)
def _distinct(c, size):
    """The distinct values of ``c`` (integers in [0, size)) in rising order, and each element's position among
    them: ``np.unique(c)`` and ``np.searchsorted`` of ``c`` in it, in two passes."""
    rank = np.full(size, -1, np.int64)
    for i in range(c.size):
        rank[c[i]] = 0
    n = 0
    for j in range(size):
        if rank[j] == 0:
            rank[j] = n
            n += 1
    some = np.empty(n, np.int64)
    pos = np.empty(c.size, np.int64)
    for i in range(c.size):
        pos[i] = rank[c[i]]
        some[pos[i]] = c[i]
    return some, pos


@nb.njit(cache=True)
def _from_earlier(p, k, members, sizes, cand, ends) -> bool:
    """Pool p's list of :func:`_best_kernel` read off an earlier pool q's whose entries hold p's, when that list
    holds ``sizes[p]`` of p's candidates or all of q's: its members of p, in its order, are then p's best (a
    candidate of p missing from q's list is worse than every one in it).  False if no earlier list serves."""
    m, s = sizes[p], ends[p]
    for q in range(p):
        inside = True
        for e in range(members.shape[1]):
            if members[p, e] and not members[q, e]:
                inside = False
                break
        if not inside:
            continue
        n = 0
        for i in range(ends[q], ends[q + 1]):
            if n >= m:
                break
            j = cand[i]
            if members[p, j // k]:
                cand[s + n] = j
                n += 1
        if n >= m or ends[q + 1] - ends[q] < sizes[q]:
            ends[p + 1] = s + n
            return True
    return False


@nb.njit(cache=True)
def _walk_kernel(pos, ends, ids, tops, taken):
    """Per pool p, along ``pos[ends[p]:ends[p + 1]]`` (indices into ``ids``), the first ``tops[p]`` of distinct
    ``ids`` marked in ``taken``."""
    for p in range(ends.size - 1):
        seen = {np.int64(0)}
        seen.clear()
        got = 0
        for i in range(ends[p], ends[p + 1]):
            if got >= tops[p]:
                break
            key = ids[pos[i]]
            if key in seen:
                continue
            seen.add(key)
            taken[pos[i]] = True
            got += 1
