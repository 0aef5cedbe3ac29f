"""Report sections on the serve (seed 000, Grosen, Kousted & Treichel 2021).

* :func:`windows` - the alpha x beta serve window of each seed player as a
  heat map, and Table 1 side by side with the paper's numbers
* :func:`peak_spin` - ball speed and spin vs impact angle (the paper's Figure
  5), the peak-spin angle per player, and the Monte Carlo margin of error of
  the optimum flat and topspin serves
* :func:`optimum` - the optimum flat and topspin serves of each player drawn on
  the court (the paper's Figures 7-9) with the paper's values beside ours

All numbers come from the workflows of :mod:`tennislab.serve` (windows computed once, shared
between sections through ``ctx.shared``); each section shows the models' caveats next to its
numbers.  The sections reproduce the paper, so they fly its constants (:data:`PRESET`, ``seed000``:
stepanek1988 aero, 59 g / 33 mm ball, air 1.22 kg/m^3, g 9.82), not every command's ``standard``
physics, and say so.  ``ctx.shared["serve_players"]`` (names or :class:`~tennislab.serve.PlayerProfile`) may
replace the paper's three players.
"""

from __future__ import annotations

import tennislab.report.html as H
from tennislab.core import PRESET_TITLES, describe_preset
from tennislab.plot import plot_optimum_serves, plot_speed_spin, plot_window_maps
from tennislab.serve import monte_carlo, simulate, window
from tennislab.serve import published as pub

PLAYERS = ("professional", "recreational", "junior")
#: The physics preset of the serve sections: the paper's constants (its sec. 2.3), as Table 1 flew them
PRESET = "seed000"
PHYSICS_NOTE = (
    f"Flown with {PRESET_TITLES['seed000']} (preset seed000: {describe_preset('seed000')}), not tennislab's "
    "standard physics; tennislab serve --preset seed000 flies the same."
)
#: (key in Table 1, column header, digits)
TABLE1_COLS = (
    ("beta", "β [deg]", 0),
    ("alpha", "α [deg]", 0),
    ("spin_rpm", "spin [rpm]", 0),
    ("speed", "v [m/s]", 1),
    ("landing_x", "X [m]", 2),
    ("net_height", "Y [m]", 2),
    ("launch_angle", "γ [deg]", 1),
)


def _windows(ctx) -> dict:
    """Serve windows of the players (1 deg step), computed once per report."""
    if "windows" not in ctx.shared:
        ws = {}
        for p in ctx.players or ctx.shared.get("serve_players", PLAYERS):
            w = window(p, step=1.0, preset=PRESET)
            ws[w.player.name] = w
            ctx.log(f"serve window {w.player.name}: {w.success.size} serves, {int(w.success.sum())} successful")
        ctx.shared["windows"] = ws
    return ctx.shared["windows"]


def _caveats(ws: dict):
    """The models' caveats, once each, as a note under the numbers."""
    return H.caveats(list(dict.fromkeys(c for w in ws.values() for c in w.caveats)))


def _range_cell(r, digits):
    return "–" if r is None else H.rng(r, digits)


def table1_rows(windows, published) -> tuple[list, list]:
    """Rows of Table 1 (ours, then the paper's where it has the player) for each player and category;
    ``published`` is :mod:`tennislab.serve.published` or None (ours only)."""
    rows, classes = [], []
    for p, w in windows.items():
        summ = w.summary()
        for cat in ("flat", "topspin"):
            ours = summ[cat]
            rows.append([p, cat, "tennislab", ours["n"]] + [_range_cell(ours[k], d) for k, _, d in TABLE1_COLS])
            classes.append("")
            if published is not None and p in published.TABLE1:
                pap = published.TABLE1[p][cat]
                rows.append(["", "", "paper", pap["n"]] + [_range_cell(pap[k], d) for k, _, d in TABLE1_COLS])
                classes.append("paper")
    return rows, classes


def _paper_n(cat: str) -> int:
    return sum(int(pub.TABLE1[p][cat]["n"]) for p in PLAYERS)  # type: ignore[call-overload]


def windows(ctx) -> None:
    """Heat maps of the three windows and Table 1 beside the paper."""
    sec = ctx.section
    ws = _windows(ctx)
    fig = plot_window_maps(ws.values())
    rows, classes = table1_rows(ws, pub)
    n_flat = sum(w.summary()["flat"]["n"] for w in ws.values())
    n_top = sum(w.summary()["topspin"]["n"] for w in ws.values())
    paper_kpi = set(ws) == set(PLAYERS)
    sec.add(
        H.para(
            "Every combination of impact angle α and racket-face angle β from 0 to 90 degrees in 1-degree "
            "steps is hit with the racket-ball impact model of Grosen, Kousted & Treichel (2021) and flown with "
            "drag and Magnus lift; a "
            "serve succeeds when the ball clears the net and lands in the service box (the paper's 2-D "
            "criteria: ball centre above 0.943 m at the net, landing at most 18.318 m from the impact "
            "point). Flat: spin below 1200 rpm; topspin: above 3200 rpm. " + PHYSICS_NOTE
        ),
        H.Raw(
            H.kpi(f"successful flat serves ({len(ws)} players)", f"{n_flat}")
            + H.kpi("successful topspin serves", f"{n_top}")
            + (H.kpi("paper", f"{_paper_n('flat')} flat / {_paper_n('topspin')} topspin") if paper_kpi else "")
        ).html,
        H.figure(
            ctx.save(fig, "serve_windows.png"),
            "Serve windows: successful serves by category over impact angle α and face angle β",
        ),
        "<h3>Table 1: successful serves, tennislab beside the paper</h3>",
        H.table(["player", "serve", "source", "n"] + [h for _, h, _ in TABLE1_COLS], rows, classes, left_cols=3),
        H.para(
            "Ranges are [min – max] over the successful serves. X: landing distance from the impact "
            "point; Y: height of the ball centre over the net; γ: launch angle (negative below the "
            "horizontal). Grey rows: the paper's Table 1. Our impact model never creates energy; the paper's "
            "numbers rest on a friction clamp and a pre-loaded string spring that do, and on a coarse time "
            "step: its spin peaks at a smaller impact angle and its flat serves are faster. docs/serve.md "
            "explains each difference.",
            "note",
        ),
        _caveats(ws),
    )


#: Monte Carlo of the margin of error: scatter (1 s.d.) of alpha, beta and face azimuth [deg], racket
#: speed [m/s]; serves per run; seed.  Modest scatter for a practised server (our choice, documented
#: in docs/report.md; the seed gives none).
MC_SCATTER = {"sd_angle": 1.0, "sd_speed": 1.0}
MC_N = 4000
MC_SEED = 2021


def _mc(player, serve: dict):
    """Monte Carlo probability of success around a nominal serve (the paper's 2-D criteria)."""
    return monte_carlo(
        player,
        serve["alpha"],
        serve["beta"],
        n=MC_N,
        seed=MC_SEED,
        sd_angle=MC_SCATTER["sd_angle"],
        sd_speed=MC_SCATTER["sd_speed"],
        preset=PRESET,
    )


MC_SCATTER_TEXT = f"α, β ±{MC_SCATTER['sd_angle']:g}°, V ±{MC_SCATTER['sd_speed']:g} m/s"


def peak_spin(ctx) -> None:
    """Speed and spin vs alpha per player (paper Fig. 5), the peak-spin alpha, the margin of error."""
    sec = ctx.section
    ws = _windows(ctx)
    fig = plot_speed_spin(ws.values())
    rows = []
    for p, w in ws.items():
        i = int(w.spin_rpm.argmax())
        paper_alpha = pub.PEAK_SPIN_ALPHA.get(p)
        rows.append(
            [
                p,
                H.num(w.peak_spin_alpha, 0),
                "–" if paper_alpha is None else paper_alpha,
                H.num(w.spin_rpm[i], 0),
                H.num(pub.OPTIMUM[p]["topspin"]["spin_rpm"], 0) if p in pub.OPTIMUM else "–",
                H.num(w.speed[i], 1),
            ]
        )
    sec.add(
        H.para(
            "Ball speed and spin after impact as the impact angle α grows (the paper's Figure 5): spin "
            "rises to a peak and then falls as the ball starts to slide across the strings, while speed "
            "falls ever faster. The peak-spin angle is where a coach would tell a player to brush the ball. "
            "Our peak lies about 8 degrees above the paper's: the paper's friction clamp and pre-loaded string "
            "spring add energy to the spin (docs/serve.md)."
        ),
        H.figure(ctx.save(fig, "peak_spin.png"), "Ball speed and spin vs impact angle (paper's Figure 5)"),
        H.table(
            [
                "player",
                "peak-spin α [deg]",
                "paper α [deg]",
                "peak spin [rpm]",
                "paper peak spin [rpm]",
                "speed at peak [m/s]",
            ],
            rows,
        ),
    )
    # margin of error
    sec.add("<h3>Margin of error</h3>")
    mrows, mc_p = [], {}
    for p, w in ws.items():
        for cat in ("flat", "topspin"):
            opt = w.optimum(cat)
            n = w.summary()[cat]["n"]
            wb = w.widest_beta(cat)
            res = None if opt is None else _mc(w.player, opt)
            if res is not None:
                mc_p[(p, cat)] = res.p_success
                ctx.log(f"Monte Carlo {p} {cat}: {MC_N} serves, P(success) = {100 * res.p_success:.1f} %")
            mrows.append(
                [
                    p,
                    cat,
                    n,
                    pub.TABLE1[p][cat]["n"] if p in pub.TABLE1 else "–",
                    H.num(wb, 0),
                    pub.WIDEST_BETA[p][cat] if p in pub.WIDEST_BETA else "–",
                    "–" if opt is None else f"α {opt['alpha']:g}, β {opt['beta']:g}",
                    "–" if res is None else H.num(100 * res.p_success, 1),
                    "–" if res is None else MC_SCATTER_TEXT,
                ]
            )
    sec.add(
        H.para(
            "The paper measures the margin of error by the number of successful (α, β) combinations: "
            "a flat serve has only a handful, a topspin serve hundreds. The Monte Carlo column hits the "
            "optimum serve many times with a player's typical scatter and counts the share that "
            "goes in."
        ),
        H.table(
            [
                "player",
                "serve",
                "successful combinations n",
                "paper n",
                "widest β [deg]",
                "paper widest β",
                "optimum serve",
                "P(success) [%]",
                "scatter (1 s.d.)",
            ],
            mrows,
            left_cols=2,
        ),
        H.para(
            "The optimum serves are chosen at the edge of the window (as deep as possible, or at peak "
            "spin), so a good part of their scatter goes long or into the net: aimed exactly there, even "
            "a practised server misses often. " + _mc_verdict(mc_p),
            "note",
        ),
        _caveats(ws),
    )


def _mc_verdict(mc_p: dict) -> str:
    """One sentence comparing the Monte Carlo success of topspin and flat optimum serves."""
    names = dict.fromkeys(p for p, _ in mc_p)
    pairs = [(mc_p[(p, "topspin")], mc_p[(p, "flat")]) for p in names if (p, "topspin") in mc_p and (p, "flat") in mc_p]
    if not pairs:
        return ""
    if all(t > f for t, f in pairs):
        return (
            "For every player the topspin serve keeps the higher probability for the same scatter: the "
            "paper's point about its larger margin of error."
        )
    if all(t <= f for t, f in pairs):
        return (
            "Here the flat serve keeps the higher probability for the same scatter, unlike the paper's "
            "conclusion from the number of combinations."
        )
    return "Which serve keeps the higher probability for the same scatter depends on the player."


def _lands(res) -> str:
    """A serve's outcome for the table: ``in``, or the fault's reason (``net``, ``long``, ...)."""
    d = res.to_dict()
    if d["success"]:
        return "in"
    return (d.get("verdict") or {}).get("reason") or "fault"


def optimum(ctx) -> None:
    """Optimum flat and topspin serves of each player on the court (paper Figs 7-9)."""
    sec = ctx.section
    ws = _windows(ctx)
    rows, classes = [], []
    keys = (
        ("beta", 0),
        ("alpha", 0),
        ("launch_angle", 1),
        ("spin_rpm", 0),
        ("speed", 1),
        ("net_height", 2),
        ("landing_x", 2),
    )
    serves: dict[str, dict] = {}
    for p, w in ws.items():
        serves[p] = {}
        for cat in ("flat", "topspin"):
            opt = w.optimum(cat)
            if opt is None:
                rows.append([p, cat, "tennislab", "–"] + ["none"] * len(keys))
                classes.append("")
                continue
            res = simulate(
                w.player, min(opt["alpha"], 89.999), opt["beta"], trajectory=True, advice=False, preset=PRESET
            )
            assert res.trajectory is not None  # asked for with trajectory=True
            serves[p][cat] = (opt, res.trajectory)
            rows.append([p, cat, "tennislab", _lands(res)] + [H.num(opt[k], d) for k, d in keys])
            classes.append("")
            if p in pub.OPTIMUM:
                pp = pub.OPTIMUM[p][cat]
                rows.append(["", "", "paper", "in"] + [H.num(pp[k], d) for k, d in keys])
                classes.append("paper")
    fig = plot_optimum_serves(ws.values(), serves)
    sec.add(
        H.para(
            "The optimum flat serve (fast, landing as deep as possible) and the optimum topspin serve "
            "(peak spin) of each player, as the paper chose them, flown over the court."
        ),
        H.figure(ctx.save(fig, "optimum_serves.png"), "Optimum flat and topspin serves (paper's Figures 7-9)"),
        H.table(
            ["player", "serve", "source", "lands", "β [deg]", "α [deg]", "γ [deg]", "spin [rpm]", "v [m/s]", "Y [m]"]
            + ["X [m]"],
            rows,
            classes,
            left_cols=4,
        ),
        _caveats(ws),
    )
