"""``core.names``: the physics' names as plain data are the registries' own, and import nothing heavy."""

from __future__ import annotations

import subprocess
import sys

import pytest

from tennislab.core import aero, flight, names
from tennislab.core.ball import Ball
from tennislab.errors import InputError


def test_the_aero_names_are_the_registered_built_ins():
    # a fresh process: another test may have registered a model of its own
    code = "from tennislab.core.aero import aero_model_names; print(','.join(aero_model_names()))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert tuple(out.stdout.strip().split(",")) == names.AERO_MODEL_NAMES


def test_the_aliases_and_the_default_are_the_registrys():
    for alias, model in names.AERO_ALIASES.items():
        assert aero.get_aero_model(alias).name == model != alias
    for name in set(names.AERO_MODEL_NAMES) - set(names.AERO_ALIASES) - {"table"}:
        assert aero.get_aero_model(name).name == name  # not an alias
    assert aero.DEFAULT_AERO == names.DEFAULT_AERO in names.AERO_MODEL_NAMES
    assert flight.PRESETS is names.PRESETS
    assert all(p.get("aero", names.DEFAULT_AERO) in names.AERO_MODEL_NAMES for p in names.PRESETS.values())


def test_the_names_module_imports_nothing_heavy():
    code = "import sys, tennislab.core.names; print(','.join(m for m in ('numpy', 'numba') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


@pytest.mark.parametrize("preset", sorted(names.PRESETS))
@pytest.mark.parametrize("given", [{}, {"mass": 0.05}, {"radius": 0.04, "mass": 0.06}])
def test_ball_from_options_is_the_flights_ball(preset, given):
    assert Ball.from_options(preset=preset, **given) == flight.FlightParams.from_options(preset=preset, **given).ball


def test_ball_from_options_refuses_what_the_flight_refuses():
    with pytest.raises(InputError, match="^preset: unknown physics preset 'nope'"):
        Ball.from_options(preset="nope")
    with pytest.raises(InputError, match="^mass:"):
        Ball.from_options(mass=5.0)


def test_the_presets_in_words_come_from_the_presets():
    """--help and the report describe each preset from PRESETS itself (no second statement of its numbers)."""
    from tennislab.core.names import PRESET_TITLES, PRESETS, describe_preset

    assert set(PRESET_TITLES) == set(PRESETS)
    assert describe_preset("seed000") == "stepanek1988 aero, ball 59 g, radius 33 mm, air 1.22 kg/m^3, g 9.82 m/s^2"
    assert describe_preset("standard") == "choppin2018 aero, ITF ball, sea-level air"
    assert describe_preset("seed002") == "launcher2015 aero, ITF ball, sea-level air"
