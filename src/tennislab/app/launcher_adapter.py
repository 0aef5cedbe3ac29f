"""Launcher planner: the app's bridge to :mod:`tennislab.launcher` (aim, drills).

:func:`aim` answers the aim form with the workflow :func:`tennislab.launcher.aim` (its
``to_dict()`` is the JSON of ``tennislab launcher aim``) plus the flight to draw; :func:`drill`
builds the drill file the page downloads (:mod:`tennislab.app.drill_format`) from shots aimed
here, and checks it with the launcher's own reader, as ``tennislab launcher drill FILE`` would.
"""

from __future__ import annotations

import json
import re

import tennislab.app.drill_format as drill_format
import tennislab.app.services as S
from tennislab.app.fields import MAX_DRILL_SHOTS, SHOT_AXIS, validate
from tennislab.errors import InputError
from tennislab.launcher import DEFAULT_PRESET, DEFAULT_SPEC, AimResult, launcher_params
from tennislab.launcher import aim as aim_workflow
from tennislab.launcher.aim import fly_settings


def _spec(v: dict):
    return DEFAULT_SPEC.with_position(v["machine_x"], v["machine_y"])


def spin_axis(v: dict) -> float:
    """Spin-axis angle [deg] of a shot type (``custom`` uses the form's value)."""
    return SHOT_AXIS.get(v["shot"], v["spin_axis_deg"])


def solve(v: dict) -> AimResult:
    """The aim of a validated aim form (the tolerances of ``launcher aim``; a ``flat`` shot keeps no spin)."""
    flat = v["shot"] == "flat"
    spin = 0.0 if flat else v["spin_rpm"]
    return aim_workflow(
        (v["target_x"], v["target_y"]),
        v["speed_kmh"],
        spin,
        spin_axis(v),
        v["height"],
        spec=_spec(v),
        params=launcher_params(),
        solution=v["solution"],
        spin_tolerance_rpm=0.0 if flat else 100.0,
    )


def aim(v: dict) -> dict:
    """``launcher aim`` JSON (settings, rollers, landing, miss_mm, net_clearance_m, ...) plus the flight."""
    res = solve(v)
    out = {**res.to_dict(), "physics_preset": DEFAULT_PRESET}  # the physics it flew, as the CLI says it
    out["flight"] = S.flight_of(fly_settings(res.settings, res.spec, res.params))
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
    solutions = []
    for i, f in enumerate(forms):  # each shot aimed here, never trusting the page's result
        try:
            solutions.append(solve(f).solution)
        except InputError as exc:
            raise InputError(f"shots[{i}]: {exc}") from None
    doc = drill_format.document(name, forms, solutions)
    text = json.dumps(doc, indent=2)
    check = drill_format.check(text)
    return {
        "name": name,
        "filename": _slug(name) + ".json",
        "media_type": "application/json",
        "text": text,
        "n_shots": len(forms),
        "check": check,
    }


def drill_document(name: str, forms: list[dict]) -> dict:
    """The drill file's content for validated aim forms (the launcher's drill format)."""
    return drill_format.document(name, forms, [solve(f).solution for f in forms])


def check_drill_text(text: str) -> dict:
    """Compile a drill file's text with the launcher's own reader."""
    return drill_format.check(text)
