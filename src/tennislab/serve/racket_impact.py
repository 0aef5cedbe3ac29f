"""One racket-ball impact (the paper's sec. 2.2 model) seen in the racket and court frames.

:func:`impact` is the workflow behind ``tennislab impact``: racket speed and impact angle in,
ball speed, spin, launch angle, contact time and the stick/slip regime out
(:class:`ImpactSummary`, whose ``to_dict()`` is ``impact --json``; ``rows()`` gives the force
history when it was kept).

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), sec. 2.2
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from tennislab.core.ball import Ball
from tennislab.core.impact import HIST_COLUMNS, ImpactParams, ImpactResult, to_court
from tennislab.core.impact import impact_single as _impact
from tennislab.core.names import DEFAULT_PRESET
from tennislab.errors import InputError, check_range
from tennislab.results import Table, jsonable
from tennislab.serve.setup import integration_caveats, seed_impact_params
from tennislab.units import RPM

__all__ = ["ImpactSummary", "impact"]


@dataclass(frozen=True)
class ImpactSummary(Table):
    """An impact and its inputs: racket speed [m/s], impact and face angles [deg], toss [m/s].
    ``rows()`` / ``to_frame()``: the contact history (``history=True``), normal positions of the racket,
    the ball and the string node [m], their velocities [m/s], the tangential stretch [m], the
    tangential velocities [m/s], the ball's spin [rad/s] and the forces [N] (racket frame)."""

    COLUMNS = HIST_COLUMNS
    FRAME_COLUMNS = {
        "t": "t_s",
        "x1": "racket_x_m",
        "x2": "ball_x_m",
        "x3": "node_x_m",
        "v1": "racket_vn_ms",
        "v2": "ball_vn_ms",
        "e": "stretch_m",
        "w1": "racket_vt_ms",
        "w2": "ball_vt_ms",
        "w3": "ball_omega_rad_s",
        "F_N": "normal_force_n",
        "F_t": "tangential_force_n",
    }

    result: ImpactResult = field(repr=False)
    racket_speed: float
    impact_angle: float
    face_angle: float
    toss_vz: float
    params: ImpactParams = field(repr=False)
    method: str = "rk4"
    dt: float = 0.0
    caveats: tuple[str, ...] = ()

    def to_dict(self) -> dict:
        res, p = self.result, self.params
        vx, vz = to_court(res.v_n, res.v_t, math.radians(self.face_angle))
        return jsonable(
            {
                "ball": {
                    "speed": res.speed,
                    "spin_rpm": res.omega / RPM,
                    "spin": res.omega,
                    "launch_angle": math.degrees(math.atan2(vz, vx)),
                    "velocity": [vx, 0.0, vz],
                    "v_n": res.v_n,
                    "v_t": res.v_t,
                    "launch_angle_deg": math.degrees(math.atan2(vz, vx)),
                },
                "racket": {"v_n": res.racket_v_n, "v_t": res.racket_v_t},
                "contact_time_ms": res.contact_time * 1e3,
                "regime": res.regime,
                "grip_time_ms": None if res.grip_time is None else res.grip_time * 1e3,
                "peak_force": res.peak_force,
                "inputs": {
                    "racket_speed": self.racket_speed,
                    "impact_angle": self.impact_angle,
                    "face_angle": self.face_angle,
                    "toss_vz": self.toss_vz,
                    "racket_mass": p.racket_mass,
                    "string_stiffness": p.string_stiffness,
                    "friction": p.friction,
                    "ball_mass": p.ball.mass,
                    "ball_radius": p.ball.radius,
                    "ball_model": p.ball_model.name,
                    "friction_model": p.friction_model,
                    "tangential_damping": p.tangential_damping,
                    "approach_gap_m": p.approach_gap,
                    "integrator": self.method,
                    "dt_s": self.dt,
                },
                "caveats": list(self.caveats),
            }
        )

    def rows(self) -> list[dict]:
        """The contact history (t [s], the state, F_N, F_t [N]) when it was kept (``history=True``)."""
        h = self.result.history
        if h is None:
            raise InputError("history: this impact kept no history (pass history=True)")
        return [{c: float(h[c][i]) for c in HIST_COLUMNS} for i in range(h["t"].size)]


def impact(
    racket_speed: float,
    impact_angle: float,
    *,
    face_angle: float = 0.0,
    toss_vz: float = 0.0,
    params: ImpactParams | None = None,
    method: str = "rk4",
    dt: float = 0.0,
    history: bool = False,
    preset: str | None = None,
) -> ImpactSummary:
    """One impact: racket speed V [m/s] at impact angle alpha = ``impact_angle`` [deg] to the face
    normal, face tilted down by beta = ``face_angle`` [deg]; ``toss_vz`` the ball's vertical
    velocity at impact [m/s] (negative: falling).  ``params`` default to the paper's racket, strings and
    contact model (:func:`tennislab.serve.seed_impact_params`) with the ball of ``preset`` (default
    :data:`tennislab.core.names.DEFAULT_PRESET`, ``standard``: the ball every serve workflow hits;
    ``"seed000"`` the paper's 59 g / 33 mm); ``method``/``dt`` set the integration."""
    if params is not None and preset is not None:
        raise InputError("preset: give impact params or a preset, not both")
    if params is None:
        params = seed_impact_params(ball=Ball.from_options(preset=DEFAULT_PRESET if preset is None else preset))
    check_range("racket_speed", racket_speed, 0.0, 100.0, "m/s", lo_open=True)
    a = math.radians(check_range("impact_angle", impact_angle, -89.999, 89.999, "deg"))
    b = math.radians(check_range("face_angle", face_angle, -90.0, 90.0, "deg"))
    check_range("toss_vz", toss_vz, -30.0, 30.0, "m/s")
    check_range("dt", dt, 0.0, 1e-3, "s")
    # toss (0, 0, vz) in the racket frame: n = (cos b, -sin b), t = (sin b, cos b) in (x, z)
    tn, tt = -toss_vz * math.sin(b), toss_vz * math.cos(b)
    res = _impact(racket_speed, a, params, toss_n=tn, toss_t=tt, dt=dt, method=method, history=history)
    return ImpactSummary(
        res,
        float(racket_speed),
        float(impact_angle),
        float(face_angle),
        float(toss_vz),
        params,
        method,
        float(dt),
        (*params.caveats(), *integration_caveats(method, dt)),
    )
