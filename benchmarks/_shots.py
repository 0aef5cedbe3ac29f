"""Shared synthetic shot sets for benchmarks."""

import math

import numpy as np

RPM = 2 * math.pi / 60


def mixed_shots(n: int, seed: int = 1) -> np.ndarray:
    """(n, 9) states: serves, groundstrokes and lobs, spin up to 6000 rpm about random axes."""
    rng = np.random.default_rng(seed)
    kind = np.arange(n) % 3
    x = np.where(kind == 2, -11.0, -11.885)
    y = rng.uniform(-4, 4, n)
    z = np.where(kind == 0, rng.uniform(2.2, 3.0, n), rng.uniform(0.3, 1.5, n))
    sp = np.choose(kind, [rng.uniform(30, 60, n), rng.uniform(15, 40, n), rng.uniform(12, 25, n)])
    el = np.radians(np.choose(kind, [rng.uniform(-10, 5, n), rng.uniform(0, 15, n), rng.uniform(25, 60, n)]))
    hd = np.radians(rng.uniform(-10, 10, n))
    ax = rng.normal(size=(n, 3))
    ax /= np.linalg.norm(ax, axis=1)[:, None]
    w = ax * (rng.uniform(0, 6000, n) * RPM)[:, None]
    v = np.stack([sp * np.cos(el) * np.cos(hd), sp * np.cos(el) * np.sin(hd), sp * np.sin(el)], axis=1)
    return np.column_stack([x, y, z, v, w])
