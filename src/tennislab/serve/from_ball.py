"""Serves from the ball: the racket that gives a ball launch (the inverse of the impact model).

Radar and trackers give a coach the ball: its speed, spin and height as it leaves the racket.  The
serve workflows take the racket: speed V, impact angle alpha (the racket's path against the face
normal: 0 a flat hit, larger brushes up the ball) and face angle beta (the face normal tilted below
the horizontal: 0 a vertical face).  :func:`racket_for` solves the serve pipeline's stages 1-2
(impact and launch, :mod:`tennislab.serve.pipeline`) backwards: the (V, alpha, beta) -- and in 3-D
the azimuth psi and the brush direction -- whose ball leaves at the asked speed, spin rate,
elevation (and heading and spin axis), by Newton's method on the same compiled impact the forward
workflows run.  A ball the model cannot give (too much spin for its speed) is refused with the
nearest it can.

Picture (side view, the ball moving to the right)::

        racket path  ->  alpha from the face normal n;  face tilted beta below the horizontal
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from tennislab.core.flight import MAX_SPEED_MS, MAX_SPIN_RPM
from tennislab.core.launch import describe_spin, describe_velocity
from tennislab.errors import InputError, check_range
from tennislab.results import Result, Table, jsonable
from tennislab.serve.pipeline import REASON_CODES, Setup, failure_counts, flights, impacts, launch, make_setup
from tennislab.units import KMH, RPM, speed_in_ms

__all__ = ["BallLaunch", "BallWindow", "RacketForBall", "ball_window", "racket_for"]

#: largest relative miss of an answer [-]: speed, spin (of max(spin, 100 rpm)); angles within 0.05 deg
TOLERANCE = 1e-3


@dataclass(frozen=True)
class BallLaunch:
    """A ball launch of a serve: speed [m/s], spin rate [rpm] about the axis angle ``spin_axis_deg``
    (0 topspin, -90/+90 sidespin; docs/conventions.md), elevation and heading [deg]."""

    speed_ms: float
    spin_rpm: float
    elevation_deg: float
    heading_deg: float = 0.0
    spin_axis_deg: float = 0.0

    @classmethod
    def of(
        cls,
        *,
        elevation_deg: float,
        speed_ms: float | None = None,
        speed_kmh: float | None = None,
        speed_mph: float | None = None,
        spin_rpm: float = 0.0,
        heading_deg: float = 0.0,
        spin_axis_deg: float = 0.0,
    ) -> BallLaunch:
        """A ball launch with its speed in m/s, km/h or mph (one of them), checked in the unit given."""
        got = speed_in_ms(1.0, MAX_SPEED_MS, speed_ms=speed_ms, speed_kmh=speed_kmh, speed_mph=speed_mph)
        if got is None:
            raise InputError("speed_ms: a ball launch needs its speed (speed_ms, speed_kmh or speed_mph)")
        return cls(got[1], spin_rpm, elevation_deg, heading_deg, spin_axis_deg)

    def to_dict(self) -> dict:
        return {
            "speed_ms": self.speed_ms,
            "speed_kmh": self.speed_ms / KMH,
            "spin_rpm": self.spin_rpm,
            "spin_axis_deg": self.spin_axis_deg,
            "elevation_deg": self.elevation_deg,
            "heading_deg": self.heading_deg,
        }


@dataclass(frozen=True)
class RacketForBall(Result):
    """The racket that gives a ball launch: ``racket_speed`` [m/s], ``alpha_deg``, ``beta_deg``,
    ``azimuth_deg``, ``brush_deg`` [deg]; ``asked`` and ``gives`` (the forward model's ball of that
    racket), ``height`` [m] the ball's height at impact."""

    racket_speed: float
    alpha_deg: float
    beta_deg: float
    azimuth_deg: float
    brush_deg: float
    height: float
    asked: BallLaunch
    gives: BallLaunch
    three_d: bool = False  #: solved with azimuth and brush (a 3-D serve)

    def to_dict(self) -> dict:
        return jsonable(
            {
                "racket_speed_ms": self.racket_speed,
                "alpha_deg": self.alpha_deg,
                "beta_deg": self.beta_deg,
                "azimuth_deg": self.azimuth_deg,
                "brush_deg": self.brush_deg,
                "height_m": self.height,
                "asked": self.asked.to_dict(),
                "gives": self.gives.to_dict(),
                "three_d": self.three_d,
            }
        )


def _ball(setup: Setup, x: np.ndarray, three_d: bool) -> np.ndarray:
    """Rows of (speed [m/s], spin [rpm], elevation [deg], heading [deg], axis [deg]) of rows of unknowns
    (V [m/s], alpha, beta [, azimuth, brush] [deg]) through stages 1-2 of the serve pipeline."""
    x = np.atleast_2d(x)
    out = np.empty((x.shape[0], 5))
    for k, row in enumerate(x):
        V, a, b = row[0], math.radians(row[1]), math.radians(row[2])
        psi = math.radians(row[3]) if three_d else 0.0
        s = replace(setup, brush=math.radians(row[4])) if three_d else setup
        imp = impacts(s, np.array([a]), np.array([b]), np.array([psi]), speed=np.array([V]))
        st = launch(s, imp["v_n"], imp["v_t"], imp["omega"], np.array([b]), np.array([psi]))[0]
        v, w = st[3:6], st[6:9]
        speed, elev, head = describe_velocity(v)  # (the launch vocabulary of core.launch)
        d = describe_spin(w, v)
        axis = math.degrees(math.atan2(d["sidespin"], d["topspin"]))
        out[k] = (speed, d["rate"] / RPM, math.degrees(elev), math.degrees(head), axis)
    return out


def _misses(got: np.ndarray, want: np.ndarray, n: int) -> np.ndarray:
    """Scaled misses: speed and spin relative, angles in units of 0.05 deg (the tolerance)."""
    d = got[:n] - want[:n]
    d[0] /= max(want[0], 1.0)
    d[1] /= max(want[1], 100.0)
    if n > 2:
        d[2:] = (d[2:] + 180.0) % 360.0 - 180.0
        d[2:] *= TOLERANCE / 0.05
    return d


def _guess(setup: Setup, speed: float, spin_rpm: float) -> tuple[float, float]:
    """(V, alpha [deg]) nearest the asked speed and spin on a coarse grid (the low-alpha branch)."""
    V, A = np.meshgrid(np.linspace(5.0, 100.0, 39), np.linspace(0.0, 60.0, 31), indexing="ij")
    imp = impacts(setup, np.radians(A.ravel()), 0.0, 0.0, speed=V.ravel())
    s, w = imp["speed"].reshape(V.shape), imp["spin"].reshape(V.shape) / RPM
    cost = ((s - speed) / max(speed, 1.0)) ** 2 + ((w - spin_rpm) / max(spin_rpm, 500.0)) ** 2
    i, j = np.unravel_index(int(np.argmin(cost)), cost.shape)
    return float(V[i, j]), float(A[i, j])


def racket_for(setup, ball: BallLaunch, *, height: float | None = None, **options) -> RacketForBall:
    """The racket (V, alpha, beta; in 3-D also azimuth and brush) whose serve launches ``ball`` from the
    setup's player position (at ``height`` [m], default the player's impact height).  ``setup`` is a
    :class:`~tennislab.serve.pipeline.Setup`, or a player (name or profile) with the keywords of the
    serve workflows in ``options`` (``flight``, ``impact_params``, ``target``, ``server_y``, ``toss_vz``,
    ``method``, ``dt``).

    2-D setups (no target) serve in the x-z plane: the heading must be 0 and the spin topspin (axis 0)
    or backspin (180).  Refused (:class:`InputError`) when the impact model gives no such ball."""
    if not isinstance(setup, Setup):
        setup = make_setup(setup, **options)
    check_range("speed_ms", ball.speed_ms, 1.0, MAX_SPEED_MS, "m/s")  # (the guard rails of every flight)
    check_range("spin_rpm", ball.spin_rpm, 0.0, MAX_SPIN_RPM, "rpm")
    check_range("elevation_deg", ball.elevation_deg, -60.0, 60.0, "deg")
    check_range("heading_deg", ball.heading_deg, -60.0, 60.0, "deg")
    three_d = setup.target is not None
    axis = (ball.spin_axis_deg + 180.0) % 360.0 - 180.0
    if not three_d:
        if ball.heading_deg != 0.0:
            raise InputError("heading_deg: a 2-D serve flies straight down the court; give a deuce or ad target")
        if ball.spin_rpm > 0 and min(abs(axis), abs(abs(axis) - 180.0)) > 1e-9:
            raise InputError(
                "spin_axis: a 2-D serve spins about the topspin axis (topspin or backspin); give a deuce or ad target"
            )
    h = setup.player.impact_height if height is None else check_range("height", height, 0.5, 4.0, "m")
    setup = replace(setup, player=setup.player.with_overrides(impact_height=h))
    backspin = not three_d and abs(axis) > 90.0
    want = np.array([ball.speed_ms, ball.spin_rpm, ball.elevation_deg, ball.heading_deg, axis])
    V0, a0 = _guess(setup, ball.speed_ms, ball.spin_rpm)
    a0 = -a0 if backspin else a0
    # beta from the launch without a toss: elevation = atan2(v_t, v_n) - beta
    x = np.array([V0, a0, 0.0, ball.heading_deg, -axis])[: 5 if three_d else 3]
    g = _ball(setup, x, three_d)[0]
    x[2] += g[2] - ball.elevation_deg
    n = x.size
    for _ in range(30):
        r = _misses(_ball(setup, x, three_d)[0], want, n)
        if np.all(np.abs(r) < TOLERANCE / 10):
            break
        steps = np.array([1e-3 * max(x[0], 1.0), 1e-2, 1e-2, 1e-2, 1e-2])[:n]
        rows = _ball(setup, x + np.diag(steps), three_d)
        J = np.stack([(_misses(rows[k], want, n) - r) / steps[k] for k in range(n)], axis=1)
        dx = np.linalg.lstsq(J, -r, rcond=None)[0]
        dx *= min(1.0, 5.0 / max(abs(dx[0]), 1e-12), 10.0 / max(np.abs(dx[1:]).max(), 1e-12))  # damped
        x = x + dx
        x[0] = min(max(x[0], 1.0), 150.0)
        x[1] = min(max(x[1], -89.0), 89.0)
        x[2] = min(max(x[2], -89.0), 89.0)
        if three_d:
            x[3] = min(max(x[3], -89.0), 89.0)
    got = _ball(setup, x, three_d)[0]
    gives = BallLaunch(float(got[0]), float(got[1]), float(got[2]), float(got[3]), float(got[4]))
    if np.any(np.abs(_misses(got, want, n)) > TOLERANCE):
        raise InputError(
            f"ball launch: the impact model gives no racket for {ball.speed_ms / KMH:.1f} km/h with "
            f"{ball.spin_rpm:.0f} rpm at elevation {ball.elevation_deg:.1f} deg "
            f"(nearest: {gives.speed_ms / KMH:.1f} km/h, "
            f"{gives.spin_rpm:.0f} rpm, elevation {gives.elevation_deg:.1f} deg); less spin or more speed"
        )
    az, br = (float(x[3]), float(x[4])) if three_d else (0.0, 0.0)
    return RacketForBall(float(x[0]), float(x[1]), float(x[2]), az + 0.0, br + 0.0, float(h), ball, gives, three_d)


@dataclass(frozen=True)
class BallWindow(Table):
    """Every launch direction of one ball (speed, spin, axis fixed): the launch elevations (and in 3-D
    headings) that go in, with the racket that gives each (``serve-window --speed-kmh ...``).  ``rows()``
    / ``to_frame()``: one launch per row."""

    COLUMNS = ("elevation_deg", "heading_deg", "beta_deg", "azimuth_deg", "success", "reason", "land_x_m", "land_y_m")

    racket: RacketForBall  #: the racket at the reference launch (V, alpha, brush are the window's)
    elevation_deg: np.ndarray  #: (n,) launch elevation of each launch [deg]
    heading_deg: np.ndarray  #: (n,) [deg]
    beta_deg: np.ndarray  #: (n,) face angle that gives it [deg]
    azimuth_deg: np.ndarray  #: (n,) face azimuth [deg]
    success: np.ndarray  #: (n,) bool
    reason: np.ndarray  #: (n,) index into REASON_CODES
    land_x: np.ndarray  #: (n,) court x [m]
    land_y: np.ndarray  #: (n,) court y [m]
    criteria: str = "seed-2d"
    caveats: tuple[str, ...] = ()

    def ranges(self) -> dict:
        """[min, max] over the launches that go in of elevation, heading, beta, azimuth [deg] (None if none)."""
        m = self.success
        keys = ("elevation_deg", "heading_deg", "beta_deg", "azimuth_deg")
        return {
            k: ([float(getattr(self, k)[m].min()), float(getattr(self, k)[m].max())] if m.any() else None) for k in keys
        }

    def failures(self) -> dict[str, int]:
        """How many launches of the window fail, by reason (:func:`~tennislab.serve.pipeline.failure_counts`)."""
        return failure_counts(self.reason)

    def rows(self) -> list[dict]:
        return [
            {
                "elevation_deg": float(e),
                "heading_deg": float(h),
                "beta_deg": float(b),
                "azimuth_deg": float(z),
                "success": bool(s),
                "reason": REASON_CODES[int(r)],
                "land_x_m": float(x),
                "land_y_m": float(y),
            }
            for e, h, b, z, s, r, x, y in zip(
                self.elevation_deg, self.heading_deg, self.beta_deg, self.azimuth_deg, self.success, self.reason,
                self.land_x, self.land_y,
            )
        ]  # fmt: skip

    def to_dict(self) -> dict:
        return jsonable(
            {
                "ball": self.racket.asked.to_dict(),
                "racket_for_ball": self.racket.to_dict(),
                "criteria": self.criteria,
                "n_launches": int(self.success.size),
                "n_success": int(self.success.sum()),
                "in": self.ranges(),
                "failures": self.failures(),
                "caveats": list(self.caveats),
            }
        )


def ball_window(
    player,
    ball: BallLaunch,
    *,
    height: float | None = None,
    step: float = 0.5,
    elevation_deg: tuple[float, float] = (-15.0, 15.0),
    heading_deg: tuple[float, float] = (-15.0, 15.0),
    **options,
) -> BallWindow:
    """Every launch direction of ``ball`` (its speed, spin and axis; its elevation and heading are swept over
    ``elevation_deg`` and, in 3-D, ``heading_deg`` [deg] at ``step``): which go in.  The racket speed, the
    impact angle (and the brush) are solved once (:func:`racket_for` at the middle of the sweep); each launch
    direction is a face angle beta (and azimuth), flown and judged by the serve pipeline."""
    setup = make_setup(player, **options)
    step = check_range("step", step, 0.05, 10.0, "deg")
    e0, e1 = (check_range("elevation_deg", e, -60.0, 60.0, "deg") for e in elevation_deg)
    h0, h1 = (check_range("heading_deg", h, -60.0, 60.0, "deg") for h in heading_deg)
    for name, (lo, hi) in (("elevation_deg", (e0, e1)), ("heading_deg", (h0, h1))):
        if hi < lo:
            raise InputError(f"{name}: give the lower bound first (got {lo:g} {hi:g} deg)")
    three_d = setup.target is not None
    mid = replace(ball, elevation_deg=0.5 * (e0 + e1), heading_deg=0.5 * (h0 + h1) if three_d else 0.0)
    r = racket_for(setup, mid, height=height)
    setup = replace(
        setup, player=setup.player.with_overrides(r.height, r.racket_speed), brush=math.radians(r.brush_deg)
    )
    de = np.arange(e0, e1 + 1e-9, step) - mid.elevation_deg
    dh = np.arange(h0, h1 + 1e-9, step) - mid.heading_deg if three_d else np.zeros(1)
    grid_b, grid_z = np.meshgrid(r.beta_deg - de, r.azimuth_deg + dh, indexing="ij")
    keep = np.abs(grid_b.ravel()) <= 89.0
    B, Z = grid_b.ravel()[keep], grid_z.ravel()[keep]
    Br, Zr = np.radians(B), np.radians(Z)
    imp = impacts(setup, np.full(B.size, math.radians(r.alpha_deg)), Br, Zr)
    states = launch(setup, imp["v_n"], imp["v_t"], imp["omega"], Br, Zr)
    out = flights({"state": states}, setup=setup)
    v = states[:, 3:6]
    elev = np.degrees(np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1])))
    head = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    return BallWindow(
        r, elev, head, B, Z, np.asarray(out["success"], bool), np.asarray(out["reason"], np.int8),
        np.asarray(out["land_x"]), np.asarray(out["land_y"]), setup.mode, setup.caveats(),
    )  # fmt: skip
