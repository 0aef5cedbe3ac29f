"""Predicted bounces of measured serves, and their misses in length and width.

A serve is flown from its impact point with its measured speed and spin, aimed (elevation and
heading solved, :func:`tennislab.calibrate.aim.aim_through_net`) so that it crosses the net plane
at its measured net point; its predicted bounce is compared with the measured one.

* The flight stops where the ball centre reaches z = r (tennislab's landing); the tracker's
  bounce has the ball centre at z_b ~ 0.03 m.  The predicted point is carried along the landing
  velocity to z = z_b (a straight extension over a few millimetres of height: a shift of
  (r - z_b) / tan(descent angle), about 1 cm for serves) so that both are compared at one height.
* **length** = (predicted - measured) . e, along the unit vector e from the impact to the measured
  bounce seen from above (> 0: the prediction lands long); **width** = (predicted - measured) . n,
  n = e turned 90 deg to the left (> 0: the prediction lands to the left of the measured bounce,
  seen from the server; < 0: to the right); **miss** = the distance between the two points.

Spin axis (:class:`SpinAxis`): the tracker gives the rate only.  An assumption gives, per serve
family (:data:`~tennislab.calibrate.serves.FAMILIES`), the fractions (f_top, f_side) of the rate
about the topspin axis and the sidespin axis of :mod:`tennislab.core.launch` (the rest along the
path, which has no Magnus force): pure topspin is (1, 0); an axis angle g across the path is
(cos g, sin g) (g = +90 deg curves the ball to its left).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.calibrate.aim import aim_through_net
from tennislab.calibrate.serves import FAMILIES, Serves
from tennislab.core.flight import FlightParams
from tennislab.core.launch import SPIN_AXES_DEG, spin_axis_angle
from tennislab.errors import InputError


@dataclass(frozen=True)
class SpinAxis:
    """An assumed spin axis per serve family (fractions of the measured rate; module docstring).

    ``top`` and ``side`` hold one value per family of :data:`FAMILIES` (flat, slice, kick, pronated, other);
    ``rate_scale`` multiplies the tracker's rate (0: no spin at all).
    """

    name: str
    top: tuple[float, ...]
    side: tuple[float, ...]
    rate_scale: float = 1.0

    def __post_init__(self):
        if len(self.top) != len(FAMILIES) or len(self.side) != len(FAMILIES):
            raise InputError(f"spin_axis: need one (top, side) pair per family ({', '.join(FAMILIES)})")
        for t, s in zip(self.top, self.side):
            if not (math.isfinite(t) and math.isfinite(s)) or t * t + s * s > 1.0 + 1e-9:
                raise InputError(
                    f"spin_axis: fractions (top {t:g}, side {s:g}) must be finite with top^2 + side^2 <= 1"
                )

    @classmethod
    def angle(cls, degrees: float, name: str | None = None) -> SpinAxis:
        """The same axis angle g [deg] across the path for every family (0 = topspin, 90 = sidespin left)."""
        g = math.radians(degrees)
        c, s = round(math.cos(g), 15), round(math.sin(g), 15)
        return cls(name or f"{degrees:g}deg", (c,) * len(FAMILIES), (s,) * len(FAMILIES))

    @classmethod
    def none(cls) -> SpinAxis:
        """No spin (the tracker's rate ignored)."""
        return cls("none", (1.0,) * len(FAMILIES), (0.0,) * len(FAMILIES), rate_scale=0.0)

    @classmethod
    def by_family(cls, values: dict, name: str = "by-family") -> SpinAxis:
        """Fractions per family: ``{"flat": (top, side), ...}``; families not given keep pure topspin."""
        unknown = sorted(set(values) - set(FAMILIES))
        if unknown:
            raise InputError(f"spin_axis: unknown serve family {unknown[0]!r}; allowed: {', '.join(FAMILIES)}")
        top = tuple(float(values.get(f, (1.0, 0.0))[0]) for f in FAMILIES)
        side = tuple(float(values.get(f, (1.0, 0.0))[1]) for f in FAMILIES)
        return cls(name, top, side)

    @classmethod
    def parse(cls, spec) -> SpinAxis:
        """From ``none``, an axis name of :data:`~tennislab.core.launch.SPIN_AXES_DEG` (``topspin``,
        ``sidespin``, ...) or an angle [deg]; a :class:`SpinAxis` is returned as is."""
        if isinstance(spec, SpinAxis):
            return spec
        if isinstance(spec, str) and spec.strip().lower() == "none":
            return cls.none()
        g = math.degrees(spin_axis_angle(spec))
        name = spec.strip().lower() if isinstance(spec, str) and spec.strip().lower() in SPIN_AXES_DEG else None
        return cls.angle(g, name)

    def fractions(self, family) -> tuple[np.ndarray, np.ndarray]:
        """(f_top, f_side) per serve from its family label."""
        idx = np.array([FAMILIES.index(f) for f in family], dtype=int)
        return np.asarray(self.top)[idx], np.asarray(self.side)[idx]

    def to_dict(self) -> dict:
        per = {f: {"top": t, "side": s} for f, t, s in zip(FAMILIES, self.top, self.side)}
        angle = {
            f: (math.degrees(math.atan2(s, t)) if (t or s) else None) for f, t, s in zip(FAMILIES, self.top, self.side)
        }
        return {"name": self.name, "rate_scale": self.rate_scale, "fractions": per, "angle_deg": angle}


@dataclass(frozen=True)
class Prediction:
    """Predicted bounces of N serves and their misses (arrays of N; metres, m/s, seconds).

    ``bounce`` (N, 2) predicted (x, y) at the measured bounce height; ``length``, ``width``,
    ``miss`` as in the module docstring; ``converged`` marks serves whose aim matched the net
    point (the others are NaN); ``speed_at_bounce`` [m/s] and ``flight_time`` [s] of the flight.
    """

    bounce: np.ndarray
    length: np.ndarray
    width: np.ndarray
    miss: np.ndarray
    converged: np.ndarray
    elevation: np.ndarray
    heading: np.ndarray
    speed_at_bounce: np.ndarray
    flight_time: np.ndarray


def predict_bounces(
    serves: Serves,
    params: FlightParams,
    axis: SpinAxis,
    *,
    start: tuple[np.ndarray, np.ndarray] | None = None,
    speed_scale: float = 1.0,
) -> Prediction:
    """Fly every serve through its net point and compare its bounce with the measured one.

    ``speed_scale`` multiplies the measured speeds (a sensitivity to a tracker speed bias; 1 = as
    measured); ``start`` optional (elevation, heading) [rad] to start the aim from.
    """
    ft, fs = axis.fractions(serves.family)
    aim = aim_through_net(
        serves.impact,
        serves.speed * speed_scale,
        serves.spin * axis.rate_scale,
        serves.net,
        params,
        f_top=ft,
        f_side=fs,
        start=start,
    )
    tab = aim.table
    zb = serves.bounce[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        dt = (tab["land_z"] - zb) / (-tab["land_vz"])
    px = tab["land_x"] + tab["land_vx"] * dt
    py = tab["land_y"] + tab["land_vy"] * dt
    ok = aim.converged & np.isfinite(px) & np.isfinite(py)
    px = np.where(ok, px, np.nan)
    py = np.where(ok, py, np.nan)
    d = np.stack([px - serves.bounce[:, 0], py - serves.bounce[:, 1]], axis=1)
    e = serves.direction
    length = d[:, 0] * e[:, 0] + d[:, 1] * e[:, 1]
    width = -d[:, 0] * e[:, 1] + d[:, 1] * e[:, 0]
    speed = np.sqrt(tab["land_vx"] ** 2 + tab["land_vy"] ** 2 + tab["land_vz"] ** 2)
    return Prediction(
        bounce=np.stack([px, py], axis=1),
        length=length,
        width=width,
        miss=np.hypot(length, width),
        converged=ok,
        elevation=aim.elevation,
        heading=aim.heading,
        speed_at_bounce=np.where(ok, speed, np.nan),
        flight_time=np.where(ok, tab["land_t"] + dt, np.nan),
    )
