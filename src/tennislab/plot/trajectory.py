"""Trajectory figures: side and top views of one or more flights on the court.

Every flight is one colour; its launch (^), bounces (o) and last point (a square, or a cross where
the net stopped it) are marked and explained in the legend.  The views are
framed (:func:`tennislab.plot.court.frame_views`) so that every bounce and the whole apex are inside
the axes.  Drawn flight lines carry ``gid="flight"``, bounce markers ``gid="bounce"`` and end markers
``gid="end"``, launch markers ``gid="launch"`` (tests find them by these ids).
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.plot.court import court_figure, frame_views
from tennislab.plot.text import num, spin_words


def _segments(item) -> list:
    """The segments of one flight: a result with ``segments``, a trajectory, a list of trajectories,
    or ``(t, states)`` samples."""
    segs = getattr(item, "segments", None)
    if segs is not None:
        return list(segs)
    if hasattr(item, "sample"):
        return [item]
    if isinstance(item, (list, tuple)) and len(item) == 2 and np.ndim(item[1]) == 2:
        return [item]
    return list(item)


def _path(seg, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(states (n, >=3) along one segment, extra points (k, 3) to keep in frame: its apex)."""
    if hasattr(seg, "sample"):
        _, ys = seg.sample(n)
        apex = getattr(seg, "apex", None)
        extra = np.asarray(apex.position, dtype=float).reshape(1, 3) if apex is not None else np.empty((0, 3))
        return np.asarray(ys, dtype=float), extra
    return np.asarray(seg[1], dtype=float), np.empty((0, 3))


#: colours of the flights drawn, bright on every court colour (a ball's yellow first)
FLIGHT_COLORS = ("#ffd500", "#ff4f79", "#00d1ff", "#a6ff4d", "#ff9a1f", "#ffffff", "#c58cff")


def _outline():
    from matplotlib import patheffects

    return [patheffects.withStroke(linewidth=3.4, foreground="#1a1a1a")]


def _end_label(item, n_segments: int) -> str:
    """What the last marker of a flight is: where it lands (and why the flight shown stops there), or
    where the net stopped it."""
    tr = getattr(item, "trajectory", None)
    if tr is not None and getattr(tr, "net_contact", None) is not None and n_segments == 1:
        return "stopped by the net"
    if n_segments == 1:
        return "landing"
    return f"landing {n_segments}: the flight shown ends ({n_segments - 1} bounces asked)"


def flight_title(res) -> str:
    """What was flown, for a figure's title: launch speed, angles, spin by name, position, bounces and
    surface, and the physics (a :class:`~tennislab.trajectory.FlightResult`)."""
    d = res.to_dict()
    la, ph = d["launch"], d["physics"]
    x, y, z = la["position"]
    line1 = (
        f"{num(la['speed_kmh'], 0)} km/h, elevation {num(la['elevation_deg'])}°, heading {num(la['heading_deg'])}°, "
        f"{spin_words(la['spin_rpm'], la['spin_axis_deg'])}, from ({num(x, 2)}, {num(y, 2)}, {num(z, 2)}) m"
    )
    nb = len(d.get("bounces", []))
    bounces = f"; {nb} bounce{'s' if nb != 1 else ''} on {d['surface']}" if "bounces" in d else ""
    return (
        f"{line1}{bounces}\naero {ph['aero']}, air {num(ph['air_density'], 3)} kg/m³, ball {num(1e3 * ph['mass'], 1)} g"
    )


def plot_trajectories(flights, labels=None, title: str | None = None, court=None, n: int = 400, surface=None):
    """Side and top views of flights on a court in the colours of ``surface``; returns the figure.

    ``flights``: a list whose items are each one flight - a :class:`~tennislab.trajectory.FlightResult`
    (all its segments, bounces marked), a :class:`~tennislab.core.flight.Trajectory`, a list of
    trajectories (segments of one flight), or ``(t, states)`` samples.  ``labels``: one per flight.
    ``title``: default, for one :class:`~tennislab.trajectory.FlightResult`, what was flown
    (:func:`flight_title`).  ``surface``: default the first flight's bounce surface (hard without one).
    Every marker is in the legend: launch (triangle), bounces (circles, numbered in the top view) and
    where each flight ends (square: a landing; cross: stopped by the net).
    """
    from matplotlib.lines import Line2D

    OUTLINE = _outline()  # a dark edge keeps a bright flight readable on every surface's colour and on white
    court = court or ITF_COURT
    if surface is None:
        surface = next((getattr(f, "surface", None) for f in flights if getattr(f, "surface", None)), None)
    if title is None and len(flights) == 1 and hasattr(flights[0], "to_dict") and hasattr(flights[0], "trajectory"):
        title = flight_title(flights[0])
    fig, ax_side, ax_top = court_figure(court=court, title=title, surface=surface)
    drawn = []
    ends: dict[str, str] = {}
    any_bounce = False
    for i, item in enumerate(flights):
        segs = _segments(item)
        color = None
        for k, seg in enumerate(segs):
            path, extra = _path(seg, n)
            lab = labels[i] if labels and k == 0 else None
            color = color or FLIGHT_COLORS[i % len(FLIGHT_COLORS)]
            ax_side.plot(path[:, 0], path[:, 2], lw=1.8, label=lab, color=color, gid="flight", path_effects=OUTLINE)
            ax_top.plot(path[:, 0], path[:, 1], lw=1.8, color=color, gid="flight", path_effects=OUTLINE)
            drawn.extend([path[:, :3], extra])
            if k == 0:
                for ax, j in ((ax_side, 2), (ax_top, 1)):
                    ax.plot(path[0, 0], path[0, j], "^", ms=6, color=color, mec="k", gid="launch")
            end = path[-1]
            if k < len(segs) - 1:  # a segment that continues bounced
                any_bounce = True
                ax_side.plot(end[0], end[2], "o", ms=5, color=color, mec="k", gid="bounce")
                ax_top.plot(end[0], end[1], "o", ms=5, color=color, mec="k", gid="bounce")
                ax_top.annotate(str(k + 1), (end[0], end[1]), xytext=(4, 4), textcoords="offset points", fontsize=8)
            else:
                what = _end_label(item, len(segs))
                mk = "X" if what == "stopped by the net" else "s"
                ends[what] = mk
                ax_side.plot(end[0], end[2], mk, ms=6, color=color, mec="k", gid="end")
                ax_top.plot(end[0], end[1], mk, ms=6, color=color, mec="k", gid="end")
    frame_views(ax_side, ax_top, np.vstack(drawn) if drawn else np.empty((0, 3)), court)
    handles = [h for h in ax_side.get_legend_handles_labels()[0] if h.get_label() != "net (centre)"]

    def proxy(marker: str, label: str):
        return Line2D([], [], ls="", marker=marker, ms=6, mfc="#dddddd", mec="k", label=label)

    handles.append(
        Line2D([], [], color="#222222", lw=3, label=f"net ({num(court.net_center_height, 3)} m at the centre)")
    )
    handles.append(Line2D([], [], color="#bbbbbb", lw=0.8, ls="--", label="baselines and service lines"))
    handles.append(proxy("^", "launch"))
    if any_bounce:
        handles.append(proxy("o", "bounce (numbered in the top view)"))
    handles += [proxy(mk, what) for what, mk in ends.items()]
    ax_side.legend(handles=handles, loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig
