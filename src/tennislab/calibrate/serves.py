"""Measured serves (Hawk-Eye CourtVision summaries): their meaning, and the checks they must pass.

:func:`load_serves` turns the columns of :func:`tennislab.io.courtvision.read_serves` into a
:class:`Serves` set in SI units: the impact point (ball centre) [m], the speed just after impact
[m/s] (``spd`` is the displayed speed in km/h), the tracker's spin rate [rad/s] (axis unknown),
the net-plane crossing (y, z) [m] and the bounce (x, y, z) [m] (ball centre at the bounce,
z ~ 0.03 m).  The match name ``<tour>_<tournament>_<year><draw>`` (e.g.
``atp_roland_garros_2019SM043``) gives the tour, the tournament and the year.

:func:`check_serves` flags the serves whose summary points cannot be one free flight (the reasons
of :data:`REASONS`); the studies use the others.  The checks use geometry only (no flight model),
so they cannot favour one model.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, fields

import numpy as np

from tennislab.core.court import ITF_COURT, Court
from tennislab.errors import InputError
from tennislab.io.courtvision import read_serves
from tennislab.units import KMH, RPM

#: serve families for the spin-axis assumption: CourtVision's ``serve_type`` -> family.  The README
#: of the data reads "Pronated (kick)", but both labels occur in every event with different flights
#: (Kick serves are 9 km/h slower and, under one shared axis, land 25 cm longer than Pronated ones:
#: docs/validation.md), so each keeps its own family.
FAMILY_OF_TYPE = {"flat": "flat", "slice": "slice", "kick": "kick", "pronated": "pronated"}
FAMILIES = ("flat", "slice", "kick", "pronated", "other")  #: "other": Unclassified or no type

#: why a serve is left out of the studies (checked in this order; a serve gets the first that applies)
REASONS = {
    "speed": "speed outside 50-260 km/h",
    "spin": "spin rate outside 0-6000 rpm",
    "impact": "impact point not a serve's (|x| outside 10-14 m or z outside 1.5-3.6 m)",
    "same_side": "the bounce is not across the net from the impact",
    "net_contact": "the ball centre crosses the net plane less than a radius above the cord (touched the net)",
    "off_path": "the net point lies more than 0.75 m off the impact-bounce line (seen from above)",
    "below_chord": "the net point lies below the straight impact-bounce line (a flight curves down)",
    "duplicate": "impact, net and bounce points identical to another serve of the match (copied tracker data)",
}
OFF_PATH_M = 0.75  #: [m] largest sideways offset of the net point from the impact-bounce line
_MATCH = re.compile(r"^(atp|wta)_([a-z_]+?)_(\d{4})")


@dataclass(frozen=True)
class Serves:
    """A set of measured serves (arrays of N; SI units).

    Attributes
    ----------
    match, point_id : identifiers (text)
    serve_num : 1 or 2
    speed : speed just after impact [m/s]
    spin : tracker's spin rate [rad/s] (axis unknown)
    impact : (N, 3) impact point, ball centre [m]
    net : (N, 2) (y, z) of the ball centre where it crossed the net plane x = 0 [m]
    bounce : (N, 3) bounce point, ball centre [m]
    serve_type : CourtVision's type as written (``Flat``, ``Slice``, ``Pronated``, ``Kick``, ...)
    family : ``flat``, ``slice``, ``kick``, ``pronated`` or ``other`` (:data:`FAMILIES`)
    tour, tournament, year : from the match name (``""`` when it does not follow the pattern)
    line : line of each serve in its file
    """

    match: np.ndarray
    point_id: np.ndarray
    serve_num: np.ndarray
    speed: np.ndarray
    spin: np.ndarray
    impact: np.ndarray
    net: np.ndarray
    bounce: np.ndarray
    serve_type: np.ndarray
    family: np.ndarray
    tour: np.ndarray
    tournament: np.ndarray
    year: np.ndarray
    line: np.ndarray

    def __len__(self) -> int:
        return int(self.speed.size)

    def subset(self, mask) -> Serves:
        """The serves selected by a boolean mask or an index array."""
        return Serves(**{f.name: getattr(self, f.name)[mask] for f in fields(self)})

    @property
    def direction(self) -> np.ndarray:
        """(N, 2) unit vector from the impact to the measured bounce, seen from above."""
        d = self.bounce[:, :2] - self.impact[:, :2]
        return d / np.linalg.norm(d, axis=1)[:, None]

    def group(self, by: str) -> np.ndarray:
        """Group label of each serve: ``serve_type``, ``family``, ``tour``, ``tournament``, ``event``
        (tournament and year), ``tour_event``, ``serve_num`` or ``all``."""
        n = len(self)
        if by == "all":
            return np.array(["all"] * n, dtype=object)
        if by == "serve_type":
            return np.array([t if t else "(none)" for t in self.serve_type], dtype=object)
        if by in ("family", "tour", "tournament"):
            return np.array([t if t else "(unknown)" for t in getattr(self, by)], dtype=object)
        if by == "event":
            return np.array(
                [f"{a}_{b}" if a else "(unknown)" for a, b in zip(self.tournament, self.year)], dtype=object
            )
        if by == "tour_event":
            return np.array(
                [f"{t}_{a}_{b}" if a else "(unknown)" for t, a, b in zip(self.tour, self.tournament, self.year)],
                dtype=object,
            )
        if by == "serve_num":
            return np.array([f"serve {int(k)}" for k in self.serve_num], dtype=object)
        raise InputError(
            f"group: unknown grouping {by!r}; allowed: all, serve_type, family, tour, tournament, event, "
            "tour_event, serve_num"
        )


def _family(t: str) -> str:
    return FAMILY_OF_TYPE.get(t.strip().lower(), "other")


def serves_from_columns(cols: dict) -> Serves:
    """A :class:`Serves` set from the columns of :func:`tennislab.io.courtvision.parse_serves`."""
    match = np.asarray(cols["match"], dtype=object)
    parts = [_MATCH.match(str(m)) for m in match]
    n = match.size
    if n == 0:
        raise InputError("serves: no serves in the file")

    def xyz(prefix_x, prefix_y, prefix_z):
        return np.stack([np.asarray(cols[c], dtype=float) for c in (prefix_x, prefix_y, prefix_z)], axis=1)

    serve_type = np.asarray(cols.get("serve_type", np.array([""] * n, dtype=object)), dtype=object)
    return Serves(
        match=match,
        point_id=np.asarray(cols["point_ID"], dtype=object),
        serve_num=np.asarray(cols["serve_num"], dtype=float).astype(int),
        speed=np.asarray(cols["spd"], dtype=float) * KMH,
        spin=np.asarray(cols["spin_rpm"], dtype=float) * RPM,
        impact=xyz("x_ball_serve_impact", "y_ball_serve_impact", "z_ball_serve_impact"),
        net=np.stack([np.asarray(cols["y_net_serve"], dtype=float), np.asarray(cols["z_net_serve"], dtype=float)], 1),
        bounce=xyz("x_serve_bounce", "y_serve_bounce", "z_serve_bounce"),
        serve_type=serve_type,
        family=np.array([_family(str(t)) for t in serve_type], dtype=object),
        tour=np.array([p.group(1) if p else "" for p in parts], dtype=object),
        tournament=np.array([p.group(2) if p else "" for p in parts], dtype=object),
        year=np.array([p.group(3) if p else "" for p in parts], dtype=object),
        line=np.asarray(cols.get("line", np.arange(2, n + 2)), dtype=np.int64),
    )


def load_serves(path) -> Serves:
    """Read a CourtVision serves CSV (``../shared/realdata/courtvision_serves.csv``) as :class:`Serves`."""
    return serves_from_columns(read_serves(path))


def check_serves(serves: Serves, court: Court = ITF_COURT, radius: float = 0.0335) -> np.ndarray:
    """The reason each serve is left out (a key of :data:`REASONS`), or ``""`` for a usable serve.

    ``radius`` [m] is the ball radius of the net-contact check (the ball centre must pass at
    least one radius above the cord, whose height at y is the court's straight-cord profile).
    """
    n = len(serves)
    out = np.array([""] * n, dtype=object)

    def flag(mask, reason):
        sel = (out == "") & mask
        out[sel] = reason

    kmh = serves.speed / KMH
    flag(~((kmh >= 50.0) & (kmh <= 260.0)), "speed")
    rpm = serves.spin / RPM
    flag(~((rpm >= 0.0) & (rpm <= 6000.0)), "spin")
    xi, zi = serves.impact[:, 0], serves.impact[:, 2]
    flag(~((np.abs(xi) >= 10.0) & (np.abs(xi) <= 14.0) & (zi >= 1.5) & (zi <= 3.6)), "impact")
    xb = serves.bounce[:, 0]
    flag(~(np.sign(xi) * np.sign(xb) < 0), "same_side")
    ny, nz = serves.net[:, 0], serves.net[:, 1]
    cord = np.asarray(court.net_height(ny), dtype=float)
    flag(nz - cord - radius < 0.0, "net_contact")
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -xi / (xb - xi)
    y_line = serves.impact[:, 1] + t * (serves.bounce[:, 1] - serves.impact[:, 1])
    z_line = zi + t * (serves.bounce[:, 2] - zi)
    flag(~(np.abs(ny - y_line) <= OFF_PATH_M), "off_path")
    flag(~(nz >= z_line), "below_chord")
    key = np.round(np.hstack([serves.impact, serves.net, serves.bounce]), 4)
    seen: dict = {}
    for i in range(n):
        k = (serves.match[i], *key[i].tolist())
        seen.setdefault(k, []).append(i)
    dup = np.zeros(n, dtype=bool)
    for idx in seen.values():
        if len(idx) > 1:
            dup[idx] = True
    flag(dup, "duplicate")
    return out


def split_serves(serves: Serves, split: str = "parity") -> tuple[np.ndarray, np.ndarray, str]:
    """(fit mask, held-out mask, description) of a calibration split.

    ``parity``: the matches sorted by name and numbered from 1; odd-numbered matches are fitted,
    even-numbered ones held out.  ``FIELD:VALUE`` with FIELD one of ``tour``, ``tournament``,
    ``year``, ``event`` (tournament_year): serves with that value are fitted, the others held
    out (e.g. ``tournament:roland_garros``).  ``none``: everything fitted, nothing held out (the
    results then say so: no held-out figure).
    """
    n = len(serves)
    key = split.strip().lower()
    if key == "none":
        return np.ones(n, dtype=bool), np.zeros(n, dtype=bool), "none: all serves fitted, none held out"
    if key == "parity":
        names = sorted(set(serves.match.tolist()))
        odd = {m for i, m in enumerate(names, start=1) if i % 2 == 1}
        fit = np.array([m in odd for m in serves.match])
        return fit, ~fit, "parity: odd-numbered matches (sorted by name) fitted, even-numbered held out"
    if ":" in key:
        fld, val = (s.strip() for s in key.split(":", 1))
        if fld in ("tour", "tournament", "year", "event"):
            labels = serves.group("event") if fld == "event" else getattr(serves, fld)
            fit = np.array([str(x).lower() == val for x in labels])
            if not fit.any():
                allowed = ", ".join(sorted({str(x) for x in labels}))
                raise InputError(f"split: no serve has {fld} {val!r}; values: {allowed}")
            return fit, ~fit, f"{fld}:{val} fitted, the rest held out"
    raise InputError(f"split: unknown split {split!r}; allowed: parity, none, tour:X, tournament:X, year:X, event:X")
