"""Batch work at scale: one API in process, on local cores or on a Dask cluster.

>>> from tennislab.batch import map_chunks
>>> out = map_chunks(fn, {"v": speeds, "w": spins}, scheduler="processes", out="out/mc")

See :func:`map_chunks` and docs/batch.md.  Pieces:

* :mod:`~tennislab.batch.api` -- :func:`map_chunks`, :func:`run_batch`, :class:`BatchResult`
* :mod:`~tennislab.batch.grid` -- :class:`GridSpec`, a lazy Cartesian grid (10^10 rows, never materialised)
* :mod:`~tennislab.batch.sources` -- array / stream chunk sources, :class:`RowRange` (lazy Monte Carlo rows)
* :mod:`~tennislab.batch.store` -- resumable Parquet output (:func:`read_output`, :func:`iter_output`)
* :mod:`~tennislab.batch.schedulers` -- ``local``, ``processes``, ``tcp://`` (registry)
* :mod:`~tennislab.batch.rng` -- per-row counter-based random numbers (chunking-independent)

The command-line flags of batch work (``--scheduler``, ``--out-dir``, ...) live in the CLI layer:
:func:`tennislab.cli.add_scheduler_flag`, :func:`tennislab.cli.batch_options_from_args`
(``tennislab.batch.add_scheduler_flag`` still works, with a :class:`DeprecationWarning`).
"""

from __future__ import annotations

import importlib
import warnings
from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.batch.api import BatchResult, execute_chunk, map_chunks, run_batch
    from tennislab.batch.grid import GridSpec
    from tennislab.batch.schedulers import check_scheduler, register_scheduler, register_url_scheme, scheduler_names
    from tennislab.batch.sources import ArraySource, RowRange, StreamSource, default_chunk_size
    from tennislab.batch.store import MANIFEST, iter_output, read_manifest, read_output

__all__ = [
    "map_chunks",
    "run_batch",
    "BatchResult",
    "execute_chunk",
    "GridSpec",
    "RowRange",
    "ArraySource",
    "StreamSource",
    "default_chunk_size",
    "register_scheduler",
    "register_url_scheme",
    "scheduler_names",
    "check_scheduler",
    "read_output",
    "iter_output",
    "read_manifest",
    "MANIFEST",
]
_getattr, __dir__ = attach_stub(__name__, __file__)

#: names that moved to the CLI layer (flags live only in tennislab.cli): kept working for users' scripts
_MOVED = {"add_scheduler_flag": "tennislab.cli.batch_flags", "batch_options_from_args": "tennislab.cli.batch_flags"}


def __getattr__(name: str):
    if name in _MOVED:
        warnings.warn(
            f"tennislab.batch.{name} moved to tennislab.cli.{name} (flags live in the CLI layer)",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(importlib.import_module(_MOVED[name]), name)
    return _getattr(name)
