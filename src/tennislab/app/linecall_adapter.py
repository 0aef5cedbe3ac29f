"""Line-call replay: the app's bridge to :mod:`tennislab.linecall` (the pipeline of ``tennislab call --track``).

CSV text -> :func:`tennislab.io.track.parse_track` -> robust fit of the flight
model through the bounce (:func:`tennislab.linecall.fit.fit_track`) -> the ball
mark (:func:`tennislab.core.mark.ball_mark`) -> in or out against a line or an
area with its probability (:func:`tennislab.linecall.decide.call_mark`).
Returns the ``tennislab call`` JSON keys (``bounce.*``, ``mark.*``, ``call``,
``p_in``, ``distance_mm``, ``fit.*``) plus what the page draws: the track, the
fitted trajectory, the mark's contact discs and the called line's rectangle.
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams


def pipeline(text: str, surface: str = "hard", line: str | None = None, target: str | None = None):
    from tennislab.core.mark import ball_mark
    from tennislab.io.track import parse_track
    from tennislab.linecall.decide import call_mark
    from tennislab.linecall.fit import fit_track

    track = parse_track(text, name="csv")
    params = FlightParams()
    fit = fit_track(track.t, track.xyz, track.sigma, params, surface)
    # as ``tennislab call --track`` (tennislab/cli/call.py): the fit's outgoing velocity (the bounce
    # model's when the track has no points after the bounce)
    mark = ball_mark(fit.bounce_xy, fit.velocity_in, fit.velocity_out, fit.spin_in, fit.surface, params.ball)
    res = call_mark(mark, court=params.court, target=target, line=line, bounce_cov=fit.bounce_cov)
    return track, fit, mark, res


def summary(fit, mark, res) -> dict:
    out = {
        "bounce": {
            "x": float(fit.bounce_xy[0]),
            "y": float(fit.bounce_xy[1]),
            "t": fit.t_bounce,
            "sigma_mm": fit.sigma_bounce * 1e3,
        },
        "mark": {"length": mark.length, "width": mark.width, "x": float(mark.center[0]), "y": float(mark.center[1])},
        "call": res["call"],
        "p_in": res["p_in"],
        "distance_mm": res["distance_mm"],
        "fit": {
            "rms_mm": fit.rms * 1e3,
            "outliers": int(np.count_nonzero(fit.outlier)),
            "has_post": bool(fit.has_post),
        },
        "line": res.get("line"),
        "target": res.get("target"),
        "lines": res.get("lines", {}),
    }
    return out


def reference_call(text: str, surface: str = "hard", line: str | None = None, target: str | None = None) -> dict:
    """The call of a track's text by the Python API (what the page must show)."""
    _, fit, mark, res = pipeline(text, surface, line, target)
    return summary(fit, mark, res)


def _closest_line(res: dict, mark) -> str | None:
    """The bounding line the mark is nearest to (smallest |distance|), for drawing."""
    lines = res.get("lines") or {}
    if not lines:
        return None
    return min(lines, key=lambda k: abs(lines[k]["distance_mm"]))


def call(v: dict, text: str) -> dict:
    """The page's line call (form ``linecall``)."""
    line = None if v["line"] == "auto" else v["line"]
    target = None if v["target"] == "auto" else v["target"]
    track, fit, mark, res = pipeline(text, v["surface"], line, target)
    out = summary(fit, mark, res)
    drawn = line or _closest_line(res, mark)
    lines = ITF_COURT.lines()
    out["line"] = drawn
    if line is None and drawn is not None:  # report the nearest line's own numbers beside the area's
        out["nearest_line"] = {"name": drawn, **res["lines"][drawn]}
    out["line_rect"] = list(lines[drawn]) if drawn in lines else None
    out["mark"]["discs"] = np.round(mark.discs, 5).tolist()
    out["mark"]["direction"] = [float(d) for d in mark.direction]
    t_fit = np.linspace(track.t[0], track.t[-1] if fit.has_post else fit.t_bounce, 200)
    pts = fit.positions(t_fit)
    out["fitted"] = np.round(pts[np.all(np.isfinite(pts), axis=1)], 4).tolist()
    step = max(1, len(track) // 400)
    out["track"] = np.round(np.column_stack([track.t, track.xyz])[::step], 5).tolist()
    return out
