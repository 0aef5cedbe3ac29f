"""The court (ITF Rules of Tennis, rule 1 and Appendix) and the net.

Frame: origin at the centre of the net on the ground; x along the court toward
the far baseline, y across (left when facing +x), z up.  The "far" half is
x > 0, the "near" half x < 0.  All court dimensions are measured to the outside
of the lines (ITF rule 1), and a line belongs to the area it bounds: a ball
touching any part of a line is in.

Dimensions (ITF rule 1): length 23.77 m; singles width 8.23 m; doubles width
10.97 m; service lines 6.40 m from the net; centre service line and centre mark
5 cm wide (mark 10 cm long); other lines 2.5-5 cm (default 5 cm); baselines up
to 10 cm (default 5 cm).

Net (ITF rule 1): 0.914 m at the centre strap, 1.07 m at the posts, whose
centres are 0.914 m outside the doubles sidelines (y_post = 6.399 m).  Between
the strap and a post the cord is modelled as a straight line: the strap pulls a
taut cord down at one point, so each half is a near-straight segment (a cord
sagging under its own weight only would be a catenary; the difference is a few
millimetres for a cord at 1 kN tension).  Outside the posts there is no net.
The same cord in compiled code, for the flight kernels: :mod:`tennislab.core._net` (this module
loads no Numba).

References
----------
.. [1] ITF, Rules of Tennis, rule 1 and Appendix I
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.errors import InputError, check_range


@dataclass(frozen=True)
class Court:
    """An ITF court; every length [m].

    Attributes
    ----------
    length : baseline to baseline, outer edges [m] (23.77)
    singles_width, doubles_width : sideline to sideline, outer edges [m] (8.23, 10.97)
    service_line : distance of the service line's outer edge from the net [m] (6.40)
    line_width : width of service lines and sidelines [m] (0.05; ITF 0.025-0.05)
    baseline_width : width of the baselines [m] (0.05; ITF up to 0.10)
    center_line_width : width of the centre service line and centre mark [m] (0.05)
    net_center_height, net_post_height : net height at the strap and the posts [m]
    post_offset : post centre outside the doubles sideline [m] (0.914)
    """

    length: float = 23.77
    singles_width: float = 8.23
    doubles_width: float = 10.97
    service_line: float = 6.40
    line_width: float = 0.05
    baseline_width: float = 0.05
    center_line_width: float = 0.05
    center_mark_length: float = 0.10
    net_center_height: float = 0.914
    net_post_height: float = 1.07
    post_offset: float = 0.914

    def __post_init__(self):
        for f in ("length", "singles_width", "doubles_width", "service_line", "net_center_height", "net_post_height"):
            check_range(f, getattr(self, f), 0.0, 100.0, "m", lo_open=True)
        check_range("line_width", self.line_width, 0.0, 0.2, "m")
        check_range("baseline_width", self.baseline_width, 0.0, 0.2, "m")
        check_range("center_line_width", self.center_line_width, 0.0, 0.2, "m")
        check_range("post_offset", self.post_offset, 0.0, 5.0, "m")
        if self.singles_width > self.doubles_width:
            raise InputError("singles_width: must not exceed doubles_width")
        if self.service_line > self.length / 2:
            raise InputError("service_line: must lie within the half court")

    # -- derived dimensions ------------------------------------------------
    @property
    def half_length(self) -> float:
        """Net to the outer edge of a baseline [m]."""
        return self.length / 2.0

    @property
    def y_post(self) -> float:
        """Lateral position of the net posts' centres [m]."""
        return self.doubles_width / 2.0 + self.post_offset

    def net_height(self, y):
        """Net cord height [m] at lateral position(s) ``y`` [m] (0 beyond the posts)."""
        y = np.asarray(y, dtype=float)
        ay = np.abs(y)
        h = self.net_center_height + (self.net_post_height - self.net_center_height) * ay / self.y_post
        out = np.where(ay > self.y_post, 0.0, h)
        return float(out) if out.ndim == 0 else out

    # -- areas ---------------------------------------------------------------
    def area_bounds(self, name: str) -> tuple[float, float, float, float]:
        """Outer bounds (xmin, xmax, ymin, ymax) [m] of a named area, lines included.

        Names: ``singles``, ``doubles``, ``deuce-box``, ``ad-box`` for the far
        half (x > 0), the same with a ``near-`` prefix for the near half, and
        ``full-singles``, ``full-doubles`` for the whole court.  The deuce box of
        a half is on its receiver's right: y > 0 in the far half, y < 0 in the
        near half.  Both boxes include the whole centre service line.
        """
        L, s, d = self.half_length, self.singles_width / 2, self.doubles_width / 2
        sl, c = self.service_line, self.center_line_width / 2
        far = {
            "singles": (0.0, L, -s, s),
            "doubles": (0.0, L, -d, d),
            "deuce-box": (0.0, sl, -c, s),
            "ad-box": (0.0, sl, -s, c),
        }
        if name in far:
            return far[name]
        if name.startswith("near-") and name[5:] in far:
            x0, x1, y0, y1 = far[name[5:]]
            return (-x1, -x0, -y1, -y0)
        if name == "full-singles":
            return (-L, L, -s, s)
        if name == "full-doubles":
            return (-L, L, -d, d)
        raise InputError(f"area: unknown name {name!r}; allowed: {', '.join(self.area_names())}")

    @staticmethod
    def area_names() -> list[str]:
        """All area names understood by :meth:`area_bounds`."""
        base = ["singles", "doubles", "deuce-box", "ad-box"]
        return base + ["near-" + b for b in base] + ["full-singles", "full-doubles"]

    def contains(self, name: str, x, y, margin: float = 0.0):
        """True where ground point(s) (x, y) lie in the named area, lines included.

        ``margin`` [m] widens the area on every side (e.g. the half-length of a
        ball mark: a mark touching the line is in).
        """
        x0, x1, y0, y1 = self.area_bounds(name)
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        res = (x >= x0 - margin) & (x <= x1 + margin) & (y >= y0 - margin) & (y <= y1 + margin)
        return bool(res) if res.ndim == 0 else res

    def judge(self, name: str, x: float, y: float) -> str:
        """Where a ground point (x, y) [m] lands relative to a named area, lines included: ``"in"``,
        ``"short"`` (on the near side of the area, toward the hitter), ``"long"`` (beyond its far
        edge) or ``"wide"`` (beside it); long before wide when both hold (as a line judge calls it)."""
        x0, x1, y0, y1 = self.area_bounds(name)
        if self.contains(name, x, y):
            return "in"
        far = x0 >= 0.0 or (x0 < 0.0 < x1 and x > 0.0)  # an area spanning the net: by the half it lands in
        if (x > x1) if far else (x < x0):
            return "long"
        if (x < x0) if far else (x > x1):
            return "short"
        return "wide"

    def areas_at(self, x: float, y: float) -> list[str]:
        """Names of every area containing the ground point (x, y)."""
        return [n for n in self.area_names() if self.contains(n, x, y)]

    def lines(self) -> dict[str, tuple[float, float, float, float]]:
        """Painted lines as rectangles (xmin, xmax, ymin, ymax) [m], far half first.

        Names: ``baseline``, ``service``, ``singles-left``/``-right``,
        ``doubles-left``/``-right``, ``center`` (service line), ``center-mark``;
        ``near-`` prefix for the near half.  Left is +y (facing +x).
        """
        L, s, d = self.half_length, self.singles_width / 2, self.doubles_width / 2
        w, wb, wc = self.line_width, self.baseline_width, self.center_line_width
        sl = self.service_line
        far = {
            "baseline": (L - wb, L, -d, d),
            "service": (sl - w, sl, -s, s),
            "singles-left": (0.0, L, s - w, s),
            "singles-right": (0.0, L, -s, -s + w),
            "doubles-left": (0.0, L, d - w, d),
            "doubles-right": (0.0, L, -d, -d + w),
            "center": (0.0, sl, -wc / 2, wc / 2),
            "center-mark": (L - self.center_mark_length, L, -wc / 2, wc / 2),
        }
        out = dict(far)
        for k, (x0, x1, y0, y1) in far.items():
            out["near-" + k] = (-x1, -x0, -y1, -y0)
        return out


ITF_COURT = Court()
