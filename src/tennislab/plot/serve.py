"""Figures of the serve analysis: impact histories (the paper's worksheet figs 2.2-2.6), the paper's
figs 5-9 (Grosen, Kousted & Treichel 2021), the serve windows as heat maps, Monte Carlo landing points.

Nothing here computes physics: every number comes from the :mod:`tennislab.serve` result drawn.
Players are labelled by :func:`tennislab.plot.text.player_words` (a profile with changed height or
speed by its numbers, never a bare ``*``).
"""

from __future__ import annotations

import numpy as np

from tennislab.plot.court import draw_court_side, draw_court_top, frame_views
from tennislab.plot.text import num, player_words
from tennislab.serve.published import PEAK_SPIN_ALPHA
from tennislab.units import RPM

PLAYER_COLORS = {"professional": "tab:blue", "recreational": "tab:orange", "junior": "tab:green"}
#: heat-map classes of a serve window: code -> colour (0 fails, 1 flat, 2 topspin, 3 other spin)
WINDOW_COLORS = ("#e6e6e6", "#1f77b4", "#2ca02c", "#ff9f1c")
#: degrees shown around the successes of a window in its heat map
WINDOW_PAD_DEG = 4.0
#: Monte Carlo landing points by reason (:data:`tennislab.serve.REASON_CODES`): colour, label (colours and
#: the net's cross chosen apart from every surface's court colours: a hard court is blue, clay red-brown)
MC_STYLE = {
    "in": ("#ffe600", "in"),
    "net": ("#ff6f00", "net (drawn where it would land)"),
    "short": ("#6d4c41", "short (before the net)"),
    "long": ("#d32f2f", "long"),
    "wide": ("#ab47bc", "wide"),
    "no-landing": ("#000000", "no landing"),
}


def _plt():
    import matplotlib.pyplot as plt  # pyplot only when a figure is drawn (0.5 s of start-up otherwise)

    return plt


def _color(player, k: int) -> str:
    return PLAYER_COLORS.get(player.name, f"C{k + 3}")


def plot_impact_history(res, title: str | None = None):
    """Positions, velocities, forces and spin through the contact (an :class:`ImpactResult` with history)."""
    H = res.history
    t = H["t"] * 1e3
    fig, ax = _plt().subplots(2, 3, figsize=(13, 7))
    ax[0, 0].plot(t, H["x1"] * 1e3, label="racket x1")
    ax[0, 0].plot(t, H["x2"] * 1e3, label="ball x2")
    ax[0, 0].plot(t, H["x3"] * 1e3, "--", label="node x3")
    ax[0, 0].set_ylabel("normal position [mm]")
    ax[0, 1].plot(t, H["v1"], label="racket")
    ax[0, 1].plot(t, H["v2"], label="ball")
    ax[0, 1].set_ylabel("normal velocity [m/s]")
    ax[0, 2].plot(t, H["F_N"], color="k", label="F_N")
    ax[0, 2].set_ylabel("normal force F_N [N]")
    ax[1, 0].plot(t, H["w1"], label="racket")
    ax[1, 0].plot(t, H["w2"], label="ball")
    ax[1, 0].set_ylabel("tangential velocity [m/s]")
    ax[1, 1].plot(t, H["F_t"], color="k", label="F_t")
    ax[1, 1].plot(t, 0.0 * t, color="0.6", lw=0.8, label="zero")
    ax[1, 1].set_ylabel("tangential force F_t [N]")
    ax[1, 2].plot(t, H["w3"] / RPM, color="tab:red", label="ball spin")
    ax[1, 2].set_ylabel("ball spin [rpm]")
    for a in ax.ravel():
        a.set_xlabel("t [ms]")
        a.legend(fontsize=8)
    fig.suptitle((title + "  -  " if title else "") + f"contact {res.contact_time * 1e3:.2f} ms, {res.regime}")
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------ windows (the paper's figs 5, 6)
def window_codes(w) -> np.ndarray:
    """Heat-map class of every serve of a window (n_beta, n_alpha): 0 fails, 1 flat, 2 topspin, 3 other."""
    return np.where(w.success, w.grid("category") + 1, 0).astype(int)


def window_labels(w) -> tuple[str, str, str, str]:
    """Labels of the heat-map classes of a window, with its spin bands."""
    c = w.criteria
    return (
        "fails",
        f"flat (< {c.flat_max_rpm:g} rpm)",
        f"topspin (> {c.topspin_min_rpm:g} rpm)",
        f"other spin ({c.flat_max_rpm:g}-{c.topspin_min_rpm:g} rpm)",
    )


def window_span(w, pad: float = WINDOW_PAD_DEG) -> tuple[float, float, float, float]:
    """(alpha lo, alpha hi, beta lo, beta hi) [deg] of the cells that succeed, ``pad`` degrees around
    them (within the grid); the whole grid when none succeeds."""
    a, b = w.alpha_deg, w.beta_deg
    ib, ia = np.nonzero(w.success)
    if ib.size == 0:
        return float(a[0]), float(a[-1]), float(b[0]), float(b[-1])
    return (
        float(max(a[0], a[ia.min()] - pad)),
        float(min(a[-1], a[ia.max()] + pad)),
        float(max(b[0], b[ib.min()] - pad)),
        float(min(b[-1], b[ib.max()] + pad)),
    )


def plot_window_maps(windows):
    """One heat map per :class:`~tennislab.serve.ServeWindow` over impact angle α and face angle β,
    coloured by what each serve does, each framed where its window is (:func:`window_span`); the
    legend counts each class."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    windows = list(windows)
    fig, axes = _plt().subplots(1, len(windows), figsize=(4.4 * max(len(windows), 2), 4.8), squeeze=False)
    counts = np.zeros(4, int)
    for ax, w in zip(axes[0], windows):
        code = window_codes(w)
        counts += np.bincount(code.ravel(), minlength=4)
        a, b = w.alpha_deg, w.beta_deg
        da, db = (a[1] - a[0]) / 2 if a.size > 1 else 0.5, (b[1] - b[0]) / 2 if b.size > 1 else 0.5
        ax.imshow(
            code,
            origin="lower",
            cmap=ListedColormap(WINDOW_COLORS),
            vmin=-0.5,
            vmax=3.5,
            extent=(a[0] - da, a[-1] + da, b[0] - db, b[-1] + db),
            aspect="auto",
            interpolation="nearest",
        )
        a0, a1, b0, b1 = window_span(w)
        ax.set_xlim(a0 - da, a1 + da)
        ax.set_ylim(b0 - db, b1 + db)
        ax.set_title(f"{player_words(w.player)}: {int(w.success.sum())} of {w.success.size} go in", fontsize=10)
        ax.set_xlabel("impact angle α [deg]")
        ax.set_ylabel("racket-face angle β [deg]")
    labels = window_labels(windows[0])
    fig.legend(
        handles=[Patch(color=c, label=f"{lab} ({n})") for c, lab, n in zip(WINDOW_COLORS, labels, counts)],
        loc="lower center",
        ncol=4,
        frameon=False,
    )
    for ax in axes[0][len(windows) :]:
        ax.set_visible(False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    return fig


def draw_speed_spin(ax, windows, published: bool = True) -> None:
    """The paper's Figure 5 on ``ax`` (and a twin axis): ball speed (crosses) and spin (circles) after
    impact vs impact angle α per window; the peak spin (square) and the paper's peak-spin α (dotted)."""
    ax2 = ax.twinx()
    for k, w in enumerate(windows):
        c, who = _color(w.player, k), player_words(w.player)
        ax.plot(w.alpha_deg, w.speed, "x-", ms=3, lw=1, color=c, label=f"{who}: speed")
        ax2.plot(w.alpha_deg, w.spin_rpm, "o-", ms=2.5, lw=1, mfc="none", color=c, label=f"{who}: spin")
        i = int(np.argmax(w.spin_rpm))
        ax2.plot(w.alpha_deg[i], w.spin_rpm[i], "s", ms=9, mfc="none", mec=c, mew=2, label=f"{who}: peak spin")
        if published and w.player.name in PEAK_SPIN_ALPHA:
            ax.axvline(PEAK_SPIN_ALPHA[w.player.name], color=c, ls=":", lw=1.2, label=f"{who}: the paper's peak-spin α")
    ax.set_xlabel("impact angle α [deg]")
    ax.set_ylabel("ball speed v [m/s] (crosses)")
    ax2.set_ylabel("spin [rpm] (circles; square = peak)")
    ax.grid(alpha=0.3)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, frameon=False)


def plot_speed_spin(windows, published: bool = True):
    """The paper's Figure 5 for several windows (:func:`draw_speed_spin`)."""
    fig, ax = _plt().subplots(figsize=(10, 6.5))
    draw_speed_spin(ax, list(windows), published)
    ax.set_title("Ball speed and spin after impact vs impact angle α")
    fig.tight_layout()
    return fig


def _draw_successes(ax, windows) -> None:
    """The paper's Figure 6: the successful (α, β) of each window, flat (|) and topspin (.), optimum (*)."""
    for k, w in enumerate(windows):
        c, who = _color(w.player, k), player_words(w.player)
        off = 0.12 * (k - (len(windows) - 1) / 2)
        for cat, mk in (("flat", "|"), ("topspin", ".")):
            ib, ia = np.nonzero(w.mask(cat))
            ax.plot(w.alpha_deg[ia], w.beta_deg[ib] + off, mk, ms=4, color=c, label=f"{who}: {cat} ({ib.size})")
        for cat in ("flat", "topspin"):
            o = w.optimum(cat)
            if o:
                ax.plot(o["alpha"], o["beta"] + off, "*", ms=14, color=c, mec="k", label=f"{who}: optimum {cat}")
    ax.set_xlabel("impact angle α [deg]")
    ax.set_ylabel("face angle β [deg]")
    ax.set_title("Fig 6: successful α per β (| flat, . topspin, * optimum)")
    ax.legend(fontsize=7, loc="upper right")


def plot_window(windows, published=True, optimum_trajectories=None):
    """The paper's figs 5 (speed and spin vs alpha) and 6 (successful alpha per beta) for one or more
    :class:`~tennislab.serve.ServeWindow`; with ``optimum_trajectories`` (a list, per window, of (flat,
    topspin) :class:`Trajectory` or None) also figs 7-9 (side view of the optimum serves)."""
    windows = list(windows)
    plt = _plt()
    if optimum_trajectories:
        fig, (a5, a6, a7) = plt.subplots(1, 3, figsize=(21, 6))
        _draw_optimum(a7, windows, optimum_trajectories)
        a7.set_title("Figs 7-9: optimum flat (-) and topspin (--) serves")
    else:
        fig, (a5, a6) = plt.subplots(1, 2, figsize=(14, 6))
    draw_speed_spin(a5, windows, published)
    a5.set_title("Fig 5: speed and spin vs α")
    _draw_successes(a6, windows)
    fig.suptitle("Serve window of " + ", ".join(player_words(w.player) for w in windows))
    fig.tight_layout()
    return fig


def _draw_optimum(ax, windows, trajectories) -> None:
    draw_court_side(ax)
    drawn = []
    for k, (w, trs) in enumerate(zip(windows, trajectories)):
        c = _color(w.player, k)
        for tr, ls, cat in zip(trs, ("-", "--"), ("flat", "topspin")):
            if tr is not None:
                _, ys = tr.sample(300)
                drawn.append(ys[:, 0:3])
                ax.plot(ys[:, 0], ys[:, 2], ls, color=c, lw=1.6, label=f"{player_words(w.player)} {cat}")
    frame_views(ax, None, np.vstack(drawn) if drawn else np.empty((0, 3)), margin=1.0, pad=0.5)
    ax.legend(fontsize=7, loc="upper right")


def plot_optimum(player_name: str, trajectories, labels):
    """The paper's figs 7-9: side view of the optimum flat and topspin serves."""
    fig, ax = _plt().subplots(figsize=(11, 4))
    draw_court_side(ax)
    drawn = []
    for tr, lab, c in zip(trajectories, labels, ("tab:blue", "tab:green")):
        _, ys = tr.sample(300)
        drawn.append(ys[:, 0:3])
        ax.plot(ys[:, 0], ys[:, 2], color=c, lw=1.8, label=lab)
    frame_views(ax, None, np.vstack(drawn) if drawn else np.empty((0, 3)), margin=1.0, pad=0.5)
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title(f"{player_name}: optimum flat and topspin serves")
    fig.tight_layout()
    return fig


def plot_optimum_serves(windows, serves):
    """The paper's Figures 7-9, one side view per window: ``serves`` maps a player's name to
    ``{category: (optimum dict, Trajectory) or None}``; every flight's label gives its α, β, speed and
    spin; the service line it must land before is marked."""
    windows = list(windows)
    fig, axes = _plt().subplots(len(windows), 1, figsize=(10, 3.4 * len(windows)), sharex=True, squeeze=False)
    for ax, w in zip(axes[:, 0], windows):
        draw_court_side(ax, zmax=3.6)
        drawn = []
        for cat, color in (("flat", "tab:blue"), ("topspin", "tab:green")):
            got = serves.get(w.player.name, {}).get(cat)
            if got is None:
                continue
            opt, tr = got
            _, ys = tr.sample(300)
            drawn.append(ys[:, :3])
            ax.plot(
                ys[:, 0],
                ys[:, 2],
                lw=2,
                color=color,
                label=f"{cat}: α {num(opt['alpha'], 0)}°, β {num(opt['beta'], 0)}°, {num(opt['speed'], 1)} m/s, "
                f"{num(opt['spin_rpm'], 0)} rpm",
            )
        pts = np.concatenate(drawn) if drawn else np.zeros((0, 3))
        # the server's half and the far service boxes (x -13 to 8 m), widened to hold every flight drawn
        ax.set_xlim(min(-13.0, float(pts[:, 0].min()) - 0.5) if len(pts) else -13.0,
                    max(8.0, float(pts[:, 0].max()) + 0.5) if len(pts) else 8.0)  # fmt: skip
        ax.set_ylim(0.0, max(3.6, float(pts[:, 2].max()) * 1.08 + 0.2) if len(pts) else 3.6)
        ax.set_title(player_words(w.player), fontsize=10)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel("x [m] (server behind the near baseline x = -11.885 m; far service line x = 6.40 m)")
    fig.tight_layout()
    return fig


# ------------------------------------------------------------------ Monte Carlo
def plot_mc(res, max_points: int = 20000):
    """Landing points of a :class:`~tennislab.serve.MonteCarloResult` that kept its samples, coloured by
    what happened (in, net, long, wide, short; a net fault is drawn where it would have landed), with
    the 95 % ellipse of every landing, on the court (top view); the legend counts each."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Ellipse

    from tennislab.serve import REASON_CODES

    fig, ax = _plt().subplots(figsize=(10, 6))
    draw_court_top(ax)
    s = res.samples
    k = slice(None) if s["land_x"].size <= max_points else slice(0, max_points)
    x, y = s["land_x"][k], s["land_y"][k]
    reason = np.asarray(s.get("reason", np.where(s["success"], 0, 3)))[k]
    handles = []
    for code, name in enumerate(REASON_CODES):
        m = (reason == code) & np.isfinite(x) & np.isfinite(y)
        if not m.any():
            continue
        color, label = MC_STYLE[name]
        marker, ms = ("x", 2.5) if name == "net" else (".", 2)
        ax.plot(x[m], y[m], marker, ms=ms, mew=0.8, color=color, zorder=3 if name == "in" else 4)
        share = 100.0 * m.sum() / reason.size
        handles.append(
            Line2D(
                [], [], ls="", marker="x" if name == "net" else "o", ms=5, color=color, label=f"{label}: {share:.1f} %"
            )
        )
    e = res.landing.get("ellipse_95")
    if e:
        mx, my = res.landing["mean"]
        ax.add_patch(
            Ellipse(
                (mx, my),
                2 * e["semi_axes"][0],
                2 * e["semi_axes"][1],
                angle=e["angle_deg"],
                fill=False,
                color="k",
                lw=1.5,
                zorder=5,
            )
        )
        handles.append(Line2D([], [], color="k", lw=1.5, label="95 % of the landings"))
    ax.set_xlim(-1, 13)
    crit = "the paper's 2-D test" if res.criteria == "seed-2d" else f"into the {res.criteria}"
    nom = res.nominal
    ax.set_title(
        f"{player_words(res.player)}, α {num(nom['alpha'], 1)}°, β {num(nom['beta'], 1)}°: "
        f"P(success) = {res.p_success:.3f} over {res.n} serves ({crit})",
        fontsize=10,
    )
    ax.legend(handles=handles, loc="upper left", fontsize=8, framealpha=0.9)
    return fig
