"""Serve explorer: the app's bridge to :mod:`tennislab.serve` and :mod:`tennislab.core.impact`.

One serve is :func:`tennislab.serve.single.simulate_serve` (the code behind
``tennislab serve``): the seed-000 impact model, the face angle beta (seed eq
21), and in 3-D the face azimuth, the brush direction (tilting the spin axis
for slice and kick), the server's position and the toss; flight with the
seed's constants.  Success: ``seed-2d`` = the paper's criteria (ball centre
above 0.943 m at the net, landing at most 18.318 m from the impact point, the
same test as the window heat map); ``deuce`` / ``ad`` = over the real net and
into that service box.  The window is :func:`tennislab.serve.window.serve_window`.
"""

from __future__ import annotations

import numpy as np

from tennislab.app import services as S

#: heat-map codes: failure and success by category
WINDOW_CODES = (
    ("fail", "#e6e6e6"),
    ("flat success", "#1f77b4"),
    ("topspin success", "#2ca02c"),
    ("other success", "#ff9f1c"),
)


def players() -> dict:
    """The registered profiles as ``{name: {height, racket_speed}}`` (seed players first)."""
    from tennislab.serve.players import get_player, player_names

    out = {}
    for n in player_names():
        p = get_player(n)
        out[n] = {"height": p.impact_height, "racket_speed": p.racket_speed}
    return out


def player_of(v: dict):
    """The :class:`tennislab.serve.Player` of a form (``custom`` uses height and racket_speed)."""
    from tennislab.serve.players import Player, get_player

    if v["player"] == "custom":
        return Player("custom", v["height"], v["racket_speed"])
    return get_player(v["player"])


def serve(v: dict) -> dict:
    """One serve (form ``serve``): :func:`tennislab.serve.single.simulate_serve` (the JSON of
    ``tennislab serve``) plus the player used and the trajectory's plot points."""
    from tennislab.serve.single import simulate_serve

    player = player_of(v)
    target = None if v["target"] == "seed-2d" else v["target"]
    out = simulate_serve(
        player,
        min(v["impact_angle"], 89.999),
        v["face_angle"],
        target=target,
        azimuth_deg=v["azimuth_deg"],
        brush_deg=v["brush_deg"],
        server_y=v["server_y"],
        toss_vz=v["toss_vz"],
        trajectory=True,
    )
    tr = out.pop("_trajectory")
    out["player"] = {"name": player.name, "height": player.impact_height, "racket_speed": player.racket_speed}
    out["regime"] = out["impact"]["regime"]
    out["contact_time_ms"] = out["impact"]["contact_time_ms"]
    out["landing_y"] = out["landing"]["y"]
    out["net_clearance"] = tr.net.clearance
    out["flight"] = S.flight_result(tr) if tr.landing is not None else None
    return out


def window(v: dict) -> dict:
    """The alpha x beta window (form ``window``): category codes per cell for the heat map."""
    from tennislab.serve.window import serve_window

    player = player_of(v)
    w = serve_window(player, step=v["step"])
    cat = w.grid("category")
    code = np.where(w.success, cat + 1, 0).astype(int)
    d = w.to_dict()
    legend = [
        {"code": k, "label": lab, "color": col, "n": int((code == k).sum())}
        for k, (lab, col) in enumerate(WINDOW_CODES)
    ]
    return {
        "player": d["player"],
        "alpha": w.alpha_deg.tolist(),
        "beta": w.beta_deg.tolist(),
        "step": v["step"],
        "code": code.tolist(),
        "palette": {str(k): c for k, (_, c) in enumerate(WINDOW_CODES)},
        "legend": legend,
        "summary": d["summary"],
        "peak_spin_alpha": d["peak_spin_alpha"],
        "optimum": d["optimum"],
        "speed": w.speed.tolist(),
        "spin_rpm": w.spin_rpm.tolist(),
    }
