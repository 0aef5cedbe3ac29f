"""Line-call figure: the mark on the lines (zoomed top view) and the track with its fit."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Ellipse, Rectangle

from tennislab.core.court import ITF_COURT


def plot_call(mark, decision: dict, court=ITF_COURT, fit=None, track=None, bounce_cov=None, zoom: float = 0.35):
    """Figure with the mark and lines (left) and, for a track, height vs time with the fit (right)."""
    ncol = 2 if track is not None else 1
    fig, axes = plt.subplots(1, ncol, figsize=(6.5 * ncol, 5.5), squeeze=False)
    ax = axes[0, 0]
    cx, cy = mark.center
    ax.add_patch(Rectangle((cx - 5, cy - 5), 10, 10, color="#3a7d44", zorder=0))
    for x0, x1, y0, y1 in court.lines().values():
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="white", lw=0, zorder=1))
    for x, y, a in mark.discs:
        if a > 0:
            ax.add_patch(Circle((x, y), a, color="#c8a24a", alpha=0.25, lw=0, zorder=2))
    ax.plot(*mark.start, "kx", zorder=4, label="first contact")
    if bounce_cov is not None and np.all(np.isfinite(bounce_cov)):
        ev, evec = np.linalg.eigh(np.asarray(bounce_cov))
        ang = np.degrees(np.arctan2(evec[1, 1], evec[0, 1]))
        for k in (1, 2):
            ax.add_patch(
                Ellipse(
                    mark.start,
                    2 * k * np.sqrt(max(ev[1], 0)),
                    2 * k * np.sqrt(max(ev[0], 0)),
                    angle=ang,
                    fill=False,
                    ec="k",
                    ls="--" if k == 2 else "-",
                    zorder=5,
                )
            )
    ax.set_xlim(cx - zoom, cx + zoom)
    ax.set_ylim(cy - zoom, cy + zoom)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    what = decision.get("line") or decision.get("target")
    ax.set_title(
        f"{decision['call'].upper()} ({what}): {decision['distance_mm']:+.1f} mm, p_in = {decision['p_in']:.3f}"
    )
    ax.legend(loc="upper right", fontsize=8)
    if track is not None:
        t, xyz = track
        ax2 = axes[0, 1]
        used = fit.segment >= 0 if fit is not None else np.ones(t.size, bool)
        ax2.plot(t[used], xyz[used, 2], ".", ms=3, color="#555555", label="track")
        if fit is not None and fit.outlier.any():
            ax2.plot(t[fit.outlier], xyz[fit.outlier, 2], "rx", ms=6, label="outliers")
        if fit is not None:
            tt = np.linspace(t[used][0], t[used][-1], 600)
            pm = fit.positions(tt)
            ax2.plot(tt, pm[:, 2], "-", color="#1f77b4", lw=1.2, label="fit")
            ax2.axvline(fit.t_bounce, color="#c8a24a", lw=1, label="bounce")
        ax2.set_xlabel("t [s]")
        ax2.set_ylabel("z [m]")
        ax2.legend(fontsize=8)
        ax2.set_title("track and fitted flight")
    fig.tight_layout()
    return fig


CALL_COLORS = {"in": "#1b7837", "out": "#c51b7d", "net": "#2166ac", "let": "#f1a340", "review": "#ffffff"}


def plot_rally(result, court=ITF_COURT):
    """Top view of the court with every called shot's bounce (colour = call; review hollow) and net
    contacts (squares on the net line); the tracker's bounce as a small cross where given."""
    from tennislab.plot.court import draw_court_top

    fig, ax = plt.subplots(figsize=(11, 6))
    draw_court_top(ax, court)
    seen = set()
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
            ax.plot(tr["bounce_x"], tr["bounce_y"], "x", ms=4, color="#333333", zorder=5)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    sm = result.summary
    ax.set_title(
        f"{sm['n_shots']} shots: " + ", ".join(f"{k} {v}" for k, v in sm["calls"].items() if v) + " (x: tracker)"
    )
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    return fig
