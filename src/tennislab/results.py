"""Result objects of the workflows, and the one JSON cleaner.

Every use case is one workflow function in its domain package (``tennislab.linecall.call_track``,
``tennislab.serve.window``, ``tennislab.launcher.aim``, ...) that returns a frozen dataclass
deriving from :class:`Result`.  Its :meth:`~Result.to_dict` is the JSON object that ``--json`` prints,
the web app answers and the report shows.  A result that has rows (a window's serves, a flight's
samples, a track's residuals) derives from :class:`Table`: :meth:`~Table.rows` are its rows (the
``--csv`` columns, a contract) and :meth:`~Table.to_frame` the same as a pandas ``DataFrame`` whose
columns all carry their unit (``speed_ms``, ``launch_angle_deg``; pandas is an optional extra:
``pip install 'tennislab[frame]'``).  A result without rows has no ``to_frame``.

Key rule for ``to_dict()`` (docs/conventions.md): a key says its unit by suffix (``_ms``, ``_kmh``,
``_rpm``, ``_m``, ``_mm``, ``_s``, ``_deg``); a key without a suffix is SI (metres, seconds, m/s,
rad/s) or dimensionless.  Non-finite floats become ``null``.  A frame's column without a suffix is
dimensionless or a label (:data:`UNIT_SUFFIXES`).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, ClassVar

import numpy as np

from tennislab.errors import InputError
from tennislab.units import RPM

__all__ = ["OldAsDict", "Result", "Table", "jsonable", "trajectory_rows"]


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


#: the unit suffixes of a table's columns (docs/conventions.md, "Tables"): a column without one is
#: dimensionless (a count, a ratio, a probability) or a label
UNIT_SUFFIXES = ("_m", "_mm", "_m2", "_s", "_ms", "_kmh", "_mph", "_rpm", "_rad_s", "_deg", "_kg", "_n", "_mpa", "_pct")


class OldAsDict:
    """``as_dict()``: the old name of ``to_dict()`` (one name per concept), kept working with a
    :class:`DeprecationWarning` for the classes that had it."""

    def as_dict(self) -> dict:
        import warnings

        warnings.warn(f"{type(self).__name__}.as_dict() is now to_dict()", DeprecationWarning, stacklevel=2)
        return self.to_dict()  # type: ignore[attr-defined]


class Result:
    """Base of the workflows' result dataclasses.

    Subclasses are frozen dataclasses; they override :meth:`to_dict` when their JSON differs from
    their fields (the default is every field, cleaned by :func:`jsonable`).  Results that are tables
    derive from :class:`Table`.
    """

    def to_dict(self) -> dict:
        """The JSON-ready dict (the ``--json`` output of the command that runs this workflow)."""
        if not dataclasses.is_dataclass(self):
            raise TypeError(f"{type(self).__name__} must be a dataclass or override to_dict()")
        return jsonable({f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.repr})


class Table(Result):
    """A result with rows: :meth:`rows` (one flat dict per row; the ``--csv`` columns) and
    :meth:`to_frame` (the rows as a pandas ``DataFrame``, every column named with its unit).

    Subclasses define :meth:`rows` (options such as a sampling step as keyword arguments, which
    :meth:`to_frame` passes on), :attr:`COLUMNS` (the row keys, for a frame without rows) and
    :attr:`FRAME_COLUMNS` (row keys without their unit -> the frame's column: the CSV keeps its
    published names, the frame says the unit).
    """

    #: the keys of a row, in order (the columns of a frame without rows)
    COLUMNS: ClassVar[tuple[str, ...]] = ()
    #: row key -> frame column, for the keys that do not say their unit
    FRAME_COLUMNS: ClassVar[dict[str, str]] = {}

    def rows(self) -> list[dict]:
        """One flat dict per row (``to_frame()``, ``--csv``)."""
        raise NotImplementedError(f"{type(self).__name__}.rows")

    def to_frame(self, **options):
        """The rows as a pandas ``DataFrame`` with unit-named columns (needs the optional pandas extra);
        ``options`` are those of :meth:`rows`."""
        try:
            import pandas as pd
        except ImportError:  # pandas is an optional third-party extra
            raise InputError("to_frame: needs pandas (pip install 'tennislab[frame]')") from None
        rows = self.rows(**options)
        frame = pd.DataFrame(rows) if rows else pd.DataFrame(columns=list(self.COLUMNS))
        return frame.rename(columns=self.FRAME_COLUMNS)


#: the columns of :func:`trajectory_rows`
TRAJECTORY_COLUMNS = (
    "segment",
    "t_s",
    "x_m",
    "y_m",
    "z_m",
    "vx_ms",
    "vy_ms",
    "vz_ms",
    "speed_ms",
    "spin_x_rpm",
    "spin_y_rpm",
    "spin_z_rpm",
    "spin_rpm",
)
DEFAULT_STEP_S = 0.01  #: sampling step of a flight's rows [s] (100 Hz, a tracker's rate)


def trajectory_rows(segments, step_s: float = DEFAULT_STEP_S) -> list[dict]:
    """Rows of flown segments (objects with ``t`` [s] and a dense solution ``sol(t)`` of the state
    (x, y, z [m], v [m/s], omega [rad/s]), as :class:`tennislab.core.flight.Trajectory`): every
    ``step_s`` [s] from each segment's start, and its end; ``segment`` counts from 0 (0 before the
    first bounce)."""
    if not (isinstance(step_s, (int, float)) and 1e-4 <= step_s <= 1.0):
        raise InputError(f"step_s: expected a sampling step in [0.0001, 1] s, got {step_s!r}")
    out = []
    for k, seg in enumerate(segments):
        t0, t1 = float(seg.t[0]), float(seg.t[-1])
        ts = t0 + step_s * np.arange(int(math.floor((t1 - t0) / step_s + 1e-9)) + 1)
        if t1 - ts[-1] > 1e-9:
            ts = np.append(ts, t1)
        ys = np.asarray(seg.sol(ts)).T
        for t, y in zip(ts, ys):
            w = y[6:9] / RPM
            values = (k, t, *y[0:6], np.linalg.norm(y[3:6]), *w, np.linalg.norm(w))
            out.append({c: (int(v) if c == "segment" else float(v)) for c, v in zip(TRAJECTORY_COLUMNS, values)})
    return out
