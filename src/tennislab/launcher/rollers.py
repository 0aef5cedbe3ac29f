"""The ball between two counter-rotating rollers (seed 002 sections 4 and 6, eqs 8-17).

Geometry (seed 002 Figs 5, 6, 14): rollers of radius r_r whose axes are d_sr
apart leave a gap g = d_sr - 2 r_r (0.05 m for the seed's 0.1 m / 0.25 m).  A
ball of radius r > g/2 is squeezed to the deformed radius r_l = g/2 (0.025 m)
at the nip, i.e. its diameter shrinks by dl = 2 r - g (17 mm for r = 33.5 mm).

Roller speeds (eqs 14-17): the ball leaves the nip with the mean of the two
surface speeds and spins with half their difference over r_l::

    V = (V1 + V2) / 2                    (14)
    omega r_l = (V2 - V1) / 2            (15)
    omega_1 = (V - omega r_l) / r_r      (16)
    omega_2 = 2 V / r_r - omega_1        (17)

So roller 2 is the faster one for positive spin: it is the roller on the side
of the ball's axis u (mechanism rotated by the spin-axis angle; above the ball
for topspin, see :mod:`.machine`).  Seed inconsistency: its text after eq 17
quotes "omega_1 = 5800 rpm and omega_2 = 4800 rpm" for 200 km/h and 2000 rpm,
but eq 16 gives omega_1 = 4805 rpm and eq 17 omega_2 = 5805 rpm: the text
swaps the two.  We follow the equations.

Pull-in (eqs 8-11, after Wusatowski 1960): the ball is drawn in when the grab
angle lambda does not exceed the friction angle eta = atan(mu).  lambda is the
angle at a roller axis between the plane of both axes and the line to the first
contact, where the undeformed ball touches both rollers:
cos(lambda) = (d_sr / 2) / (r_r + r)  (20.5 deg for the seed's geometry).

Throw without slip (eqs 12-13): the friction of both rollers must supply the
ball's inertia force.  Seed eq 12 reads ``F_w >= 2T``, the reverse of its own
sentence ("the friction force ... should be equal or greater than the inertia
force"): the condition is ``2 T >= F_w``.  Eq 13: N = E s dl / (2 r) with the
ball's Young's modulus E, contact area s and deformation dl (the seed's
definition of E from flat-plate tests, section 5.1).  The seed does not say how
to get F_w: we take a uniform acceleration from rest to V over the path of the
ball centre from first contact to the nip, L = (r_r + r) sin(lambda) (4.7 cm),
because eqs 14-15 use the deformed radius r_l, i.e. the ball must roll without
slip by the time it reaches the nip: F_w = m V^2 / (2 L).  This is a modelling
choice (documented in docs/launcher.md), not a seed value.

References
----------
.. [1] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), sec. 4 and 6, eqs 8-17
.. [2] Wusatowski (1960), as quoted by seed 002 (pull-in)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.core.ball import Ball
from tennislab.errors import InputError, check_range
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec
from tennislab.launcher.materials import SEED_CONTACT_AREA  # 2.12 cm^2 implied by seed Tables 1-2
from tennislab.results import Result
from tennislab.units import RPM

#: Ball Young's modulus adopted by seed 002 (section 5.1, mean of its Table 2) [Pa].
SEED_YOUNG_MODULUS = 4.20e6
#: Ball-roller friction coefficient adopted by seed 002 (Table 3, roller segment, 35 mm contact) [-].
SEED_FRICTION = 2.05


@dataclass(frozen=True)
class RollerGeometry:
    """Deformation of a ball of radius ``ball_radius`` [m] between the machine's rollers.

    Attributes: gap [m], deformed_radius r_l [m], deformation dl [m], grab_angle lambda [rad],
    entry_length L (ball-centre path from first contact to the nip) [m].
    """

    roller_radius: float
    axis_distance: float
    ball_radius: float
    gap: float
    deformed_radius: float
    deformation: float
    grab_angle: float
    entry_length: float


def roller_geometry(spec: MachineSpec = DEFAULT_SPEC, ball: Ball | None = None) -> RollerGeometry:
    """Gap, deformed radius r_l, deformation dl and grab angle lambda (seed 002 Figs 5, 6, 14)."""
    ball = ball or Ball()
    rr, d, r = spec.roller_radius, spec.roller_axis_distance, ball.radius
    gap = d - 2.0 * rr
    if gap <= 0:
        raise InputError(f"roller_axis_distance: {d:g} m must exceed twice the roller radius {2 * rr:g} m")
    if gap >= 2.0 * r:
        raise InputError(
            f"roller_axis_distance: gap {gap:g} m between the rollers is not smaller than the "
            f"ball diameter {2 * r:g} m; the rollers cannot grip the ball "
            f"(allowed gap (0, {2 * r:g}) m)"
        )
    cos_l = (d / 2.0) / (rr + r)
    lam = math.acos(cos_l)
    return RollerGeometry(rr, d, r, gap, gap / 2.0, 2.0 * r - gap, lam, (rr + r) * math.sin(lam))


def roller_speeds(speed, spin, roller_radius: float, deformed_radius: float):
    """Roller angular speeds (omega_1, omega_2) [rad/s] for ball speed V [m/s] and spin omega [rad/s].

    Seed 002 eqs 16-17: omega_1 = (V - omega r_l) / r_r, omega_2 = 2 V / r_r - omega_1.
    Arrays broadcast.
    """
    v = np.asarray(speed, dtype=float)
    w = np.asarray(spin, dtype=float)
    w1 = (v - w * deformed_radius) / roller_radius
    w2 = 2.0 * v / roller_radius - w1
    return w1, w2


def surface_speeds(speed, spin, deformed_radius: float):
    """Roller circumferential speeds (V1, V2) [m/s] (seed 002 eqs 14-15 solved for V1, V2)."""
    v = np.asarray(speed, dtype=float)
    w = np.asarray(spin, dtype=float)
    return v - w * deformed_radius, v + w * deformed_radius


def ball_from_rollers(omega_1, omega_2, roller_radius: float, deformed_radius: float):
    """Ball speed V [m/s] and spin omega [rad/s] from roller speeds (seed 002 eqs 14-15)."""
    v1 = np.asarray(omega_1, dtype=float) * roller_radius
    v2 = np.asarray(omega_2, dtype=float) * roller_radius
    return (v1 + v2) / 2.0, (v2 - v1) / (2.0 * deformed_radius)


@dataclass(frozen=True)
class RollerReport(Result):
    """Roller speeds and the pull-in and no-slip checks for one throw (SI units, rpm where named)."""

    speed: float  #: ball speed V [m/s]
    spin: float  #: ball spin omega [rad/s]
    geometry: RollerGeometry
    omega_1: float  #: roller 1 (slower for positive spin) [rad/s]
    omega_2: float  #: roller 2 [rad/s]
    surface_1: float  #: V1 [m/s]
    surface_2: float  #: V2 [m/s]
    friction: float  #: mu [-]
    friction_angle: float  #: eta = atan(mu) [rad]
    pulls_in: bool  #: lambda <= eta (eq 11)
    young_modulus: float  #: E [Pa]
    contact_area: float  #: s [m^2]
    normal_force: float  #: N = E s dl / (2 r) [N] (eq 13)
    friction_force: float  #: T = mu N [N]
    inertia_force: float  #: F_w = m V^2 / (2 L) [N]
    throws: bool  #: 2 T >= F_w (eq 12, corrected direction)
    max_no_slip_speed: float  #: largest V with 2 T >= F_w [m/s]

    @property
    def rpm1(self) -> float:
        return self.omega_1 / RPM

    @property
    def rpm2(self) -> float:
        return self.omega_2 / RPM

    def to_dict(self) -> dict:
        g = self.geometry
        return {
            "rpm1": self.rpm1,
            "rpm2": self.rpm2,
            "surface_speed1_ms": self.surface_1,
            "surface_speed2_ms": self.surface_2,
            "grab_angle_deg": math.degrees(g.grab_angle),
            "friction_angle_deg": math.degrees(self.friction_angle),
            "friction": self.friction,
            "pulls_in": self.pulls_in,
            "deformed_radius_m": g.deformed_radius,
            "deformation_m": g.deformation,
            "gap_m": g.gap,
            "entry_length_m": g.entry_length,
            "young_modulus_pa": self.young_modulus,
            "contact_area_m2": self.contact_area,
            "normal_force_n": self.normal_force,
            "friction_force_n": self.friction_force,
            "inertia_force_n": self.inertia_force,
            "throws": self.throws,
            "max_no_slip_speed_kmh": self.max_no_slip_speed * 3.6,
            "speed_kmh": self.speed * 3.6,
            "spin_rpm": self.spin / RPM,
        }


def roller_report(
    speed: float,
    spin: float = 0.0,
    spec: MachineSpec = DEFAULT_SPEC,
    ball: Ball | None = None,
    friction: float = SEED_FRICTION,
    young_modulus: float = SEED_YOUNG_MODULUS,
    contact_area: float = SEED_CONTACT_AREA,
) -> RollerReport:
    """Roller speeds (eqs 14-17), pull-in (eqs 8-11) and no-slip (eqs 12-13) for V [m/s], omega [rad/s].

    Defaults: mu = 2.05 and E = 4.2 MPa (the values seed 002 adopts), s = 2.12 cm^2
    (implied by its Tables 1-2).  A throw with V - omega r_l < 0 would need roller 1
    to turn backwards; that is allowed (reported as a negative rpm).
    """
    ball = ball or Ball()
    check_range("speed", speed, 0.0, 200.0, "m/s", lo_open=True)
    check_range("spin", spin, -1000.0, 1000.0, "rad/s")
    check_range("friction", friction, 0.0, 100.0, lo_open=True)
    check_range("young_modulus", young_modulus, 0.0, 1e11, "Pa", lo_open=True)
    check_range("contact_area", contact_area, 0.0, 0.01, "m^2", lo_open=True)
    g = roller_geometry(spec, ball)
    w1, w2 = roller_speeds(speed, spin, spec.roller_radius, g.deformed_radius)
    v1, v2 = surface_speeds(speed, spin, g.deformed_radius)
    eta = math.atan(friction)
    n = young_modulus * contact_area * g.deformation / (2.0 * ball.radius)
    t = friction * n
    fw = ball.mass * speed**2 / (2.0 * g.entry_length)
    vmax = math.sqrt(2.0 * t * 2.0 * g.entry_length / ball.mass)
    return RollerReport(
        float(speed),
        float(spin),
        g,
        float(w1),
        float(w2),
        float(v1),
        float(v2),
        float(friction),
        eta,
        bool(g.grab_angle <= eta),
        float(young_modulus),
        float(contact_area),
        n,
        t,
        fw,
        bool(2.0 * t >= fw),
        vmax,
    )
