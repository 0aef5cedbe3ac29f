"""Figures of the serve analysis: impact histories (the paper's worksheet figs 2.2-2.6), the paper's
figs 5-9 (Grosen, Kousted & Treichel 2021), Monte Carlo landing points."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Ellipse

from tennislab.plot.court import draw_court_side, draw_court_top, frame_views
from tennislab.serve.published import PEAK_SPIN_ALPHA
from tennislab.units import RPM

PLAYER_COLORS = {"professional": "tab:blue", "recreational": "tab:orange", "junior": "tab:green"}


def plot_impact_history(res, title: str | None = None):
    """Positions, velocities, forces and spin through the contact (an :class:`ImpactResult` with history)."""
    H = res.history
    t = H["t"] * 1e3
    fig, ax = plt.subplots(2, 3, figsize=(13, 7))
    ax[0, 0].plot(t, H["x1"] * 1e3, label="racket x1")
    ax[0, 0].plot(t, H["x2"] * 1e3, label="ball x2")
    ax[0, 0].plot(t, H["x3"] * 1e3, "--", label="node x3")
    ax[0, 0].set_ylabel("normal position [mm]")
    ax[0, 1].plot(t, H["v1"], label="racket")
    ax[0, 1].plot(t, H["v2"], label="ball")
    ax[0, 1].set_ylabel("normal velocity [m/s]")
    ax[0, 2].plot(t, H["F_N"], color="k")
    ax[0, 2].set_ylabel("normal force F_N [N]")
    ax[1, 0].plot(t, H["w1"], label="racket")
    ax[1, 0].plot(t, H["w2"], label="ball")
    ax[1, 0].set_ylabel("tangential velocity [m/s]")
    ax[1, 1].plot(t, H["F_t"], color="k", label="F_t")
    ax[1, 1].plot(t, 0.0 * t, color="0.6", lw=0.8)
    ax[1, 1].set_ylabel("tangential force F_t [N]")
    ax[1, 2].plot(t, H["w3"] / RPM, color="tab:red")
    ax[1, 2].set_ylabel("ball spin [rpm]")
    for a in ax.ravel():
        a.set_xlabel("t [ms]")
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=8)
    fig.suptitle((title + "  -  " if title else "") + f"contact {res.contact_time * 1e3:.2f} ms, {res.regime}")
    fig.tight_layout()
    return fig


def plot_window(windows, published=True, optimum_trajectories=None):
    """The paper's figs 5 (speed and spin vs alpha) and 6 (successful alpha per beta) for one or more
    :class:`~tennislab.serve.ServeWindow`; with ``optimum_trajectories`` (a list, per window, of (flat,
    topspin) :class:`Trajectory` or None) also figs 7-9 (side view of the optimum serves)."""
    if optimum_trajectories:
        fig, (a5, a6, a7) = plt.subplots(1, 3, figsize=(21, 5.5))
        draw_court_side(a7)
        drawn = []
        for k, (w, trs) in enumerate(zip(windows, optimum_trajectories)):
            c = PLAYER_COLORS.get(w.player.name, f"C{k}")
            for tr, ls, cat in zip(trs, ("-", "--"), ("flat", "topspin")):
                if tr is not None:
                    _, ys = tr.sample(300)
                    drawn.append(ys[:, 0:3])
                    a7.plot(ys[:, 0], ys[:, 2], ls, color=c, lw=1.6, label=f"{w.player.name} {cat}")
        frame_views(a7, None, np.vstack(drawn) if drawn else np.empty((0, 3)), margin=1.0, pad=0.5)
        a7.legend(fontsize=7, loc="upper right")
        a7.set_title("Figs 7-9: optimum flat (-) and topspin (--) serves")
    else:
        fig, (a5, a6) = plt.subplots(1, 2, figsize=(14, 5.5))
    a5b = a5.twinx()
    for k, w in enumerate(windows):
        c = PLAYER_COLORS.get(w.player.name, f"C{k}")
        a5.plot(w.alpha_deg, w.speed, "x-", ms=3, color=c, label=f"{w.player.name} speed")
        a5b.plot(w.alpha_deg, w.spin_rpm, "o-", ms=2.5, mfc="none", color=c, label=f"{w.player.name} spin")
        i = int(np.argmax(w.spin_rpm))
        a5b.plot(w.alpha_deg[i], w.spin_rpm[i], "s", ms=9, color=c, mec="k")
        if published and w.player.name in PEAK_SPIN_ALPHA:
            a5b.axvline(PEAK_SPIN_ALPHA[w.player.name], color=c, ls=":", lw=1)
        off = 0.12 * (k - (len(windows) - 1) / 2)
        for cat, mk in (("flat", "|"), ("topspin", "_")):
            m = w.mask(cat)
            ib, ia = np.nonzero(m)
            a6.plot(
                w.alpha_deg[ia],
                w.beta_deg[ib] + off,
                mk if cat == "flat" else ".",
                ms=4,
                color=c,
                label=f"{w.player.name} {cat}",
            )
        for cat, mk in (("flat", "*"), ("topspin", "*")):
            o = w.optimum(cat)
            if o:
                a6.plot(o["alpha"], o["beta"] + off, mk, ms=14, color=c, mec="k")
    a5.set_xlabel("impact angle alpha [deg]")
    a5.set_ylabel("ball speed [m/s] (x)")
    a5b.set_ylabel("spin [rpm] (o); square = peak, dotted = the paper's peak")
    a5.set_title("Fig 5: speed and spin vs alpha")
    a5.legend(loc="lower left", fontsize=8)
    a6.set_xlabel("impact angle alpha [deg]")
    a6.set_ylabel("face angle beta [deg]")
    a6.set_title("Fig 6: successful alpha per beta (| flat, . topspin, * optimum)")
    a6.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    return fig


def plot_optimum(player_name: str, trajectories, labels):
    """The paper's figs 7-9: side view of the optimum flat and topspin serves."""
    fig, ax = plt.subplots(figsize=(11, 4))
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


def plot_mc(res, max_points: int = 20000):
    """Landing points (yellow in, red fault) of a :class:`~tennislab.serve.MonteCarloResult` that kept
    its samples, and the 95 % ellipse on the court (top view)."""
    fig, ax = plt.subplots(figsize=(10, 6))
    draw_court_top(ax)
    samples = res.samples
    x, y, s = samples["land_x"], samples["land_y"], samples["success"]
    k = slice(None) if x.size <= max_points else slice(0, max_points)
    ax.plot(x[k][~s[k]], y[k][~s[k]], ".", ms=1.5, color="tab:red", label="fault")
    ax.plot(x[k][s[k]], y[k][s[k]], ".", ms=1.5, color="yellow", label="in")
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
    ax.set_xlim(-1, 13)
    ax.set_title(f"{res.player.name}: P(success) = {res.p_success:.3f} ({res.n} serves, {res.criteria})")
    ax.legend(loc="upper left", fontsize=8)
    return fig
