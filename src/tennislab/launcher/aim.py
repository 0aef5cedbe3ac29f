"""Forward model and inverse aiming of the launcher (Wojcicki, Pucilowski & Kulesza 2010).

Forward: :class:`~.machine.Settings` -> launch state (:func:`~.machine.machine_states`)
-> flight (:func:`tennislab.core.flight.fly_dense` / ``fly_batch``; the ``standard`` physics by
default, ``preset="seed002"`` the paper's eqs 1-7, aero ``launcher2015``) -> first ground contact, net clearance,
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
import warnings
from dataclasses import dataclass, field

import numpy as np

import tennislab.core.shoot as shoot_mod
import tennislab.launcher._search as _search
from tennislab.core.flight import FlightParams, fly_batch, fly_dense
from tennislab.core.launch import spin_axis_angle
from tennislab.core.names import DEFAULT_PRESET
from tennislab.errors import InputError, check_vector
from tennislab.launcher.machine import (
    DEFAULT_SPEC,
    MachineSpec,
    Settings,
    machine_entry,
    machine_states,
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
from tennislab.launcher.reach import MapUse, get_map
from tennislab.launcher.rollers import roller_geometry, roller_speeds
from tennislab.results import Result
from tennislab.units import DEG, KMH, RPM

SOLUTIONS = ("low", "high")


_DEFAULT_PARAMS: list[FlightParams] = []


def launcher_params(preset: str | None = None, **options) -> FlightParams:
    """:class:`FlightParams` of the launcher: *preset* (default :data:`tennislab.core.names.DEFAULT_PRESET`,
    ``standard``, the physics of every command; ``seed002`` the launcher paper's aero ``launcher2015``) and
    *options* on top; without either the one default object (built once: a frozen value, and the key of
    its cached reach map is found at once)."""
    if options or (preset is not None and preset != DEFAULT_PRESET):
        return FlightParams.from_options(preset=DEFAULT_PRESET if preset is None else preset, **options)
    if not _DEFAULT_PARAMS:
        _DEFAULT_PARAMS.append(FlightParams.from_options(preset=DEFAULT_PRESET))
    return _DEFAULT_PARAMS[0]


def fly_settings(settings: Settings, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None, **fly_kw):
    """Forward model for one shot with the reference integrator :func:`tennislab.core.flight.fly_dense`."""
    params = params or launcher_params()
    spec.validate(settings)
    s = settings_states(spec, settings)[0]
    return fly_dense(s[0:3], s[3:6], s[6:9], params, **fly_kw)


def fly_settings_batch(
    spec: MachineSpec, params: FlightParams | None = None, rtol: float = 1e-7, atol: float = 1e-7, **settings_arrays
):
    """Forward model for arrays of settings (keywords of :func:`machine_states`) -> ``FlightTable``."""
    params = params or launcher_params()
    return fly_batch(machine_states(spec, **settings_arrays), params, rtol=rtol, atol=atol)


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
    asked : the settings as asked (height, speed, spin, axis; elevation/heading the exact ones; the
        height NaN when it was searched)
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

    @property
    def height_searched(self) -> bool:
        """True when the height was not given but searched (every step of the machine's range)."""
        return self.asked is not None and math.isnan(self.asked.height_m)

    def deviation(self) -> dict:
        """How far each chosen setting is from what was asked (chosen - asked; spin as a vector too)."""
        a = self.asked or self.settings
        s = self.settings
        return {
            "speed_kmh": s.speed_kmh - a.speed_kmh,
            "spin_rpm": s.spin_rpm - a.spin_rpm,
            "spin_axis_deg": float(wrap_deg(s.spin_axis_deg - a.spin_axis_deg)),
            "spin_vector_rpm": float(spin_change_rpm(s.spin_rpm, s.spin_axis_deg, a.spin_rpm, a.spin_axis_deg)),
            "height_m": None if math.isnan(a.height_m) else s.height_m - a.height_m,
            "elevation_deg": s.elevation_deg - self.exact_elevation_deg,
            "heading_deg": s.heading_deg - self.exact_heading_deg,
        }

    def exact_state(self, spec: MachineSpec | None = None) -> np.ndarray:
        """The launch state (9,) [m, m/s, rad/s] of the continuous solution on machine ``spec``: the asked
        speed, spin and axis at the exact elevation and heading, from the chosen height (the asked one, or
        the one the search chose), for :func:`~tennislab.core.flight.fly_dense` or ``fly_batch``."""
        a = self.asked or self.settings
        e, b = self.exact_elevation_deg, self.exact_heading_deg
        h = self.settings.height_m
        return machine_states(spec or DEFAULT_SPEC, h, a.speed_kmh, e, b, a.spin_rpm, a.spin_axis_deg)[0]

    def to_dict(self, spec: MachineSpec | None = None, params: FlightParams | None = None) -> dict:
        """The JSON of this solution on machine ``spec`` flown with ``params`` (``launcher aim``'s keys,
        below)."""
        return _solution_json(self, spec or DEFAULT_SPEC, params)


def _solution_json(sol: AimSolution, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None) -> dict:
    """The JSON of one aim solution (:meth:`AimSolution.to_dict`; the contract keys of ``launcher aim``).

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
        "asked": {
            k: (None if math.isnan(v) else v)
            for k, v in asked.to_dict().items()
            if k not in ("elevation_deg", "heading_deg")
        },
        "height_searched": sol.height_searched,
        "net_limited": sol.net_limited,
        "deviation": sol.deviation(),
        "machine": machine_entry(spec, sol.position),
        "physics": params.to_dict(),
    }


def rollers_rpm(st: Settings, spec: MachineSpec, params: FlightParams) -> tuple[float, float]:
    """Roller speeds [rpm] for a shot's speed and spin (the paper's eqs 14-17)."""
    g = roller_geometry(spec, params.ball)
    w1, w2 = roller_speeds(st.speed_kmh * KMH, st.spin_rpm * RPM, spec.roller_radius, g.deformed_radius)
    return float(w1) / RPM, float(w2) / RPM


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
    #: how this aim got the machine's reach map (built, read from the cache folder, or kept in memory)
    reach_map: MapUse | None = field(default=None, repr=False)

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
        """The JSON of ``tennislab launcher aim``: :meth:`AimSolution.to_dict`, the request, the other branch."""
        out = self.solution.to_dict(self.spec, self.params)
        out["trajectory"] = self.preferences.trajectory
        out["tolerances"] = self.tolerances.to_dict()
        out["preferences"] = self.preferences.to_dict()
        out["reach_map"] = None if self.reach_map is None else self.reach_map.to_dict()
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
    """Deprecated: ``sol.to_dict()`` (an :class:`AimResult`) or ``sol.to_dict(spec, params)`` (an
    :class:`AimSolution`)."""
    warnings.warn("aim_result_dict(sol) is now sol.to_dict()", DeprecationWarning, stacklevel=2)
    if isinstance(sol, AimResult):
        return sol.to_dict()
    return sol.to_dict(spec, params)


def solution_dict(sol: AimSolution, spec: MachineSpec = DEFAULT_SPEC, params: FlightParams | None = None) -> dict:
    """Deprecated: ``sol.to_dict(spec, params)``."""
    warnings.warn("solution_dict(sol, spec, params) is now sol.to_dict(spec, params)", DeprecationWarning, stacklevel=2)
    return sol.to_dict(spec, params)


def _net_required(spec: MachineSpec, target) -> bool:
    """True when the flight must cross the net (machine and target on opposite halves)."""
    return (spec.position[0] < 0) != (target[0] < 0)


def _fmt(speed, spin, axis, height):
    where = f"height {height:g} m" if isinstance(height, float) else f"any height {height[0]:g}-{height[1]:g} m"
    return f"{speed:g} km/h, {spin:g} rpm, spin axis {axis:g} deg, {where}"


def spin_axis_deg_of(spin_axis) -> float:
    """A spin axis given by name (``topspin``, ``slice``, ...) or in degrees -> degrees."""
    return math.degrees(spin_axis_angle(spin_axis))


def _heights(spec: MachineSpec, params: FlightParams, height_m, prefs: Preferences) -> np.ndarray:
    """The launch heights searched [m]: the asked one (rounded to its step), or every step the ball and the
    apex bound allow."""
    r = params.ball.radius
    if height_m is not None:
        q = spec.height.quantise(spec.height.check("height_m", height_m))
        if q < r:
            raise InputError(f"height_m: {q:g} m is below the ball radius {r:g} m")
        prefs.check_height(q)
        return np.array([q])
    hs = _search._steps(spec.height, spec.height.lo, spec.height.hi)
    hs = hs[hs >= r]
    if prefs.max_apex_m is not None:
        hs = hs[hs <= prefs.max_apex_m]
    if hs.size == 0:
        prefs.check_height(spec.height.lo)
        raise InputError(f"height_m: no launch height of [{spec.height.lo:g}, {spec.height.hi:g}] m holds a ball")
    return hs


def _aim_all(
    target,
    speed_kmh: float | None = None,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float | None = None,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
    *,
    tolerances: Tolerances | None = None,
    preferences: Preferences | None = None,
    speed_ms: float | None = None,
    speed_mph: float | None = None,
):
    """Every aim solution that exists for a target, why the others are missing, and how the reach map was got:
    ``({"low"|"high": AimSolution}, {name: reason}, MapUse)``.

    ``target`` (x, y) [m] on the court; speed [km/h] (or ``speed_ms``/``speed_mph``), spin [rpm],
    spin axis [deg] and height [m] are range-checked (InputError naming the parameter); ``height_m``
    None searches every height step (ties of the miss go to the height nearest 1 m).  Each branch is
    searched on the machine's steps within ``tolerances`` (default 3 km/h, 100 rpm, 10 deg) and must
    meet ``preferences``' bounds (its ``trajectory`` is not applied here: both branches are
    returned).  A solution is missing (with its reason) when no elevation in the range lands there,
    its heading is outside the heading range, it (or every neighbour) hits the net, or no neighbour
    meets the preferences.
    """
    params = params or launcher_params()
    tolerances = tolerances or Tolerances()
    preferences = preferences or Preferences()
    tx, ty = check_vector("target", target, 2)
    asked: dict[str, float] = {
        "speed_kmh": float(speed_in_kmh(spec, speed_kmh, speed_ms, speed_mph)),  # type: ignore[arg-type]
        "spin_rpm": spec.spin.check("spin_rpm", spin_rpm),
        "spin_axis_deg": spec.spin_axis.check("spin_axis_deg", spin_axis_deg),
    }
    heights = _heights(spec, params, height_m, preferences)
    free = height_m is None
    q = {f: spec.range_of(f).quantise(v) for f, v in asked.items()}
    px, py = spec.position
    dx, dy = tx - px, ty - py
    dist = math.hypot(dx, dy)
    desc = _fmt(q["speed_kmh"], q["spin_rpm"], q["spin_axis_deg"], (heights[0], heights[-1]) if free else heights[0])
    if dist < 0.5:
        raise InputError(f"target: ({tx:g}, {ty:g}) m is within 0.5 m of the machine at ({px:g}, {py:g}) m")
    b0 = math.degrees(math.atan2(dy, dx))
    hr = spec.heading
    if not (hr.lo - 10.0 <= b0 <= hr.hi + 10.0):
        raise InputError(
            f"target: ({tx:g}, {ty:g}) m lies at heading {b0:.1f} deg from the machine at "
            f"({px:g}, {py:g}) m, outside the heading range [{hr.lo:g}, {hr.hi:g}] deg"
        )
    ask = _search.Ask(
        (tx, ty),
        asked["speed_kmh"],
        asked["spin_rpm"],
        asked["spin_axis_deg"],
        q["speed_kmh"],
        q["spin_rpm"],
        q["spin_axis_deg"],
        heights,
        free,
        tolerances,
    )
    shoot5 = _search.Shooter(spec, params)
    use = get_map(spec, params)
    rows, flown = _search.rows_of(shoot5, spec, params, use.map, ask)
    reasons = {}
    for name in SOLUTIONS:
        if not rows.on(name).any():
            rows, failed = _search.probe(shoot5, spec, params, ask, name, rows)
            if failed:
                reasons[name] = _missing(name, failed, spec, (tx, ty), dist, desc)
    inside = (rows.b >= hr.lo) & (rows.b <= hr.hi)
    for name in SOLUTIONS:
        heads = rows.b[rows.on(name)]
        if heads.size and not inside[rows.on(name)].any():
            b = float(heads[np.argmin(np.abs(heads))])
            reasons[name] = (
                f"heading: the {name} solution needs {b:.2f} deg, outside the allowed range [{hr.lo:g}, {hr.hi:g}] deg"
            )
    live = rows.take(inside)
    flown = flown.keep(inside)  # its parents index the rows searched
    if not len(live):
        if not reasons:  # pragma: no cover - every missing branch has its reason
            raise InputError(f"target: no shot lands at ({tx:g}, {ty:g}) m with {desc}")
        return {}, reasons, use
    need_net = _net_required(spec, (tx, ty))
    c = _search.search(shoot5, spec, ask, live, flown, need_net, preferences)
    low = live.low[c.row]
    picked: dict[str, tuple[_search.Candidates, int, bool]] = {}
    for name in SOLUTIONS:
        if name in reasons:
            continue
        try:
            on = low if name == "low" else ~low
            picked[name] = _quantised(spec, ask, live, c.take(on), name, need_net, preferences)
        except InputError as exc:
            reasons[name] = str(exc)
    exact = _exact(spec, params, ask, [live[p[0].row[p[1]]] for p in picked.values()])
    out = {name: _solution(spec, ask, name, *p, *e) for (name, p), e in zip(picked.items(), exact)}
    return out, reasons, use


def aim_all(
    target,
    speed_kmh: float | None = None,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float | None = None,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
    *,
    tolerances: Tolerances | None = None,
    preferences: Preferences | None = None,
    speed_ms: float | None = None,
    speed_mph: float | None = None,
):
    """Every aim solution that exists for a target: ``({"low"|"high": AimSolution}, {name: reason})``
    (:func:`_aim_all`, whose docstring says how)."""
    sols, reasons, _ = _aim_all(
        target,
        speed_kmh,
        spin_rpm,
        spin_axis_deg,
        height_m,
        spec,
        params,
        tolerances=tolerances,
        preferences=preferences,
        speed_ms=speed_ms,
        speed_mph=speed_mph,
    )
    return sols, reasons


def _missing(name: str, failed: list, spec: MachineSpec, target, dist: float, desc: str) -> str:
    """Why a branch has no solution, from the real scans of :func:`._search.probe` (one line)."""
    tx, ty = target
    er = spec.elevation
    codes = [int(s.reason[0]) for _, s in failed]
    reach = np.array([s.scan.reach[0] for _, s in failed if s.scan is not None])
    if all(c == shoot_mod.NO_FLIGHT for c in codes) or reach.size == 0:
        return f"target: no shot lands at {desc}"
    if all(c == shoot_mod.TOO_FAR for c in codes):
        return (
            f"target: ({tx:g}, {ty:g}) m is {dist:.2f} m from the machine, beyond its reach "
            f"{np.nanmax(reach[:, 1]):.2f} m at {desc}; raise speed_kmh (max {spec.speed.hi:g})"
        )
    if all(c == shoot_mod.TOO_NEAR for c in codes):
        return (
            f"target: ({tx:g}, {ty:g}) m is {dist:.2f} m from the machine, nearer than its "
            f"shortest flight {np.nanmin(reach[:, 0]):.2f} m at {desc}; lower speed_kmh "
            f"(min {spec.speed.lo:g}) or height_m"
        )
    if name == "low":
        return (
            f"elevation_deg: no low solution within the allowed range [{er.lo:g}, {er.hi:g}] deg: "
            f"even at {er.lo:g} deg the ball flies beyond the target ({desc})"
        )
    return (
        f"elevation_deg: no high (lob) solution within the allowed range [{er.lo:g}, "
        f"{er.hi:g}] deg: even at {er.hi:g} deg the ball flies beyond the target ({desc})"
    )


def _quantised(spec, ask, rows, c, name, need_net, prefs) -> tuple[_search.Candidates, int, bool]:
    """The best flown candidate of a branch (:mod:`._search`): (candidates, its index, net-limited), or
    InputError why not."""
    asked = {"speed_kmh": ask.speed_kmh, "spin_rpm": ask.spin_rpm, "spin_axis_deg": ask.spin_axis_deg}
    ref = _search.REFERENCE_HEIGHT_M if ask.height_free else None
    target = ask.target
    if c.miss_m.size == 0:
        raise InputError(f"target: no {name} flight lands near ({target[0]:g}, {target[1]:g}) m")
    net_ok, pref_ok = _search.acceptable(c, need_net, prefs)
    where = " at any height" if ask.height_free else ""
    if not net_ok.any():
        i = int(np.nanargmin(np.where(np.isfinite(c.miss_m), c.miss_m, np.inf)))
        r = rows[c.row[i]]
        raise InputError(
            f"target: the {name} solution (elevation {r.a:.2f} deg, heading {r.b:.2f} deg) goes "
            f"into the net{where} (clearance {c.clearance_m[i]:.3f} m); try the other solution or another "
            f"speed/spin"
        )
    order = _search.ranking(c, asked, ref)
    i_net = _search.first(order, net_ok)
    r = rows[c.row[i_net]]
    dist = math.hypot(target[0] - spec.position[0], target[1] - spec.position[1])
    bound = 0.5 * spec.elevation.step * abs(r.slope) + 0.5 * math.radians(spec.heading.step) * dist
    near_m = 1.05 * bound + 1e-3
    if c.miss_m[i_net] > near_m:
        # the steps near the exact solution go into the net; the nearest one that clears it is far off
        raise InputError(
            f"target: the {name} solution (elevation {r.a:.2f} deg, heading {r.b:.2f} deg) goes into "
            f"the net at the machine's {spec.elevation.step:g} deg steps{where} (the nearest step "
            f"clearing it lands {c.miss_m[i_net]:.2f} m from the target); try the other solution or "
            f"another speed/spin"
        )
    near = net_ok & (c.miss_m <= near_m)
    i = _search.first(order, pref_ok & near)
    if i < 0:
        what = f"{name} flights to ({target[0]:g}, {target[1]:g}) m"
        raise InputError(prefs.violation(c.apex_z_m[near], c.clearance_m[near], c.flight_time_s[near], what))
    i_any = _search.first(order, c.landed)
    net_limited = bool(need_net and c.miss_m[i] > c.miss_m[i_any] + 0.01)
    return c, i, net_limited


def _solution(spec, ask, name, c, i, net_limited, a, b, bound) -> AimSolution:
    """The :class:`AimSolution` of candidate ``i`` of ``c``, with the exact angles and bound of :func:`_exact`."""
    target = ask.target
    st = Settings(
        float(c.height_m[i]),
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
        a,
        b,
        (float(c.land_x[i]), float(c.land_y[i])),
        float(c.miss_m[i] * 1e3),
        float(c.clearance_m[i]),
        net_result,
        float(c.flight_time_s[i]),
        float(c.apex_z_m[i]),
        float(c.landing_speed_ms[i]),
        float(bound * 1e3),
        tuple(spec.position),
        Settings(math.nan if ask.height_free else st.height_m, ask.speed_kmh, a, b, ask.spin_rpm, ask.spin_axis_deg),
        net_limited,
    )


def _exact(spec: MachineSpec, params: FlightParams, ask, rows: list) -> list[tuple[float, float, float]]:
    """Per row, the exact (continuous) elevation and heading [deg] at the asked speed and spin and the row's
    height (one batched :func:`tennislab.core.shoot.shoot` of every row, from the rows' solutions), and the
    first-order bound [m] of the miss from rounding the two angles alone."""
    if not rows:
        return []
    om = math.radians(ask.spin_axis_deg)
    w = ask.spin_rpm * RPM
    lo, hi = [], []
    for row in rows:
        side = (
            (-0.5 * math.pi, math.radians(row.split))
            if row.branch == "low"
            else (math.radians(row.split), 0.5 * math.pi)
        )
        lo.append(min(side[0], math.radians(row.a)))
        hi.append(max(side[1], math.radians(row.a)))
    s = shoot_mod.shoot(
        [(spec.position[0], spec.position[1], row.height) for row in rows],
        ask.speed_kmh * KMH,
        ask.target,
        params,
        spin=(w * math.cos(om), w * math.sin(om), 0.0),
        start=(np.radians([row.a for row in rows]), np.radians([row.b for row in rows])),
        bounds=(np.array(lo), np.array(hi)),
    )
    dist = math.hypot(ask.target[0] - spec.position[0], ask.target[1] - spec.position[1])
    out = []
    for k, row in enumerate(rows):
        J = s.jacobian[k] * DEG  # [m/deg]
        if not s.converged[k] or not np.isfinite(J).all():
            bound = 0.5 * spec.elevation.step * abs(row.slope) + 0.5 * spec.heading.step * DEG * dist
            out.append((row.a, row.b, bound))
            continue
        a, b = math.degrees(s.elevation[k]), math.degrees(s.heading[k])
        out.append(
            (a, b, 0.5 * spec.elevation.step * np.hypot(*J[:, 0]) + 0.5 * spec.heading.step * np.hypot(*J[:, 1]))
        )
    return out


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
    height_m: float | None = None,
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
    ``topspin``, ``slice``, ``sidespin-left``, or degrees); launch ``height_m`` (as given, rounded to
    its 0.1 m steps; None: searched like the other settings, every step of the machine's range, ties
    of the miss to the height nearest 1 m).  ``trajectory`` ``low`` (default), ``high`` or ``any`` (``solution`` is its
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
    sols, reasons, use = _aim_all(
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
    return AimResult(chosen, sols.get(other_name), reasons.get(other_name, ""), spec, params, tols, prefs, use)


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
