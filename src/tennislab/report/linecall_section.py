"""Report section: a line call from a synthetic track, the ball mark drawn against the line.

The track is the example serve (:func:`tennislab.linecall.synth.sample_serve`, 340 Hz, 3 mm noise,
seed 7), so the truth is known and the error of the call can be shown beside it.  The call is the
workflow of ``tennislab call --track`` (:func:`tennislab.linecall.call_track`); this module only draws
and tabulates its result.
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle, Ellipse, Rectangle

from tennislab.core.court import ITF_COURT
from tennislab.linecall import call_track
from tennislab.linecall.synth import sample_serve
from tennislab.plot.court import draw_court_side, frame_views
from tennislab.report import html as H

TARGET = "deuce-box"
SIGMA = 3e-3  #: [m] the example track's noise, given to the call as its sigma column


def linecall(ctx) -> None:
    sec = ctx.section
    tr = sample_serve(seed=7)
    truth = (tr.bounce.x, tr.bounce.y)
    res = call_track(tr.t, tr.xyz, np.full(tr.t.size, SIGMA), surface="hard", target=TARGET)
    out = res.to_dict()
    fit, mark = res.fit_result, res.mark_result
    if fit is None or mark is None:  # pragma: no cover - the example serve always bounces
        raise RuntimeError(f"the example serve was not called: {out['reason']}")
    err_mm = 1e3 * math.hypot(out["bounce"]["x"] - truth[0], out["bounce"]["y"] - truth[1])

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 5), width_ratios=[1, 1.5])
    cx, cy, half = float(mark.center[0]), float(mark.center[1]), 0.16
    ax.add_patch(Rectangle((cx - 1, cy - 1), 2, 2, color="#3a7d44", zorder=0))
    lines = out.get("lines") or {}
    for name, (x0, x1, y0, y1) in ITF_COURT.lines().items():
        hit = name in lines and abs(lines[name]["distance_mm"]) < 100
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="#ffe066" if hit else "white", zorder=1))
    for x, y, r in mark.discs:
        if r > 0:
            color = "#c81e1e" if out["provisional_call"] == "out" else "#8a4b1c"
            ax.add_patch(Circle((x, y), r, color=color, alpha=0.25, lw=0, zorder=2))
    ev, evec = np.linalg.eigh(fit.bounce_cov)
    ang = math.degrees(math.atan2(evec[1, 1], evec[0, 1]))
    for k, ls in ((1, "-"), (2, "--")):
        ax.add_patch(
            Ellipse(
                (out["bounce"]["x"], out["bounce"]["y"]),
                2 * k * math.sqrt(max(ev[1], 0)),
                2 * k * math.sqrt(max(ev[0], 0)),
                angle=ang,
                fill=False,
                ec="black",
                ls=ls,
                lw=1,
                zorder=3,
            )
        )
    ax.plot(out["bounce"]["x"], out["bounce"]["y"], "k.", zorder=4, label="fitted first contact (1σ, 2σ)")
    ax.plot(truth[0], truth[1], "bx", ms=8, zorder=4, label="true first contact")
    ax.set_xlim(cx - half, cx + half)
    ax.set_ylim(cy - half * 0.8, cy + half * 0.8)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"mark vs the service line: {out['call'].upper()} ({abs(out['distance_mm']):.1f} mm)")
    ax.legend(loc="lower right", fontsize=8)
    draw_court_side(ax2)
    ax2.plot(tr.xyz[:, 0], tr.xyz[:, 2], ".", ms=2, color="#777", label="track (3 mm noise)")
    ts = res.track[0] if res.track is not None else tr.t - tr.t[0]  # the call's relative clock
    pts = fit.positions(np.linspace(ts[0], ts[-1], 400))
    ax2.plot(pts[:, 0], pts[:, 2], "-", color="#d62828", lw=1.5, label="fitted flight and bounce")
    frame_views(ax2, None, np.vstack([tr.xyz, pts]), margin=1.0, pad=0.5)
    ax2.legend(loc="upper right", fontsize=8)
    fig.tight_layout()

    rows = [
        ["call", out["call"] + (f" (the numbers say {out['provisional_call']})" if out["call"] == "review" else "")],
        ["against", f"{TARGET} (lines included)"],
        ["distance of the mark to the line [mm]", H.num(out["distance_mm"], 1)],
        ["probability the ball is in", H.num(out["p_in"], 3)],
        ["first contact x, y [m]", f"{H.num(out['bounce']['x'], 4)}, {H.num(out['bounce']['y'], 4)}"],
        ["true first contact x, y [m]", f"{H.num(truth[0], 4)}, {H.num(truth[1], 4)}"],
        ["error of the fitted contact point [mm]", H.num(err_mm, 1)],
        ["bounce uncertainty (1σ, worst direction) [mm]", H.num(out["bounce"]["sigma_mm"], 2)],
        [
            "mark length × width [mm]",
            f"{H.num(1e3 * out['mark']['length'], 0)} × {H.num(1e3 * out['mark']['width'], 0)}",
        ],
        ["fit rms [mm] / outliers", f"{H.num(out['fit']['rms_mm'], 2)} / {out['fit']['outliers']}"],
    ]
    if out["reason"]:
        rows.append(["why review", out["reason"]])
    for name, d in lines.items():
        rows.append(
            [
                f"line {name}: call, distance [mm], P(in)",
                f"{d['call']}, {H.num(d['distance_mm'], 1)}, {H.num(d['p_in'], 3)}",
            ]
        )
    sec.add(
        H.para(
            "A first serve down the T, tracked at 340 frames per second with 3 mm of noise per axis (a "
            "synthetic track with known truth). The flight model is fitted to the approach and the bounce, "
            "the ball mark is rebuilt from the contact (compression and skid), and the mark is called "
            "against the service box: a ball is in when any part of its mark touches the line. A call whose "
            "probability lies between 5 % and 95 % is answered 'review'."
        ),
        H.figure(
            ctx.save(fig, "line_call.png"),
            "Left: the mark (red/brown) against the service line, with the fit's 1σ and 2σ uncertainty. "
            "Right: the track and the fitted flight.",
        ),
        H.table(["quantity", "value"], rows, left_cols=2),
        H.para(
            "The probability accounts for the fit's uncertainty of the contact point (Monte Carlo over "
            "its covariance); a call closer than a few millimetres is genuinely uncertain, as the ITF's "
            "5 mm limit for line-calling systems acknowledges.",
            "note",
        ),
    )
