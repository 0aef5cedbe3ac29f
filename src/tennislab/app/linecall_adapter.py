"""Line-call replay: the app's bridge to :func:`tennislab.linecall.call_track` (the workflow of
``tennislab call --track``).

CSV text -> :func:`tennislab.io.track.parse_track` -> :func:`tennislab.linecall.call_track` -> its
``to_dict()`` (every ``tennislab call --json`` key: ``bounce.*``, ``mark.*``, ``call``, ``p_in``,
``distance_mm``, ``fit.*``, ``review_reasons``, ``spin``, ``net``) plus what the page draws: the
track, the fitted trajectory, the mark's contact discs and the called line's rectangle, and ``words``: the
signed distance, the fitted scales and the spin said as the CLI and the report say them
(:mod:`tennislab.plot.text`: "out by 3.1 mm", "1171 ± 733 rpm ...").
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams
from tennislab.io.track import Track, parse_track
from tennislab.linecall import TrackCall, call_track
from tennislab.plot import in_out_by, plus_minus, spin_fit_words


def pipeline(
    text: str, surface: str = "hard", line: str | None = None, target: str | None = None
) -> tuple[Track, TrackCall]:
    """The track parsed from CSV text and its call."""
    track = parse_track(text, name="csv")
    res = call_track(
        track.t, track.xyz, track.sigma, params=FlightParams(), surface=surface, line=line, target=target, strict=False
    )  # as `call --track`: a track too short to fit is answered review, never refused
    return track, res


def summary(res: TrackCall) -> dict:
    """The call's JSON (exactly ``tennislab call --track --json``)."""
    return res.to_dict()


def reference_call(text: str, surface: str = "hard", line: str | None = None, target: str | None = None) -> dict:
    """The call of a track's text by the Python API (what the page must show)."""
    return summary(pipeline(text, surface, line, target)[1])


def _closest_line(lines: dict) -> str | None:
    """The bounding line the mark is nearest to (smallest |distance|), for drawing."""
    if not lines:
        return None
    return min(lines, key=lambda k: abs(lines[k]["distance_mm"]))


def call(v: dict, text: str) -> dict:
    """The page's line call (form ``linecall``)."""
    line = None if v["line"] == "auto" else v["line"]
    target = None if v["target"] == "auto" else v["target"]
    track, res = pipeline(text, v["surface"], line, target)
    out = summary(res)
    drawn = line or _closest_line(out.get("lines") or {})
    lines = ITF_COURT.lines()
    out["line"] = drawn
    if line is None and drawn is not None:  # report the nearest line's own numbers beside the area's
        out["nearest_line"] = {"name": drawn, **out["lines"][drawn]}
    out["line_rect"] = list(lines[drawn]) if drawn in lines else None
    mark = res.mark_result
    out["mark"] = dict(out["mark"] or {})
    out["mark"]["discs"] = [] if mark is None else np.round(mark.discs, 5).tolist()
    out["mark"]["direction"] = [] if mark is None else [float(d) for d in mark.direction]
    fit = res.fit_result
    if fit is not None and res.track is not None:
        ts = res.track[0]  # the call's relative clock
        t_fit = np.linspace(ts[0], ts[-1] if fit.has_post else fit.t_bounce, 200)
        pts = fit.positions(t_fit)
        out["fitted"] = np.round(pts[np.all(np.isfinite(pts), axis=1)], 4).tolist()
    else:
        out["fitted"] = []
    f = out.get("fit") or {}
    out["words"] = {  # what the page says, in the words of the CLI and the report
        "distance": in_out_by(out.get("distance_mm")),
        "drag_scale": plus_minus(f.get("drag_scale"), f.get("drag_scale_sigma"), digits=3),
        "lift_scale": plus_minus(f.get("lift_scale"), f.get("lift_scale_sigma"), digits=3),
        "spin": spin_fit_words(out["spin"]) if (out.get("spin") or {}).get("rpm") is not None else "–",
    }
    step = max(1, len(track) // 400)
    out["track"] = np.round(np.column_stack([track.t, track.xyz])[::step], 5).tolist()
    return out
