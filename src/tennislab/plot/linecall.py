"""Line-call figures: one call's mark on the lines with the track and its fit (:func:`plot_call`, drawn by
``tennislab call --plot`` and the report), and a rally's bounces on the court (:func:`plot_rally`).

Nothing here decides a call: the numbers come from the :class:`~tennislab.linecall.TrackCall` drawn.
"""

from __future__ import annotations

import math

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.plot.court import draw_court_side, draw_court_top, frame_views, surface_colors
from tennislab.plot.text import in_out_by, num

#: colour of a call (the mark, the rally's bounces)
CALL_COLORS = {"in": "#1b7837", "out": "#c51b7d", "net": "#2166ac", "let": "#f1a340", "review": "#ffffff"}
#: lines nearer than this to the mark are drawn highlighted [mm]
NEAR_LINE_MM = 100.0


def call_title(out: dict) -> str:
    """The call in words: ``"OUT against singles: out by 3.1 mm, P(in) = 0.009"`` (a call's ``to_dict()``)."""
    what = out.get("line") or out.get("target") or "the court"
    head = out["call"].upper()
    if out["call"] == "review" and out.get("provisional_call"):
        head += f" (the numbers say {out['provisional_call']})"
    if out.get("distance_mm") is None:
        return f"{head} against {what}"
    return f"{head} against {what}: mark {in_out_by(out['distance_mm'])}, P(in) = {num(out['p_in'], 3)}"


def _ellipses(ax, centre, cov):
    from matplotlib.patches import Ellipse

    ev, evec = np.linalg.eigh(np.asarray(cov, dtype=float))
    ang = math.degrees(math.atan2(evec[1, 1], evec[0, 1]))
    for k, ls in ((1, "-"), (2, "--")):
        ax.add_patch(
            Ellipse(
                centre,
                2 * k * math.sqrt(max(ev[1], 0.0)),
                2 * k * math.sqrt(max(ev[0], 0.0)),
                angle=ang,
                fill=False,
                ec="black",
                ls=ls,
                lw=1,
                zorder=5,
            )
        )


def _draw_mark(ax, res, out: dict, court, truth, zoom: float, surface: str | None) -> list:
    """The zoomed top view: lines (the near ones highlighted), the mark, the fitted first contact with
    its 1σ and 2σ ellipses, the true contact; returns the legend's handles."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle, Patch, Rectangle

    mark = res.mark_result
    cx, cy = float(mark.center[0]), float(mark.center[1])
    ax.add_patch(Rectangle((cx - 5, cy - 5), 10, 10, color=surface_colors(surface)[0], zorder=0))
    near = {k for k, d in (out.get("lines") or {}).items() if abs(d["distance_mm"]) < NEAR_LINE_MM}
    if out.get("line"):
        near.add(out["line"])
    for name, (x0, x1, y0, y1) in court.lines().items():
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="#ffe066" if name in near else "white", zorder=1))
    color = "#e8789a" if (out.get("provisional_call") or out["call"]) == "out" else "#c9a27a"
    for x, y, r in mark.discs:  # opaque: the union of the discs is the mark, its thin start as visible as its body
        if r > 0:
            ax.add_patch(Circle((x, y), r, color=color, lw=0, zorder=2))
    handles: list = [
        Patch(color="#ffe066", label="line(s) judged"),
        Patch(color=color, label=f"ball mark ({num(1e3 * mark.length, 0)} × {num(1e3 * mark.width, 0)} mm)"),
    ]
    b = out.get("bounce") or {}
    fit = res.fit_result
    if b.get("x") is not None:
        if fit is not None and np.all(np.isfinite(fit.bounce_cov)):
            _ellipses(ax, (b["x"], b["y"]), fit.bounce_cov)
            handles.append(Line2D([], [], color="k", lw=1, label="1σ (solid) and 2σ (dashed) of the contact"))
        ax.plot(b["x"], b["y"], "k.", ms=6, zorder=6)
        handles.append(Line2D([], [], ls="", marker=".", color="k", ms=6, label="fitted first contact"))
    if truth is not None:
        ax.plot(truth[0], truth[1], "x", color="#1f4fff", ms=8, mew=2, zorder=6)
        handles.append(Line2D([], [], ls="", marker="x", color="#1f4fff", mew=2, label="true first contact"))
    ax.set_xlim(cx - zoom, cx + zoom)
    ax.set_ylim(cy - zoom * 0.8, cy + zoom * 0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(call_title(out), fontsize=10)
    return handles


def _draw_track(ax, res, court, surface: str | None) -> None:
    """The side view: the points the fit used, its outliers and the fitted flight through the bounce."""
    draw_court_side(ax, court, surface=surface)
    ts, xyz = res.track
    fit = res.fit_result
    used = fit.segment >= 0 if fit is not None else np.ones(len(ts), bool)
    ax.plot(xyz[used, 0], xyz[used, 2], ".", ms=2.5, color="#555555", label="track points used")
    drawn = [xyz]
    if fit is not None:
        if fit.outlier.any():
            ax.plot(xyz[fit.outlier, 0], xyz[fit.outlier, 2], "x", color="#d62828", ms=6, label="outliers (left out)")
        pts = fit.positions(np.linspace(ts[0], ts[-1] if fit.has_post else fit.t_bounce, 400))
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        ax.plot(pts[:, 0], pts[:, 2], "-", color="#1f77b4", lw=1.5, label="fitted flight and bounce")
        drawn.append(pts)
    frame_views(ax, None, np.vstack(drawn), court, margin=1.0, pad=0.5)
    ax.set_title("track and fitted flight (side view)", fontsize=10)
    ax.legend(loc="upper right", fontsize=8)


def plot_call(res, court=ITF_COURT, truth=None, zoom: float = 0.16, surface: str | None = None):
    """One line call (a :class:`~tennislab.linecall.TrackCall` with its mark): left, the mark against
    the lines with the fitted first contact, its uncertainty and (``truth``, (x, y) [m]) the true contact;
    right, for a tracked ball, the track, its outliers and the fitted flight.  ``surface``: the court's
    colour (default the call's surface)."""
    import matplotlib.pyplot as plt

    if res.mark_result is None:
        raise ValueError("plot_call: the call has no mark to draw")
    out = res.to_dict()
    surface = surface or out.get("surface")
    has_track = res.track is not None
    fig, axes = plt.subplots(1, 2 if has_track else 1, figsize=(13 if has_track else 6.5, 5.2), squeeze=False)
    handles = _draw_mark(axes[0, 0], res, out, court, truth, zoom, surface)
    axes[0, 0].legend(handles=handles, loc="lower right", fontsize=8, framealpha=0.9)
    if has_track:
        _draw_track(axes[0, 1], res, court, surface)
    fig.tight_layout()
    return fig


def plot_rally(result, court=ITF_COURT, surface: str | None = None):
    """Top view of the court with every called shot's bounce (colour = call; review hollow) and net
    contacts (squares on the net line); the tracker's bounce as a small cross where given."""
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig, ax = plt.subplots(figsize=(11, 6))
    draw_court_top(ax, court, surface=surface)
    seen = set()
    tracker = False
    for s in result.shots:
        b = s.get("bounce") or {}
        call = s["call"]
        label = None if call in seen else call
        seen.add(call)
        if b.get("x") is not None:
            ec = "k" if call == "review" else CALL_COLORS.get(call, "k")
            ax.plot(b["x"], b["y"], "o", ms=6, mfc=CALL_COLORS.get(call, "k"), mec=ec, label=label, zorder=4)
        elif (s.get("net") or {}).get("contact"):
            ax.plot(0.0, s["net"]["y"], "s", ms=6, color=CALL_COLORS["net"], label=label, zorder=4)
        tr = s.get("tracker") or {}
        if tr.get("bounce_x") is not None:
            tracker = True
            ax.plot(tr["bounce_x"], tr["bounce_y"], "x", ms=4, color="#333333", zorder=5)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    sm = result.summary
    ax.set_title(f"{sm['n_shots']} shots called: " + ", ".join(f"{k} {v}" for k, v in sm["calls"].items() if v))
    handles, _ = ax.get_legend_handles_labels()
    if tracker:
        handles.append(Line2D([], [], ls="", marker="x", ms=5, color="#333333", label="the tracker's bounce"))
    ax.legend(handles=handles, loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig
