"""The two-roller tennis-ball launcher of Wójcicki, Puciłowski & Kulesza (2010): the public API.

Workflows (plain parameters in, a :class:`tennislab.results.Result` out; ``to_dict()`` is the
command's ``--json``):

* :func:`aim` - machine settings on the machine's steps that land a ball nearest a target
  (``launcher aim``), within speed/spin tolerances and trajectory preferences, the height given or searched;
* :func:`inverse_aim` - any target at once: the continuous angles from the machine's reach map, refined
  by one Newton step on the flight kernel;
* :class:`HitsDB` - a database of hits and drills: :meth:`~HitsDB.info`, :meth:`~HitsDB.lookup`,
  :meth:`~HitsDB.play`, :meth:`~HitsDB.fill`, drills (``launcher info | lookup | play | table | drills``);
* :func:`compile_drill` / :func:`load_drill` - a training program compiled to settings (``launcher drill``);
* :func:`roller_report`, :func:`power_report` - rollers and motors (the paper's eqs 8-31).

Modules: :mod:`.machine` (spec, settings, launch states), :mod:`.aim`, :mod:`.preferences`,
:mod:`.drills` and :mod:`.drill_schema` (drill programs and their file format), :mod:`.db`,
:mod:`.lookup`, :mod:`.table` (the database), :mod:`.hitsdb` and :mod:`.hitsdb_results`, :mod:`.rollers`, :mod:`.power`,
:mod:`.materials`, :mod:`.reach` (the reach map) and :mod:`.inverse`.
"""

from __future__ import annotations

import importlib
import warnings
from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.core.launch import launch_spin
    from tennislab.launcher.aim import (
        DEFAULT_PRESET,
        AimResult,
        AimSolution,
        aim,
        aim_all,
        fly_settings,
        launcher_params,
    )
    from tennislab.launcher.drill_schema import find_drill_source, load_drill, parse_drill, shipped_drills
    from tennislab.launcher.drills import (
        CSV_COLUMNS,
        CompiledDrill,
        Drill,
        compile_drill,
        drill_key,
        drill_trajectories,
        expand_program,
    )
    from tennislab.launcher.hitsdb import HitsDB
    from tennislab.launcher.hitsdb_results import DbInfo, DrillList, DrillsImported, LookupResult, PlayResult
    from tennislab.launcher.inverse import InverseResult, inverse_aim
    from tennislab.launcher.machine import (
        DEFAULT_POSITION,
        DEFAULT_SPEC,
        PAPER,
        MachineSpec,
        Range,
        Settings,
        machine_states,
        settings_states,
        speed_in_kmh,
    )
    from tennislab.launcher.materials import SEED_BALL_RADIUS, SEED_CONTACT_AREA, friction_coefficient, young_modulus
    from tennislab.launcher.power import DEFAULT_MOTOR_POWER, DEFAULT_ROLLER_MASS, DEFAULT_THROW_TIME, power_report
    from tennislab.launcher.preferences import DEFAULT_SPIN_AXIS_TOLERANCE_DEG, TRAJECTORIES, Preferences, Tolerances
    from tennislab.launcher.rollers import roller_report
    from tennislab.launcher.table import (
        DEFAULT_CHUNK,
        FillPlan,
        FillReport,
        FillReports,
        TableGrid,
        make_grid,
        plan_fill,
    )

__all__ = [
    "CSV_COLUMNS",
    "DEFAULT_CHUNK",
    "DEFAULT_MOTOR_POWER",
    "DEFAULT_POSITION",
    "DEFAULT_PRESET",
    "DEFAULT_ROLLER_MASS",
    "DEFAULT_SPEC",
    "DEFAULT_SPIN_AXIS_TOLERANCE_DEG",
    "DEFAULT_THROW_TIME",
    "PAPER",
    "SEED_BALL_RADIUS",
    "SEED_CONTACT_AREA",
    "TRAJECTORIES",
    "AimResult",
    "AimSolution",
    "CompiledDrill",
    "DbInfo",
    "Drill",
    "DrillList",
    "DrillsImported",
    "FillPlan",
    "FillReport",
    "FillReports",
    "HitsDB",
    "InverseResult",
    "LookupResult",
    "MachineSpec",
    "PlayResult",
    "Preferences",
    "Range",
    "Settings",
    "TableGrid",
    "Tolerances",
    "aim",
    "aim_all",
    "compile_drill",
    "drill_key",
    "drill_trajectories",
    "expand_program",
    "find_drill_source",
    "fly_settings",
    "friction_coefficient",
    "inverse_aim",
    "launch_spin",
    "launcher_params",
    "load_drill",
    "machine_states",
    "make_grid",
    "parse_drill",
    "plan_fill",
    "power_report",
    "roller_report",
    "settings_states",
    "shipped_drills",
    "speed_in_kmh",
    "young_modulus",
]
_getattr, __dir__ = attach_stub(__name__, __file__)


def __getattr__(name: str):
    if name == "spin_vector":  # the old name: core.launch.spin_vector builds a spin from launch-frame components
        warnings.warn(
            "tennislab.launcher.spin_vector is now launch_spin (tennislab.core.launch_spin, the same arguments)",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.import_module("tennislab.core.launch").launch_spin
    if name == "launch_states":  # the old name: core.launch.launch_states builds states from launch-frame spin
        warnings.warn(
            "tennislab.launcher.launch_states is now machine_states (tennislab.core.launch.launch_states takes "
            "the spin's launch-frame components)",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.import_module("tennislab.launcher.machine").machine_states
    return _getattr(name)
