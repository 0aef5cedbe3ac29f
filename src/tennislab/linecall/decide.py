"""In or out: a ball mark against the court's lines and areas, with its probability.

Rules (ITF rule 1 and the Hawk-Eye convention): a line belongs to the area it
bounds, and a ball is in when any part of its mark touches the line.  The mark
is the union of contact discs of :mod:`tennislab.core.mark`.

* Against an area (``--target deuce-box``, ``singles`` ...; lines included):
  ``distance`` = how far the mark reaches into the area [m] (>= 0: in; < 0:
  the gap between mark and area).
* Against a line (``--line baseline`` ...): the line's outer edge (the one away
  from the court's centre; for the centre service line, the edge on the far
  side from the mark) bounds a half-plane; ``distance`` = how far the mark
  reaches past that edge toward the inside (>= 0: in).
* ``p_in``: Monte Carlo over the bounce point's 2-D Gaussian uncertainty (the
  fit's covariance), the mark translated with it; 1 or 0 without uncertainty.

Without ``--line``/``--target`` the area is the singles court of the half the
ball lands in, and each of its lines is reported.

References
----------
.. [1] ITF, Rules of Tennis, rule 1 and Appendix I (the lines belong to the areas they bound)
"""

from __future__ import annotations

import numpy as np

from tennislab.core.court import ITF_COURT, Court
from tennislab.core.mark import BallMark, depth_in_halfplane, depth_in_rect
from tennislab.errors import InputError

N_SAMPLES = 4000  #: Monte Carlo samples for p_in


def default_target(x: float) -> str:
    """Singles court of the half containing x."""
    return "singles" if x >= 0 else "near-singles"


def line_halfplane(name: str, court: Court, mark_y: float = 0.0) -> tuple[int, float, float]:
    """(axis, outer edge [m], inward sign) of a painted line."""
    lines = court.lines()
    if name not in lines:
        raise InputError(f"line: unknown name {name!r}; allowed: {', '.join(lines)}")
    x0, x1, y0, y1 = lines[name]
    axis = 0 if (x1 - x0) < (y1 - y0) else 1
    lo, hi = (x0, x1) if axis == 0 else (y0, y1)
    mid = 0.5 * (lo + hi)
    if abs(mid) < 1e-9:  # centre service line / centre mark: inside is the mark's side
        inward = 1.0 if mark_y >= 0 else -1.0
    else:
        inward = -1.0 if mid > 0 else 1.0
    edge = lo if inward > 0 else hi
    return axis, edge, inward


def area_lines(area: str, court: Court) -> list[tuple[str, int, float, float]]:
    """The painted lines bounding an area: (line name, axis, outer edge, inward sign)."""
    x0, x1, y0, y1 = court.area_bounds(area)
    edges = [(0, x1, -1.0, (y0, y1)), (0, x0, 1.0, (y0, y1)), (1, y1, -1.0, (x0, x1)), (1, y0, 1.0, (x0, x1))]
    out = []
    for axis, edge, inward, (a, b) in edges:
        for name, (lx0, lx1, ly0, ly1) in court.lines().items():
            lo, hi = (lx0, lx1) if axis == 0 else (ly0, ly1)
            olo, ohi = (ly0, ly1) if axis == 0 else (lx0, lx1)
            outer = lo if inward > 0 else hi
            if abs(outer - edge) < 1e-9 and min(ohi, b) - max(olo, a) > 1e-6 and (hi - lo) < (ohi - olo):
                out.append((name, axis, edge, inward))
                break
    return out


def _offsets(cov, n: int, seed: int):
    if cov is None:
        return None
    cov = np.asarray(cov, dtype=float)
    if not np.all(np.isfinite(cov)) or np.allclose(cov, 0):
        return None
    rng = np.random.default_rng(seed)
    return rng.multivariate_normal(np.zeros(2), cov, size=n, method="eigh")


def _decision(depth0: float, samples) -> dict:
    p = (1.0 if depth0 >= 0 else 0.0) if samples is None else float(np.mean(samples >= 0))
    return {"call": "in" if depth0 >= 0 else "out", "distance_mm": depth0 * 1000.0, "p_in": p}


def call_mark(
    mark: BallMark,
    *,
    court: Court = ITF_COURT,
    target: str | None = None,
    line: str | None = None,
    bounce_cov=None,
    n_samples: int = N_SAMPLES,
    seed: int = 0,
) -> dict:
    """Decide a mark against ``line`` or ``target`` (default: the singles court of its half).

    Returns ``call`` (in/out), ``distance_mm``, ``p_in``, the ``target`` or ``line``
    name, and ``lines``: the same three numbers for each line bounding the target.
    """
    if line is not None and target is not None:
        raise InputError("target: give a line or a target area, not both")
    off = _offsets(bounce_cov, n_samples, seed)
    discs = mark.discs
    if line is not None:
        axis, edge, inward = line_halfplane(line, court, float(mark.center[1]))
        d0 = depth_in_halfplane(discs, axis, edge, inward)
        ds = None if off is None else depth_in_halfplane(discs, axis, edge, inward, off)
        res = _decision(d0, ds)
        res["line"] = line
        res["lines"] = {line: dict(res)}
        res["lines"][line].pop("line", None)
        res["lines"][line].pop("lines", None)
        return res
    area = target or default_target(float(mark.start[0]))
    rect = court.area_bounds(area)
    d0 = depth_in_rect(discs, rect)
    ds = None if off is None else depth_in_rect(discs, rect, off)
    res = _decision(d0, ds)
    res["target"] = area
    per = {}
    for name, axis, edge, inward in area_lines(area, court):
        l0 = depth_in_halfplane(discs, axis, edge, inward)
        ls = None if off is None else depth_in_halfplane(discs, axis, edge, inward, off)
        per[name] = _decision(l0, ls)
    res["lines"] = per
    return res
