"""Serve explorer: the app's bridge to the workflows of :mod:`tennislab.serve`.

One serve is :func:`tennislab.serve.simulate` (the workflow behind ``tennislab serve``): the
paper's impact model, the face angle beta, and in 3-D the face azimuth, the brush direction, the
server's position and the toss; flight with the standard physics of every command.  Success: ``seed-2d`` = the
paper's criteria (ball centre above 0.943 m at the net, landing at most 18.318 m from the impact
point, the same test as the window heat map); ``deuce`` / ``ad`` = over the real net and into that
service box.  Every answer carries the result's ``verdict`` (why it failed, what would fix it) and
``caveats`` unchanged.  The window is :func:`tennislab.serve.window`; the explorer's opening serve
is :func:`tennislab.serve.default_serve`.
"""

from __future__ import annotations

import tennislab.app.services as S
from tennislab.plot import WINDOW_COLORS, window_codes, window_labels, window_span
from tennislab.serve import (
    DEFAULT_PRESET,
    PlayerProfile,
    default_flight,
    default_serve,
    get_player,
    player_names,
    simulate,
)
from tennislab.serve import window as serve_window


def _physics() -> dict:
    """The flight physics of the explorer's serves, as the serve commands' JSON states it."""
    return {"physics": default_flight().to_dict(), "physics_preset": DEFAULT_PRESET}


def players() -> dict:
    """The registered profiles as ``{name: {height, racket_speed}}`` (the paper's players first)."""
    out = {}
    for n in player_names():
        p = get_player(n)
        out[n] = {"height": p.impact_height, "racket_speed": p.racket_speed}
    return out


def player_of(v: dict) -> PlayerProfile:
    """The :class:`tennislab.serve.PlayerProfile` of a form (``custom`` uses height and racket_speed)."""
    if v["player"] == "custom":
        return PlayerProfile("custom", v["height"], v["racket_speed"])
    return get_player(v["player"])


def opening_serve(player: str = "professional") -> dict:
    """The serve the explorer opens with for ``player``: :func:`tennislab.serve.default_serve` (it goes in,
    with the most room for error); ``impact_angle``, ``face_angle`` [deg] and its margin."""
    return default_serve(player).to_dict()


def serve(v: dict) -> dict:
    """One serve (form ``serve``): ``simulate(...).to_dict()`` (the JSON of ``tennislab serve``, with
    ``verdict``, ``caveats`` and ``player_profile``; every key unchanged) plus the trajectory's plot
    points."""
    player = player_of(v)
    target = None if v["target"] == "seed-2d" else v["target"]
    res = simulate(
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
    out = res.to_dict()
    tr = res.trajectory
    out["regime"] = out["impact"]["regime"]
    out["contact_time_ms"] = out["impact"]["contact_time_ms"]
    out["landing_y"] = out["landing"]["y"]
    out["flight"] = S.flight_of(tr) if tr is not None and tr.landing is not None else None
    return {**out, **_physics()}


def window(v: dict) -> dict:
    """The alpha x beta window (form ``window``): ``serve.window(...).to_dict()`` (the JSON of
    ``tennislab serve-window``, every key unchanged) plus what the heat map draws: the grid's ``alpha``
    and ``beta`` [deg], the class ``code`` of every cell (:func:`tennislab.plot.serve.window_codes`), its
    ``palette`` and ``legend`` (counted), the ``span`` where the window is and the per-cell ``speed``
    [m/s] and ``spin_rpm`` (for the CSV)."""
    w = serve_window(player_of(v), step=v["step"])
    code = window_codes(w)
    out = w.to_dict()
    labels = window_labels(w)
    out.update(
        alpha=w.alpha_deg.tolist(),
        beta=w.beta_deg.tolist(),
        step=v["step"],
        code=code.tolist(),
        palette={str(k): c for k, c in enumerate(WINDOW_COLORS)},
        legend=[
            {"code": k, "label": lab, "color": col, "n": int((code == k).sum())}
            for k, (lab, col) in enumerate(zip(labels, WINDOW_COLORS))
        ],
        span=dict(zip(("alpha_lo", "alpha_hi", "beta_lo", "beta_hi"), window_span(w))),
        speed=w.grid("speed").tolist(),
        spin_rpm=w.grid("spin_rpm").tolist(),
    )
    return {**out, **_physics()}
