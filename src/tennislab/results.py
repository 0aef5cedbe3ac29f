"""Result objects of the workflows, and the one JSON cleaner.

Every use case is one workflow function in its domain package (``tennislab.linecall.call_track``,
``tennislab.serve.window``, ``tennislab.launcher.aim``, ...) that returns a frozen dataclass
deriving from :class:`Result`.  Its :meth:`~Result.to_dict` is the JSON object that ``--json`` prints,
the web app answers and the report shows; for tables :meth:`~Result.to_frame` gives a pandas
``DataFrame`` (pandas is an optional extra: ``pip install 'tennislab[frame]'``).

Key rule for ``to_dict()`` (docs/conventions.md): a key says its unit by suffix (``_ms``, ``_kmh``,
``_rpm``, ``_m``, ``_mm``, ``_s``, ``_deg``); a key without a suffix is SI (metres, seconds, m/s,
rad/s) or dimensionless.  Non-finite floats become ``null``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from tennislab.errors import InputError


def jsonable(obj: Any) -> Any:
    """A JSON-ready copy of ``obj``: NumPy -> Python, NaN/inf -> ``None``, results -> their ``to_dict()``.

    Containers are walked iteratively up to a depth of 64 (deeper structures are refused: no
    workflow produces them, and a recursion error must never reach a user).
    """
    return _clean(obj, 0)


def _clean(obj: Any, depth: int) -> Any:
    if depth > 64:
        raise InputError("result: nested deeper than 64 levels")
    if obj is None or isinstance(obj, (bool, str, int)) and not isinstance(obj, np.integer):
        return obj
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, Result):
        return _clean(obj.to_dict(), depth + 1)
    if isinstance(obj, dict):
        return {str(k): _clean(v, depth + 1) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v, depth + 1) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist(), depth + 1)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return _clean({f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}, depth + 1)
    return obj


class Result:
    """Base of the workflows' result dataclasses.

    Subclasses are frozen dataclasses; they override :meth:`to_dict` when their JSON differs from
    their fields (the default is every field, cleaned by :func:`jsonable`), and :meth:`rows` when
    they are tables.
    """

    def to_dict(self) -> dict:
        """The JSON-ready dict (the ``--json`` output of the command that runs this workflow)."""
        if not dataclasses.is_dataclass(self):
            raise TypeError(f"{type(self).__name__} must be a dataclass or override to_dict()")
        return jsonable({f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.repr})

    def rows(self) -> list[dict]:
        """One flat dict per row, for tabular results (``to_frame()``, ``--csv``)."""
        raise TypeError(f"{type(self).__name__} is not a table")

    def to_frame(self):
        """The rows as a pandas ``DataFrame`` (needs the optional pandas extra)."""
        try:
            import pandas as pd
        except ImportError:  # pandas is an optional third-party extra
            raise InputError("to_frame: needs pandas (pip install 'tennislab[frame]')") from None
        return pd.DataFrame(self.rows())
