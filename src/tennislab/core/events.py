"""Flight events, described once, and the column layout of the batch event table.

An :class:`Event` says which state component reaches which value in which
direction, whether that ends the flight, and which state components are
recorded when it happens.  Both integration paths read the same descriptions:
the SciPy path (:func:`tennislab.core.flight.fly_dense`) turns them into
``solve_ivp`` event functions, the compiled kernel
(:mod:`tennislab.core.integrators`) receives them as rows of a small array
(:func:`event_array`) and locates every one of them with the same loop, by
root-finding on each step's interpolant (never at a step end).

The events of a flight (:data:`FLIGHT_EVENTS`):

``land``     first ground contact: the ball centre comes down to z = r; ends the flight.
``net``      first crossing of the net plane x = 0 by the ball centre, toward the other half.
``apex``     the highest point: v_z falls through 0 (the start if the ball starts going down).

With the net as an obstacle (``FlightParams(net_obstacle=True)``,
:data:`OBSTACLE_EVENTS`) two more, which end the flight where the ball meets
the net (status :data:`STATUS_NET`, columns ``net_hit_*``):

``net_hit``   the mesh: the ball's surface reaches the net plane (centre at
              x = -r on the near side, +r on the far side) at or below the top
              of the net, h(y), between the posts.
``net_tape``  the tape: a ball whose surface reached the plane above the cord
              has its centre cross x = 0 less than r above the cord (the
              crossing the pass-through net calls ``net``).  Located at the
              crossing: the first touch of the cord came up to r earlier along
              the path (~1 ms at 30 m/s); what the cord does to the ball (a let,
              a ball dropping back) is not modelled.

So with the obstacle the flights whose crossing says ``net`` without it end at
the net, and so does a ball whose surface reaches the mesh although it lands
with its centre less than r before the net plane (its crossing says ``none``:
it touched the bottom of the net); every other flight is unchanged.

Conventions shared by both paths:

* ``side`` is the half the ball starts in (-1 near, x < 0; +1 far; on the
  plane x = 0, the half it moves away from).  ``TOWARD`` events are crossed in
  the direction -side and their ``radii`` offset lies on the start's side.
* At the start an event whose value is already past its target happens at the
  start (the apex of a ball starting downward); if it would end the flight the
  start is invalid (a ball below the ground or inside the net).  A value
  exactly on the target, moving away from it (a flight starting on the ground
  going up, after a bounce), is *armed*: the event is the next crossing.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

#: The state vector: position [m], velocity [m/s], spin [rad/s] (see :mod:`tennislab.core.dynamics`)
STATE = ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz")
STATE_INDEX = {name: i for i, name in enumerate(STATE)}

# Columns of the batch event table (names are a contract: add, never rename).
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
    "net_hit_t",
    "net_hit_x",
    "net_hit_y",
    "net_hit_z",
    "net_hit_vx",
    "net_hit_vy",
    "net_hit_vz",
    "net_hit_wx",
    "net_hit_wy",
    "net_hit_wz",
)
COL = {name: i for i, name in enumerate(COLUMNS)}
NCOLS = len(COLUMNS)

NET_NONE, NET_OVER, NET_HIT = 0, 1, 2  #: net_status codes
NET_RESULTS = ("none", "over", "net")

#: status codes of a batch row (``FlightTable["status"]``; docs/flight.md)
STATUS_OK = 0  # landed
STATUS_NO_LANDING = 1  # still flying at t_max
STATUS_BAD_START = 2  # a non-finite value, the ball below the ground (z < r) or inside the net
STATUS_NET = 3  # stopped by the net (net_obstacle=True): see the net_hit_* columns
STATUS_OUT_OF_RANGE = 4  # launch speed above MAX_SPEED_MS or spin above MAX_SPIN_RPM (tennislab.core.flight)
STATUS_FAILED = 5  # integration failed: step limit (rejected steps counted) or a non-finite state
STATUS_NAMES = ("landed", "no landing", "bad start", "net", "out of range", "failed")

# direction codes of an event
DOWN, UP, TOWARD = -1, 1, 0
# stop codes: what the event does to the flight
NEVER, ALWAYS, IF_NET = 0, 1, 2


@dataclass(frozen=True)
class Event:
    """One flight event: ``component`` reaches ``target + radii * r`` going ``direction``.

    Attributes
    ----------
    name : event name; its columns in the batch table are ``<name>_t`` and ``<name>_<component>``
    component : the state component watched (a name of :data:`STATE`)
    target : value reached [SI unit of the component]
    radii : plus this many ball radii (on the start's side of the net plane for ``TOWARD`` events)
    direction : ``DOWN`` (falling through the target), ``UP`` or ``TOWARD`` (from the start's side)
    stop : ``NEVER`` (recorded, the flight goes on), ``ALWAYS`` (ends the flight) or
        ``IF_NET`` (ends it when the centre is at most ``net_margin`` radii above the
        net's top h(y) between the posts; recorded only then)
    status : the row's status when this event ends the flight
    record : state components recorded when it happens
    columns : prefix of its batch columns (default: ``name``; two events may share them)
    net_margin : see ``stop`` [ball radii]
    aim : the compiled path shortens the step that would reach it so that the step ends just
        past it (the ground: see :func:`tennislab.core.integrators._aim_at`); a position
        component falling (``DOWN``) only
    """

    name: str
    component: str
    target: float = 0.0
    radii: float = 0.0
    direction: int = DOWN
    stop: int = NEVER
    status: int = STATUS_OK
    record: tuple[str, ...] = ()
    aim: bool = False
    columns: str = ""
    net_margin: float = 0.0

    @property
    def prefix(self) -> str:
        """Prefix of the event's batch columns and its key in a trajectory's events."""
        return self.columns or self.name

    def __post_init__(self):
        if self.component not in STATE_INDEX or any(c not in STATE_INDEX for c in self.record):
            raise ValueError(f"event {self.name}: unknown state component")
        if self.direction not in (DOWN, UP, TOWARD) or self.stop not in (NEVER, ALWAYS, IF_NET):
            raise ValueError(f"event {self.name}: bad direction or stop code")
        if self.aim and (self.direction != DOWN or STATE_INDEX[self.component] > 2):
            raise ValueError(f"event {self.name}: only a falling position component can be aimed at")
        for c in ("t", *self.record):
            if f"{self.prefix}_{c}" not in COL:
                raise ValueError(f"event {self.name}: no column {self.prefix}_{c} in COLUMNS")

    @property
    def index(self) -> int:
        """Index of :attr:`component` in the state vector."""
        return STATE_INDEX[self.component]

    def target_value(self, radius: float, side: float) -> float:
        """The value reached, for a ball of ``radius`` [m] starting in half ``side`` (-1 or +1)."""
        s = side if self.direction == TOWARD else 1.0
        return self.target + self.radii * radius * s

    def direction_value(self, side: float) -> float:
        """The crossing direction (-1 or +1) for a ball starting in half ``side``."""
        return -side if self.direction == TOWARD else float(self.direction)


LAND = Event("land", "z", radii=1.0, direction=DOWN, stop=ALWAYS, status=STATUS_OK, record=STATE, aim=True)
NET = Event("net", "x", direction=TOWARD, record=("y", "z"))
APEX = Event("apex", "vz", direction=DOWN, record=("x", "y", "z"))
NET_MESH = Event("net_hit", "x", radii=1.0, direction=TOWARD, stop=IF_NET, status=STATUS_NET, record=STATE)
NET_TAPE = Event(
    "net_tape", "x", direction=TOWARD, stop=IF_NET, status=STATUS_NET, record=STATE, columns="net_hit", net_margin=1.0
)

#: events of a flight with the net as a plane the ball passes through (the default)
#: How a flight treats the net (the one net rule): ``obstacle`` stops the ball where it meets the net
#: (mesh or tape, :data:`OBSTACLE_EVENTS`), ``through`` lets it pass and only says whether it cleared
#: (:data:`FLIGHT_EVENTS`, the seeds' models).  Every workflow that flies a state a user gives
#: (``fly``, ``call --position``) defaults to :data:`DEFAULT_NET`;
#: :func:`tennislab.core.flight.with_net` applies a mode to a set of parameters.
NET_MODES = ("obstacle", "through")
DEFAULT_NET = "obstacle"

FLIGHT_EVENTS = (LAND, NET, APEX)
#: events of a flight with the net as an obstacle
OBSTACLE_EVENTS = (LAND, NET, APEX, NET_MESH, NET_TAPE)

# Layout of a row of the kernel's event array (all float64; codes and column indices as exact integers)
EVENT_FIELDS = ("component", "target", "radii", "direction", "stop", "status", "aim", "net_margin", "t_col") + tuple(
    f"col_{c}" for c in STATE
)
EV_COMPONENT, EV_TARGET, EV_RADII, EV_DIRECTION, EV_STOP, EV_STATUS, EV_AIM, EV_MARGIN, EV_TCOL = range(9)
EV_COL0 = 9  # EV_COL0 + i: column recording state component i, or -1
NEVFIELDS = len(EVENT_FIELDS)
#: most events a kernel handles (size of its per-event scratch)
MAX_EVENTS = 8


def event_array(events: tuple[Event, ...]) -> np.ndarray:
    """The kernel's (n, :data:`NEVFIELDS`) array describing ``events`` (a fresh copy)."""
    return _event_array(tuple(events)).copy()


@lru_cache(maxsize=32)
def _event_array(events: tuple[Event, ...]) -> np.ndarray:
    if not 0 < len(events) <= MAX_EVENTS:
        raise ValueError(f"1 to {MAX_EVENTS} events, got {len(events)}")
    a = np.full((len(events), NEVFIELDS), -1.0)
    for i, ev in enumerate(events):
        a[i, EV_COMPONENT] = ev.index
        a[i, EV_TARGET] = ev.target
        a[i, EV_RADII] = ev.radii
        a[i, EV_DIRECTION] = ev.direction
        a[i, EV_STOP] = ev.stop
        a[i, EV_STATUS] = ev.status
        a[i, EV_AIM] = 1.0 if ev.aim else 0.0
        a[i, EV_MARGIN] = ev.net_margin
        a[i, EV_TCOL] = COL[f"{ev.prefix}_t"]
        for c in ev.record:
            a[i, EV_COL0 + STATE_INDEX[c]] = COL[f"{ev.prefix}_{c}"]
    a.setflags(write=False)
    return a


def net_status(net_t, clearance):
    """``net_status`` code(s) from the crossing time (NaN: none) and the clearance z - h - r [m]."""
    t = np.asarray(net_t, dtype=float)
    c = np.asarray(clearance, dtype=float)
    with np.errstate(invalid="ignore"):
        out = np.where(np.isnan(t), NET_NONE, np.where(c < 0.0, NET_HIT, NET_OVER))
    return int(out) if out.ndim == 0 else out


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
    reaches x = 0; then the other fields are NaN).  A ball stopped by the net
    (:class:`NetContact`) has ``result = "net"`` and the contact's t, y, z.
    """

    t: float
    y: float
    z: float
    net_height: float
    clearance: float
    result: str


@dataclass(frozen=True)
class NetContact:
    """Where a ball met the net (``net_obstacle=True``): time [s], ball centre [m], velocity [m/s]
    and spin [rad/s] at the contact, and ``part``: ``mesh`` (the centre at x = -+r, the contact
    point (0, y, z) at or below the cord) or ``tape`` (the centre crossing x = 0 less than r
    above the cord, the contact point on the cord, (0, y, h(y)))."""

    t: float
    position: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray
    part: str = "mesh"

    @property
    def y(self) -> float:
        return float(self.position[1])

    @property
    def z(self) -> float:
        return float(self.position[2])


@dataclass(frozen=True)
class Apex:
    """Highest point: time [s] and position [m] (the start if the ball starts going down)."""

    t: float
    position: np.ndarray

    @property
    def z(self) -> float:
        return float(self.position[2])
