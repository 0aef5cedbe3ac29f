"""The flight use case: one ball launched from a state, to its landing or through N bounces.

:func:`fly` is the workflow behind ``tennislab fly``, the web app's Flight page and the report's
flight section; its :class:`FlightResult` gives each of them the same numbers (``to_dict()``).

A launch is given either as vectors (``position`` [m], ``velocity`` [m/s], ``spin`` [rad/s]) or in
the launch vocabulary of :mod:`tennislab.core.launch` (``speed_ms``, ``elevation_deg``,
``heading_deg``, ``spin_rpm`` about ``spin_axis``: a name such as ``topspin``, an angle [deg], or a
vector); the speed may be given in km/h or mph instead (``speed_kmh``, ``speed_mph``).

Guard rails (stated once, in :mod:`tennislab.core.flight`, and re-exported here): a launch outside
what a tennis ball can do is refused with the allowed range (:data:`MAX_SPEED_MS`, :data:`MAX_SPIN_RPM`,
:data:`MAX_DISTANCE_M`; a ball centre below its radius is refused by :func:`tennislab.core.flight.fly_dense`),
and a flight whose numbers are not finite is an error, never an answer.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab._lazy import attach_stub

if TYPE_CHECKING:
    from tennislab.trajectory.flight import (
        MAX_DISTANCE_M,
        MAX_SPEED_MS,
        MAX_SPIN_RPM,
        NET_MODES,
        FlightResult,
        fly,
        launch_vectors,
    )

__all__ = ["MAX_DISTANCE_M", "MAX_SPEED_MS", "MAX_SPIN_RPM", "NET_MODES", "FlightResult", "fly", "launch_vectors"]
__getattr__, __dir__ = attach_stub(__name__, __file__)
