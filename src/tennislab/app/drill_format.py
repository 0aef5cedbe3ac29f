"""The drill file the launcher planner downloads, in the launcher's format (docs/launcher.md).

Each clicked shot becomes a named shot with its target, a zone, and every setting given
explicitly (speed, spin, spin axis, height, trajectory), so the shot type only labels it.  The
zone is the smallest court area holding both the target and the landing point of the aimed shot
(deuce/ad box, singles, doubles half), else a rectangle 0.3 m around both.  The text is checked by
the launcher's own reader and compiler (:func:`tennislab.launcher.parse_drill`,
:func:`tennislab.launcher.compile_drill`), the code behind ``tennislab launcher drill FILE``.
This module only builds and checks documents: the aiming is done by the caller
(:mod:`tennislab.app.launcher_adapter`), which passes each shot's solution in.
"""

from __future__ import annotations

from tennislab.core.court import ITF_COURT
from tennislab.launcher import compile_drill, parse_drill

#: page shot type -> drill shot type (tennislab.launcher.drills.SHOT_TYPES)
TYPE_MAP = {
    "topspin": "topspin",
    "flat": "drive",
    "backspin": "slice",
    "sidespin-left": "drive",
    "sidespin-right": "drive",
    "custom": "drive",
}
#: areas tried for a shot's zone, smallest first
ZONE_ORDER = ("deuce-box", "ad-box", "singles", "doubles")


def zone_for(target, landing) -> object:
    """Smallest named area containing both points, else a rectangle [xmin, xmax, ymin, ymax] [m]."""
    near = target[0] < 0
    for base in ZONE_ORDER:
        name = ("near-" + base) if near else base
        if ITF_COURT.contains(name, *target) and ITF_COURT.contains(name, *landing):
            return name
    m = 0.3
    return [
        round(min(target[0], landing[0]) - m, 3),
        round(max(target[0], landing[0]) + m, 3),
        round(min(target[1], landing[1]) - m, 3),
        round(max(target[1], landing[1]) + m, 3),
    ]


def document(name: str, forms: list[dict], solutions: list) -> dict:
    """The drill mapping for validated aim forms and their aim solutions (one per form, same order)."""
    shots, program = {}, []
    for i, (v, sol) in enumerate(zip(forms, solutions), 1):
        key = f"shot-{i}"
        shots[key] = {
            "type": TYPE_MAP[v["shot"]],
            "description": f"{v['shot']} to ({v['target_x']:.2f}, {v['target_y']:.2f}) m",
            "target": [round(v["target_x"], 3), round(v["target_y"], 3)],
            "zone": zone_for((v["target_x"], v["target_y"]), sol.landing),
            "speed_kmh": sol.settings.speed_kmh,
            "spin_rpm": sol.settings.spin_rpm,
            "spin_axis_deg": sol.settings.spin_axis_deg,
            "height_m": sol.settings.height_m,
            "trajectory": v["solution"],
            "speed_tolerance_kmh": 0,
            "spin_tolerance_rpm": 0,
        }
        program.append({"shot": key})
    return {
        "name": name.strip() or "drill",
        "description": "made with the tennislab launcher planner",
        "machine": {"position": [forms[0]["machine_x"], forms[0]["machine_y"]]},
        "defaults": {"interval_s": 4},
        "shots": shots,
        "program": program,
    }


def check(text: str) -> dict:
    """Compile the drill text as ``tennislab launcher drill`` would; ``{"ok", "n_shots", "problems"}``."""
    comp = compile_drill(parse_drill(text, source="drill", fmt="json"))
    return {
        "ok": bool(comp.ok),
        "n_shots": len(comp.shots),
        "problems": [f"{u.label}: {u.problem}" for u in comp.unique if u.problem],
    }
