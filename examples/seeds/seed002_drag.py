"""Seed 002's drag as printed (eqs 5-7) against drag opposite the velocity (eq 1), on launcher shots.

    .venv/bin/python examples/seeds/seed002_drag.py

Wojcicki, Pucilowski & Kulesza write eq 1 as F_d = -1/2 c_d rho pi r^2 V V (against the velocity) but
its components, eqs 5-7, as m x'' = -1/2 r^2 c_d pi rho V_x dx/dt (and y, z alike). With V_x = dx/dt that
is -k V_x^2 on every axis: it does not change sign with the velocity (a falling ball is pushed down,
a ball going to -y is pushed further to -y) and takes V_x^2 where eq 1 has |V| V_x. This script flies the
same launcher shots both ways with the paper's ball (m = 0.058 kg, r = 0.0333 m; its "0,333 m" read as
the typo it is), tennislab's launcher aero constants (c_d = 0.55, Magnus 1/2 c_l pi r^3 rho omega x V,
c_l = 0.6: eqs 3, 5-7's lift) and air, and prints how far apart their first bounces are.

Shots: from the machine (x = -12.385 m, 1 m up), heading 0, 20-140 km/h (the paper's range) every
20 km/h, elevation -5 to 45 deg every 5 deg, spin 0, +-1000, +-2000, +-3000 rpm (+ topspin); the shots
that land in the far singles court (0 < x < 11.885 m with eq 1's drag), and all of them.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp

from tennislab.core.flight import FlightParams

MASS, RADIUS = 0.058, 0.0333  # seed 002 sec. 3 (r printed "0,333 m")
CD, CL = 0.55, 0.6  # tennislab's launcher2015 defaults (the seed gives no values)
X0, Z0 = -12.385, 1.0  # the launcher's default position (tennislab.launcher.machine) and height


def landing(v0, elevation_deg, spin_rpm, printed: bool, rho: float, g: float) -> float:
    """x [m] of the first bounce (ball centre at z = r) of a shot in the x-z plane."""
    kd = 0.5 * CD * rho * math.pi * RADIUS**2 / MASS
    kl = 0.5 * CL * rho * math.pi * RADIUS**3 / MASS
    w = np.array([0.0, spin_rpm * math.pi / 30.0, 0.0])

    def rhs(_t, s):
        v = s[3:6]
        drag = -kd * v * v if printed else -kd * np.linalg.norm(v) * v  # eqs 5-7 as printed / eq 1
        return np.concatenate([v, drag + kl * np.cross(w, v) + (0.0, 0.0, -g)])

    def ground(_t, s):
        return s[2] - RADIUS

    ground.terminal, ground.direction = True, -1
    e = math.radians(elevation_deg)
    s0 = [X0, 0.0, Z0, v0 * math.cos(e), 0.0, v0 * math.sin(e)]
    sol = solve_ivp(rhs, (0.0, 20.0), s0, rtol=1e-10, atol=1e-10, events=ground)
    return float(sol.y_events[0][0][0])


def main():
    p = FlightParams.from_options(preset="seed002")
    rho, g = p.atmosphere.density, p.atmosphere.gravity
    shots, court = [], []
    for kmh in range(20, 141, 20):
        for elev in range(-5, 46, 5):
            for rpm in (-3000, -2000, -1000, 0, 1000, 2000, 3000):
                right = landing(kmh / 3.6, elev, rpm, False, rho, g)
                shot = (abs(landing(kmh / 3.6, elev, rpm, True, rho, g) - right), kmh, elev, rpm)
                shots.append(shot)
                if 0.0 < right < 11.885:
                    court.append(shot)
    print(f"air {rho} kg/m^3, g {g} m/s^2; first bounce with eqs 5-7 as printed vs eq 1's drag:")
    for name, part in (("in the far singles court", court), ("all", shots)):
        d = np.array([x[0] for x in part])
        worst = max(part)
        print(
            f"  {len(part)} shots {name}: {d.min():.2f} to {d.max():.2f} m apart (median {np.median(d):.2f} m);"
            f" largest at {worst[1]} km/h, elevation {worst[2]} deg, {worst[3]} rpm"
        )


if __name__ == "__main__":
    main()
