"""Serve analysis after Grosen, Kousted & Treichel (2021): player profiles, one serve with its
verdict, the alpha x beta serve window (the paper's Table 1), Monte Carlo margins of error,
racket-ball impacts and 3-D serves.

Workflows (plain parameters in, a frozen :class:`tennislab.results.Result` out; ``to_dict()`` is
the command's ``--json``):

* :func:`simulate` -> :class:`ServeResult` (``tennislab serve``)
* :func:`window` / :func:`windows` -> :class:`ServeWindow` / :class:`ServeWindows` (``serve-window``);
  :func:`window_of_setup` flies another window of a window's ``setup``
* :func:`monte_carlo` -> :class:`MonteCarloResult` (``serve-mc``)
* :func:`impact` -> :class:`ImpactSummary` (``tennislab impact``)
* :func:`racket_for` -> :class:`RacketForBall`: the racket (V, alpha, beta) that gives a ball launch
  (``serve --speed-kmh ...``)
* :func:`default_serve` -> :class:`DefaultServe`, a serve that goes in for a player with the most room
  for error
* :func:`window_hint` -> :class:`WindowHint`: why no serve of a window goes in, and the azimuth toward
  the box that lets some in (``serve-window``'s ``hint``)

All of them run the one serve pipeline (impact -> launch -> flight -> judgement) of
:mod:`tennislab.serve.pipeline`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.serve import published
    from tennislab.serve.from_ball import BallLaunch, BallWindow, RacketForBall, ball_window, racket_for
    from tennislab.serve.hint import WindowHint, window_hint
    from tennislab.serve.mc import MonteCarloResult, block_size, monte_carlo
    from tennislab.serve.pipeline import DEFAULT_PRESET, REASON_CODES, default_flight
    from tennislab.serve.players import (
        SEED_PLAYERS,
        PlayerProfile,
        get_player,
        player_names,
        register_player,
    )
    from tennislab.serve.published import PEAK_SPIN_ALPHA, TABLE1
    from tennislab.serve.racket_impact import ImpactSummary, impact
    from tennislab.serve.setup import (
        IMPACT_SCHEMES,
        SeedCriteria,
        scheme_integration,
        seed_flight_params,
        seed_impact_params,
    )
    from tennislab.serve.single import REASONS, ServeResult, Verdict, simulate
    from tennislab.serve.window import (
        DefaultServe,
        ServeWindow,
        ServeWindows,
        default_serve,
        window,
        window_of_setup,
        windows,
    )

__all__ = [
    "PEAK_SPIN_ALPHA",
    "TABLE1",
    "block_size",
    "published",
    "DefaultServe",
    "IMPACT_SCHEMES",
    "REASONS",
    "REASON_CODES",
    "DEFAULT_PRESET",
    "default_flight",
    "SEED_PLAYERS",
    "ImpactSummary",
    "MonteCarloResult",
    "PlayerProfile",
    "BallLaunch",
    "BallWindow",
    "ball_window",
    "RacketForBall",
    "racket_for",
    "SeedCriteria",
    "ServeResult",
    "ServeWindow",
    "ServeWindows",
    "Verdict",
    "default_serve",
    "get_player",
    "impact",
    "monte_carlo",
    "player_names",
    "register_player",
    "scheme_integration",
    "seed_flight_params",
    "seed_impact_params",
    "simulate",
    "window",
    "window_of_setup",
    "windows",
    "WindowHint",
    "window_hint",
]
__getattr__, __dir__ = attach_stub(__name__, __file__)
