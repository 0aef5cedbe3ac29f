"""Any target at once: the launch angles for a target from the machine's reach map, refined on the real kernel.

A controller asks "which elevation and heading land this speed and spin there" for any target, and
wants the answer at once, without the 3 x 10^13-setting table of every machine step.  The reach map
(:mod:`tennislab.launcher.reach`, a Chebyshev fit of where every setting lands) inverts in
microseconds to within a few hundredths of a degree (0.024 deg at the 95th percentile,
docs/launcher.md); one Newton step on the compiled batch kernel
(:func:`tennislab.core.shoot.shoot` started there: three flights, and one more that checks it)
removes that error.  The answer is the continuous elevation and heading (what a machine with fine
steps dials, and where :func:`tennislab.launcher.aim.aim` starts its search on the machine's
steps) and where the checked flight lands.

References
----------
Wojcicki, Pucilowski & Kulesza (2010), Mathematical analysis for a new tennis ball launcher,
Acta Mech. Autom. 4(4) (seed 002: "the database of different possible hits ... implemented in the
control system").
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

import tennislab.core.shoot as shoot_mod
from tennislab.core.flight import FlightParams
from tennislab.errors import InputError, check_vector
from tennislab.launcher.aim import launcher_params, machine_entry
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec, speed_in_kmh
from tennislab.launcher.preferences import TRAJECTORIES
from tennislab.launcher.reach import MapUse, get_map
from tennislab.results import Result
from tennislab.units import DEG, KMH, RPM

#: Newton steps on the real kernel after the map's guess (one brings it from ~cm to ~um)
NEWTON_STEPS = 1
#: [m] a refined answer farther than this from the target gets more Newton steps (up to 6 more): the
#: map is fitted without wind, so a windy flight can start centimetres to decimetres off
REFINE_MISS_M = 0.02


@dataclass(frozen=True)
class InverseResult(Result):
    """The angles for a target (``to_dict()``: ``settings`` with the continuous ``elevation_deg`` and
    ``heading_deg``, ``landing``, ``miss_mm`` of the checked flight, the map's guess, the time, and
    ``reach_map``: whether this call built the map, read it from the cache folder or reused it from
    memory, what the call spent on it and what its fit cost, :class:`~.reach.MapUse`)."""

    solution: str
    target: tuple
    height_m: float
    speed_kmh: float
    spin_rpm: float
    spin_axis_deg: float
    elevation_deg: float
    heading_deg: float
    map_elevation_deg: float
    map_heading_deg: float
    landing: tuple
    miss_mm: float
    flight_time_s: float
    apex_z_m: float
    net_clearance_m: float
    elapsed_ms: float
    flights: int
    spec: MachineSpec = field(repr=False)
    params: FlightParams = field(repr=False)
    reach_map: MapUse | None = field(default=None, repr=False)

    def to_dict(self) -> dict:
        return {
            "solution": self.solution,
            "target": {"x": self.target[0], "y": self.target[1]},
            "settings": {
                "height_m": self.height_m,
                "speed_kmh": self.speed_kmh,
                "elevation_deg": self.elevation_deg,
                "heading_deg": self.heading_deg,
                "spin_rpm": self.spin_rpm,
                "spin_axis_deg": self.spin_axis_deg,
            },
            "on_steps": False,
            "map": {"elevation_deg": self.map_elevation_deg, "heading_deg": self.map_heading_deg},
            "landing": {"x": self.landing[0], "y": self.landing[1]},
            "miss_mm": self.miss_mm,
            "flight_time_s": self.flight_time_s,
            "apex_z_m": self.apex_z_m,
            "net_clearance_m": self.net_clearance_m,
            "elapsed_ms": self.elapsed_ms,
            "flights": self.flights,
            "reach_map": None if self.reach_map is None else self.reach_map.to_dict(),
            "machine": machine_entry(self.spec),
            "physics": self.params.to_dict(),
        }


def inverse_aim(
    target,
    speed_kmh: float | None = None,
    spin_rpm: float = 0.0,
    spin_axis_deg: float = 0.0,
    height_m: float = 1.0,
    spec: MachineSpec = DEFAULT_SPEC,
    params: FlightParams | None = None,
    *,
    trajectory: str = "low",
    speed_ms: float | None = None,
    speed_mph: float | None = None,
    newton_steps: int = NEWTON_STEPS,
) -> InverseResult:
    """The continuous elevation and heading that land the asked launch on ``target`` (module docstring).

    ``target`` (x, y) [m]; speed [km/h] (or ``speed_ms``/``speed_mph``), spin [rpm] about
    ``spin_axis_deg``, launch ``height_m`` [m], all range-checked; ``trajectory`` ``low``, ``high``
    or ``any`` (the low one if it exists).  InputError (naming the parameter) when the map finds no
    such flight or the refined flight does not land.
    """
    t0 = time.perf_counter()
    params = params or launcher_params()
    if trajectory not in TRAJECTORIES:
        raise InputError(f"trajectory: {trajectory!r} is not one of {', '.join(TRAJECTORIES)}")
    tx, ty = check_vector("target", target, 2)
    v = float(speed_in_kmh(spec, speed_kmh, speed_ms, speed_mph))  # type: ignore[arg-type]
    w = spec.spin.check("spin_rpm", spin_rpm)
    g = spec.spin_axis.check("spin_axis_deg", spin_axis_deg)
    h = spec.height.check("height_m", height_m)
    if not isinstance(newton_steps, int) or not 0 <= newton_steps <= 10:
        raise InputError(f"newton_steps: {newton_steps!r} is outside the allowed range [0, 10]")
    px, py = spec.position
    dist = math.hypot(tx - px, ty - py)
    if dist < 0.5:
        raise InputError(f"target: ({tx:g}, {ty:g}) m is within 0.5 m of the machine at ({px:g}, {py:g}) m")
    beta = math.atan2(ty - py, tx - px)
    top, side = w * math.cos(g * DEG), w * math.sin(g * DEG)
    use = get_map(spec, params)
    rmap = use.map
    found = None
    for branch in ("low", "high") if trajectory == "any" else (trajectory,):
        m = rmap.aim(dist, h, v, top, side, branch)
        if np.isfinite(m["elevation_deg"][0]):
            found = branch, m
            break
    if found is None:
        raise InputError(
            f"target: ({tx:g}, {ty:g}) m, {dist:.2f} m from the machine, is outside its reach map for a "
            f"{trajectory} flight at {v:g} km/h, {w:g} rpm, height {h:g} m (reach "
            f"{m['reach'][0, 0]:.2f}-{m['reach'][0, 1]:.2f} m); try launcher aim"
        )
    branch, m = found
    a0, b0 = float(m["elevation_deg"][0]) * DEG, beta - float(m["phi"][0])
    split = float(m["split_deg"][0]) * DEG
    bounds = (-0.5 * math.pi, max(split, a0)) if branch == "low" else (min(split, a0), 0.5 * math.pi)
    spin = (top * RPM, side * RPM, 0.0)

    def refine(start, steps):
        return shoot_mod.shoot(
            (px, py, h), v * KMH, (tx, ty), params, spin=spin, branch=branch, start=start, bounds=bounds,
            max_iter=steps,
        )  # fmt: skip

    s = refine((a0, b0), newton_steps)
    flights = int(s.flights)
    if newton_steps and not s.miss[0] <= REFINE_MISS_M:  # the map's guess was far (a wind the map has not)
        s = refine((s.elevation[0], s.heading[0]), 6)
        flights += int(s.flights)
    tab = s.table
    if not tab.ok[0]:
        raise InputError(
            f"target: the refined {branch} flight to ({tx:g}, {ty:g}) m does not land ({tab.status_name[0]})"
        )
    return InverseResult(
        branch,
        (tx, ty),
        h,
        v,
        w,
        g,
        math.degrees(s.elevation[0]),
        math.degrees(s.heading[0]),
        math.degrees(a0),
        math.degrees(b0),
        (float(tab["land_x"][0]), float(tab["land_y"][0])),
        float(s.miss[0] * 1e3),
        float(tab["land_t"][0]),
        float(tab["apex_z"][0]),
        float(tab.clearance[0]),
        (time.perf_counter() - t0) * 1e3,
        flights,
        spec,
        params,
        use,
    )


__all__ = ["NEWTON_STEPS", "REFINE_MISS_M", "InverseResult", "inverse_aim"]
