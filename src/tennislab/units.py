"""Unit conversions used at the edges (CLI flags, plots, reports).  SI inside."""

from __future__ import annotations

import math

__all__ = [
    "DEG",
    "KMH",
    "MPH",
    "RPM",
    "SPEED_UNITS",
    "kmh_to_ms",
    "ms_to_kmh",
    "rads_to_rpm",
    "rpm_to_rads",
    "speed_in_ms",
]

KMH = 1.0 / 3.6  #: 1 km/h in m/s
RPM = 2.0 * math.pi / 60.0  #: 1 rpm in rad/s
DEG = math.pi / 180.0  #: 1 degree in rad
MPH = 0.44704  #: 1 mile per hour in m/s (exact: 1609.344 m / 3600 s)

#: the speed parameters of the workflows and their units: name -> (m/s per unit, unit label)
SPEED_UNITS = {"speed_ms": (1.0, "m/s"), "speed_kmh": (KMH, "km/h"), "speed_mph": (MPH, "mph")}


def _nice(x: float) -> float:
    """A bound for a message: rounded to 0.1, shown without ``.0`` when whole."""
    r = round(x, 1)
    return int(r) if r.is_integer() else r


def speed_in_ms(lo_ms: float, hi_ms: float, **speeds) -> tuple[str, float] | None:
    """(the parameter given, its speed [m/s]) of the one speed among ``speed_ms``, ``speed_kmh`` and
    ``speed_mph`` that is not None, checked against [``lo_ms``, ``hi_ms``] [m/s] in the unit it was given
    in (the error names that parameter); None when none is given, an error when several are."""
    from tennislab.errors import InputError, check_range

    given = [k for k, v in speeds.items() if v is not None]
    unknown = [k for k in speeds if k not in SPEED_UNITS]
    if unknown:
        raise TypeError(f"speed_in_ms: unknown speed parameter {unknown[0]!r}")
    if len(given) > 1:
        raise InputError(f"{given[0]}: give one speed ({' or '.join(given)}), not {len(given)}")
    if not given:
        return None
    key = given[0]
    factor, unit = SPEED_UNITS[key]
    value = check_range(key, speeds[key], _nice(lo_ms / factor), _nice(hi_ms / factor), unit)
    return key, min(max(value * factor, lo_ms), hi_ms)


def kmh_to_ms(v):
    """Speed [km/h] -> [m/s]."""
    return v / 3.6


def ms_to_kmh(v):
    """Speed [m/s] -> [km/h]."""
    return v * 3.6


def rpm_to_rads(w):
    """Spin [rpm] -> [rad/s]."""
    return w * RPM


def rads_to_rpm(w):
    """Spin [rad/s] -> [rpm]."""
    return w / RPM
