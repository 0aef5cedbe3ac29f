"""Flight events and the column layout of the batch event table.

Events (located by root-finding on each step's interpolant, never at a step
end): the first crossing of the net plane x = 0, the apex (first vz = 0 going
down) and the first ground contact (ball centre at height r).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Columns of the batch event table (see tennislab.core.integrators).
COLUMNS = (
    "land_t",
    "land_x",
    "land_y",
    "land_z",
    "land_vx",
    "land_vy",
    "land_vz",
    "land_wx",
    "land_wy",
    "land_wz",
    "net_t",
    "net_y",
    "net_z",
    "net_h",
    "net_status",
    "apex_t",
    "apex_x",
    "apex_y",
    "apex_z",
    "n_steps",
    "status",
)
COL = {name: i for i, name in enumerate(COLUMNS)}
NCOLS = len(COLUMNS)

NET_NONE, NET_OVER, NET_HIT = 0, 1, 2  #: net_status codes
NET_RESULTS = ("none", "over", "net")
STATUS_OK, STATUS_NO_LANDING, STATUS_BAD_START = 0, 1, 2  #: status codes


@dataclass(frozen=True)
class Landing:
    """First ground contact: time [s], ball-centre position [m], velocity [m/s], spin [rad/s]."""

    t: float
    position: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray

    @property
    def x(self) -> float:
        return float(self.position[0])

    @property
    def y(self) -> float:
        return float(self.position[1])


@dataclass(frozen=True)
class NetCrossing:
    """Crossing of the plane x = 0.

    ``z`` is the ball-centre height [m], ``net_height`` the cord height at the
    crossing's y [m], ``clearance = z - net_height - r`` [m]; ``result`` is
    ``over``, ``net`` (clearance < 0 between the posts) or ``none`` (never
    reaches x = 0; then the other fields are NaN).
    """

    t: float
    y: float
    z: float
    net_height: float
    clearance: float
    result: str


@dataclass(frozen=True)
class Apex:
    """Highest point: time [s] and position [m] (the start if the ball starts going down)."""

    t: float
    position: np.ndarray

    @property
    def z(self) -> float:
        return float(self.position[2])
