"""The two-roller ball launcher of Wojcicki, Pucilowski & Kulesza (2010; seed 002): settings, ranges, launch states.

The paper (Acta Mech. Autom., section 2 "Brief for design") fixes the ranges and steps of every setting:

==================  ===============  ==========  ===================================
setting             range            step        field of :class:`Settings`
==================  ===============  ==========  ===================================
launch height       0.1 - 3.0 m      0.1 m       ``height_m`` (ball centre)
ball speed          30 - 200 km/h    1 km/h      ``speed_kmh``
elevation           -20 - 80 deg     1 deg       ``elevation_deg``
heading             -40 - 40 deg     1 deg       ``heading_deg``
spin-axis rotation  -180 - 180 deg   1 deg       ``spin_axis_deg``
spin                0 - 2000 rpm     1 rpm       ``spin_rpm``
launch interval     1 - 15 s         1 s         (per drill shot, :meth:`MachineSpec.check_interval`)
==================  ===============  ==========  ===================================

The seed gives "up to 3 m" for the height; its lower bound is ours: 0.1 m (a
ball centre must be above its radius).  Roller geometry (seed section 4.2):
roller radius r_r = 0.1 m, distance between roller axes d_sr = 0.25 m.

Conventions (court frame of :mod:`tennislab.core.court`; the machine faces +x)
-------------------------------------------------------------------------------
* direction of launch d = (cos a cos b, cos a sin b, sin a) for elevation a
  (above the horizontal) and heading b (positive toward +y, i.e. to the left
  of a machine facing +x);
* spin axis, for spin-axis rotation g (the throwing mechanism turned about its
  symmetry axis, seed section 2): omega = w (cos g h + sin g u) with
  h = unit(e_z x d) (horizontal, to the left of the flight) and u = d x h (up,
  perpendicular to d).  Hence g = 0 is pure topspin (the ball dips),
  g = 180 (or -180) pure backspin / slice (the ball floats), g = +90 sidespin
  curving to the left (+y), g = -90 sidespin curving to the right (-y).
  Magnus force along omega x v (:mod:`tennislab.core.dynamics`).
* Default position: ``(-12.385, 0.0)``, on the centre line 0.5 m behind the
  outer edge of the near baseline (x = -11.885 m), so the machine stands off
  the court and shoots toward the far half (x > 0).  Any position is allowed.

References
----------
.. [1] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002),
    section 2 (settings, ranges and steps)
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, fields, replace

import numpy as np

from tennislab.core import launch
from tennislab.errors import InputError, check_finite, check_range, check_vector
from tennislab.results import OldAsDict
from tennislab.units import DEG, KMH, RPM

#: The paper behind the launcher (seed 002), as help texts and outputs name it.
PAPER = "Wójcicki, Puciłowski & Kulesza 2010"

#: Default machine position on court [m]: centre line, 0.5 m behind the near baseline.
DEFAULT_POSITION = (-12.385, 0.0)


@dataclass(frozen=True)
class Range:
    """An adjustable setting: ``lo``..``hi`` in steps of ``step``, in ``unit`` (edge units)."""

    lo: float
    hi: float
    step: float
    unit: str

    def check(self, name: str, value: float) -> float:
        """Return ``float(value)`` if within [lo, hi] (with a 1e-9 tolerance), else InputError."""
        v = check_finite(name, value)
        tol = 1e-9 * max(1.0, abs(self.step))
        if v < self.lo - tol or v > self.hi + tol:
            raise InputError(
                f"{name}: {v:g} {self.unit} is outside the allowed range [{self.lo:g}, {self.hi:g}] {self.unit}"
            )
        return min(max(v, self.lo), self.hi)

    def quantise(self, value):
        """Nearest step(s) (``lo + k step``), clipped to the range; works on arrays."""
        v = np.asarray(value, dtype=float)
        k = np.round((v - self.lo) / self.step)
        q = np.clip(self.lo + k * self.step, self.lo, self.hi)
        q = np.round(q, 9) + 0.0  # remove binary noise (0.30000000000000004 -> 0.3) and -0.0
        return float(q) if q.ndim == 0 else q

    def on_step(self, value: float) -> bool:
        """True if ``value`` lies on a step (within 1e-6 step)."""
        k = (float(value) - self.lo) / self.step
        return abs(k - round(k)) < 1e-6

    def neighbours(self, value: float, extra: int = 1) -> np.ndarray:
        """Steps around ``value``: floor - extra .. ceil + extra, within the range."""
        k = (float(value) - self.lo) / self.step
        ks = np.arange(math.floor(k) - extra, math.ceil(k) + extra + 1)
        vals = self.lo + ks * self.step
        vals = vals[(vals >= self.lo - 1e-9) & (vals <= self.hi + 1e-9)]
        return np.round(vals, 9)


@dataclass(frozen=True)
class Settings(OldAsDict):
    """One shot's machine settings, in the machine's (edge) units.

    Attributes
    ----------
    height_m : launch height of the ball centre above the court [m]
    speed_kmh : ball speed at launch [km/h]
    elevation_deg : launch angle above the horizontal [deg]
    heading_deg : launch direction from +x, positive toward +y [deg]
    spin_rpm : spin rate [rpm]
    spin_axis_deg : spin-axis rotation: 0 topspin, 180 backspin, +90 curve to +y [deg]
    """

    height_m: float
    speed_kmh: float
    elevation_deg: float
    heading_deg: float
    spin_rpm: float = 0.0
    spin_axis_deg: float = 0.0

    def to_dict(self) -> dict:
        return {f.name: float(getattr(self, f.name)) for f in fields(self)}


#: Settings fields and the :class:`MachineSpec` range attribute that bounds each.
SETTING_RANGES = {
    "height_m": "height",
    "speed_kmh": "speed",
    "elevation_deg": "elevation",
    "heading_deg": "heading",
    "spin_rpm": "spin",
    "spin_axis_deg": "spin_axis",
}


@dataclass(frozen=True)
class MachineSpec:
    """The launcher: adjustable ranges and steps (seed 002 section 2), roller geometry, position.

    Attributes
    ----------
    height, speed, elevation, heading, spin, spin_axis, interval : :class:`Range`
        [m], [km/h], [deg], [deg], [rpm], [deg], [s] (defaults: seed 002 section 2)
    roller_radius : r_r [m] (0.1, seed 002 section 4.2)
    roller_axis_distance : d_sr, distance between the roller axes [m] (0.25, seed 002 section 4.2)
    position : (x, y) of the launch point on court [m] (default (-12.385, 0))
    """

    height: Range = Range(0.1, 3.0, 0.1, "m")
    speed: Range = Range(30.0, 200.0, 1.0, "km/h")
    elevation: Range = Range(-20.0, 80.0, 1.0, "deg")
    heading: Range = Range(-40.0, 40.0, 1.0, "deg")
    spin: Range = Range(0.0, 2000.0, 1.0, "rpm")
    spin_axis: Range = Range(-180.0, 180.0, 1.0, "deg")
    interval: Range = Range(1.0, 15.0, 1.0, "s")
    roller_radius: float = 0.1
    roller_axis_distance: float = 0.25
    position: tuple = DEFAULT_POSITION

    def __post_init__(self):
        check_range("roller_radius", self.roller_radius, 0.0, 1.0, "m", lo_open=True)
        check_range("roller_axis_distance", self.roller_axis_distance, 2 * self.roller_radius, 3.0, "m", lo_open=True)
        object.__setattr__(self, "position", check_vector("position", self.position, 2))
        for name in ("height", "speed", "elevation", "heading", "spin", "spin_axis", "interval"):
            r = getattr(self, name)
            if not (r.lo <= r.hi and r.step > 0):
                raise InputError(f"{name}: range needs lo <= hi and step > 0, got {r}")

    def with_position(self, x: float, y: float) -> MachineSpec:
        """The same machine standing at (x, y) [m]."""
        return replace(self, position=(x, y))

    def range_of(self, field_name: str) -> Range:
        """The :class:`Range` bounding a :class:`Settings` field."""
        return getattr(self, SETTING_RANGES[field_name])

    def validate(self, settings: Settings, require_steps: bool = False) -> Settings:
        """Check every field against its range (and step if ``require_steps``); return ``settings``.

        Raises :class:`InputError` naming the field and its allowed range.
        """
        for fname, attr in SETTING_RANGES.items():
            rng = getattr(self, attr)
            v = rng.check(fname, getattr(settings, fname))
            if require_steps and not rng.on_step(v):
                raise InputError(
                    f"{fname}: {v:g} {rng.unit} is not on the machine's {rng.step:g} "
                    f"{rng.unit} steps in [{rng.lo:g}, {rng.hi:g}] {rng.unit}"
                )
        return settings

    def quantise(self, settings: Settings) -> Settings:
        """Validate the ranges, then round every field to the nearest machine step."""
        self.validate(settings)
        return Settings(**{f: self.range_of(f).quantise(getattr(settings, f)) for f in SETTING_RANGES})

    def check_interval(self, interval_s: float, name: str = "interval_s") -> float:
        """Validate a launch interval [s] (range and 1 s steps) and return it."""
        v = self.interval.check(name, interval_s)
        if not self.interval.on_step(v):
            raise InputError(
                f"{name}: {v:g} s is not on the machine's {self.interval.step:g} s steps "
                f"in [{self.interval.lo:g}, {self.interval.hi:g}] s"
            )
        return v


def launch_direction(elevation_rad, heading_rad):
    """Unit launch direction d (..., 3) and the spin basis h (left), u (up): :mod:`tennislab.core.launch`."""
    h, u = launch.spin_basis(elevation_rad, heading_rad)
    return launch.direction(elevation_rad, heading_rad), h, u


def settings_columns(*settings) -> np.ndarray:
    """Scalars and arrays of settings broadcast together: one (k, *shape) float array, row i setting i
    (broadcast by assignment: ``np.broadcast_arrays`` costs ~30 us a call, a hot path of the aim's search)."""
    cols = [np.asarray(x, dtype=float) for x in settings]
    try:
        shape = np.broadcast(*cols).shape
    except ValueError as exc:
        raise InputError(f"machine_states: settings arrays do not broadcast together ({exc})") from None
    out = np.empty((len(cols),) + shape)
    for i, x in enumerate(cols):
        out[i] = x
    return out


def machine_states(
    spec: MachineSpec, height_m, speed_kmh, elevation_deg, heading_deg, spin_rpm=0.0, spin_axis_deg=0.0
) -> np.ndarray:
    """Initial flight states (N, 9) of machine settings, for :func:`tennislab.core.flight.fly_batch`.

    Every argument is a scalar or an array (edge units: m, km/h, deg, rpm, deg);
    they broadcast together and are flattened to N rows of (x, y, z, vx, vy, vz,
    wx, wy, wz) in SI units, launched from ``spec.position`` at height
    ``height_m``.  Direction and spin vector: :mod:`tennislab.core.launch` (the
    one statement of the convention).  No range check here (hot path): call
    :meth:`MachineSpec.validate` or :func:`validate_arrays` first for user input.
    """
    cols = settings_columns(height_m, speed_kmh, elevation_deg, heading_deg, spin_rpm, spin_axis_deg)
    h, v, a, b, w, g = cols.reshape(6, -1)
    pos = np.empty((h.size, 3))
    pos[:, 0], pos[:, 1], pos[:, 2] = spec.position[0], spec.position[1], h
    top, side = launch.axis_components(w * RPM, g * DEG)
    # launch_states without its broadcasting checks (every column is (N,) here): the same arithmetic
    return launch.launch_rows(pos, h.size, v * KMH, a * DEG, b * DEG, top, side, 0.0)


def settings_states(spec: MachineSpec, settings) -> np.ndarray:
    """:func:`machine_states` for one :class:`Settings` or a sequence of them."""
    if isinstance(settings, Settings):
        settings = [settings]
    cols = {f: np.array([getattr(s, f) for s in settings], dtype=float) for f in SETTING_RANGES}
    return machine_states(spec, **cols)


def validate_arrays(spec: MachineSpec, **arrays) -> None:
    """Range-check arrays of settings (keywords: :class:`Settings` field names); InputError on the first bad one."""
    for fname, vals in arrays.items():
        if fname not in SETTING_RANGES:
            raise InputError(f"{fname}: unknown setting; allowed: {', '.join(SETTING_RANGES)}")
        rng = spec.range_of(fname)
        v = np.asarray(vals, dtype=float).reshape(-1)
        bad = ~np.isfinite(v) | (v < rng.lo - 1e-9) | (v > rng.hi + 1e-9)
        if bad.any():
            rng.check(fname, v[np.argmax(bad)])


DEFAULT_SPEC = MachineSpec()


def machine_entry(spec: MachineSpec, position=None) -> dict:
    """The ``machine`` entry of a launcher result: where it stands [m] and its rollers [m]."""
    return {
        "position": list(spec.position if position is None else position),
        "roller_radius_m": spec.roller_radius,
        "roller_axis_distance_m": spec.roller_axis_distance,
    }


#: Speed units of the launch vocabulary: parameter name -> (km/h per unit, unit label).
SPEED_UNITS = {"speed_kmh": (1.0, "km/h"), "speed_ms": (3.6, "m/s"), "speed_mph": (1.609344, "mph")}


def speed_in_kmh(
    spec: MachineSpec, speed_kmh=None, speed_ms=None, speed_mph=None, *, required: bool = True
) -> float | None:
    """The asked ball speed [km/h] from exactly one of its units, range-checked in the unit given.

    The error names the parameter used (``speed_ms: 70 m/s is outside the allowed range [8.333,
    55.56] m/s``).  None when no speed is given and ``required`` is False.
    """
    given = [(n, v) for n, v in zip(SPEED_UNITS, (speed_kmh, speed_ms, speed_mph)) if v is not None]
    if len(given) > 1:
        raise InputError("speed_kmh: give the ball speed once (speed_kmh, speed_ms or speed_mph)")
    if not given:
        if required:
            raise InputError(f"speed_kmh: required, in [{spec.speed.lo:g}, {spec.speed.hi:g}] km/h")
        return None
    name, v = given[0]
    factor, unit = SPEED_UNITS[name]
    v = check_finite(name, v)
    r = spec.speed
    if not (r.lo - 1e-9 <= v * factor <= r.hi + 1e-9):
        raise InputError(
            f"{name}: {v:g} {unit} is outside the allowed range [{r.lo / factor:.4g}, {r.hi / factor:.4g}] {unit}"
        )
    return min(max(v * factor, r.lo), r.hi)


#: Old names of this module and what they are now (one name, one thing: ``core.launch.launch_states`` and
#: ``core.launch.spin_vector`` take the spin's launch-frame components, not a machine's settings).
_RENAMED = {
    "launch_states": ("machine_states", "tennislab.core.launch.launch_states takes launch-frame spin components"),
    "spin_vector": ("launch_spin", "tennislab.core.launch_spin, the same arguments"),
}


def __getattr__(name: str):
    """``launch_states`` (now :func:`machine_states`) and ``spin_vector`` (now
    :func:`tennislab.core.launch.launch_spin`): kept working with a :class:`DeprecationWarning`."""
    if name in _RENAMED:
        new, why = _RENAMED[name]
        warnings.warn(f"tennislab.launcher.machine.{name} is now {new} ({why})", DeprecationWarning, stacklevel=2)
        return launch.launch_spin if new == "launch_spin" else machine_states
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
