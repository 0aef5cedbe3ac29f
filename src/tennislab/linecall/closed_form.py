"""Seed 001 (Deng 2014, BTAIJ 10(8):2650): the closed-form drop-point model, corrected.

No spin (seed eqs 1-15): rotate the frame so the horizontal velocity is along
x'; drag is split into independent components, m x'' = -k x'^2 and
m z'' = -/+ k z'^2 - m g (k = 1/2 rho C_D A, the seed's f = k v^2), giving

    x'(t) = (m/k) ln(1 + k v0x t / m)                                  (5)
    rising  (t <= t1):  z = h - (m/k) ln[cos a0 / cos(a0 - c t)],       (8)
            a0 = arctan(v0z sqrt(k/(m g))),  c = sqrt(g k / m),
            t1 = a0 / c,  z_max = h - (m/k) ln cos a0                   (9, 10)
    falling (t >= t1):  v_z = -sqrt(m g/k) tanh(c (t - t1))            (11, corrected)
                        z = z_max - (m/k) ln cosh(c (t - t1))           (14, corrected)
    landing at z_land:  T = t1 + arccosh(exp(k (z_max - z_land)/m)) / c (15, corrected)

and the drop point x_t = x0 + x'(T) p/sqrt(p^2+q^2), y_t = y0 + x'(T) q/sqrt(...).

Errors found in the seed (details and numbers in docs/linecall.md):

1. Eq 11 has exp(c (t - t1)) where the solution of m dv/dt = k v^2 - m g needs
   exp(2 c (t - t1)) (v = -sqrt(mg/k) tanh(c (t - t1))); eq 13 also writes the
   prefactor sqrt(kg/m) for sqrt(mg/k).  Eqs 14 and 15 inherit the missing 2:
   the seed's descent is z_max - (2m/k) ln cosh(c (t - t1)/2), which falls
   only half as fast initially (z'' = -g/2 at the apex).
2. Its worked example's numbers do not follow from its own equations: z_max =
   1.0503 m (eq 10 gives 1.0484 m) and the drop point (1.5249, 12.1991): a range
   of 12.29 m, beyond even the drag-free range (8.84 m) of the same launch;
   eq 15 as printed gives 10.66 m, the corrected eq 15 8.16 m.
3. The spin model (eqs 16-29, spin about the vertical axis) drops drag by
   assuming k v0 t << m (eq 25), but k v0 T / m = 0.18 in its own example;
   the vertical motion has no drag at all (eq 16).  Its v0 is the full speed
   used as the horizontal speed; the implied ball mass is 0.2 kg (G/m =
   0.3495 /s with G = 0.0699 kg/s); its printed y(t) has cos 0.3495 for
   cos 0.3495 t.  ``vertical_spin_drop_point(..., drag=True)`` keeps drag:
   with a Magnus force G v normal to v the heading turns at the constant rate
   G/m (eq 21 holds exactly), and the path integrals of eq 23-24 have the
   closed form (v0/beta)[cos c (Ci) + sin c (Si)] in sine/cosine integrals.
4. The paper's transform x' = x cos a + y sin a, y' = x sin a - y cos a is a
   reflection (det -1), its own inverse, so it is applied consistently here;
   the side the ball curves to follows the sign of omega_z (omega x v).

The model lands the ball where its centre reaches ``z_land`` (the seed uses the
ground, 0; tennislab's flight engine uses the ball radius r).

References
----------
.. [1] Deng (2014), BioTechnology: An Indian Journal 10(8):2650 (seed 001)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import sici

from tennislab.errors import InputError, check_range, check_vector
from tennislab.results import OldAsDict


@dataclass(frozen=True)
class DropPoint(OldAsDict):
    """Closed-form drop point: (x, y) [m], flight time t [s], and the model's intermediates."""

    x: float
    y: float
    t: float
    range: float
    t_apex: float
    z_apex: float
    model: str

    def to_dict(self) -> dict:
        return {
            "x": self.x,
            "y": self.y,
            "t": self.t,
            "range": self.range,
            "t_apex": self.t_apex,
            "z_apex": self.z_apex,
            "model": self.model,
        }


def _vertical(h, v0z, m_over_k, g, z_land, paper: bool):
    """(T, t1, z_max) of the seed's vertical motion with quadratic drag (eqs 2, 6-15)."""
    c = math.sqrt(g / m_over_k)  # sqrt(g k / m)
    vt = math.sqrt(g * m_over_k)  # terminal speed sqrt(m g / k)
    if v0z >= 0:
        a0 = math.atan(v0z / vt)
        t1 = a0 / c
        zmax = h - m_over_k * math.log(math.cos(a0))
    else:
        if -v0z >= vt:
            raise InputError(
                f"velocity z: descending at {-v0z:g} m/s, faster than the terminal speed "
                f'{vt:g} m/s of the closed form (use method="numeric")'
            )
        t1 = -math.atanh(-v0z / vt) / c  # virtual apex before t = 0
        zmax = h + m_over_k * math.log(math.cosh(c * t1))
    if zmax < z_land:
        raise InputError(f"position z: the ball never reaches the landing height {z_land:g} m")
    if paper:  # eq 15 as printed
        E = math.exp(-(zmax - z_land) / m_over_k)
        T = t1 + math.log((2.0 - E + 2.0 * math.sqrt(1.0 - E)) / E) / c
    else:
        T = t1 + math.acosh(math.exp((zmax - z_land) / m_over_k)) / c
    return T, t1, zmax


def no_spin_drop_point(
    position, velocity, m_over_k: float, g: float = 9.80665, z_land: float = 0.0, paper: bool = False
) -> DropPoint:
    """Seed 001 eqs 1-15 with the coordinate rotation: drop point of a non-spinning ball.

    position [m], velocity [m/s] (3-vectors); m_over_k = m / k [m] with the
    seed's drag f = k v^2 (k = 1/2 rho C_D A [kg/m]); g [m/s^2]; z_land: height
    of the ball centre at landing [m]; ``paper=True`` uses eq 15 as printed.
    """
    x0, y0, h = check_vector("position", position)
    vx, vy, vz = check_vector("velocity", velocity)
    mk = check_range("m_over_k", m_over_k, 0.0, None, "m", lo_open=True)
    g = check_range("gravity", g, 0.0, None, "m/s^2", lo_open=True)
    vh = math.hypot(vx, vy)
    T, t1, zmax = _vertical(h, vz, mk, g, z_land, paper)
    rng = mk * math.log(1.0 + vh * T / mk)
    ux, uy = (vx / vh, vy / vh) if vh > 0 else (1.0, 0.0)
    return DropPoint(x0 + rng * ux, y0 + rng * uy, T, rng, t1, zmax, "seed001-eq15" + ("-paper" if paper else ""))


def vertical_spin_drop_point(
    position, velocity, m_over_k: float, g_over_m: float, g: float = 9.80665, z_land: float = 0.0, drag: bool = True
) -> DropPoint:
    """Seed 001 eqs 16-29: spin about the vertical axis, Magnus force G v in the horizontal plane.

    g_over_m = G/m [1/s], signed: > 0 turns the heading counter-clockwise (to the
    left, +y for a ball moving +x; omega_z > 0).  ``drag=False`` is the seed's
    version (eqs 25-28: no drag at all, vertical motion in vacuum, eq 16);
    ``drag=True`` keeps horizontal drag (eq 19 with the exact turning of eq 21)
    and the corrected vertical motion of eqs 7-15.
    """
    x0, y0, h = check_vector("position", position)
    vx, vy, vz = check_vector("velocity", velocity)
    mk = check_range("m_over_k", m_over_k, 0.0, None, "m", lo_open=True)
    om = float(g_over_m)
    vh = math.hypot(vx, vy)
    if drag:
        T, t1, zmax = _vertical(h, vz, mk, g, z_land, paper=False)
    else:  # eq 16: z = h + v0z t - g t^2/2
        disc = vz * vz + 2.0 * g * (h - z_land)
        if disc < 0:
            raise InputError(f"position z: the ball never reaches the landing height {z_land:g} m")
        T = (vz + math.sqrt(disc)) / g
        t1 = max(vz / g, 0.0)
        zmax = h + max(vz, 0.0) ** 2 / (2 * g)
    xp, yp = _turning_path(vh, mk if drag else math.inf, om, T)
    ux, uy = (vx / vh, vy / vh) if vh > 0 else (1.0, 0.0)
    # heading frame -> court frame (x' along the heading, y' to its left)
    x = x0 + xp * ux - yp * uy
    y = y0 + xp * uy + yp * ux
    return DropPoint(x, y, T, math.hypot(xp, yp), t1, zmax, "seed001-eq29" + ("-drag" if drag else ""))


def _turning_path(v0: float, m_over_k: float, om: float, t: float):
    """(x', y') at time t of a path with speed v0/(1 + beta t), beta = v0 k/m, heading om t."""
    if not math.isfinite(m_over_k):  # seed eqs 27-28 (no drag)
        if om == 0:
            return v0 * t, 0.0
        return v0 / om * math.sin(om * t), v0 / om * (1.0 - math.cos(om * t))
    beta = v0 / m_over_k
    if om == 0 or beta == 0:
        return m_over_k * math.log1p(beta * t), 0.0
    c = abs(om) / beta
    u1 = 1.0 + beta * t
    s1, c1 = sici(c * u1)
    s0, c0 = sici(c)
    dci, dsi = c1 - c0, s1 - s0
    xp = v0 / beta * (math.cos(c) * dci + math.sin(c) * dsi)
    yp = v0 / beta * (math.cos(c) * dsi - math.sin(c) * dci)
    return xp, math.copysign(yp, om)


def closed_form_from_physics(position, velocity, spin, params, z_land: float | None = None) -> DropPoint:
    """The seed-001 closed form with constants from tennislab physics.

    k = 1/2 rho A C_D with C_D of the aero model at the launch speed and spin
    (so m/k = 1/(params.k C_D)); G/m = params.k C_L |v0| signed by omega_z.
    Spin must be about the vertical axis (the seed's eqs 16-29); wind must be 0.
    """
    v = np.array(check_vector("velocity", velocity))
    w = np.array(check_vector("spin", spin))
    if np.hypot(w[0], w[1]) > 1e-9 * max(1.0, abs(w[2])):
        raise InputError(
            'spin: the closed form (seed 001 eqs 16-29) handles spin about the vertical axis only; use method="numeric"'
        )
    if any(params.atmosphere.wind):
        raise InputError('wind: the closed form assumes still air (seed 001); use method="numeric"')
    speed = float(np.linalg.norm(v))
    cd, cl = params.aero.coefficients(speed, abs(w[2]), params.ball.radius)
    k = params.k
    mk = 1.0 / (k * cd)
    g = params.atmosphere.gravity
    zl = params.ball.radius if z_land is None else z_land
    if w[2] == 0:
        return no_spin_drop_point(position, v, mk, g, zl)
    return vertical_spin_drop_point(position, v, mk, math.copysign(k * cl * speed, w[2]), g, zl, drag=True)


# ------------------------------------------------------------------ the seed's worked example
#: Constants of the seed's worked example, read back from its printed equations:
#: x = 50.226 ln(0.3130 t + 1) -> m/k = 50.226 m, v0x = 0.3130 * 50.226 m/s;
#: arctan 0.0439 -> v0z = 0.0439 sqrt(m g / k); 0.4417 = sqrt(g k / m) with g = 9.8;
#: launch at (0, 0, 1) toward (p, q) = (2, 16) (its cos a = 2/sqrt 260, and its
#: drop points lie on y/x = 8); spin example: G/m = 0.3495 /s, v0 = 15.75 m/s.
SEED001_EXAMPLE: dict[str, Any] = {
    "m_over_k": 50.226,
    "g": 9.8,
    "h": 1.0,
    "pq": (2.0, 16.0),
    "v0x": 0.3130 * 50.226,
    "v0z": 0.0439 * math.sqrt(50.226 * 9.8),
    "g_over_m": 0.3495,
    "v0_spin": 15.75,
    "v0z_spin": 0.975,
    "published": {
        "t1": 0.0993,
        "z_max": 1.0503,
        "drop": (1.5249, 12.1991),
        "T_spin": 0.5621,
        "drop_spin": (1.9474, 8.6042),
    },
}


def seed001_example() -> dict:
    """Recompute the seed's worked examples: published vs the seed's own equations vs corrected."""
    ex = SEED001_EXAMPLE
    p, q = ex["pq"]
    n = math.hypot(p, q)
    vel = (ex["v0x"] * p / n, ex["v0x"] * q / n, ex["v0z"])
    pos = (0.0, 0.0, ex["h"])
    fixed = no_spin_drop_point(pos, vel, ex["m_over_k"], ex["g"], 0.0)
    printed = no_spin_drop_point(pos, vel, ex["m_over_k"], ex["g"], 0.0, paper=True)
    vs = (ex["v0_spin"] * p / n, ex["v0_spin"] * q / n, ex["v0z_spin"])
    # The seed turns toward -y' in its reflected frame, i.e. clockwise seen from above (to +x here).
    spin_seed = vertical_spin_drop_point(pos, vs, ex["m_over_k"], -ex["g_over_m"], ex["g"], 0.0, drag=False)
    spin_drag = vertical_spin_drop_point(pos, vs, ex["m_over_k"], -ex["g_over_m"], ex["g"], 0.0, drag=True)
    vac_T = (vel[2] + math.sqrt(vel[2] ** 2 + 2 * ex["g"] * ex["h"])) / ex["g"]
    return {
        "published": ex["published"],
        "corrected": fixed.to_dict(),
        "seed_equations": printed.to_dict(),
        "vacuum_range": ex["v0x"] * vac_T,
        "spin_seed": spin_seed.to_dict(),
        "spin_with_drag": spin_drag.to_dict(),
    }


def closed_form_study(
    params=None,
    speeds=(10.0, 15.0, 20.0, 30.0, 45.0),
    angles_deg=(-6.0, 0.0, 5.0, 15.0, 30.0),
    spins=(0.0, 150.0),
    height: float = 1.0,
) -> list[dict]:
    """Drop-point error of the closed form over a grid, against :func:`~tennislab.core.flight.fly_dense`.

    Shots start at (-11.885, 0, height) toward +x with the given speeds [m/s],
    elevation angles [deg] and spins about the vertical axis [rad/s]; the same
    physics (``params``, default tennislab's: :data:`~tennislab.core.aero.DEFAULT_AERO`) drives both.
    Returns one row per shot: range of the numerical flight [m], error [m] and
    relative error.
    """
    from tennislab.core.flight import FlightParams, fly_dense

    params = params or FlightParams()
    rows = []
    for v in speeds:
        for a in angles_deg:
            for w in spins:
                vel = (v * math.cos(math.radians(a)), 0.0, v * math.sin(math.radians(a)))
                pos = (-11.885, 0.0, height)
                tr = fly_dense(pos, vel, (0.0, 0.0, w), params)
                if tr.landing is None:
                    continue
                try:
                    dp = closed_form_from_physics(pos, vel, (0.0, 0.0, w), params)
                except InputError:
                    continue
                rng = math.hypot(tr.landing.x - pos[0], tr.landing.y - pos[1])
                err = math.hypot(dp.x - tr.landing.x, dp.y - tr.landing.y)
                rows.append(
                    {
                        "speed": v,
                        "angle_deg": a,
                        "spin_z": w,
                        "range": rng,
                        "error": err,
                        "rel_error": err / rng,
                        "t_error": dp.t - tr.landing.t,
                    }
                )
    return rows
