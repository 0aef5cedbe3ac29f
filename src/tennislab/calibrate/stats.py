"""Summary statistics of bounce misses: medians, 90th percentiles, biases, with bootstrap intervals.

Serves of one match share balls, air and tracker calibration, so they are not independent: the
confidence intervals resample whole matches (a cluster bootstrap, Efron & Tibshirani 1993,
An Introduction to the Bootstrap, ch. 6; percentile intervals), with a fixed seed so that a study
is reproducible.

References
----------
.. [1] Efron & Tibshirani (1993), An Introduction to the Bootstrap, ch. 6 (percentile intervals)
"""

from __future__ import annotations

import numpy as np

BOOTSTRAP = 200  #: resamples of the cluster bootstrap
SEED = 20260  #: seed of the bootstrap's generator


def _stats(length: np.ndarray, width: np.ndarray) -> np.ndarray:
    miss = np.hypot(length, width)
    return np.array(
        [
            np.median(miss),
            np.quantile(miss, 0.9),
            np.median(length),
            np.median(width),
            np.mean(length),
            np.mean(width),
        ]
    )


def summarize(length, width, cluster=None, *, ci: bool = True, n_boot: int = BOOTSTRAP) -> dict:
    """Statistics of the misses of one group of serves (NaN entries are left out).

    Keys: ``n``, ``miss_median_m``, ``miss_p90_m``, ``length_median_m`` (> 0 long),
    ``width_median_m`` (> 0 left), ``length_mean_m``, ``width_mean_m``, ``length_mad_m``
    (1.4826 x median absolute deviation: a robust standard deviation of the length miss) and,
    with ``ci`` and a ``cluster`` label per serve (the match), ``*_ci95_m`` pairs from the
    cluster bootstrap.
    """
    length = np.asarray(length, dtype=float)
    width = np.asarray(width, dtype=float)
    ok = np.isfinite(length) & np.isfinite(width)
    n = int(ok.sum())
    keys = ("miss_median_m", "miss_p90_m", "length_median_m", "width_median_m", "length_mean_m", "width_mean_m")
    out: dict = {"n": n}
    if n == 0:
        out.update({k: None for k in keys})
        return out
    L, W = length[ok], width[ok]
    out.update(dict(zip(keys, _stats(L, W).tolist())))
    out["length_mad_m"] = float(1.4826 * np.median(np.abs(L - np.median(L))))
    if ci and cluster is not None and n >= 10:
        labels = np.asarray(cluster, dtype=object)[ok]
        _, inv = np.unique(labels.astype(str), return_inverse=True)
        groups = [np.flatnonzero(inv == g) for g in range(inv.max() + 1)]
        if len(groups) >= 5:
            rng = np.random.default_rng(SEED)
            boots = np.empty((n_boot, len(keys)))
            for b in range(n_boot):
                pick = rng.integers(0, len(groups), len(groups))
                idx = np.concatenate([groups[g] for g in pick])
                boots[b] = _stats(L[idx], W[idx])
            lo, hi = np.quantile(boots, [0.025, 0.975], axis=0)
            for k, a, c in zip(keys, lo, hi):
                out[k[:-2] + "_ci95_m"] = [float(a), float(c)]
    return out


def by_group(length, width, labels, cluster=None, *, ci: bool = False) -> dict:
    """:func:`summarize` per group label (sorted), as ``{label: stats}``."""
    labels = np.asarray(labels, dtype=object)
    out = {}
    for g in sorted(set(labels.tolist()), key=str):
        m = labels == g
        out[str(g)] = summarize(
            np.asarray(length)[m], np.asarray(width)[m], None if cluster is None else np.asarray(cluster)[m], ci=ci
        )
    return out
