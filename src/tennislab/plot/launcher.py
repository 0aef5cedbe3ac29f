"""Launcher figures: an aimed shot, and a drill's shots and zones on the court (no physics here: the
trajectories come from the launcher's workflows)."""

from __future__ import annotations

import numpy as np

from tennislab.plot.court import court_figure, frame_views


def _draw_machine(ax_side, ax_top, position, height):
    ax_top.plot(position[0], position[1], "s", ms=9, color="#d9822b", mec="k", zorder=5, label="machine")
    ax_side.plot([position[0], position[0]], [0, height], color="#d9822b", lw=3, zorder=5)


def plot_aim(solution, trajectory, title: str | None = None):
    """Side and top views of one aimed shot (an :class:`~tennislab.launcher.aim.AimSolution` and its
    trajectory): trajectory, target, landing and machine; the axes hold the whole flight."""
    st = solution.settings
    title = title or (
        f"{solution.solution} solution: elev {st.elevation_deg:g} deg, head {st.heading_deg:g} deg, "
        f"{st.speed_kmh:g} km/h, {st.spin_rpm:g} rpm @ {st.spin_axis_deg:g} deg; "
        f"miss {solution.miss_mm:.0f} mm"
    )
    fig, ax_side, ax_top = court_figure(title=title)
    _, ys = trajectory.sample(400)
    ax_side.plot(ys[:, 0], ys[:, 2], lw=1.8, color="#f2e600")
    ax_top.plot(ys[:, 0], ys[:, 1], lw=1.8, color="#f2e600")
    ax_top.plot(*solution.target, "x", ms=10, mew=2.5, color="#c0392b", zorder=6, label="target")
    ax_top.plot(*solution.landing, "o", ms=6, color="#f2e600", mec="k", zorder=6, label="landing")
    _draw_machine(ax_side, ax_top, solution.position, st.height_m)
    machine = [[solution.position[0], solution.position[1], st.height_m]]
    frame_views(ax_side, ax_top, np.vstack([ys[:, 0:3], machine]), margin=1.0, pad=0.5)
    ax_top.legend(loc="upper left", fontsize=8)
    return fig


def plot_drill(compiled, trajectories, title: str | None = None):
    """Every distinct shot of a compiled drill with its trajectory (``trajectories``, one per distinct
    shot, from :func:`tennislab.launcher.drills.drill_trajectories`), numbered as in the drill's table;
    its target (x), landing (o) and zone (dashed: green when the shot lands in it and clears the net, red
    otherwise) and the machine (square), each explained in the legend."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    d = compiled.drill
    fig, ax_side, ax_top = court_figure(title=title or f"drill: {d.name} ({len(compiled.shots)} shots)")
    drawn = []
    colors = ["#f2e600", "#4fc3f7", "#ff8a65", "#ba68c8", "#aed581", "#ffffff", "#90a4ae", "#f06292"]
    for i, (u, tr) in enumerate(zip(compiled.unique, trajectories)):
        c = colors[i % len(colors)]
        x0, x1, y0, y1 = u.shot.zone_bounds()
        ax_top.add_patch(
            Rectangle(
                (x0, y0), x1 - x0, y1 - y0, fill=False, lw=1.5, ls="--", ec="#2ecc71" if u.ok else "#e74c3c", zorder=3
            )
        )
        if u.solution is None or tr is None:
            continue
        _, ys = tr.sample(300)
        ax_side.plot(ys[:, 0], ys[:, 2], lw=1.6, color=c, label=f"{i + 1}: {u.label} ({u.shot.type})")
        ax_top.plot(ys[:, 0], ys[:, 1], lw=1.6, color=c)
        lx, ly = u.solution.landing
        ax_top.plot(lx, ly, "o", ms=5, color=c, mec="k", zorder=6)
        ax_top.annotate(str(i + 1), (lx, ly), xytext=(5, 5), textcoords="offset points", color="white", weight="bold")
        ax_top.plot(*u.shot.target, "x", ms=7, mew=2, color="#c0392b", zorder=6)
        drawn.append(ys[:, 0:3])
    h = max(u.shot.height_m for u in compiled.unique)
    _draw_machine(ax_side, ax_top, d.spec.position, h)
    drawn.append(np.array([[d.spec.position[0], d.spec.position[1], h]]))
    frame_views(ax_side, ax_top, np.vstack(drawn), margin=1.0, pad=0.5)
    ax_side.legend(loc="upper right", fontsize=7)
    ax_top.legend(
        handles=[
            Line2D([], [], ls="", marker="s", ms=7, color="#d9822b", mec="k", label="machine"),
            Line2D([], [], ls="", marker="x", ms=7, mew=2, color="#c0392b", label="target"),
            Line2D([], [], ls="", marker="o", ms=5, color="#dddddd", mec="k", label="landing (numbered)"),
            Line2D([], [], ls="--", color="#2ecc71", label="zone: lands in it, clears the net"),
            Line2D([], [], ls="--", color="#e74c3c", label="zone: missed"),
        ],
        loc="upper left",
        fontsize=7,
    )
    fig.tight_layout()
    return fig
