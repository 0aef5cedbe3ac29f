"""Unit conversions used at the edges (CLI flags, plots, reports).  SI inside."""

from __future__ import annotations

import math

__all__ = ["DEG", "KMH", "RPM", "kmh_to_ms", "ms_to_kmh", "rads_to_rpm", "rpm_to_rads"]

KMH = 1.0 / 3.6  #: 1 km/h in m/s
RPM = 2.0 * math.pi / 60.0  #: 1 rpm in rad/s
DEG = math.pi / 180.0  #: 1 degree in rad


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
