"""Ready-made batch functions (module-level, picklable) for :func:`map_chunks`."""

from __future__ import annotations

import numpy as np

from tennislab.core.flight import FlightParams, fly_batch

#: Input columns of :func:`fly_chunk` when no ``states`` (N, 9) column is given.
STATE_KEYS = ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")


def chunk_states(chunk: dict) -> np.ndarray:
    """The (n, 9) initial states of a chunk: its ``states`` column or the nine :data:`STATE_KEYS`."""
    if "states" in chunk:
        return np.asarray(chunk["states"], dtype=np.float64)
    return np.column_stack([np.asarray(chunk[k], dtype=np.float64) for k in STATE_KEYS])


def fly_chunk(
    chunk: dict,
    params: FlightParams | None = None,
    *,
    rtol: float | None = None,
    atol: float | None = None,
    parallel: bool = True,
    columns=None,
) -> dict:
    """Fly a chunk of initial states with :func:`fly_batch`; return its event columns.

    Use with ``functools.partial(fly_chunk, params=...)``; ``columns`` keeps a
    subset (e.g. ``("land_x", "land_y", "status")``) to shrink the output.
    ``rtol``/``atol`` default to :func:`fly_batch`'s own defaults.
    """
    table = fly_batch(chunk_states(chunk), params, rtol=rtol, atol=atol, parallel=parallel)
    d = table.to_dict()
    if columns is not None:
        d = {k: d[k] for k in columns}
    return {k: np.ascontiguousarray(v) for k, v in d.items()}
