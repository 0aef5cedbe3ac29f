"""The two-roller tennis-ball launcher of seed 002 (Wojcicki, Pucilowski & Kulesza 2010).

* :mod:`.machine` - :class:`MachineSpec`, :class:`Settings`, :func:`launch_states`
* :mod:`.aim` - forward model and inverse aiming (low / lob solutions, quantised)
* :mod:`.rollers` - roller speeds, pull-in and no-slip conditions (seed eqs 8-17)
* :mod:`.power` - energy per throw, motor power, start-up time (seed eqs 18-31, corrected)
* :mod:`.materials` - Young's modulus and friction coefficient from test tables (seed section 5)
* :mod:`.drills` - training programs compiled to machine settings
"""

from tennislab.launcher.machine import (
    DEFAULT_POSITION,
    DEFAULT_SPEC,
    MachineSpec,
    Range,
    Settings,
    launch_states,
    settings_states,
    spin_vector,
)

__all__ = [
    "DEFAULT_POSITION",
    "DEFAULT_SPEC",
    "MachineSpec",
    "Range",
    "Settings",
    "launch_states",
    "settings_states",
    "spin_vector",
]
