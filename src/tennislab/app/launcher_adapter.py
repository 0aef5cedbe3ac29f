"""Launcher planner: the app's bridge to :mod:`tennislab.launcher` (aim, rollers, drills).

Uses ``tennislab.launcher.aim.aim`` / ``aim_result_dict`` (the JSON of
``tennislab launcher aim``) and, for the drill download, the launcher's drill
reader (``tennislab.io.drill``) so that the file the page downloads is checked
by the same code as ``tennislab launcher drill FILE``.
"""

from __future__ import annotations

import json
import re

from tennislab.app import services as S
from tennislab.app.fields import MAX_DRILL_SHOTS, SHOT_AXIS, validate
from tennislab.errors import InputError


def _spec(v: dict):
    from tennislab.launcher.machine import DEFAULT_SPEC

    return DEFAULT_SPEC.with_position(v["machine_x"], v["machine_y"])


def spin_axis(v: dict) -> float:
    """Spin-axis angle [deg] of a shot type (``custom`` uses the form's value)."""
    return SHOT_AXIS.get(v["shot"], v["spin_axis_deg"])


def solve(v: dict):
    """The quantised :class:`AimSolution` of an aim form, with the machine spec and flight params."""
    from tennislab.launcher.aim import aim, launcher_params

    spec = _spec(v)
    params = launcher_params()
    spin = 0.0 if v["shot"] == "flat" else v["spin_rpm"]
    sol = aim(
        (v["target_x"], v["target_y"]),
        v["speed_kmh"],
        spin,
        spin_axis(v),
        v["height"],
        spec=spec,
        params=params,
        solution=v["solution"],
    )
    return sol, spec, params


def aim(v: dict) -> dict:
    """``launcher aim`` JSON (settings, rollers, landing, miss_mm, net_clearance_m, ...) plus the flight."""
    from tennislab.launcher.aim import aim_result_dict, fly_settings

    sol, spec, params = solve(v)
    out = aim_result_dict(sol, spec, params)
    tr = fly_settings(sol.settings, spec, params)
    out["flight"] = S.flight_result(tr)
    return out


def _slug(name: str) -> str:
    s = re.sub(r"[^A-Za-z0-9_-]+", "-", name).strip("-").lower()
    return s[:40] or "drill"


def drill(shots, name=None) -> dict:
    """A drill document from aim forms: the shots' targets, speeds, spins and the machine.

    Returns ``{"name", "filename", "media_type", "text", "n_shots", "check"}`` where ``text`` is
    the file ``tennislab launcher drill`` reads and ``check`` its compiled result (every shot
    clears the net and lands in its zone), so the page never offers a file the CLI rejects.
    """
    if not isinstance(shots, list) or not shots:
        raise InputError(f"shots: expected a list of 1 to {MAX_DRILL_SHOTS} shots")
    if len(shots) > MAX_DRILL_SHOTS:
        raise InputError(f"shots: {len(shots)} shots is more than the limit of {MAX_DRILL_SHOTS}")
    if name is None:
        name = "drill"
    if not isinstance(name, str) or len(name) > 60:
        raise InputError("name: expected a text of at most 60 characters")
    forms = []
    for i, s in enumerate(shots):
        try:
            forms.append(validate("aim", s))
        except InputError as exc:
            raise InputError(f"shots[{i}].{exc}") from None
    m0 = (forms[0]["machine_x"], forms[0]["machine_y"], forms[0]["height"])
    for i, f in enumerate(forms):
        if (f["machine_x"], f["machine_y"], f["height"]) != m0:
            raise InputError(f"shots[{i}]: every shot of a drill must use the same machine position and height")
    doc = drill_document(name, forms)
    text = json.dumps(doc, indent=2)
    check = check_drill_text(text)
    return {
        "name": name,
        "filename": _slug(name) + ".json",
        "media_type": "application/json",
        "text": text,
        "n_shots": len(forms),
        "check": check,
    }


def drill_document(name: str, forms: list[dict]) -> dict:
    """The drill file's content (the launcher's drill format; see ``docs/launcher.md``)."""
    from tennislab.app import drill_format

    return drill_format.document(name, forms, spin_axis)


def check_drill_text(text: str) -> dict:
    """Compile a drill file's text with the launcher's own reader."""
    from tennislab.app import drill_format

    return drill_format.check(text)
