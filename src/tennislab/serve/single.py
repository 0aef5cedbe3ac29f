"""One serve: impact, launch and flight, judged by the paper's 2-D criteria or a real service box.

:func:`simulate` is the workflow behind ``tennislab serve``, the app's serve explorer and the
report; its :class:`ServeResult` says whether the serve goes in, and if not why (``net``,
``long``, ``wide``, ...) and what would fix it (:mod:`tennislab.serve.verdict`).

2-D (default, the paper's): ball centre at (baseline, y = 0, impact height), face normal in the
x-z plane, success = net_top / service_line of :class:`SeedCriteria`.  3-D (``target="deuce"`` or
``"ad"``): the server at (baseline, ``server_y``), the face turned by ``azimuth_deg`` and brushed
along ``brush_deg`` (see :mod:`tennislab.core.impact_3d`); success = over the real net (ITF
profile) and first bounce inside the far deuce/ad service box (lines are in).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from tennislab.core.flight import FlightParams, Trajectory, fly_dense
from tennislab.core.impact import REGIMES, ImpactParams
from tennislab.errors import InputError, check_range
from tennislab.results import DEFAULT_STEP_S, TRAJECTORY_COLUMNS, Table, jsonable, trajectory_rows
from tennislab.serve.pipeline import REASONS, Setup, make_setup, serves
from tennislab.serve.players import PlayerProfile
from tennislab.serve.setup import CATEGORIES, SeedCriteria
from tennislab.serve.verdict import advise, describe
from tennislab.units import KMH, RPM

__all__ = ["ServeResult", "Verdict", "simulate", "REASONS"]


@dataclass(frozen=True)
class Verdict:
    """Why a serve goes in or fails and what would fix it.

    success : the serve goes in
    reason : ``None`` or a code of :data:`REASONS` (``net``, ``short``, ``long``, ``wide``, ``no-landing``)
    detail : one sentence with the numbers (net clearance, distance beyond the line, ...)
    advice : what would make it go in (or how much margin it has), computed from scans of the face
        angle, the impact angle (and in 3-D the azimuth) with the same physics; None if nothing found
    """

    success: bool
    reason: str | None
    detail: str
    advice: str | None

    def to_dict(self) -> dict:
        return {"success": self.success, "reason": self.reason, "detail": self.detail, "advice": self.advice}

    def line(self) -> str:
        """One line for a terminal: ``IN: ...`` or ``FAULT (net): ...``."""
        head = "IN" if self.success else f"FAULT ({self.reason})"
        return f"{head}: {self.detail}"


@dataclass(frozen=True)
class ServeResult(Table):
    """One serve (angles in degrees, SI otherwise).  ``to_dict()`` is ``tennislab serve --json``;
    ``rows(step_s)`` / ``to_frame()`` the ball's flight from the impact to the first bounce, every
    ``step_s`` [s] (kept with ``simulate(..., trajectory=True)``)."""

    COLUMNS = TRAJECTORY_COLUMNS

    player: PlayerProfile
    impact_angle: float  #: alpha [deg]
    face_angle: float  #: beta [deg]
    speed: float  #: ball speed after impact [m/s]
    spin_rpm: float  #: [rpm] (> 0 topspin about the brush axis)
    launch_angle: float  #: gamma above the horizontal [deg]
    net_height: float  #: ball centre at the net plane [m]
    net_clearance: float  #: margin over the criterion's net top [m] (negative: into the net)
    landing_x: float  #: landing distance from the impact point [m]
    landing: dict  #: court x, y [m] and time t [s] of the first bounce
    success: bool
    category: str  #: flat, topspin or other (by spin)
    impact: dict  #: contact_time [s], regime, v_n, v_t [m/s], omega [rad/s] (racket frame)
    velocity: tuple  #: launch velocity [m/s] (court frame)
    spin: tuple  #: launch spin vector [rad/s]
    criteria: str  #: ``seed-2d`` or ``deuce-box`` / ``ad-box``
    verdict: Verdict
    caveats: tuple[str, ...]
    inputs: dict  #: the 3-D options and the model names
    trajectory: Trajectory | None = field(default=None, repr=False)

    def rows(self, step_s: float = DEFAULT_STEP_S) -> list[dict]:
        """The flight every ``step_s`` [s]: time [s], position [m], velocity and speed [m/s], spin [rpm]."""
        if self.trajectory is None:
            raise InputError("trajectory: this serve kept no flight (pass simulate(..., trajectory=True))")
        return trajectory_rows([self.trajectory], step_s)

    def to_dict(self) -> dict:
        imp = self.impact
        return jsonable(
            {
                "player": self.player.name,
                "alpha": self.impact_angle,
                "beta": self.face_angle,
                "speed": self.speed,
                "spin_rpm": self.spin_rpm,
                "launch_angle": self.launch_angle,
                "net_height": self.net_height,
                "landing_x": self.landing_x,
                "success": self.success,
                "category": self.category,
                "landing": self.landing,
                "impact": {
                    "contact_time_ms": imp["contact_time"] * 1e3,
                    "regime": imp["regime"],
                    "v_n": imp["v_n"],
                    "v_t": imp["v_t"],
                    "omega": imp["omega"],
                },
                "velocity": self.velocity,
                "spin": self.spin,
                "criteria": self.criteria,
                # added keys (unit-suffixed twins, the verdict, the caveats, the profile)
                "alpha_deg": self.impact_angle,
                "beta_deg": self.face_angle,
                "launch_angle_deg": self.launch_angle,
                "speed_kmh": self.speed / KMH,
                "net_clearance": self.net_clearance,
                "verdict": self.verdict.to_dict(),
                "caveats": list(self.caveats),
                "player_profile": self.player.to_dict(),
                "inputs": self.inputs,
            }
        )


def simulate(
    player,
    impact_angle: float,
    face_angle: float,
    *,
    flight: FlightParams | None = None,
    preset: str | None = None,
    impact_params: ImpactParams | None = None,
    criteria: SeedCriteria | None = None,
    target: str | None = None,
    azimuth_deg: float = 0.0,
    brush_deg: float = 0.0,
    server_y: float = 0.0,
    toss_vz: float = 0.0,
    trajectory: bool = False,
    dt: float = 0.0,
    method: str = "rk4",
    advice: bool = True,
) -> ServeResult:
    """Simulate one serve of ``player`` (a registered name or :class:`PlayerProfile`) hit at impact
    angle alpha = ``impact_angle`` and face angle beta = ``face_angle`` [deg].

    ``flight``/``impact_params`` default to the serve workflows' physics, the ``standard`` preset of every
    command (``preset="seed000"``: the paper's constants; :func:`tennislab.serve.pipeline.make_setup`);
    ``dt``/``method`` set the impact integration.
    ``target`` ``deuce``/``ad``: 3-D, with ``azimuth_deg``, ``brush_deg`` [deg] and ``server_y`` [m].
    ``toss_vz``: vertical ball velocity at impact [m/s] (negative: falling), a Galilean shift of the
    impact.  ``trajectory=True`` keeps the SciPy :class:`Trajectory` (for plots).  ``advice=False``
    skips the scans behind ``verdict.advice``.
    """
    check_range("impact_angle", impact_angle, -89.999, 89.999, "deg")
    check_range("face_angle", face_angle, -90.0, 90.0, "deg")
    setup = make_setup(
        player,
        flight=flight,
        preset=preset,
        impact_params=impact_params,
        criteria=criteria,
        target=target,
        azimuth_deg=azimuth_deg,
        brush_deg=brush_deg,
        server_y=server_y,
        toss_vz=toss_vz,
        dt=dt,
        method=method,
    )
    o = serves(setup, impact_angle, face_angle, azimuth_deg)
    table, imp = o["table"], o["impact"]
    state = o["states"][0]
    vel, spin = state[3:6], state[6:9]
    spin_rpm = float(imp["omega"][0]) / RPM
    clearance = _clearance(setup, table)
    verdict = _verdict(setup, table, o, clearance, float(impact_angle), float(face_angle), float(azimuth_deg), advice)
    crit, flight, impact_params = setup.criteria, setup.flight, setup.impact_params
    return ServeResult(
        player=setup.player,
        impact_angle=float(impact_angle),
        face_angle=float(face_angle),
        speed=float(np.linalg.norm(vel)),
        spin_rpm=spin_rpm,
        launch_angle=math.degrees(math.atan2(vel[2], math.hypot(vel[0], vel[1]))),
        net_height=float(o["net_height"][0]),
        net_clearance=clearance,
        landing_x=float(o["landing_x"][0]),
        landing={"x": float(table["land_x"][0]), "y": float(table["land_y"][0]), "t": float(table["land_t"][0])},
        success=bool(o["success"][0]),
        category=CATEGORIES[int(crit.category(spin_rpm))],
        impact={
            "contact_time": float(imp["contact_time"][0]),
            "regime": REGIMES[int(imp["regime"][0])],
            "v_n": float(imp["v_n"][0]),
            "v_t": float(imp["v_t"][0]),
            "omega": float(imp["omega"][0]),
        },
        velocity=tuple(float(v) for v in vel),
        spin=tuple(float(w) for w in spin),
        criteria=setup.mode,
        verdict=verdict,
        caveats=setup.caveats(),
        inputs={
            "target": target,
            "azimuth_deg": float(azimuth_deg),
            "brush_deg": float(brush_deg),
            "server_y": float(server_y),
            "toss_vz": float(toss_vz),
            "aero": flight.aero.name,
            "ball_model": impact_params.ball_model.name,
            "friction_model": impact_params.friction_model,
            "tangential_damping": impact_params.tangential_damping,
            "approach_gap_m": impact_params.approach_gap,
            "integrator": method,
            "dt_s": float(dt),
        },
        trajectory=fly_dense(state[0:3], vel, spin, flight) if trajectory else None,
    )


# ---------------------------------------------------------------------------------------- verdict


def _clearance(setup: Setup, table) -> float:
    """Margin [m] of the ball centre over what the test needs at the net (NaN if it never gets there)."""
    if table["net_status"][0] == 0:
        return math.nan
    if setup.target is None:
        return float(table["net_z"][0] - setup.criteria.net_top)
    return float(table.clearance[0])


def _verdict(setup: Setup, table, o, clearance, alpha, beta, azimuth, advice: bool) -> Verdict:
    reason, detail = describe(setup, table, o, clearance)
    adv = advise(setup, reason, alpha, beta, azimuth) if advice else None
    return Verdict(reason is None, reason, detail, adv)
