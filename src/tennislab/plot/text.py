"""Numbers and names as people read them: the words of plot titles, CLI lines and report cells.

Nothing here computes physics or reads a file; the JSON keeps every number at full precision, and
these helpers only say them (``"in by 7.6 mm"``, ``"2500 rpm topspin"``, ``"1115 ± 4922 rpm"``).
Conventions: a signed distance of a mark to a line is positive inside (docs/linecall.md); a spin axis
angle is the launch vocabulary's (:mod:`tennislab.core.launch`: 0 topspin, 180 backspin, +90
sidespin curving the ball to its left).
"""

from __future__ import annotations

import math

#: named spin-axis angles [deg] (the launch vocabulary) and how the axis is said
AXIS_WORDS = (
    (0.0, "topspin"),
    (180.0, "backspin"),
    (90.0, "sidespin (curving left)"),
    (-90.0, "sidespin (curving right)"),
)
#: an axis angle within this many degrees of a named one is said by that name [deg]
AXIS_SNAP_DEG = 2.5


def num(x, digits: int = 1) -> str:
    """``x`` with ``digits`` decimals ("–" for None or a non-finite number); ``-0.0`` is said ``0``."""
    if x is None or not math.isfinite(float(x)):
        return "–"
    s = f"{float(x):.{digits}f}"
    return s[1:] if s.startswith("-") and float(s) == 0.0 else s


def length_mm(mm: float, digits: int = 1) -> str:
    """A length given in mm as people say it: mm below a metre, m (2 decimals) above."""
    a = abs(float(mm))
    return f"{num(a / 1000, 2)} m" if a >= 1000 else f"{num(a, digits)} mm"


def in_out_by(distance_mm: float | None, digits: int = 1) -> str:
    """A signed distance of a mark to a line [mm] (positive: in) in words: ``"in by 7.6 mm"``,
    ``"out by 0.6 mm"``, ``"out by 5.49 m"``."""
    if distance_mm is None or not math.isfinite(float(distance_mm)):
        return "–"
    return f"{'in' if distance_mm >= 0 else 'out'} by {length_mm(distance_mm, digits)}"


def _wrap(angle_deg: float) -> float:
    """An angle in (-180, 180] [deg]."""
    a = math.fmod(float(angle_deg), 360.0)
    if a > 180.0:
        a -= 360.0
    if a <= -180.0:
        a += 360.0
    return a


def spin_axis_name(angle_deg: float | None) -> str:
    """The spin axis in words: ``"topspin"``, ``"backspin"``, ``"sidespin (curving left)"``, or for
    an axis in between ``"topspin and sidespin to the left (axis 30°)"``; ``"along the path"`` for
    None (spin about the direction of flight, which has no axis angle)."""
    if angle_deg is None or not math.isfinite(float(angle_deg)):
        return "along the path"
    a = _wrap(angle_deg)
    for ref, word in AXIS_WORDS:
        if abs(_wrap(a - ref)) <= AXIS_SNAP_DEG:
            return word
    fwd = "topspin" if abs(a) < 90 else "backspin"
    side = "to the left" if a > 0 else "to the right"
    return f"{fwd} and sidespin {side} (axis {a:.0f}°)"


def spin_words(rpm: float | None, axis_deg: float | None) -> str:
    """A spin in words: ``"2500 rpm topspin"``; ``"no spin"`` below 0.5 rpm."""
    if rpm is None or not math.isfinite(float(rpm)):
        return "–"
    if abs(rpm) < 0.5:
        return "no spin"
    return f"{num(rpm, 0)} rpm {spin_axis_name(axis_deg)}"


def plus_minus(value: float | None, sigma: float | None, unit: str = "", digits: int = 0) -> str:
    """A fitted quantity with its uncertainty: ``"1115 ± 4922 rpm"`` (no ± when sigma is None)."""
    u = f" {unit}" if unit else ""
    if sigma is None or not math.isfinite(float(sigma)):
        return f"{num(value, digits)}{u}"
    return f"{num(value, digits)} ± {num(sigma, digits)}{u}"


def spin_fit_words(spin: dict) -> str:
    """A fitted spin (the ``spin`` of a line call's ``to_dict()``) with its 1σ: the rate with the
    uncertainty of the whole vector (the root sum of the components' variances, an upper bound of the
    rate's), then each component with its own; a rate within 2σ of zero is said to be indistinguishable
    from no spin.  ``"2066 ± 2110 rpm, not told apart from no spin (topspin +619 ± 183, ...)"``."""
    keys = ("topspin", "sidespin", "along_path")
    sig = [spin.get(f"{k}_sigma_rpm") for k in keys]
    known = [float(s) for s in sig if s is not None]
    total = math.sqrt(sum(s * s for s in known)) if len(known) == len(sig) else None
    head = plus_minus(spin["rpm"], total, "rpm")
    if total is not None and spin["rpm"] < 2 * total:
        head += ", not told apart from no spin"
    parts = []
    for k, s in zip(keys, sig):
        v = spin.get(f"{k}_rpm")
        if v is not None:
            parts.append(f"{k.replace('_', ' ')} {v:+.0f}" + ("" if s is None else f" ± {s:.0f}"))
    return head + (f" ({', '.join(parts)})" if parts else "")


def player_words(player) -> str:
    """A player profile as people name it: ``"professional"``; a profile whose height or racket speed was
    changed (named ``"professional*"`` in the JSON) by its numbers: ``"professional, 2.5 m, 35 m/s"``."""
    name = str(player.name)
    if name.endswith("*"):
        return f"{name[:-1]}, {round(player.impact_height, 2):g} m, {round(player.racket_speed, 1):g} m/s"
    return name


def format_duration(s: float) -> str:
    """A duration [s] as a person says it (s, min, h, days, years, three significant digits)."""
    for unit, size in (("years", 365.25 * 86400), ("days", 86400), ("h", 3600), ("min", 60)):
        if s >= size:
            return f"{s / size:.3g} {unit}"
    return f"{s:.3g} s"
