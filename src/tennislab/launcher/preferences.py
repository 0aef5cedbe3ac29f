"""What a coach asks of a shot besides its target: trajectory preferences and setting tolerances.

The same two small parameter sets serve ``aim`` (the search over the machine's steps), the
database ``lookup`` (a filter on the stored hits) and drills (per shot), so that a drive asked
for is a drive in every path.

:class:`Preferences`
    ``trajectory`` ``low`` (the rising branch of distance against elevation: drives, feeds),
    ``high`` (the falling branch: lobs) or ``any``; ``max_apex_m`` the highest ball-centre height
    [m]; ``net_clearance_m`` (MIN, MAX) the band of clearance over the net cord [m] (only for
    flights that cross the net); ``max_flight_time_s`` the longest time to the bounce [s].
:class:`Tolerances`
    how far the machine may move the speed [km/h] and the spin [rpm] from what was asked to
    land nearer the target (0 = exact, up to the rounding to the machine's steps).  In ``aim`` the
    spin tolerance bounds the change of the spin *vector* |omega - omega_asked| (rate and axis
    together: at 1500 rpm a 100 rpm tolerance lets the axis turn by up to 3.8 deg); a table
    lookup, whose file holds a few spin axes, applies it to the spin rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.core.launch import axis_components
from tennislab.errors import InputError, check_range
from tennislab.results import OldAsDict

#: Trajectory preferences by name.
TRAJECTORIES = ("low", "high", "any")
#: Branch codes stored per hit in the database (``hits.branch``).
BRANCH_LOW, BRANCH_HIGH = 0, 1


@dataclass(frozen=True)
class Preferences(OldAsDict):
    """Trajectory preferences (module docstring); every bound optional (None = no bound)."""

    trajectory: str = "low"
    max_apex_m: float | None = None
    net_clearance_m: tuple[float, float] | None = None
    max_flight_time_s: float | None = None

    def __post_init__(self):
        if self.trajectory not in TRAJECTORIES:
            raise InputError(f"trajectory: {self.trajectory!r} is not one of {', '.join(TRAJECTORIES)}")
        if self.max_apex_m is not None:
            object.__setattr__(self, "max_apex_m", check_range("max_apex_m", self.max_apex_m, 0, 100, "m", True))
        if self.max_flight_time_s is not None:
            object.__setattr__(
                self,
                "max_flight_time_s",
                check_range("max_flight_time_s", self.max_flight_time_s, 0, 60, "s", lo_open=True),
            )
        if self.net_clearance_m is not None:
            band = tuple(self.net_clearance_m)
            if len(band) != 2:
                raise InputError(f"net_clearance_m: expected MIN MAX [m], got {len(band)} values")
            lo = check_range("net_clearance_m", band[0], 0, 50, "m")
            hi = check_range("net_clearance_m", band[1], 0, 50, "m")
            if lo > hi:
                raise InputError(f"net_clearance_m: MIN {lo:g} m is above MAX {hi:g} m")
            object.__setattr__(self, "net_clearance_m", (lo, hi))

    @property
    def branches(self) -> tuple[str, ...]:
        """The aiming branches this preference allows, preferred first."""
        return ("low", "high") if self.trajectory == "any" else (self.trajectory,)

    def check_height(self, height_m: float) -> None:
        """Refuse a maximum apex below the launch height (no flight can meet it)."""
        if self.max_apex_m is not None and self.max_apex_m < height_m:
            raise InputError(
                f"max_apex_m: {self.max_apex_m:g} m is below the launch height {height_m:g} m; no flight stays under it"
            )

    def accepts(self, apex_z_m, net_clearance_m, flight_time_s) -> np.ndarray:
        """Mask of the flights meeting the bounds (a NaN clearance, no net crossing, passes the band)."""
        apex = np.asarray(apex_z_m, dtype=float)
        ok = np.ones(apex.shape, bool)
        with np.errstate(invalid="ignore"):
            if self.max_apex_m is not None:
                ok &= apex <= self.max_apex_m
            if self.max_flight_time_s is not None:
                ok &= np.asarray(flight_time_s, dtype=float) <= self.max_flight_time_s
            if self.net_clearance_m is not None:
                c = np.asarray(net_clearance_m, dtype=float)
                ok &= np.isnan(c) | ((c >= self.net_clearance_m[0]) & (c <= self.net_clearance_m[1]))
        return ok

    def violation(self, apex_z_m, net_clearance_m, flight_time_s, what: str) -> str:
        """A one-line reason naming the first bound that none of the flights meets (their range in it)."""
        apex = np.asarray(apex_z_m, dtype=float)
        clr = np.asarray(net_clearance_m, dtype=float)
        t = np.asarray(flight_time_s, dtype=float)
        if apex.size == 0:
            return f"trajectory: none of the {what} lands"
        if self.max_apex_m is not None and not (apex <= self.max_apex_m).any():
            return (
                f"max_apex_m: the {what} peak at {np.nanmin(apex):.2f}-{np.nanmax(apex):.2f} m, above the "
                f"allowed {self.max_apex_m:g} m"
            )
        if self.max_flight_time_s is not None and not (t <= self.max_flight_time_s).any():
            return (
                f"max_flight_time_s: the {what} take {np.nanmin(t):.2f}-{np.nanmax(t):.2f} s, longer than the "
                f"allowed {self.max_flight_time_s:g} s"
            )
        if self.net_clearance_m is not None:
            lo, hi = self.net_clearance_m
            fin = clr[np.isfinite(clr)]
            if fin.size and not ((fin >= lo) & (fin <= hi)).any():
                return (
                    f"net_clearance_m: the {what} clear the net by {fin.min():.2f}-{fin.max():.2f} m, outside "
                    f"the allowed [{lo:g}, {hi:g}] m"
                )
        return f"trajectory: none of the {what} meets every preference together ({self.describe()})"

    def describe(self) -> str:
        parts = [f"trajectory {self.trajectory}"]
        if self.max_apex_m is not None:
            parts.append(f"apex <= {self.max_apex_m:g} m")
        if self.net_clearance_m is not None:
            parts.append(f"net clearance {self.net_clearance_m[0]:g}-{self.net_clearance_m[1]:g} m")
        if self.max_flight_time_s is not None:
            parts.append(f"flight <= {self.max_flight_time_s:g} s")
        return ", ".join(parts)

    def to_dict(self) -> dict:
        return {
            "trajectory": self.trajectory,
            "max_apex_m": self.max_apex_m,
            "net_clearance_m": None if self.net_clearance_m is None else list(self.net_clearance_m),
            "max_flight_time_s": self.max_flight_time_s,
        }


#: Default turn of the spin axis allowed while aiming [deg]: the ball keeps cos 10 deg = 98.5 % of its
#: spin about the asked axis and gains at most sin 10 deg = 17 % of it about the perpendicular one, so a
#: topspin drive stays a topspin drive; the turn moves the bounce across the flight, which the 1 deg
#: heading steps alone cannot do finer than ~0.37 m at 21 m (docs/launcher.md, "Aiming on the steps").
DEFAULT_SPIN_AXIS_TOLERANCE_DEG = 10.0


@dataclass(frozen=True)
class Tolerances(OldAsDict):
    """How far ``aim`` may move speed [km/h] and spin [rpm] from what was asked (module docstring)."""

    speed_kmh: float = 3.0
    spin_rpm: float = 100.0
    spin_axis_deg: float = DEFAULT_SPIN_AXIS_TOLERANCE_DEG

    def __post_init__(self):
        object.__setattr__(self, "speed_kmh", check_range("speed_tolerance_kmh", self.speed_kmh, 0, 170, "km/h"))
        object.__setattr__(self, "spin_rpm", check_range("spin_tolerance_rpm", self.spin_rpm, 0, 2000, "rpm"))
        object.__setattr__(
            self, "spin_axis_deg", check_range("spin_axis_tolerance_deg", self.spin_axis_deg, 0, 180, "deg")
        )

    def allows(self, spin_rpm, spin_axis_deg, asked_rpm: float, asked_axis_deg: float) -> np.ndarray:
        """Mask of spins (rate [rpm], axis [deg]) within tolerance of the asked one.

        Within ``spin_rpm`` as a vector, or (with ``spin_axis_deg`` > 0) a rate within ``spin_rpm``
        of the asked rate about an axis turned by at most ``spin_axis_deg``.
        """
        w = np.asarray(spin_rpm, dtype=float)
        g = np.asarray(spin_axis_deg, dtype=float)
        ok = spin_change_rpm(w, g, asked_rpm, asked_axis_deg) <= self.spin_rpm + 1e-9
        if self.spin_axis_deg > 0 and asked_rpm > 0:
            ok |= (np.abs(w - asked_rpm) <= self.spin_rpm + 1e-9) & (
                np.abs(wrap_deg(g - asked_axis_deg)) <= self.spin_axis_deg + 1e-9
            )
        return ok

    def to_dict(self) -> dict:
        return {"speed_kmh": self.speed_kmh, "spin_rpm": self.spin_rpm, "spin_axis_deg": self.spin_axis_deg}


#: Exact: only the rounding of the asked speed and spin to the machine's steps.
EXACT = Tolerances(0.0, 0.0, 0.0)


def wrap_deg(angle):
    """Angle(s) [deg] wrapped into [-180, 180)."""
    return (np.asarray(angle, dtype=float) + 180.0) % 360.0 - 180.0


def spin_rpm_components(spin_rpm, spin_axis_deg) -> np.ndarray:
    """(..., 2) components of a spin vector about its flight [rpm]: (topspin axis h, up axis u) of core.launch
    (:func:`tennislab.core.launch.axis_components` in rpm and degrees)."""
    top, side = axis_components(spin_rpm, np.radians(np.asarray(spin_axis_deg, dtype=float)))
    return np.stack([top, side], axis=-1)


def __getattr__(name: str):
    """``spin_components``: the old name of :func:`spin_rpm_components`, kept working with a
    :class:`DeprecationWarning` (``linecall``'s ``spin_components`` describes a fitted spin)."""
    if name == "spin_components":
        import warnings

        warnings.warn(
            "tennislab.launcher.preferences.spin_components is now spin_rpm_components",
            DeprecationWarning,
            stacklevel=2,
        )
        return spin_rpm_components
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def spin_change_rpm(spin_rpm, spin_axis_deg, asked_rpm: float, asked_axis_deg: float):
    """|omega - omega_asked| [rpm] between spin vectors given by rate and axis angle."""
    d = spin_rpm_components(spin_rpm, spin_axis_deg) - spin_rpm_components(asked_rpm, asked_axis_deg)
    return np.hypot(d[..., 0], d[..., 1])


def isfinite_or_none(v) -> float | None:
    return None if v is None or not math.isfinite(float(v)) else float(v)
