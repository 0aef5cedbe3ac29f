"""The physics' names as plain data: the built-in aero models, the default one and the physics presets.

What a help text or a front-end lists without loading the physics: this module imports nothing (no
NumPy, no Numba), so ``tennislab fly --help`` can name the aero models and the presets' defaults
without compiling a kernel.  :mod:`tennislab.core.aero` registers the models named here (and takes
:data:`DEFAULT_AERO` from here); :mod:`tennislab.core.flight` builds :data:`PRESETS`.
``tests/core/test_names.py`` checks that these names are the registry's.
"""

from __future__ import annotations

__all__ = [
    "AERO_ALIASES",
    "AERO_MODEL_NAMES",
    "DEFAULT_AERO",
    "DEFAULT_PRESET",
    "PRESETS",
    "PRESET_TITLES",
    "describe_preset",
]

#: The default aero model of every command and workflow (stated here only; see docs/validation.md
#: for the evidence behind the choice).
DEFAULT_AERO = "choppin2018"

#: Names of the aero models :mod:`tennislab.core.aero` registers (aliases and ``table`` included), sorted
#: as :func:`tennislab.core.aero.aero_model_names` lists them.
AERO_MODEL_NAMES: tuple[str, ...] = (
    "choppin2018",
    "constant",
    "cross2014",
    "launcher2015",
    "stepanek1988",
    "table",
    "tennislab2026",
    "wojcicki2010",
)

#: Built-in aero names that are another model's alias: {alias: the model's name}
AERO_ALIASES: dict[str, str] = {"wojcicki2010": "launcher2015"}

#: The preset every command and workflow flies when none is asked for (``fly``, ``call``, the serve family,
#: the launcher and ``impact``'s ball alike).
DEFAULT_PRESET = "standard"

#: Named base sets of physics options for :meth:`FlightParams.from_options` (options not given
#: keep the dataclass defaults: ITF type-2 ball, ISA sea-level moist air, DEFAULT_AERO).
PRESETS: dict[str, dict] = {
    "standard": {},
    # seed 000 sec. 2.3: rho 1.22 kg/m^3, g 9.82 m/s^2, r 0.033 m, m 0.059 kg; Stepanek 1988 aero (eqs 3-4)
    "seed000": {"aero": "stepanek1988", "mass": 0.059, "radius": 0.033, "air_density": 1.22, "gravity": 9.82},
    # seed 002 eqs 1, 3 (Wojcicki et al. 2010): constant c_d, Magnus linear in spin
    "seed002": {"aero": "launcher2015"},
}

#: what each preset is, in a few words (for --help, the outputs and the report)
PRESET_TITLES: dict[str, str] = {
    "standard": "tennislab's ball and air",
    "seed000": "the serve paper's constants",
    "seed002": "the launcher paper's aero",
}


def describe_preset(name: str) -> str:
    """A preset's physics in words, from :data:`PRESETS` itself (``seed000``: "stepanek1988 aero, ball 59 g,
    radius 33 mm, air 1.22 kg/m^3, g 9.82 m/s^2"); what a preset leaves to the defaults is named, not
    numbered (the defaults are stated once, in the dataclasses: "ITF ball", "sea-level air")."""
    p = PRESETS[name]
    ball = [
        f"{p['mass'] * 1000:g} g" if "mass" in p else "",
        f"radius {p['radius'] * 1000:g} mm" if "radius" in p else "",
    ]
    ball_words = "ball " + ", ".join(b for b in ball if b) if any(ball) else "ITF ball"
    parts = [f"{p.get('aero', DEFAULT_AERO)} aero", ball_words]
    parts.append(f"air {p['air_density']:g} kg/m^3" if "air_density" in p else "sea-level air")
    if "gravity" in p:
        parts.append(f"g {p['gravity']:g} m/s^2")
    return ", ".join(parts)
