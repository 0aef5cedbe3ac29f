"""Serve explorer, launcher planner and line-call replay: adapters to the physics modules.

Each function takes the validated values of its form (user units) and returns a
JSON-able dict.  The modules behind them (``tennislab.serve`` with
``tennislab.core.impact``, ``tennislab.launcher``, ``tennislab.linecall``) are
imported inside the functions, after :func:`services.require`, so that a
missing module only disables its own page (HTTP 503, "not available").
"""

from __future__ import annotations

import io

import numpy as np

from tennislab.app import services as S
from tennislab.core.flight import FlightParams, fly
from tennislab.errors import InputError

#: Seed 000 section 2.3 (Grosen, Kousted & Treichel 2021): impact height [m], racket speed [m/s].
#: Used only when ``tennislab.serve`` does not provide its own profiles.
SEED_PLAYERS = {
    "professional": {"height": 3.0, "racket_speed": 40.0},
    "recreational": {"height": 2.8, "racket_speed": 30.0},
    "junior": {"height": 2.2, "racket_speed": 25.0},
}


def players() -> dict:
    """Player profiles ``{name: {height, racket_speed}}`` (from ``tennislab.serve`` when available)."""
    try:
        from tennislab.app import serve_adapter

        return serve_adapter.players()
    except Exception:
        return dict(SEED_PLAYERS)


# ------------------------------------------------------------------ serve
def serve(v: dict) -> dict:
    """One serve: impact -> launch -> 3-D flight -> success (form ``serve``)."""
    S.require("serve")
    from tennislab.app import serve_adapter

    return serve_adapter.serve(v)


def serve_window(v: dict) -> dict:
    """The alpha x beta window of a player (form ``window``) as grids for the heat map."""
    S.require("serve")
    from tennislab.app import serve_adapter

    return serve_adapter.window(v)


# ------------------------------------------------------------------ launcher
def aim(v: dict) -> dict:
    """Quantised machine settings, rollers and trajectory for a target (form ``aim``)."""
    S.require("launcher")
    from tennislab.app import launcher_adapter

    return launcher_adapter.aim(v)


def drill(v: dict, shots=None, name=None) -> dict:
    """A drill document (the file ``tennislab launcher drill`` reads) from a list of aim forms."""
    S.require("launcher")
    try:
        import tennislab.io.drill
        import tennislab.launcher.drills  # noqa: F401
    except ImportError as exc:
        raise S.Unavailable(f"drill files: not available in this installation ({exc})") from None
    from tennislab.app import launcher_adapter

    return launcher_adapter.drill(shots, name)


# ------------------------------------------------------------------ line calling
def linecall(v: dict, csv=None) -> dict:
    """A line call from an uploaded track (CSV text ``t,x,y,z[,sigma]``; form ``linecall``)."""
    from tennislab.app.fields import MAX_TRACK_BYTES

    if csv is None:
        raise InputError("csv: a track file is required (columns t,x,y,z and optionally sigma)")
    if not isinstance(csv, str):
        raise InputError("csv: expected the file's text")
    if len(csv.encode("utf-8", "replace")) > MAX_TRACK_BYTES:
        raise InputError(f"csv: the track file is larger than {MAX_TRACK_BYTES // 1000} kB")
    S.require("linecall")
    from tennislab.app import linecall_adapter

    return linecall_adapter.call(v, csv)


#: The example serve of the line-call page and the report: hard and flat down the T, landing
#: about 6 mm beyond the far service line's outer edge (x = 6.40 m): a close call.
SAMPLE_SERVE = {"position": (-11.8, 0.4, 2.85), "velocity": (48.0, -0.9, -4.257), "spin": (0.0, 60.0, 0.0)}


def synthetic_track(
    seed: int = 7,
    sigma: float = 0.003,
    rate: float = 340.0,
    shot: dict | None = None,
    params: FlightParams | None = None,
):
    """A synthetic track (t, x, y, z) [s, m] sampled at ``rate`` Hz with Gaussian noise ``sigma`` [m].

    With :mod:`tennislab.linecall` installed the track runs through the bounce
    (:func:`tennislab.linecall.synth.synthetic_track`); otherwise it stops at the
    first ground contact.  Returns (samples (N, 4), true first contact (x, y)).
    """
    shot = shot or SAMPLE_SERVE
    try:
        from tennislab.linecall.synth import synthetic_track as synth
    except ImportError:
        synth = None
    if synth is not None:
        tr = synth(
            shot["position"], shot["velocity"], shot["spin"], params, rate=rate, sigma=sigma, seed=seed, after=0.15
        )
        keep = tr.t >= tr.bounce.t - 0.35  # what a tracker near the line sees
        return np.column_stack([tr.t[keep], tr.xyz[keep]]), (tr.bounce.x, tr.bounce.y)
    tr = fly(shot["position"], shot["velocity"], shot["spin"], params)
    t_end = tr.landing.t
    t = np.arange(0.0, t_end, 1.0 / rate)
    t = t[t >= t_end - 0.35]
    pts = tr.sol(t)[0:3].T
    rng = np.random.default_rng(seed)
    pts = pts + rng.normal(0.0, sigma, pts.shape)
    return np.column_stack([t, pts]), (tr.landing.x, tr.landing.y)


def sample_track() -> str:
    """CSV text of :func:`synthetic_track` (the example serve, sigma 3 mm at 340 Hz)."""
    data, _ = synthetic_track()
    buf = io.StringIO()
    buf.write("t,x,y,z,sigma\n")
    for row in data:
        buf.write(f"{row[0]:.6f},{row[1]:.5f},{row[2]:.5f},{row[3]:.5f},0.003\n")
    return buf.getvalue()
