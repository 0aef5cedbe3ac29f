"""Forward model and inverse aiming of the launcher.

Forward: :class:`~.machine.Settings` -> launch state (:func:`~.machine.launch_states`)
-> flight (:func:`tennislab.core.flight.fly` / ``fly_batch``; default aero
``launcher2015``, seed 002 eqs 1-7) -> first ground contact, net clearance,
trajectory.

Inverse: for a target bounce point (x, y), a ball speed, spin and spin axis and
a launch height, find the elevation a and heading b that land the ball on the
target.  Method:

1. scan a over the machine's elevation steps at the geometric heading with one
   ``fly_batch`` call; the distance flown along the target direction rises then
   falls with a, so its crossings of the target distance bracket the low
   (rising branch) and high / lob (falling branch) solutions;
2. solve L(a, b) = target in both unknowns by Newton's method with a
   finite-difference Jacobian, safeguarded by the bracket in a (bisection
   when a step leaves it), to 1e-7 m;
3. quantise: fly every combination of the elevation and heading steps around
   the exact solution (floor - 1 .. ceil + 1, i.e. up to 4 x 4) and keep the
   one landing closest to the target that clears the net.  Speed, spin, spin
   axis and height are rounded to their steps first.

Unreachable targets raise :class:`~tennislab.errors.InputError` saying why
(beyond the reach at that speed, nearer than the shortest flight, outside the
heading range, only into the net).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from tennislab.core.flight import FlightParams, fly, fly_batch
from tennislab.errors import InputError, check_vector
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec, Settings, launch_states, settings_states
from tennislab.units import KMH, RPM

#: Tolerances of the aiming integrations (fly_batch); tighter than fly_batch's default so
#: that finite-difference Jacobians are smooth.
AIM_RTOL = 1e-9
AIM_ATOL = 1e-9
SOLUTIONS = ("low", "high")


def launcher_params(**options) -> FlightParams:
    """:class:`FlightParams` with the launcher's default aero model ``launcher2015`` (seed 002)."""
    return FlightParams.from_options(preset="seed002", **options)


def fly_settings(settings: Settings, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None, **fly_kw):
    """Forward model for one shot with the reference integrator :func:`tennislab.core.flight.fly`."""
    params = params or launcher_params()
    spec.validate(settings)
    s = settings_states(spec, settings)[0]
    return fly(s[0:3], s[3:6], s[6:9], params, **fly_kw)


def fly_settings_batch(
    spec: MachineSpec, params: FlightParams | None = None, rtol: float = 1e-7, atol: float = 1e-7, **settings_arrays
):
    """Forward model for arrays of settings (keywords of :func:`launch_states`) -> ``FlightTable``."""
    params = params or launcher_params()
    return fly_batch(launch_states(spec, **settings_arrays), params, rtol=rtol, atol=atol)


@dataclass(frozen=True)
class AimSolution:
    """A quantised aim: machine settings, where they land and how far from the target.

    Attributes
    ----------
    solution : ``low`` or ``high`` (lob)
    target : (x, y) [m]
    settings : quantised :class:`Settings`
    exact_elevation_deg, exact_heading_deg : the continuous solution [deg]
    landing : (x, y) of the quantised shot's first ground contact [m]
    miss_mm : distance landing - target [mm]
    net_clearance_m : ball bottom above the net cord [m] (NaN if it does not cross x = 0)
    net_result : ``over``, ``net`` or ``none``
    flight_time_s, apex_z_m : time to the bounce [s], highest ball-centre height [m]
    landing_speed_ms : speed at the bounce [m/s]
    quantisation_bound_mm : first-order bound of the miss from rounding a and b to
        the nearest step, 1/2 step |dL/da| + 1/2 step |dL/db| [mm]
    """

    solution: str
    target: tuple
    settings: Settings
    exact_elevation_deg: float
    exact_heading_deg: float
    landing: tuple
    miss_mm: float
    net_clearance_m: float
    net_result: str
    flight_time_s: float
    apex_z_m: float
    landing_speed_ms: float
    quantisation_bound_mm: float
    position: tuple = field(default=(0.0, 0.0))


def _net_required(spec: MachineSpec, target) -> bool:
    """True when the flight must cross the net (machine and target on opposite halves)."""
    return (spec.position[0] < 0) != (target[0] < 0)


class _Shooter:
    """Fly (a, b) pairs [deg] with fixed speed, spin, axis and height; one fly_batch per call."""

    def __init__(self, spec, params, height, speed, spin, axis):
        self.spec, self.params = spec, params
        self.fixed = dict(height_m=height, speed_kmh=speed, spin_rpm=spin, spin_axis_deg=axis)
        self.calls = 0

    def __call__(self, elev, head):
        self.calls += 1
        st = launch_states(
            self.spec, elevation_deg=np.asarray(elev, float), heading_deg=np.asarray(head, float), **self.fixed
        )
        return fly_batch(st, self.params, rtol=AIM_RTOL, atol=AIM_ATOL)


def _landing(tab):
    xy = np.column_stack([tab["land_x"], tab["land_y"]])
    xy[~tab.ok] = np.nan
    return xy


def _newton(shoot, target, a0, b0, a_lo, a_hi, tol=1e-7, h=1e-3, max_iter=40):
    """Solve landing(a, b) = target; a kept within [a_lo, a_hi] (deg). Returns (a, b, J (2x2, m/deg))."""
    a, b = a0, b0
    tgt = np.asarray(target, float)
    J = None
    for _ in range(max_iter):
        xy = _landing(shoot([a, a + h, a], [b, b, b + h]))
        if np.isnan(xy).any():
            break
        r = xy[0] - tgt
        J = np.column_stack([(xy[1] - xy[0]) / h, (xy[2] - xy[0]) / h])
        if np.hypot(*r) < tol:
            return a, b, J
        try:
            da, db = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            da, db = 0.5 * (a_lo + a_hi) - a, 0.0
        an = a + da
        if not (a_lo <= an <= a_hi):
            an = 0.5 * (a + (a_hi if an > a_hi else a_lo))
        a, b = an, b + float(np.clip(db, -5.0, 5.0))
    xy = _landing(shoot([a], [b]))[0]
    if J is None or np.isnan(xy).any() or np.hypot(*(xy - tgt)) > 1e-4:
        raise InputError(f"target: aiming did not converge for ({target[0]:g}, {target[1]:g}) m")
    return a, b, J


def _fmt(speed, spin, axis, height):
    return f"{speed:g} km/h, {spin:g} rpm, spin axis {axis:g} deg, height {height:g} m"


def aim_all(
    target,
    speed_kmh: float,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float = 1.0,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
):
    """Every aim solution that exists for a target: ``({"low"|"high": AimSolution}, {name: reason})``.

    ``target`` (x, y) [m] on the court; speed [km/h], spin [rpm], spin axis [deg]
    and height [m] are range-checked (InputError naming the field) and rounded
    to the machine's steps.  A solution is missing (with its reason) when its
    exact elevation is outside the elevation range, its heading outside the
    heading range, or it (or every quantised neighbour) hits the net.
    """
    params = params or launcher_params()
    tx, ty = check_vector("target", target, 2)
    q = {
        f: spec.range_of(f).quantise(spec.range_of(f).check(f, v))
        for f, v in (
            ("speed_kmh", speed_kmh),
            ("spin_rpm", spin_rpm),
            ("spin_axis_deg", spin_axis_deg),
            ("height_m", height_m),
        )
    }
    if q["height_m"] < params.ball.radius:
        raise InputError(f"height_m: {q['height_m']:g} m is below the ball radius {params.ball.radius:g} m")
    px, py = spec.position
    dx, dy = tx - px, ty - py
    dist = math.hypot(dx, dy)
    desc = _fmt(q["speed_kmh"], q["spin_rpm"], q["spin_axis_deg"], q["height_m"])
    if dist < 0.5:
        raise InputError(f"target: ({tx:g}, {ty:g}) m is within 0.5 m of the machine at ({px:g}, {py:g}) m")
    b0 = math.degrees(math.atan2(dy, dx))
    hr = spec.heading
    if not (hr.lo - 10.0 <= b0 <= hr.hi + 10.0):
        raise InputError(
            f"target: ({tx:g}, {ty:g}) m lies at heading {b0:.1f} deg from the machine at "
            f"({px:g}, {py:g}) m, outside the heading range [{hr.lo:g}, {hr.hi:g}] deg"
        )
    shoot = _Shooter(spec, params, q["height_m"], q["speed_kmh"], q["spin_rpm"], q["spin_axis_deg"])
    er = spec.elevation
    grid = np.arange(er.lo, er.hi + 0.5 * er.step, er.step)
    xy = _landing(shoot(grid, np.full_like(grid, b0)))
    e = np.array([dx, dy]) / dist
    f = (xy - np.array([px, py])) @ e - dist
    ok = np.isfinite(f)
    if not ok.any():
        raise InputError(f"target: no shot lands at {desc}")
    if np.nanmax(f) < 0:
        raise InputError(
            f"target: ({tx:g}, {ty:g}) m is {dist:.2f} m from the machine, beyond its reach "
            f"{dist + np.nanmax(f):.2f} m at {desc}; raise speed_kmh (max {spec.speed.hi:g})"
        )
    if np.nanmin(f) > 0:
        raise InputError(
            f"target: ({tx:g}, {ty:g}) m is {dist:.2f} m from the machine, nearer than its "
            f"shortest flight {dist + np.nanmin(f):.2f} m at {desc}; lower speed_kmh "
            f"(min {spec.speed.lo:g}) or height_m"
        )
    brackets = {}
    for i in range(len(grid) - 1):
        if not (ok[i] and ok[i + 1]):
            continue
        if f[i] < 0 <= f[i + 1] and "low" not in brackets:
            brackets["low"] = (grid[i], grid[i + 1], f[i], f[i + 1])
        if f[i] >= 0 > f[i + 1]:
            brackets["high"] = (grid[i], grid[i + 1], f[i], f[i + 1])
    reasons = {}
    if "low" not in brackets:
        reasons["low"] = (
            f"elevation_deg: no low solution within the allowed range [{er.lo:g}, {er.hi:g}] deg: "
            f"even at {er.lo:g} deg the ball flies beyond the target ({desc})"
        )
    if "high" not in brackets:
        reasons["high"] = (
            f"elevation_deg: no high (lob) solution within the allowed range [{er.lo:g}, "
            f"{er.hi:g}] deg: even at {er.hi:g} deg the ball flies beyond the target ({desc})"
        )
    need_net = _net_required(spec, (tx, ty))
    out = {}
    for name, (a_lo, a_hi, f_lo, f_hi) in brackets.items():
        a0 = a_lo + (a_hi - a_lo) * f_lo / (f_lo - f_hi)
        # the bracket was found at the geometric heading; a curving ball needs another heading,
        # which shifts the elevation a little: widen the bracket by 3 steps on each side.
        widen = 3 * er.step
        a, b, J = _newton(shoot, (tx, ty), a0, b0, max(er.lo, a_lo - widen), min(er.hi, a_hi + widen))
        if not (hr.lo <= b <= hr.hi):
            reasons[name] = (
                f"heading: the {name} solution needs {b:.2f} deg, outside the allowed range [{hr.lo:g}, {hr.hi:g}] deg"
            )
            continue
        try:
            out[name] = _quantise(shoot, spec, q, name, (tx, ty), a, b, J, need_net)
        except InputError as exc:
            reasons[name] = str(exc)
    return out, reasons


def _quantise(shoot, spec, q, name, target, a, b, J, need_net) -> AimSolution:
    ea = spec.elevation.neighbours(a)
    eb = spec.heading.neighbours(b)
    A, B = np.meshgrid(ea, eb, indexing="ij")
    A, B = A.ravel(), B.ravel()
    tab = shoot(A, B)
    xy = _landing(tab)
    miss = np.hypot(xy[:, 0] - target[0], xy[:, 1] - target[1])
    clr = tab.clearance
    good = np.isfinite(miss)
    if need_net:
        good &= (tab["net_status"] == 1) & (clr >= 0)
    if not good.any():
        a_q, b_q = spec.elevation.quantise(a), spec.heading.quantise(b)
        i = int(np.argmin(np.hypot(A - a_q, B - b_q)))
        raise InputError(
            f"target: the {name} solution (elevation {a:.2f} deg, heading {b:.2f} deg) goes "
            f"into the net (clearance {clr[i]:.3f} m); try the other solution or another "
            f"speed/spin"
        )
    i = int(np.argmin(np.where(good, miss, np.inf)))
    bound = 0.5 * spec.elevation.step * np.hypot(*J[:, 0]) + 0.5 * spec.heading.step * np.hypot(*J[:, 1])
    if miss[i] * 1e3 > 1.05 * bound * 1e3 + 1.0:
        # the steps near the exact solution go into the net; the nearest one that clears it is far off
        raise InputError(
            f"target: the {name} solution (elevation {a:.2f} deg, heading {b:.2f} deg) goes into "
            f"the net at the machine's {spec.elevation.step:g} deg steps (the nearest step "
            f"clearing it lands {miss[i]:.2f} m from the target); try the other solution or "
            f"another speed/spin"
        )
    speed = math.sqrt(tab["land_vx"][i] ** 2 + tab["land_vy"][i] ** 2 + tab["land_vz"][i] ** 2)
    st = Settings(q["height_m"], q["speed_kmh"], float(A[i]), float(B[i]), q["spin_rpm"], q["spin_axis_deg"])
    return AimSolution(
        name,
        tuple(map(float, target)),
        st,
        float(a),
        float(b),
        (float(xy[i, 0]), float(xy[i, 1])),
        float(miss[i] * 1e3),
        float(clr[i]),
        ("none", "over", "net")[int(tab["net_status"][i])],
        float(tab["land_t"][i]),
        float(tab["apex_z"][i]),
        speed,
        float(bound * 1e3),
        tuple(spec.position),
    )


def aim(
    target,
    speed_kmh: float,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float = 1.0,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
    solution: str = "low",
) -> AimSolution:
    """The ``low`` or ``high`` (lob) quantised aim for a target; InputError saying why if it does not exist."""
    if solution not in SOLUTIONS:
        raise InputError(f"solution: {solution!r} is not one of {', '.join(SOLUTIONS)}")
    sols, reasons = aim_all(target, speed_kmh, spin_rpm, spin_axis_deg, height_m, spec, params)
    return pick_solution(sols, reasons, solution)


def pick_solution(sols: dict, reasons: dict, solution: str) -> AimSolution:
    """The named solution from :func:`aim_all`'s result, or InputError with the reason it is missing."""
    if solution in sols:
        return sols[solution]
    other = [s for s in sols if s != solution]
    hint = f" (a {other[0]} solution exists)" if other else ""
    raise InputError(reasons[solution] + hint)


def aim_result_dict(sol: AimSolution, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None) -> dict:
    """The JSON object of ``tennislab launcher aim`` (also used by ``launcher lookup``).

    Keys (contract): ``settings.height_m``, ``settings.speed_kmh``, ``settings.elevation_deg``,
    ``settings.heading_deg``, ``settings.spin_rpm``, ``settings.spin_axis_deg``, ``rollers.rpm1``,
    ``rollers.rpm2``, ``landing.x``, ``landing.y``, ``miss_mm``, ``net_clearance_m``; plus
    ``solution``, ``target``, ``exact``, ``flight_time_s``, ``apex_z_m``, ``landing_speed_kmh``,
    ``quantisation_bound_mm``, ``machine``.
    """
    from tennislab.launcher.rollers import roller_geometry, roller_speeds

    params = params or launcher_params()
    g = roller_geometry(spec, params.ball)
    st = sol.settings
    w1, w2 = roller_speeds(st.speed_kmh * KMH, st.spin_rpm * RPM, spec.roller_radius, g.deformed_radius)
    return {
        "solution": sol.solution,
        "target": {"x": sol.target[0], "y": sol.target[1]},
        "settings": st.as_dict(),
        "rollers": {"rpm1": float(w1) / RPM, "rpm2": float(w2) / RPM},
        "landing": {"x": sol.landing[0], "y": sol.landing[1]},
        "miss_mm": sol.miss_mm,
        "net_clearance_m": sol.net_clearance_m,
        "net_result": sol.net_result,
        "exact": {"elevation_deg": sol.exact_elevation_deg, "heading_deg": sol.exact_heading_deg},
        "quantisation_bound_mm": sol.quantisation_bound_mm,
        "flight_time_s": sol.flight_time_s,
        "apex_z_m": sol.apex_z_m,
        "landing_speed_kmh": sol.landing_speed_ms / KMH,
        "machine": {
            "position": list(sol.position),
            "roller_radius_m": spec.roller_radius,
            "roller_axis_distance_m": spec.roller_axis_distance,
        },
        "physics": {
            "aero": params.aero.name,
            "mass": params.ball.mass,
            "radius": params.ball.radius,
            "air_density": params.atmosphere.density,
            "gravity": params.atmosphere.gravity,
            "wind": list(params.atmosphere.wind),
        },
    }


__all__ = [
    "AimSolution",
    "aim",
    "aim_all",
    "pick_solution",
    "aim_result_dict",
    "fly_settings",
    "fly_settings_batch",
    "launcher_params",
]
