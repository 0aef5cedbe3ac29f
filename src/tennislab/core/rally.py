"""Flight with bounces: flight segments chained through the bounce model.

Each segment is a :func:`~tennislab.core.flight.fly_dense` flight to its landing
(ball centre at z = r).  At a landing the bounce model
(:mod:`tennislab.core.bounce`) gives the outgoing velocity and spin, and the
mark model (:mod:`tennislab.core.mark`) the contact: the ball stays on the
ground for the contact time T_c while its centre advances by the contact
displacement, so the next segment starts at (landing + displacement, z = r) at
time t_land + T_c.  The chain stops after ``bounces`` impacts or when the ball
leaves the ground slower than ``min_vz`` (it is then rolling).

:func:`fly_bounces_batch` does the same for N initial states with the compiled
batch integrator (positions and velocities only; no marks).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.core.bounce import MODES, bounce, bounce_batch
from tennislab.core.flight import FlightParams, Trajectory, fly_batch, fly_dense
from tennislab.core.mark import BallMark, MarkParams, ball_mark, contact_displacement
from tennislab.core.surfaces import get_surface
from tennislab.errors import InputError, check_range
from tennislab.results import OldAsDict

MIN_VZ = 0.05  #: [m/s] below this vertical take-off speed the ball is considered rolling


@dataclass(frozen=True)
class Bounce(OldAsDict):
    """One bounce: first-contact point (x, y) [m] and time t [s], velocities [m/s], spins [rad/s]."""

    x: float
    y: float
    t: float
    velocity_in: np.ndarray
    velocity_out: np.ndarray
    spin_in: np.ndarray
    spin_out: np.ndarray
    mode: str
    mark: BallMark

    def to_dict(self) -> dict:
        return {
            "x": self.x,
            "y": self.y,
            "t": self.t,
            "velocity_in": self.velocity_in,
            "velocity_out": self.velocity_out,
            "spin_in": self.spin_in,
            "spin_out": self.spin_out,
            "mode": self.mode,
            "mark": self.mark.to_dict(),
        }


@dataclass(frozen=True)
class Rally:
    """Flight segments (one more than bounces, unless the chain stopped) and the bounces."""

    segments: list
    bounces: list

    @property
    def first(self) -> Trajectory:
        return self.segments[0]


def bounce_at(landing, surface, params: FlightParams, mark_params: MarkParams = MarkParams()) -> Bounce:
    """The :class:`Bounce` at a :class:`~tennislab.core.events.Landing`."""
    s = get_surface(surface)
    res = bounce(landing.velocity, landing.spin, s, params.ball)
    mk = ball_mark(landing.position[:2], landing.velocity, res.velocity_out, landing.spin, s, params.ball, mark_params)
    return Bounce(
        landing.x,
        landing.y,
        landing.t,
        np.asarray(landing.velocity).copy(),
        res.velocity_out,
        np.asarray(landing.spin).copy(),
        res.spin_out,
        res.mode,
        mk,
    )


def fly_bounces(
    position,
    velocity,
    spin=(0.0, 0.0, 0.0),
    params: FlightParams | None = None,
    *,
    surface="hard",
    bounces: int = 1,
    mark_params: MarkParams = MarkParams(),
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> Rally:
    """Integrate a flight through up to ``bounces`` bounces on ``surface``.

    Returns a :class:`Rally`; ``segments[i]`` is the flight ending at bounce i (the
    last segment is the flight after the last bounce, to its next landing).
    """
    params = params or FlightParams()
    n = int(check_range("bounces", bounces, 0, 100))
    s = get_surface(surface)
    segs, bnc = [], []
    tr = fly_dense(position, velocity, spin, params, rtol=rtol, atol=atol)
    segs.append(tr)
    for _ in range(n):
        if tr.landing is None:
            break
        b = bounce_at(tr.landing, s, params, mark_params)
        bnc.append(b)
        if b.velocity_out[2] < MIN_VZ:
            break
        p0 = (b.x + b.mark.displacement[0], b.y + b.mark.displacement[1], params.ball.radius)
        tr = fly_dense(p0, b.velocity_out, b.spin_out, params, rtol=rtol, atol=atol, t0=b.t + mark_params.contact_time)
        segs.append(tr)
    return Rally(segs, bnc)


def fly_bounces_batch(
    states,
    params: FlightParams | None = None,
    *,
    surface="hard",
    bounces: int = 1,
    contact_time: float = MarkParams().contact_time,
    rtol: float | None = None,
    atol: float | None = None,
) -> dict[str, np.ndarray]:
    """N flights through ``bounces`` bounces with the compiled batch integrator.

    ``rtol``, ``atol``: of :func:`~tennislab.core.flight.fly_batch` (default: half the aero model's
    ``batch_tol``, since each bounce starts from the previous flight's end).

    Returns arrays (N, bounces): ``x``, ``y``, ``t`` of each first contact,
    ``vin``/``vout``/``wout`` (N, bounces, 3) and ``mode`` codes (index into
    :data:`bounce.MODES`); NaN where a ball stopped bouncing or never landed.
    The contact displacement is that of the mark model (as :func:`fly_bounces`).
    """
    params = params or FlightParams()
    rtol = 0.5 * params.aero.batch_tol if rtol is None else rtol
    atol = 0.5 * params.aero.batch_tol if atol is None else atol
    s = get_surface(surface)
    nb_ = int(check_range("bounces", bounces, 1, 100))
    st = np.ascontiguousarray(np.asarray(states, dtype=np.float64))
    if st.ndim != 2 or st.shape[1] != 9:
        raise InputError(f"states: expected an (N, 9) array, got shape {st.shape}")
    N = st.shape[0]
    out = {k: np.full((N, nb_), np.nan) for k in ("x", "y", "t")}
    for k in ("vin", "vout", "wout"):
        out[k] = np.full((N, nb_, 3), np.nan)
    out["mode"] = np.full((N, nb_), -1, dtype=np.int64)
    t0 = np.zeros(N)
    alive = np.arange(N)
    r = params.ball.radius
    for j in range(nb_):
        if alive.size == 0:
            break
        tab = fly_batch(st[alive], params, rtol=rtol, atol=atol)
        ok = tab.ok
        idx = alive[ok]
        vin = np.column_stack([tab["land_vx"], tab["land_vy"], tab["land_vz"]])[ok]
        win = np.column_stack([tab["land_wx"], tab["land_wy"], tab["land_wz"]])[ok]
        vout, wout, modes = bounce_batch(vin, win, s, params.ball)
        tl = t0[idx] + tab["land_t"][ok]
        out["x"][idx, j] = tab["land_x"][ok]
        out["y"][idx, j] = tab["land_y"][ok]
        out["t"][idx, j] = tl
        out["vin"][idx, j] = vin
        out["vout"][idx, j] = vout
        out["wout"][idx, j] = wout
        out["mode"][idx, j] = modes
        disp = np.empty((idx.size, 2))
        for i in range(idx.size):
            contact_displacement(
                vin[i, 0], vin[i, 1], vout[i, 0], vout[i, 1], vin[i, 2], s.mu, s.e, contact_time, disp[i]
            )
        new = np.column_stack(
            [out["x"][idx, j] + disp[:, 0], out["y"][idx, j] + disp[:, 1], np.full(idx.size, r), vout, wout]
        )
        keep = vout[:, 2] >= MIN_VZ
        st[idx[keep]] = new[keep]
        t0[idx] = tl + contact_time
        alive = idx[keep]
    return out


__all__ = ["Bounce", "Rally", "bounce_at", "fly_bounces", "fly_bounces_batch", "MODES", "MIN_VZ"]
