"""Report section: a line call from a synthetic track, the ball mark drawn against the line.

The track is the example serve (:func:`tennislab.linecall.synth.sample_serve`, 340 Hz, 3 mm noise,
seed 7), so the truth is known and the error of the call can be shown beside it.  The call is the
workflow of ``tennislab call --track`` (:func:`tennislab.linecall.call_track`); this module only draws
and tabulates its result.
"""

from __future__ import annotations

import math

import numpy as np

import tennislab.report.html as H
from tennislab.core.court import ITF_COURT
from tennislab.linecall import call_track
from tennislab.linecall.synth import sample_serve
from tennislab.plot import in_out_by, plot_call, plus_minus, spin_fit_words

TARGET = "deuce-box"
SIGMA = 3e-3  #: [m] the example track's noise, given to the call as its sigma column


def scale(fit: dict, key: str, digits: int) -> str:
    """A fitted scale with its 1σ (``1.001 ± 0.002``)."""
    return plus_minus(fit.get(key), fit.get(f"{key}_sigma"), digits=digits)


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

    fig = plot_call(res, ITF_COURT, truth=truth)
    lines = out.get("lines") or {}
    f, sp = out["fit"], out.get("spin") or {}

    rows = [
        ["call", out["call"] + (f" (the numbers say {out['provisional_call']})" if out["call"] == "review" else "")],
        ["against", f"{TARGET} (lines included)"],
        ["the mark against the deuce box's lines", in_out_by(out["distance_mm"])],
        ["probability the ball is in", H.num(out["p_in"], 3)],
        ["first contact x, y [m]", f"{H.num(out['bounce']['x'], 4)}, {H.num(out['bounce']['y'], 4)}"],
        ["true first contact x, y [m]", f"{H.num(truth[0], 4)}, {H.num(truth[1], 4)}"],
        ["error of the fitted contact point [mm]", H.num(err_mm, 1)],
        ["bounce uncertainty (1σ, worst direction) [mm]", H.num(out["bounce"]["sigma_mm"], 2)],
        [
            "mark length × width [mm]",
            f"{H.num(1e3 * out['mark']['length'], 0)} × {H.num(1e3 * out['mark']['width'], 0)}",
        ],
        ["fit rms [mm] / outliers", f"{H.num(f['rms_mm'], 2)} / {f['outliers']}"],
        ["fitted drag scale / lift scale (1σ)", f"{scale(f, 'drag_scale', 3)} / {scale(f, 'lift_scale', 2)}"],
    ]
    if sp.get("rpm") is not None:
        rows.append(["fitted spin (1σ)", spin_fit_words(sp)])
    if out["reason"]:
        rows.append(["why review", out["reason"]])
    for name, d in lines.items():
        rows.append(
            [
                f"line {name}: call, mark, P(in)",
                f"{d['call']}, {in_out_by(d['distance_mm'])}, {H.num(d['p_in'], 3)}",
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
            "Left: the mark against the lines it is judged by (yellow), the fitted first contact with its 1σ "
            "and 2σ uncertainty and the true contact. Right: the track and the fitted flight.",
        ),
        H.table(["quantity", "value"], rows, left_cols=2),
        H.para(
            "The probability accounts for the fit's uncertainty of the contact point (Monte Carlo over "
            "its covariance); a call closer than a few millimetres is genuinely uncertain, as the ITF's "
            "5 mm limit for line-calling systems acknowledges.",
            "note",
        ),
    )
