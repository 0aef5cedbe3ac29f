"""The one serve pipeline: impact -> launch -> flight -> judgement.

Every serve workflow runs the same four stages on one :class:`Setup` (everything but the angles):

1. **impact** (:func:`impacts`): racket speed V and impact angle alpha -> the ball after contact in
   the racket frame (v_n, v_t, omega; :func:`tennislab.core.impact.impact_batch`).  The toss, if any,
   is resolved in the face frame.  The window computes it once per alpha, the Monte Carlo tabulates
   it over (V, alpha) and interpolates (:mod:`tennislab.serve.mc`): both feed the same next stage.
2. **launch** (:func:`launch`): racket-frame results, face angle beta, azimuth psi, the brush angle
   and the toss -> court-frame initial states (N, 9), one compiled kernel for every workflow (the
   algebra of :mod:`tennislab.core.impact_3d`: velocity v_n n + v_t t, spin omega (t x n)).  A ball
   launch given directly (speed, spin, elevation, heading) enters here as its states.
3. **flight** (:func:`fly_serves`): :func:`tennislab.core.flight.fly_batch` with the setup's
   :class:`~tennislab.core.flight.FlightParams` -- all of it (aero, ball, air, wind, court,
   ``t_max``, ``net_obstacle``): the workers receive the parameters themselves, never a copy of a few
   fields.
4. **judgement** (:func:`judge`): the paper's 2-D test (:class:`~tennislab.serve.setup.SeedCriteria`,
   the one statement of its numbers) or the real net and a service box of the flight's court; per
   serve a reason code (:data:`REASON_CODES`).

:func:`serves` runs all four for arrays of angles (the single serve, the advice scans);
:func:`flights` runs stages 2-4 on rows of racket-frame results or states (the window's and the Monte
Carlo's per-chunk work, module level so that a process or Dask worker can run it).

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), sec. 2.2 (the impact) and its 2-D test
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numba as nb
import numpy as np

from tennislab.core.events import NET_HIT, STATUS_NET
from tennislab.core.flight import FlightParams, FlightTable, fly_batch
from tennislab.core.impact import ImpactParams, impact_batch
from tennislab.core.names import DEFAULT_PRESET as _DEFAULT_PRESET
from tennislab.errors import InputError, check_range
from tennislab.serve.players import PlayerProfile, get_player
from tennislab.serve.setup import (
    SeedCriteria,
    criteria_caveats,
    integration_caveats,
    seed_impact_params,
)

__all__ = [
    "REASONS",
    "REASON_CODES",
    "failure_counts",
    "Setup",
    "TARGETS",
    "box_name",
    "check_serve_options",
    "flights",
    "fly_serves",
    "impacts",
    "judge",
    "launch",
    "launch_3d",
    "make_setup",
    "serves",
]

TARGETS = {"deuce": "deuce-box", "ad": "ad-box"}

#: Why a serve fails (``verdict.reason``); ``None`` when it goes in.
REASONS = {
    "net": "the ball does not clear the net (the paper's 2-D test: its centre passes below 0.943 m)",
    "short": "the ball lands on the server's side, before the net",
    "long": "the ball lands beyond the service line",
    "wide": "the ball lands beside the service box (3-D targets only)",
    "no-landing": "the ball does not land within the flight's time limit",
}
#: ``reason`` codes of :func:`judge`: index -> name (0 = the serve goes in; the rest as :data:`REASONS`)
REASON_CODES = ("in", "net", "short", "long", "wide", "no-landing")
_IN, _NET, _SHORT, _LONG, _WIDE, _NO_LANDING = range(6)


def failure_counts(reason) -> dict[str, int]:
    """How many serves fail, by reason (``net``, ``short``, ``long``, ``wide``, ``no-landing``), of an array
    of indices into :data:`REASON_CODES` (any shape; reasons with no serve left out)."""
    counts = np.bincount(np.asarray(reason, int).ravel(), minlength=len(REASON_CODES))
    return {REASON_CODES[k]: int(n) for k, n in enumerate(counts) if k and n}


def box_name(target: str) -> str:
    """The court area of a 3-D target (``deuce`` -> ``deuce-box``)."""
    try:
        return TARGETS[target]
    except KeyError:
        raise InputError(f"target: unknown {target!r}; choose from {', '.join(TARGETS)}") from None


def check_serve_options(target, azimuth_deg, brush_deg, server_y) -> tuple[float, float]:
    """Validate the 3-D options; (azimuth, brush) [rad]."""
    psi = math.radians(check_range("azimuth_deg", azimuth_deg, -90.0, 90.0, "deg"))
    ph = math.radians(check_range("brush_deg", brush_deg, -180.0, 180.0, "deg"))
    check_range("server_y", server_y, -10.0, 10.0, "m")
    if target is None and (psi != 0 or ph != 0 or server_y != 0):
        raise InputError("azimuth_deg: the 3-D options (azimuth, brush, server_y) need a deuce or ad target")
    if target is not None:
        box_name(target)
    return psi, ph


@dataclass(frozen=True)
class Setup:
    """Everything but the angles of a serve (SI, rad): player, physics, criteria, 3-D options.

    Attributes
    ----------
    player : the server (impact height [m], racket speed [m/s])
    flight : the flight physics, every field honoured
    impact_params : racket and ball constants of the impact
    criteria : the paper's 2-D test (used when ``target`` is None) and the spin categories
    target : None (the paper's 2-D test) or ``deuce`` / ``ad`` (the real net and that far box)
    server_y : lateral position of the server at the baseline [m]
    brush : brush direction in the face [rad] (0 topspin, -pi/2 slice)
    toss_vz : vertical ball velocity at impact [m/s] (negative: falling)
    dt : impact step [s] (0: ``steps`` per half period)
    method : impact integrator (``rk4`` or ``euler``)
    steps : impact steps per half period of the normal oscillation [-]
    rtol : flight tolerance rtol = atol [-] (None: the aero model's ``batch_tol``)
    """

    player: PlayerProfile
    flight: FlightParams
    impact_params: ImpactParams
    criteria: SeedCriteria
    target: str | None = None
    server_y: float = 0.0
    brush: float = 0.0
    toss_vz: float = 0.0
    dt: float = 0.0
    method: str = "rk4"
    steps: int = 400
    rtol: float | None = None

    @property
    def mode(self) -> str:
        """The success test: ``seed-2d`` or ``deuce-box`` / ``ad-box``."""
        return "seed-2d" if self.target is None else box_name(self.target)

    def caveats(self) -> tuple[str, ...]:
        """The models' caveats shown next to every result of this setup."""
        return (
            *self.impact_params.caveats(),
            *integration_caveats(self.method, self.dt),
            *criteria_caveats(self.target),
        )


#: The physics preset of a serve workflow when no flight is given: every command's default
#: (:data:`tennislab.core.names.DEFAULT_PRESET`, stated there); the paper's constants are ``preset="seed000"``.
DEFAULT_PRESET = _DEFAULT_PRESET


def default_flight(preset: str | None = None) -> FlightParams:
    """The flight physics of a serve workflow when none is given (the one statement of that default):
    ``preset`` (default :data:`DEFAULT_PRESET`, the physics of every command; ``"seed000"`` the paper's
    constants, :func:`~tennislab.serve.setup.seed_flight_params`)."""
    return FlightParams.from_options(preset=DEFAULT_PRESET if preset is None else preset)


def make_setup(
    player,
    *,
    flight: FlightParams | None = None,
    impact_params: ImpactParams | None = None,
    criteria: SeedCriteria | None = None,
    target: str | None = None,
    azimuth_deg: float = 0.0,
    brush_deg: float = 0.0,
    server_y: float = 0.0,
    toss_vz: float = 0.0,
    dt: float = 0.0,
    method: str = "rk4",
    steps: int = 400,
    rtol: float | None = None,
    preset: str | None = None,
) -> Setup:
    """The :class:`Setup` of a workflow's keywords, checked, with the defaults of every serve workflow:
    ``flight`` :func:`default_flight` of ``preset`` (``"standard"``, every command's physics; ``"seed000"``
    the paper's constants; not with a ``flight`` of its own), ``impact_params`` the paper's racket with
    the flight's ball (:func:`~tennislab.serve.setup.seed_impact_params`), ``criteria`` the paper's
    (:class:`~tennislab.serve.setup.SeedCriteria`)."""
    player = get_player(player)
    if flight is not None and preset is not None:
        raise InputError("preset: give a flight or a preset, not both")
    flight = flight or default_flight(preset)
    impact_params = impact_params or seed_impact_params(ball=flight.ball)
    _, brush = check_serve_options(target, azimuth_deg, brush_deg, server_y)
    check_range("toss_vz", toss_vz, -30.0, 30.0, "m/s")
    check_range("dt", dt, 0.0, 1e-3, "s")
    return Setup(
        player,
        flight,
        impact_params,
        criteria or SeedCriteria(),
        target,
        float(server_y),
        brush,
        float(toss_vz),
        float(dt),
        method,
        int(steps),
        rtol,
    )


# ------------------------------------------------------------------ stage 1: impact
def _face_toss(setup: Setup, beta, azimuth):
    """The toss (0, 0, toss_vz) resolved along the face normal n and the brush direction t [m/s]."""
    b = np.asarray(beta, float)
    tz = setup.toss_vz
    return -np.sin(b) * tz, math.cos(setup.brush) * np.cos(b) * tz


def impacts(setup: Setup, alpha, beta=0.0, azimuth=0.0, speed=None) -> dict[str, np.ndarray]:
    """Stage 1: impacts at impact angles ``alpha`` [rad] (arrays broadcast with ``beta``, ``azimuth``
    [rad], which matter only through the toss, and ``speed`` [m/s], default the player's racket
    speed); the rows of :func:`tennislab.core.impact.impact_batch` (racket frame)."""
    V = setup.player.racket_speed if speed is None else speed
    tn, tt = _face_toss(setup, beta, azimuth)
    return impact_batch(
        V, alpha, setup.impact_params, toss_n=tn, toss_t=tt, steps=setup.steps, dt=setup.dt, method=setup.method
    )


# ------------------------------------------------------------------ stage 2: launch
@nb.njit(cache=True)
def _launch_kernel(v_n, v_t, omega, beta, psi, height, brush, toss_vz, server_x, server_y, out):
    """Court-frame states (N, 9) of balls leaving faces (beta, psi [rad]) with racket-frame (v_n, v_t,
    omega) in the plane of the brush direction; the toss's part outside that plane is added back."""
    cph, sph = math.cos(brush), math.sin(brush)
    for k in range(v_n.shape[0]):  # serial: ~10 ns a row, no threads to wake for it
        cb, sb, cp, sp = math.cos(beta[k]), math.sin(beta[k]), math.cos(psi[k]), math.sin(psi[k])
        # face basis (core.impact_3d.face_basis): n, t_up, t_left; brush direction t = cos ph t_up + sin ph t_left
        n0, n1, n2 = cb * cp, cb * sp, -sb
        t0, t1, t2 = cph * sb * cp - sph * sp, cph * sb * sp + sph * cp, cph * cb
        tn, tt = n2 * toss_vz, t2 * toss_vz  # toss (0, 0, toss_vz) along n and t
        out[k, 0] = server_x
        out[k, 1] = server_y
        out[k, 2] = height[k]
        out[k, 3] = v_n[k] * n0 + v_t[k] * t0 - tn * n0 - tt * t0
        out[k, 4] = v_n[k] * n1 + v_t[k] * t1 - tn * n1 - tt * t1
        out[k, 5] = v_n[k] * n2 + v_t[k] * t2 + toss_vz - tn * n2 - tt * t2
        # spin omega (t x n)
        out[k, 6] = omega[k] * (t1 * n2 - t2 * n1)
        out[k, 7] = omega[k] * (t2 * n0 - t0 * n2)
        out[k, 8] = omega[k] * (t0 * n1 - t1 * n0)


def _rows(x, n: int) -> np.ndarray:
    """``x`` as a contiguous float64 array of n rows (a copy only when it has to be broadcast)."""
    a = np.asarray(x, np.float64)
    if a.shape == (n,) and a.flags.c_contiguous:
        return a
    return np.broadcast_to(a.ravel() if a.size == n else a, (n,)).copy()


def launch(setup: Setup, v_n, v_t, omega, beta, azimuth=0.0, height=None) -> np.ndarray:
    """Stage 2: initial states (N, 9) from racket-frame results (v_n, v_t [m/s], omega [rad/s]), face
    angle ``beta`` and ``azimuth`` [rad] and the ball's ``height`` at impact [m] (default the
    player's); served from (baseline, ``setup.server_y``)."""
    h = setup.player.impact_height if height is None else height
    inputs = (v_n, v_t, omega, beta, azimuth, h)
    n = math.prod(np.broadcast_shapes(*(np.shape(a) for a in inputs)))
    vn, vt, w, b, psi, z = (_rows(a, n) for a in inputs)
    out = np.empty((n, 9))
    _launch_kernel(
        vn, vt, w, b, psi, z, float(setup.brush), float(setup.toss_vz), float(setup.criteria.server_x),
        float(setup.server_y), out,
    )  # fmt: skip
    return out


def launch_3d(v_n, v_t, omega, beta, azimuth=0.0, brush=0.0):
    """Court-frame (velocity (..., 3), spin (..., 3)) of balls leaving faces (beta, azimuth [rad]) with
    racket-frame (v_n, v_t, omega) in the plane of the brush direction [rad] (no toss): stage 2's
    kernel, for arrays of any shape."""
    shape = np.broadcast_shapes(*(np.shape(a) for a in (v_n, v_t, omega, beta, azimuth)))
    n = math.prod(shape)
    inputs = (v_n, v_t, omega, beta, azimuth)
    rows = (_rows(np.broadcast_to(np.asarray(a, np.float64), shape).ravel(), n) for a in inputs)
    out = np.empty((n, 9))
    _launch_kernel(*rows, np.zeros(n), float(brush), 0.0, 0.0, 0.0, out)
    return out[:, 3:6].reshape(shape + (3,)), out[:, 6:9].reshape(shape + (3,))


# ------------------------------------------------------------------ stage 3: flight
def fly_serves(setup: Setup, states) -> FlightTable:
    """Stage 3: the flights of initial states (N, 9) with the setup's physics (every field)."""
    return fly_batch(states, setup.flight, rtol=setup.rtol, atol=setup.rtol)


# ------------------------------------------------------------------ stage 4: judgement
def judge(setup: Setup, table: FlightTable) -> dict[str, np.ndarray]:
    """Stage 4: per serve ``landing_x`` (from the impact point) [m], ``net_height`` (ball centre at the
    net plane) [m], ``success`` (bool) and ``reason`` (index into :data:`REASON_CODES`: 0 in, then
    net, short, long, wide, no-landing; the first that applies in that order).

    2-D (``setup.target`` None): the paper's test, ball centre above ``criteria.net_top`` at the net
    and landing at most ``criteria.service_line`` from the impact point.  3-D: over the net of the
    flight's court (``net_status`` over) and into the far service box of that court (lines in).
    """
    crit = setup.criteria
    X = table["land_x"] - crit.server_x
    Y = table["net_z"]
    ns = table["net_status"]
    landed = table.ok
    reason = np.full(len(table), _IN, np.int8)
    beyond = landed & (ns > 0) & (table["land_x"] > 0)  # landed on the far side
    if setup.target is None:
        net = (table["status"] == STATUS_NET) | (beyond & ~(Y > crit.net_top))
        long = beyond & (X > crit.service_line)
        wide = np.zeros_like(beyond)
    else:
        x0, x1, y0, y1 = setup.flight.court.area_bounds(box_name(setup.target))
        net = (table["status"] == STATUS_NET) | (beyond & (ns == NET_HIT))
        long = beyond & (table["land_x"] > x1)
        wide = beyond & ((table["land_y"] < y0) | (table["land_y"] > y1))
    # codes in reverse order of priority: the first reason that applies wins
    reason[wide] = _WIDE
    reason[long] = _LONG
    reason[net] = _NET
    reason[landed & ~((ns > 0) & (table["land_x"] > 0))] = _SHORT
    reason[~landed & (table["status"] != STATUS_NET)] = _NO_LANDING
    return {"landing_x": X, "net_height": Y, "success": reason == _IN, "reason": reason}


# ------------------------------------------------------------------ the stages together
def flights(inputs: dict, *, setup: Setup) -> dict[str, np.ndarray]:
    """Stages 2-4 on rows: either racket-frame results (``v_n``, ``v_t`` [m/s], ``omega`` [rad/s],
    ``beta`` [rad], optional ``azimuth`` [rad] and ``height`` [m]) or initial states (``state``, (N, 9)).
    Returns per row ``land_x``, ``land_y`` (court) [m], ``landing_x`` [m], ``net_height`` [m],
    ``success``, ``reason``, ``status`` and ``landed`` (bool).  The per-chunk worker of the window
    (``tennislab.batch.map_chunks``) and the body of the Monte Carlo's blocks."""
    if "state" in inputs:
        states = np.asarray(inputs["state"], float)
    else:
        states = launch(
            setup,
            inputs["v_n"],
            inputs["v_t"],
            inputs["omega"],
            inputs["beta"],
            inputs.get("azimuth", 0.0),
            inputs.get("height"),
        )
    table = fly_serves(setup, states)
    j = judge(setup, table)
    return {
        "land_x": table["land_x"],
        "land_y": table["land_y"],
        "landing_x": j["landing_x"],
        "net_height": j["net_height"],
        "success": j["success"],
        "reason": j["reason"],
        "status": table["status"],
        "landed": table.ok,
    }


def serves(setup: Setup, alpha_deg, beta_deg, azimuth_deg=0.0) -> dict:
    """All four stages for arrays (broadcast) of impact angle, face angle and azimuth [deg]: the impacts
    (``impact``), the launch ``states`` (N, 9), the flight ``table`` and :func:`judge`'s columns."""
    a, b, z = (np.atleast_1d(np.asarray(x, float)) for x in np.broadcast_arrays(alpha_deg, beta_deg, azimuth_deg))
    A, B, Z = np.radians(a), np.radians(b), np.radians(z)
    imp = impacts(setup, A, B, Z)
    states = launch(setup, imp["v_n"], imp["v_t"], imp["omega"], B, Z)
    table = fly_serves(setup, states)
    return {"impact": imp, "states": states, "table": table, **judge(setup, table)}


def __getattr__(name: str):
    """``fly``: the old name of :func:`fly_serves`, kept working with a :class:`DeprecationWarning`
    (``tennislab.trajectory.fly`` is the flight workflow: one name, one thing)."""
    if name == "fly":
        warnings.warn(
            "tennislab.serve.pipeline.fly is now fly_serves (tennislab.trajectory.fly is the flight workflow)",
            DeprecationWarning,
            stacklevel=2,
        )
        return fly_serves
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
