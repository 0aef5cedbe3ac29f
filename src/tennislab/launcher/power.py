"""Energy, motor power and start-up time of the roller drive (seed 002 section 7, eqs 18-31, corrected).

Derivation from energy and momentum conservation
-----------------------------------------------
Rollers: solid cylinders, I_r = 1/2 m_r r_r^2 (seed eq 19).  Ball: I_p = a m r^2
(a = 2/3, thin shell, seed eq 21).  The rollers must turn at omega_1, omega_2
(eqs 16-17) at the moment of release; during the throw they give up energy,
so before it they turn faster, at omega_10, omega_20.

Friction impulses: the rollers push the ball with impulses J1, J2 at its
contact points, a distance r_l from its centre.  Momentum and angular momentum
of the ball: m V = J1 + J2 and I_p omega = (J2 - J1) r_l, so::

    J1 = (m V - I_p omega / r_l) / 2,   J2 = (m V + I_p omega / r_l) / 2

Work of roller i, whose surface turns at V_i (eq 14-15 solved: V_{1,2} = V -/+ omega r_l):

* no slip at all (the seed's tacit assumption, a lower bound): the contact
  point of the ball moves on average at V_i / 2 while J_i acts, so
  W_i = J_i V_i / 2, and W_1 + W_2 = 1/2 m V^2 + 1/2 I_p omega^2 = E_ball
  (seed eq 20) exactly;
* the ball starts at rest and slips until it rolls (kinetic friction, the
  roller surface at nearly constant speed): W_i = J_i V_i, i.e. twice the
  ball's energy: half of it is dissipated in the slip.  This is the classic
  result for a body accelerated by a moving belt; we report it as an upper
  bound (``slip=True``).

Speeds before the throw (energy of each roller, replaces seed eqs 22-25)::

    1/2 I_r omega_i0^2 = 1/2 I_r omega_i^2 + W_i   ->   omega_i0 = sqrt(omega_i^2 + 2 W_i / I_r)

Seed eqs 24-25, omega_i0 = omega_i + sqrt(1/2 I_p omega^2), add the square root of
an energy to an angular speed (dimensionally wrong), do not contain the roller
inertia and do not give the "90 rpm" the seed quotes (sqrt(0.94 J) = 0.97,
i.e. 9 rpm if read as rad/s).  Seed eq 23 (omega_10/omega_20 = omega_1/omega_2) is not
needed.  Its eq 26 gives -1/4 (m V^2 + I_p omega^2), half the ball's energy, as "the
work needed to throw the ball": that is one roller's share.  Its eqs 27-29
(start-up work per roller 1/2 I_r omega_i^2 + 1/4 (m V^2 + I_p omega^2)) equal ours with
no slip and no spin.

Power (eqs 30-31): the motor of roller i must restore W_i within the launch
interval t_d: P_d = max_i W_i / t_d (the rating of the busier motor; for no
spin both take half of E_ball, the seed's 45 W at 200 km/h and t_d = 1 s).
Start-up of a motor of constant power P from rest (lossless, no torque limit):
t_r = max_i 1/2 I_r omega_i0^2 / P (seed: 35 s at 45 W).

Roller mass: the seed gives none.  Its 35 s at 45 W imply
I_r = 2 (P t_r - E_ball/2) / omega^2 = 0.0099 kg m^2, i.e. m_r = 2.0 kg for
r_r = 0.1 m; independently, a solid polyurethane wheel (density ~1200 kg/m^3)
of 0.2 m diameter and 50 mm width has 1.9 kg.  Default 2.0 kg (a seed-implied
value, stated as such); t_r scales linearly with m_r (docs/launcher.md).

References
----------
.. [1] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), sec. 7, eqs 18-31
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from tennislab.core.ball import Ball
from tennislab.errors import InputError, check_answer, check_range
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec
from tennislab.launcher.rollers import roller_geometry, roller_speeds, surface_speeds
from tennislab.results import Result
from tennislab.units import RPM

#: Default roller mass [kg] (implied by seed 002's 35 s start-up at 45 W; see module docstring).
DEFAULT_ROLLER_MASS = 2.0
#: Default motor power [W] (seed 002 section 7: "45 W motors").
DEFAULT_MOTOR_POWER = 45.0
#: Default throw time = shortest launch interval [s] (seed 002 sections 2 and 7).
DEFAULT_THROW_TIME = 1.0


@dataclass(frozen=True)
class PowerReport(Result):
    """Energy and power of one throw (SI units)."""

    speed: float  #: V [m/s]
    spin: float  #: omega [rad/s]
    ball_energy: float  #: 1/2 m V^2 + 1/2 I_p omega^2 [J] (eq 20)
    roller_inertia: float  #: I_r [kg m^2] (eq 19)
    impulse: tuple  #: (J1, J2) [N s]
    work: tuple  #: (W1, W2) energy each roller gives up per throw [J]
    omega: tuple  #: roller speeds at release (eqs 16-17) [rad/s]
    omega0: tuple  #: roller speeds before the throw [rad/s]
    startup_energy: tuple  #: 1/2 I_r omega_i0^2 [J]
    throw_time: float  #: t_d [s]
    motor_power: float  #: P [W]
    slip: bool

    @property
    def energy_per_throw(self) -> float:
        return self.work[0] + self.work[1]

    @property
    def throw_power(self) -> float:
        """Power of the busier motor to restore its roller within t_d [W] (eq 30)."""
        return max(self.work) / self.throw_time

    @property
    def startup_time(self) -> float:
        """Start-up time of the slower-starting roller at constant motor power [s] (eq 31)."""
        return max(self.startup_energy) / self.motor_power

    def to_dict(self) -> dict:
        return {
            "energy_per_throw_j": self.energy_per_throw,
            "throw_power_w": self.throw_power,
            "startup_time_s": self.startup_time,
            "throw_power_total_w": self.energy_per_throw / self.throw_time,
            "ball_energy_j": self.ball_energy,
            "roller_work_j": list(self.work),
            "roller_impulse_ns": list(self.impulse),
            "rpm_release": [w / RPM for w in self.omega],
            "rpm_before_throw": [w / RPM for w in self.omega0],
            "rpm_drop": [(a - b) / RPM for a, b in zip(self.omega0, self.omega)],
            "startup_energy_j": list(self.startup_energy),
            "roller_inertia_kgm2": self.roller_inertia,
            "throw_time_s": self.throw_time,
            "motor_power_w": self.motor_power,
            "slip": self.slip,
            "speed_kmh": self.speed * 3.6,
            "spin_rpm": self.spin / RPM,
        }


def power_report(
    speed: float,
    spin: float = 0.0,
    roller_mass: float = DEFAULT_ROLLER_MASS,
    motor_power: float = DEFAULT_MOTOR_POWER,
    throw_time: float = DEFAULT_THROW_TIME,
    spec: MachineSpec = DEFAULT_SPEC,
    ball: Ball | None = None,
    slip: bool = False,
) -> PowerReport:
    """Energy per throw, motor power and start-up time for ball speed V [m/s] and spin omega [rad/s].

    ``roller_mass`` [kg] of each (solid cylinder) roller, ``motor_power`` [W] of
    each motor, ``throw_time`` [s] the time the motor has to restore its roller
    (the launch interval).  ``slip=False``: no-slip lower bound (seed 002);
    ``slip=True``: ball from rest slipping until it rolls (twice the energy).
    """
    ball = ball or Ball()
    check_range("speed", speed, 0.0, 200.0, "m/s", lo_open=True)
    check_range("spin", spin, -1000.0, 1000.0, "rad/s")
    check_range("roller_mass", roller_mass, 0.0, 1000.0, "kg", lo_open=True)
    check_range("motor_power", motor_power, 0.0, 1e6, "W", lo_open=True)
    check_range("throw_time", throw_time, 0.0, 3600.0, "s", lo_open=True)
    g = roller_geometry(spec, ball)
    rl, rr = g.deformed_radius, spec.roller_radius
    i_r = 0.5 * roller_mass * rr**2
    i_p = ball.inertia
    m = ball.mass
    e_ball = 0.5 * m * speed**2 + 0.5 * i_p * spin**2
    j1 = 0.5 * (m * speed - i_p * spin / rl)
    j2 = 0.5 * (m * speed + i_p * spin / rl)
    v1, v2 = (float(v) for v in surface_speeds(speed, spin, rl))
    k = 1.0 if slip else 0.5
    w_1, w_2 = k * j1 * v1, k * j2 * v2
    o1, o2 = (float(w) for w in roller_speeds(speed, spin, rr, rl))
    o10 = math.copysign(math.sqrt(max(o1 * o1 + 2.0 * w_1 / i_r, 0.0)), o1)
    o20 = math.copysign(math.sqrt(max(o2 * o2 + 2.0 * w_2 / i_r, 0.0)), o2)
    e0 = (0.5 * i_r * o10**2, 0.5 * i_r * o20**2)
    for name, v, unit in (
        ("roller_inertia", i_r, "kg m^2"),
        ("rpm_before_throw", max(abs(o10), abs(o20)), "rad/s"),
        ("startup_energy", max(e0), "J"),
        ("startup_time", max(e0) / motor_power, "s"),
        ("throw_power", max(w_1, w_2) / throw_time, "W"),
    ):
        check_answer(name, v, unit)
    if i_r <= 0.0:
        raise InputError("roller_mass: too small: the roller's inertia is 0 (give a mass of a real roller, kg)")
    return PowerReport(
        float(speed),
        float(spin),
        e_ball,
        i_r,
        (j1, j2),
        (w_1, w_2),
        (o1, o2),
        (o10, o20),
        e0,
        float(throw_time),
        float(motor_power),
        bool(slip),
    )
