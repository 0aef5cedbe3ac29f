"""Forward model and inverse aiming of the launcher (Wojcicki, Pucilowski & Kulesza 2010).

Forward: :class:`~.machine.Settings` -> launch state (:func:`~.machine.launch_states`)
-> flight (:func:`tennislab.core.flight.fly_dense` / ``fly_batch``; default aero
``launcher2015``, the paper's eqs 1-7) -> first ground contact, net clearance,
trajectory.

Inverse (:func:`aim`, the workflow behind ``tennislab launcher aim``): for a target bounce
point (x, y), an asked ball speed, spin rate, spin axis and launch height, find machine settings
on the machine's steps that land the ball nearest the target.

1. scan the elevation a over the machine's steps at the geometric heading with one
   ``fly_batch`` call; the distance flown along the target direction rises then falls with a,
   so its crossings of the target distance bracket the low (rising branch) and high / lob
   (falling branch) solutions, and its maximum splits the two branches;
2. solve L(a, b) = target in both unknowns by Newton's method with a finite-difference
   Jacobian, safeguarded by the bracket in a (bisection when a step leaves it), to 1e-7 m;
3. search the quantised neighbourhood of every setting jointly (:mod:`._search`): elevation,
   heading, speed within ``speed_tolerance_kmh``, spin vector within ``spin_tolerance_rpm``
   (rate and axis rotation), height as given; keep the candidate nearest the target that clears
   the net and meets the trajectory preferences (:class:`~.preferences.Preferences`).

Unreachable targets and impossible preferences raise :class:`~tennislab.errors.InputError`
saying why, naming the parameter (beyond the reach at that speed, nearer than the shortest
flight, outside the heading range, only into the net, every flight above ``max_apex_m``, ...).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

import tennislab.launcher._search as _search
from tennislab.core.flight import FlightParams, fly_batch, fly_dense
from tennislab.core.launch import spin_axis_angle
from tennislab.errors import InputError, check_vector
from tennislab.launcher.machine import (
    DEFAULT_SPEC,
    MachineSpec,
    Settings,
    launch_states,
    settings_states,
    speed_in_kmh,
)
from tennislab.launcher.preferences import (
    DEFAULT_SPIN_AXIS_TOLERANCE_DEG,
    Preferences,
    Tolerances,
    spin_change_rpm,
    wrap_deg,
)
from tennislab.launcher.rollers import roller_geometry, roller_speeds
from tennislab.results import Result
from tennislab.units import KMH, RPM

#: Tolerances of the aiming integrations (fly_batch); tighter than fly_batch's default so
#: that finite-difference Jacobians are smooth.
AIM_RTOL = 1e-9
AIM_ATOL = 1e-9
SOLUTIONS = ("low", "high")
#: Batches smaller than this are flown on one thread.
PARALLEL_MIN = 4096


def launcher_params(**options) -> FlightParams:
    """:class:`FlightParams` with the launcher's preset (``seed002``: aero ``launcher2015``)."""
    return FlightParams.from_options(preset="seed002", **options)


def fly_settings(settings: Settings, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None, **fly_kw):
    """Forward model for one shot with the reference integrator :func:`tennislab.core.flight.fly_dense`."""
    params = params or launcher_params()
    spec.validate(settings)
    s = settings_states(spec, settings)[0]
    return fly_dense(s[0:3], s[3:6], s[6:9], params, **fly_kw)


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
    solution : ``low`` or ``high`` (lob): the branch of the flight
    target : (x, y) [m]
    settings : the chosen :class:`Settings` (on the machine's steps)
    exact_elevation_deg, exact_heading_deg : the continuous solution at the asked settings [deg]
    landing : (x, y) of the chosen shot's first ground contact [m]
    miss_mm : distance landing - target [mm]
    net_clearance_m : ball bottom above the net cord [m] (NaN if it does not cross x = 0)
    net_result : ``over``, ``net`` or ``none``
    flight_time_s, apex_z_m : time to the bounce [s], highest ball-centre height [m]
    landing_speed_ms : speed at the bounce [m/s]
    quantisation_bound_mm : first-order bound of the miss from rounding a and b alone to
        the nearest step, 1/2 step |dL/da| + 1/2 step |dL/db| [mm]
    position : the machine's (x, y) [m]
    asked : the settings as asked (height, speed, spin, axis; elevation/heading the exact ones)
    net_limited : True when steps nearer the target exist but go into the net
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
    asked: Settings | None = None
    net_limited: bool = False

    def deviation(self) -> dict:
        """How far each chosen setting is from what was asked (chosen - asked; spin as a vector too)."""
        a = self.asked or self.settings
        s = self.settings
        return {
            "speed_kmh": s.speed_kmh - a.speed_kmh,
            "spin_rpm": s.spin_rpm - a.spin_rpm,
            "spin_axis_deg": float(wrap_deg(s.spin_axis_deg - a.spin_axis_deg)),
            "spin_vector_rpm": float(spin_change_rpm(s.spin_rpm, s.spin_axis_deg, a.spin_rpm, a.spin_axis_deg)),
            "height_m": s.height_m - a.height_m,
            "elevation_deg": s.elevation_deg - self.exact_elevation_deg,
            "heading_deg": s.heading_deg - self.exact_heading_deg,
        }

    def to_dict(self, spec: MachineSpec | None = None, params: FlightParams | None = None) -> dict:
        """The JSON of this solution on machine ``spec`` flown with ``params`` (``launcher aim``'s keys,
        :func:`solution_dict`)."""
        return solution_dict(self, spec or DEFAULT_SPEC, params)


def solution_dict(sol: AimSolution, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None) -> dict:
    """The JSON of one aim solution (the contract keys of ``launcher aim``).

    Keys (contract): ``settings.height_m``, ``settings.speed_kmh``, ``settings.elevation_deg``,
    ``settings.heading_deg``, ``settings.spin_rpm``, ``settings.spin_axis_deg``, ``rollers.rpm1``,
    ``rollers.rpm2``, ``landing.x``, ``landing.y``, ``miss_mm``, ``net_clearance_m``; plus
    ``solution``, ``target``, ``exact``, ``flight_time_s``, ``apex_z_m``, ``landing_speed_kmh``,
    ``quantisation_bound_mm``, ``machine``, ``physics``, ``asked``, ``deviation``.
    """
    params = params or launcher_params()
    st = sol.settings
    w1, w2 = rollers_rpm(st, spec, params)
    asked = sol.asked or st
    return {
        "solution": sol.solution,
        "target": {"x": sol.target[0], "y": sol.target[1]},
        "settings": st.to_dict(),
        "rollers": {"rpm1": w1, "rpm2": w2},
        "landing": {"x": sol.landing[0], "y": sol.landing[1]},
        "miss_mm": sol.miss_mm,
        "net_clearance_m": sol.net_clearance_m,
        "net_result": sol.net_result,
        "exact": {"elevation_deg": sol.exact_elevation_deg, "heading_deg": sol.exact_heading_deg},
        "quantisation_bound_mm": sol.quantisation_bound_mm,
        "flight_time_s": sol.flight_time_s,
        "apex_z_m": sol.apex_z_m,
        "landing_speed_kmh": sol.landing_speed_ms / KMH,
        "asked": {k: v for k, v in asked.to_dict().items() if k not in ("elevation_deg", "heading_deg")},
        "net_limited": sol.net_limited,
        "deviation": sol.deviation(),
        "machine": machine_dict(spec, sol.position),
        "physics": params.to_dict(),
    }


def rollers_rpm(st: Settings, spec: MachineSpec, params: FlightParams) -> tuple[float, float]:
    """Roller speeds [rpm] for a shot's speed and spin (the paper's eqs 14-17)."""
    g = roller_geometry(spec, params.ball)
    w1, w2 = roller_speeds(st.speed_kmh * KMH, st.spin_rpm * RPM, spec.roller_radius, g.deformed_radius)
    return float(w1) / RPM, float(w2) / RPM


def machine_dict(spec: MachineSpec, position=None) -> dict:
    return {
        "position": list(spec.position if position is None else position),
        "roller_radius_m": spec.roller_radius,
        "roller_axis_distance_m": spec.roller_axis_distance,
    }


@dataclass(frozen=True)
class AimResult(Result):
    """The answer of :func:`aim`: the chosen solution, the other branch (or why it is missing), the request."""

    solution: AimSolution
    other: AimSolution | None
    other_reason: str
    spec: MachineSpec = field(repr=False)
    params: FlightParams = field(repr=False)
    tolerances: Tolerances
    preferences: Preferences

    @property
    def settings(self) -> Settings:
        return self.solution.settings

    @property
    def landing(self) -> tuple:
        return self.solution.landing

    @property
    def miss_mm(self) -> float:
        return self.solution.miss_mm

    def to_dict(self) -> dict:
        """The JSON of ``tennislab launcher aim`` (:func:`solution_dict` plus the request and the other branch)."""
        out = solution_dict(self.solution, self.spec, self.params)
        out["trajectory"] = self.preferences.trajectory
        out["tolerances"] = self.tolerances.to_dict()
        out["preferences"] = self.preferences.to_dict()
        name = "high" if self.solution.solution == "low" else "low"
        if self.other is not None:
            o = self.other
            out["other_solution"] = {
                "solution": o.solution,
                "elevation_deg": o.settings.elevation_deg,
                "heading_deg": o.settings.heading_deg,
                "speed_kmh": o.settings.speed_kmh,
                "spin_rpm": o.settings.spin_rpm,
                "spin_axis_deg": o.settings.spin_axis_deg,
                "miss_mm": o.miss_mm,
                "net_clearance_m": o.net_clearance_m,
                "apex_z_m": o.apex_z_m,
                "flight_time_s": o.flight_time_s,
            }
        else:
            out["other_solution"] = {"solution": name, "unavailable": self.other_reason}
        return out


def aim_result_dict(sol, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None) -> dict:
    """JSON of an :class:`AimResult` (its ``to_dict()``) or of a bare :class:`AimSolution`."""
    if isinstance(sol, AimResult):
        return sol.to_dict()
    return solution_dict(sol, spec, params)


def _net_required(spec: MachineSpec, target) -> bool:
    """True when the flight must cross the net (machine and target on opposite halves)."""
    return (spec.position[0] < 0) != (target[0] < 0)


def _shooter(spec: MachineSpec, params: FlightParams, height: float):
    """fly(elevation, heading, speed, spin, axis) arrays at a fixed height -> ``FlightTable``."""

    def shoot(elev, head, speed, spin, axis):
        st = launch_states(spec, height, speed, elev, head, spin, axis)
        # threads pay only on large batches: on busy cores a parallel kernel waits for its slowest thread
        return fly_batch(st, params, rtol=AIM_RTOL, atol=AIM_ATOL, parallel=len(st) >= PARALLEL_MIN)

    return shoot


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


def spin_axis_deg_of(spin_axis) -> float:
    """A spin axis given by name (``topspin``, ``slice``, ...) or in degrees -> degrees."""
    return math.degrees(spin_axis_angle(spin_axis))


def aim_all(
    target,
    speed_kmh: float | None = None,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float = 1.0,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
    *,
    tolerances: Tolerances | None = None,
    preferences: Preferences | None = None,
    speed_ms: float | None = None,
    speed_mph: float | None = None,
):
    """Every aim solution that exists for a target: ``({"low"|"high": AimSolution}, {name: reason})``.

    ``target`` (x, y) [m] on the court; speed [km/h] (or ``speed_ms``/``speed_mph``), spin [rpm],
    spin axis [deg] and height [m] are range-checked (InputError naming the parameter).  Each
    branch is searched on the machine's steps within ``tolerances`` (default 3 km/h, 100 rpm) and
    must meet ``preferences``' bounds (its ``trajectory`` is not applied here: both branches are
    returned).  A solution is missing (with its reason) when its exact elevation is outside the
    elevation range, its heading outside the heading range, it (or every neighbour) hits the net,
    or no neighbour meets the preferences.
    """
    params = params or launcher_params()
    tolerances = tolerances or Tolerances()
    preferences = preferences or Preferences()
    tx, ty = check_vector("target", target, 2)
    asked = {
        "speed_kmh": speed_in_kmh(spec, speed_kmh, speed_ms, speed_mph),
        "spin_rpm": spec.spin.check("spin_rpm", spin_rpm),
        "spin_axis_deg": spec.spin_axis.check("spin_axis_deg", spin_axis_deg),
        "height_m": spec.height.check("height_m", height_m),
    }
    q = {f: spec.range_of(f).quantise(v) for f, v in asked.items()}
    if q["height_m"] < params.ball.radius:
        raise InputError(f"height_m: {q['height_m']:g} m is below the ball radius {params.ball.radius:g} m")
    preferences.check_height(q["height_m"])
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
    shoot5 = _shooter(spec, params, q["height_m"])

    def shoot(elev, head):  # the exact solve flies the asked speed, spin and axis (rounded to the steps)
        e = np.asarray(elev, float)
        return shoot5(e, np.asarray(head, float), q["speed_kmh"], q["spin_rpm"], q["spin_axis_deg"])

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
    a_split = float(grid[int(np.nanargmax(np.where(ok, f, -np.inf)))])  # the longest flight splits the branches
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
        limits = (er.lo, a_split) if name == "low" else (a_split, er.hi)
        try:
            out[name] = _quantised(
                shoot5, spec, asked, q, name, (tx, ty), a, b, J, need_net, tolerances, preferences, limits
            )
        except InputError as exc:
            reasons[name] = str(exc)
    return out, reasons


def _quantised(shoot5, spec, asked, q, name, target, a, b, J, need_net, tolerances, prefs, limits) -> AimSolution:
    """The best candidate of the joint search around the exact (a, b) (:mod:`._search`), or InputError why not."""
    c = _search.search(shoot5, spec, target, (a, b), asked, tolerances, limits)
    net_ok, pref_ok = _search.acceptable(c, need_net, prefs)
    bound = 0.5 * spec.elevation.step * np.hypot(*J[:, 0]) + 0.5 * spec.heading.step * np.hypot(*J[:, 1])
    if not net_ok.any():
        i = int(np.nanargmin(np.where(np.isfinite(c.miss_m), c.miss_m, np.inf)))
        raise InputError(
            f"target: the {name} solution (elevation {a:.2f} deg, heading {b:.2f} deg) goes "
            f"into the net (clearance {c.clearance_m[i]:.3f} m); try the other solution or another "
            f"speed/spin"
        )
    i_net = _search.choose(c, asked, (a, b), net_ok)
    near_m = 1.05 * bound + 1e-3
    if c.miss_m[i_net] > near_m:
        # the steps near the exact solution go into the net; the nearest one that clears it is far off
        raise InputError(
            f"target: the {name} solution (elevation {a:.2f} deg, heading {b:.2f} deg) goes into "
            f"the net at the machine's {spec.elevation.step:g} deg steps (the nearest step "
            f"clearing it lands {c.miss_m[i_net]:.2f} m from the target); try the other solution or "
            f"another speed/spin"
        )
    near = net_ok & (c.miss_m <= near_m)
    i = _search.choose(c, asked, (a, b), pref_ok & near)
    if i < 0:
        what = f"{name} flights to ({target[0]:g}, {target[1]:g}) m"
        raise InputError(prefs.violation(c.apex_z_m[near], c.clearance_m[near], c.flight_time_s[near], what))
    i_any = _search.choose(c, asked, (a, b), c.landed)
    net_limited = bool(need_net and c.miss_m[i] > c.miss_m[i_any] + 0.01)
    st = Settings(
        q["height_m"],
        float(c.speed_kmh[i]),
        float(c.elevation_deg[i]),
        float(c.heading_deg[i]),
        float(c.spin_rpm[i]),
        float(c.spin_axis_deg[i]),
    )
    spec.validate(st, require_steps=True)
    net_result = ("none", "over", "net")[int(c.net_status[i])]
    return AimSolution(
        name,
        tuple(map(float, target)),
        st,
        float(a),
        float(b),
        (float(c.land_x[i]), float(c.land_y[i])),
        float(c.miss_m[i] * 1e3),
        float(c.clearance_m[i]),
        net_result,
        float(c.flight_time_s[i]),
        float(c.apex_z_m[i]),
        float(c.landing_speed_ms[i]),
        float(bound * 1e3),
        tuple(spec.position),
        Settings(asked["height_m"], asked["speed_kmh"], float(a), float(b), asked["spin_rpm"], asked["spin_axis_deg"]),
        net_limited,
    )


def pick_solution(sols: dict, reasons: dict, trajectory: str) -> AimSolution:
    """The solution for a trajectory preference (``low``, ``high``, ``any``: the nearer) from :func:`aim_all`."""
    if trajectory == "any":
        if not sols:
            raise InputError("; ".join(reasons[k] for k in SOLUTIONS if k in reasons) or "target: no solution")
        return min(sols.values(), key=lambda s: (round(s.miss_mm, 2), s.solution != "low"))
    if trajectory in sols:
        return sols[trajectory]
    other = [s for s in sols if s != trajectory]
    hint = f" (a {other[0]} solution exists)" if other else ""
    raise InputError(reasons[trajectory] + hint)


def aim(
    target,
    speed_kmh: float | None = None,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float = 1.0,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
    solution: str | None = None,
    *,
    speed_ms: float | None = None,
    speed_mph: float | None = None,
    spin_axis: str | float | None = None,
    trajectory: str | None = None,
    speed_tolerance_kmh: float = 3.0,
    spin_tolerance_rpm: float = 100.0,
    spin_axis_tolerance_deg: float = DEFAULT_SPIN_AXIS_TOLERANCE_DEG,
    max_apex_m: float | None = None,
    net_clearance_m: tuple[float, float] | None = None,
    max_flight_time_s: float | None = None,
) -> AimResult:
    """Machine settings, on the machine's steps, that land a ball nearest a target (the ``launcher aim`` workflow).

    ``target`` (x, y) [m]; the ball speed in km/h (``speed_kmh``), m/s (``speed_ms``) or mph
    (``speed_mph``); ``spin_rpm`` about ``spin_axis_deg`` (or ``spin_axis``: a name such as
    ``topspin``, ``slice``, ``sidespin-left``, or degrees); launch ``height_m`` (as given, on its
    0.1 m steps).  ``trajectory`` ``low`` (default), ``high`` or ``any`` (``solution`` is its
    older name); ``max_apex_m``, ``net_clearance_m`` (MIN, MAX), ``max_flight_time_s`` bound the
    flight; ``speed_tolerance_kmh`` and ``spin_tolerance_rpm`` (0 = exact) how far speed and spin
    may move to land nearer.  Returns an :class:`AimResult`; InputError (naming the parameter)
    when the target cannot be reached or no flight meets the preferences.
    """
    if solution is not None and trajectory is not None and solution != trajectory:
        raise InputError(f"trajectory: {trajectory!r} contradicts solution {solution!r}; give one of them")
    traj = trajectory or solution or "low"
    if solution is not None and solution not in SOLUTIONS:
        raise InputError(f"solution: {solution!r} is not one of {', '.join(SOLUTIONS)}")
    prefs = Preferences(traj, max_apex_m, net_clearance_m, max_flight_time_s)
    tols = Tolerances(speed_tolerance_kmh, spin_tolerance_rpm, spin_axis_tolerance_deg)
    if spin_axis is not None:
        spin_axis_deg = spin_axis_deg_of(spin_axis)
    params = params or launcher_params()
    sols, reasons = aim_all(
        target,
        speed_kmh,
        spin_rpm,
        spin_axis_deg,
        height_m,
        spec,
        params,
        tolerances=tols,
        preferences=prefs,
        speed_ms=speed_ms,
        speed_mph=speed_mph,
    )
    chosen = pick_solution(sols, reasons, traj)
    other_name = "high" if chosen.solution == "low" else "low"
    return AimResult(chosen, sols.get(other_name), reasons.get(other_name, ""), spec, params, tols, prefs)


__all__ = [
    "AimResult",
    "AimSolution",
    "aim",
    "aim_all",
    "pick_solution",
    "aim_result_dict",
    "solution_dict",
    "fly_settings",
    "fly_settings_batch",
    "launcher_params",
    "rollers_rpm",
]
