"""Pure physics on SI floats and NumPy arrays: no I/O, no plotting, no CLI.

The primitives every workflow composes (docs/architecture.md shows which uses which):

* flight (:mod:`~tennislab.core.flight`): :class:`FlightParams` (every physics setting, with
  :meth:`~FlightParams.to_dict` / :meth:`~FlightParams.from_dict`), :func:`fly_dense` (one flight, SciPy dense
  output: the accuracy reference), :func:`fly_batch` (N flights, the compiled kernel of
  :mod:`~tennislab.core.integrators`: an event table), the net rule (:data:`NET_MODES`, :func:`with_net`)
  and the guard rails (:data:`MAX_SPEED_MS`, :data:`MAX_SPIN_RPM`, :data:`MAX_DISTANCE_M`); the one
  right-hand side is :mod:`~tennislab.core.dynamics`, the events :mod:`~tennislab.core.events`;
* the ball, the air and the court: :class:`Ball`, :class:`Atmosphere`, :class:`Court` /
  :data:`ITF_COURT`; aero models by name (:func:`get_aero_model`, :func:`register_aero`,
  :data:`DEFAULT_AERO`; the names as plain data, for a help text: :mod:`~tennislab.core.names`);
* the launch vocabulary (:mod:`~tennislab.core.launch`): speeds, angles and spin axes to vectors and back;
* the bounce: :func:`bounce` / :func:`bounce_batch` on a :class:`Surface` (:func:`get_surface`), a flight
  through bounces (:func:`fly_bounces`) and the ball's mark (:func:`ball_mark`);
* the racket-ball impact (:mod:`~tennislab.core.impact`, Haake et al. 2003 ball models in
  :mod:`~tennislab.core.haake2003`): :func:`impact_single` (one impact, its history on request) and
  :func:`impact_batch`.

:mod:`~tennislab.core._jit` holds the Numba options of every kernel.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.core.aero import (
        AeroModel,
        aero_model_names,
        callable_model,
        get_aero_model,
        register_aero,
    )
    from tennislab.core.atmosphere import Atmosphere, air_density
    from tennislab.core.ball import Ball
    from tennislab.core.bounce import bounce, bounce_batch
    from tennislab.core.court import ITF_COURT, Court
    from tennislab.core.events import DEFAULT_NET, NET_MODES, STATUS_NAMES, Apex, Landing, NetContact, NetCrossing
    from tennislab.core.flight import (
        MAX_DISTANCE_M,
        MAX_SPEED_MS,
        MAX_SPIN_RPM,
        FlightParams,
        FlightTable,
        Trajectory,
        fly_batch,
        fly_dense,
        with_net,
    )
    from tennislab.core.haake2003 import BallImpactModel, ball_model_names, get_ball_model
    from tennislab.core.impact import (
        FRICTION_MODELS,
        TANGENTIAL_DAMPING,
        ImpactParams,
        ImpactResult,
        impact_batch,
        impact_single,
    )
    from tennislab.core.launch import (
        SPIN_AXES_DEG,
        describe_spin,
        describe_velocity,
        launch_spin,
        launch_velocity,
        spin_axis_angle,
    )
    from tennislab.core.mark import BallMark, MarkParams, ball_mark
    from tennislab.core.names import (
        AERO_ALIASES,
        AERO_MODEL_NAMES,
        DEFAULT_AERO,
        DEFAULT_PRESET,
        PRESET_TITLES,
        PRESETS,
        describe_preset,
    )
    from tennislab.core.rally import Bounce, Rally, fly_bounces
    from tennislab.core.surfaces import Surface, get_surface, register_surface, surface_names

__all__ = [
    "AERO_ALIASES",
    "AERO_MODEL_NAMES",
    "DEFAULT_AERO",
    "DEFAULT_NET",
    "FRICTION_MODELS",
    "ITF_COURT",
    "MAX_DISTANCE_M",
    "MAX_SPEED_MS",
    "MAX_SPIN_RPM",
    "NET_MODES",
    "DEFAULT_PRESET",
    "PRESETS",
    "PRESET_TITLES",
    "SPIN_AXES_DEG",
    "STATUS_NAMES",
    "TANGENTIAL_DAMPING",
    "AeroModel",
    "Apex",
    "Atmosphere",
    "Ball",
    "BallImpactModel",
    "BallMark",
    "Bounce",
    "Court",
    "FlightParams",
    "FlightTable",
    "ImpactParams",
    "ImpactResult",
    "Landing",
    "MarkParams",
    "NetContact",
    "NetCrossing",
    "Rally",
    "Surface",
    "Trajectory",
    "aero_model_names",
    "air_density",
    "ball_mark",
    "ball_model_names",
    "bounce",
    "bounce_batch",
    "callable_model",
    "describe_preset",
    "describe_spin",
    "describe_velocity",
    "fly_batch",
    "fly_dense",
    "fly_bounces",
    "get_aero_model",
    "get_ball_model",
    "get_surface",
    "impact_batch",
    "impact_single",
    "launch_spin",
    "launch_velocity",
    "register_aero",
    "register_surface",
    "spin_axis_angle",
    "surface_names",
    "with_net",
]
__getattr__, __dir__ = attach_stub(__name__, __file__)
