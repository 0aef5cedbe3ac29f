"""The app's pages as jobs: each takes the validated values of its form and returns a JSON-able dict.

The serve explorer, launcher planner and line-call replay call their domain
workflows through the adapters (:mod:`~tennislab.app.serve_adapter`,
:mod:`~tennislab.app.launcher_adapter`, :mod:`~tennislab.app.linecall_adapter`);
the flight page calls :func:`tennislab.app.services.flight`.  :data:`JOBS` is the
table the worker processes of :mod:`tennislab.app.pool` run from (a job is named,
never given as code).
"""

from __future__ import annotations

import io
from collections.abc import Callable

import numpy as np

import tennislab.app.launcher_adapter as launcher_adapter
import tennislab.app.linecall_adapter as linecall_adapter
import tennislab.app.serve_adapter as serve_adapter
import tennislab.app.services as S
from tennislab.app.fields import MAX_TRACK_BYTES
from tennislab.errors import InputError
from tennislab.linecall.synth import sample_serve


def players() -> dict:
    """Player profiles ``{name: {height, racket_speed}}`` of :mod:`tennislab.serve.players`."""
    return serve_adapter.players()


# ------------------------------------------------------------------ serve
def serve(v: dict) -> dict:
    """One serve: impact -> launch -> 3-D flight -> success and verdict (form ``serve``)."""
    return serve_adapter.serve(v)


def serve_window(v: dict) -> dict:
    """The alpha x beta window of a player (form ``window``) as grids for the heat map."""
    return serve_adapter.window(v)


# ------------------------------------------------------------------ launcher
def aim(v: dict) -> dict:
    """Quantised machine settings, rollers and trajectory for a target (form ``aim``)."""
    return launcher_adapter.aim(v)


def drill(v: dict, shots=None, name=None) -> dict:
    """A drill document (the file ``tennislab launcher drill`` reads) from a list of aim forms."""
    return launcher_adapter.drill(shots, name)


# ------------------------------------------------------------------ line calling
def linecall(v: dict, csv=None) -> dict:
    """A line call from an uploaded track (CSV text ``t,x,y,z[,sigma]``; form ``linecall``)."""
    if csv is None:
        raise InputError("csv: a track file is required (columns t,x,y,z and optionally sigma)")
    if not isinstance(csv, str):
        raise InputError("csv: expected the file's text")
    if len(csv.encode("utf-8", "replace")) > MAX_TRACK_BYTES:
        raise InputError(f"csv: the track file is larger than {MAX_TRACK_BYTES // 1000} kB")
    return linecall_adapter.call(v, csv)


def synthetic_track(seed: int = 7, sigma: float = 0.003, rate: float = 340.0):
    """The example serve as a tracker near the line sees it (:func:`tennislab.linecall.synth.sample_serve`).

    Returns (samples (N, 4): t, x, y, z [s, m], true first contact (x, y) [m]).
    """
    tr = sample_serve(seed=seed, sigma=sigma, rate=rate)
    return np.column_stack([tr.t, tr.xyz]), (tr.bounce.x, tr.bounce.y)


def sample_track(v: dict | None = None) -> str:
    """CSV text of :func:`synthetic_track` (the example serve, sigma 3 mm at 340 Hz), every number at full
    precision, so that ``tennislab call --track`` on it and the report's line-call section (the same
    samples) give the same call to the last digit."""
    data, _ = synthetic_track()
    buf = io.StringIO()
    buf.write("t,x,y,z,sigma\n")
    for row in data:
        buf.write(",".join(repr(float(c)) for c in row) + ",0.003\n")
    return buf.getvalue()


#: job name -> function(values, **extra) run by the worker processes (:mod:`tennislab.app.pool`)
JOBS: dict[str, Callable[..., object]] = {
    "flight": S.flight,
    "serve": serve,
    "window": serve_window,
    "aim": aim,
    "drill": drill,
    "linecall": linecall,
    "sample": sample_track,
}
