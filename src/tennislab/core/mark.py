"""The ball mark: the footprint a bouncing ball leaves on the court.

Model (documented in docs/bounce.md; no published mark sizes in mm were found,
so the mark is derived, not fitted):

* Contact duration T_c: the ball is a linear spring in the normal direction, so
  the normal force is a half-sine of duration T_c, independent of speed.  T_c =
  4.5 ms, the middle of the 4-5 ms Brody reports for a ball on a court
  (reference-data.md [S]; cf. 3.5 ms on strings, Kawazoe [P]).
* Compression: delta(t) = delta_max sin(pi t / T_c), delta_max = |v_z,in| T_c / pi
  (the spring's amplitude for an impact speed v_z,in), capped at r.
* Contact patch: the ball flattened by delta against a plane touches it in a disc
  of radius a = sqrt(2 r delta - delta^2) (sphere-plane geometry).
* Skid: the horizontal friction impulse builds up as mu times the cumulative
  normal impulse, F(t) = (1 - cos(pi t / T_c)) / 2, until it reaches the total
  of the bounce model (sliding: the whole contact; gripping: until the slip
  stops).  The centre moves with v_t(t) = v_t,in + P(t), so it advances
  T_c (v_t,in + v_t,out) / 2 during contact; the contact point slides over the
  ground by the integral of the slip speed (``skid``).
* Mark = union of the contact discs along the path: it starts at the first
  contact point (the landing point, ball centre at z = r) as a point and grows
  forward into a comet/tear-drop shape (cf. reference-data.md: hard serves leave
  comet-shaped marks, lobs round ones).  ``length`` is its extent along the
  mean horizontal velocity, ``width`` across.

Line-calling geometry on the discs (a mark touching a line is in) is in
:func:`depth_in_rect` and :func:`depth_in_halfplane`.

References
----------
.. [1] Brody, contact time of a ball on a court (4-5 ms), as quoted in reference-data.md
.. [2] the bounce model of :mod:`tennislab.core.bounce` (Brody 1984; Cross 2002)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba as nb
import numpy as np

from tennislab.core._jit import JIT
from tennislab.core.ball import Ball
from tennislab.core.surfaces import get_surface
from tennislab.errors import check_range
from tennislab.results import OldAsDict


@dataclass(frozen=True)
class MarkParams:
    """Ball-mark model parameters.

    Attributes
    ----------
    contact_time : duration of the ball-court contact [s] (4.5e-3, Brody [S])
    n_discs : number of contact discs sampled over the contact [-]
    """

    contact_time: float = 4.5e-3
    n_discs: int = 41

    def __post_init__(self):
        check_range("contact_time", self.contact_time, 0.0, 0.05, "s", lo_open=True)
        check_range("n_discs", self.n_discs, 3, 10000)


@dataclass(frozen=True)
class BallMark(OldAsDict):
    """A ball mark on the ground.

    Attributes
    ----------
    start : first-contact point (x, y) [m] (the landing point)
    center : centre of the mark's bounding box along/across its direction [m]
    direction : unit vector (x, y) of the mean horizontal velocity during contact
    length, width : extent along / across ``direction`` [m]
    compression : maximum compression of the ball [m]
    contact_time : [s]
    skid : distance the contact point slides over the ground [m]
    displacement : travel of the ball centre during contact (x, y) [m]
    discs : (K, 3) contact discs (x, y, radius) [m]
    """

    start: np.ndarray
    center: np.ndarray
    direction: np.ndarray
    length: float
    width: float
    compression: float
    contact_time: float
    skid: float
    displacement: np.ndarray
    discs: np.ndarray

    def to_dict(self) -> dict:
        return {
            "length": self.length,
            "width": self.width,
            "x": float(self.center[0]),
            "y": float(self.center[1]),
            "start_x": float(self.start[0]),
            "start_y": float(self.start[1]),
            "direction": self.direction,
            "compression": self.compression,
            "contact_time": self.contact_time,
            "skid": self.skid,
        }

    def translated(self, dx: float, dy: float) -> BallMark:
        d = np.array([dx, dy])
        discs = self.discs.copy()
        discs[:, :2] += d
        return BallMark(
            self.start + d,
            self.center + d,
            self.direction,
            self.length,
            self.width,
            self.compression,
            self.contact_time,
            self.skid,
            self.displacement,
            discs,
        )


def contact_kinematics(
    vz_in: float,
    vt_in,
    vt_out,
    slip_in,
    mu: float,
    e: float,
    alpha: float,
    radius: float,
    params: MarkParams = MarkParams(),
):
    """Times, centre displacement (K, 2), patch radius (K,) and skid of one contact.

    vz_in : incoming vertical speed magnitude [m/s]; vt_in, vt_out : horizontal
    velocity in/out (2,) [m/s]; slip_in : incoming contact-point slip (2,) [m/s];
    mu, e : surface friction and COR; alpha : I/(m r^2); radius [m].
    """
    T = params.contact_time
    K = params.n_discs
    t = np.linspace(0.0, T, K)
    vt_in = np.asarray(vt_in, dtype=float)
    vt_out = np.asarray(vt_out, dtype=float)
    ptot = vt_out - vt_in
    pmag = float(np.hypot(*ptot))
    F = 0.5 * (1.0 - np.cos(np.pi * t / T))
    pn = (1.0 + e) * abs(vz_in)
    if pmag > 0:
        frac = np.minimum(mu * pn * F, pmag) / pmag
    else:
        frac = F
    v = vt_in[None, :] + frac[:, None] * ptot[None, :]
    disp = np.zeros((K, 2))
    dt = np.diff(t)
    disp[1:] = np.cumsum(0.5 * (v[1:] + v[:-1]) * dt[:, None], axis=0)
    slip = np.asarray(slip_in, dtype=float)[None, :] + frac[:, None] * ptot[None, :] * (1.0 + 1.0 / alpha)
    sp = np.hypot(slip[:, 0], slip[:, 1])
    skid = float(np.sum(0.5 * (sp[1:] + sp[:-1]) * dt))
    dmax = min(abs(vz_in) * T / math.pi, radius)
    delta = dmax * np.sin(np.pi * t / T)
    a = np.sqrt(np.clip(2.0 * radius * delta - delta**2, 0.0, None))
    return t, disp, a, skid, dmax


def ball_mark(
    start, velocity_in, velocity_out, spin_in, surface, ball=None, params: MarkParams = MarkParams()
) -> BallMark:
    """The mark of one bounce.

    start : first-contact point (x, y) [m]; velocity_in/out [m/s] (3,); spin_in [rad/s] (3,);
    surface : :class:`~tennislab.core.surfaces.Surface` or name; ball : :class:`Ball`.
    """
    s = get_surface(surface)
    ball = ball or Ball()
    r = ball.radius
    vin = np.asarray(velocity_in, dtype=float)
    vout = np.asarray(velocity_out, dtype=float)
    win = np.asarray(spin_in, dtype=float)
    slip = np.array([vin[0] - r * win[1], vin[1] + r * win[0]])
    t, disp, a, skid, dmax = contact_kinematics(
        abs(vin[2]), vin[:2], vout[:2], slip, s.mu, s.e, ball.inertia_factor, r, params
    )
    start = np.asarray(start, dtype=float)[:2]
    centres = start[None, :] + disp
    dvec = disp[-1]
    n = float(np.hypot(*dvec))
    if n > 1e-12:
        d = dvec / n
    else:
        h = float(np.hypot(*vin[:2]))
        d = vin[:2] / h if h > 0 else np.array([1.0, 0.0])
    perp = np.array([-d[1], d[0]])
    along = centres @ d
    across = centres @ perp
    lo, hi = float(np.min(along - a)), float(np.max(along + a))
    clo, chi = float(np.min(across - a)), float(np.max(across + a))
    center = d * (lo + hi) / 2 + perp * (clo + chi) / 2
    discs = np.column_stack([centres, a])
    return BallMark(start, center, d, hi - lo, chi - clo, dmax, params.contact_time, skid, dvec, discs)


@nb.njit(**JIT)
def impulse_time_fraction(pmag, mu_pn, T):
    """Integral over the contact of the friction-impulse fraction, divided by T [-].

    The friction impulse builds up as min(mu P_n F(t), |P|), F(t) = (1 - cos(pi t/T))/2;
    the centre's contact displacement is T v_t,in + (v_t,out - v_t,in) T * this.
    1/2 when the ball slides throughout.
    """
    if pmag <= 0.0 or mu_pn <= pmag:
        return 0.5
    fs = pmag / mu_pn
    ts = math.acos(1.0 - 2.0 * fs) / math.pi  # t*/T where the cap is reached
    return (0.5 * ts - math.sin(math.pi * ts) / (2.0 * math.pi)) / fs + (1.0 - ts)


@nb.njit(**JIT)
def contact_displacement(vxi, vyi, vxo, vyo, vz_in, mu, e, T, out):
    """Horizontal travel (out[0], out[1]) [m] of the ball centre during a contact of duration T [s]."""
    px = vxo - vxi
    py = vyo - vyi
    f = impulse_time_fraction(math.sqrt(px * px + py * py), mu * (1.0 + e) * abs(vz_in), T)
    out[0] = T * (vxi + f * px)
    out[1] = T * (vyi + f * py)


# ------------------------------------------------------------------ geometry
@nb.njit(**JIT)
def _depth_rect_kernel(discs, x0, x1, y0, y1, off, out):
    for m in range(off.shape[0]):
        best = -np.inf
        for i in range(discs.shape[0]):
            cx = discs[i, 0] + off[m, 0]
            cy = discs[i, 1] + off[m, 1]
            dx = min(cx - x0, x1 - cx)
            dy = min(cy - y0, y1 - cy)
            if dx >= 0.0 and dy >= 0.0:
                d = min(dx, dy)
            else:
                d = -math.sqrt(max(0.0, -dx) ** 2 + max(0.0, -dy) ** 2)
            d += discs[i, 2]
            if d > best:
                best = d
        out[m] = best


@nb.njit(**JIT)
def _depth_half_kernel(discs, axis, edge, inward, off, out):
    for m in range(off.shape[0]):
        best = -np.inf
        for i in range(discs.shape[0]):
            d = inward * (discs[i, axis] + off[m, axis] - edge) + discs[i, 2]
            if d > best:
                best = d
        out[m] = best


def _offsets(offsets):
    if offsets is None:
        return np.zeros((1, 2))
    return np.ascontiguousarray(np.asarray(offsets, dtype=float).reshape(-1, 2))


def depth_in_rect(discs: np.ndarray, rect, offsets=None):
    """How far the mark reaches into a rectangle [m]: >= 0 when any part touches it.

    For each disc (x, y, a): depth of its centre inside ``rect`` = (xmin, xmax,
    ymin, ymax) (positive inside: distance to the nearest edge; negative
    outside: minus the Euclidean distance), plus a; the mark's value is the
    maximum over discs.  ``offsets`` (M, 2) translates the mark (Monte Carlo
    over the bounce-point uncertainty); returns (M,) or a scalar.
    """
    off = _offsets(offsets)
    out = np.empty(off.shape[0])
    x0, x1, y0, y1 = (float(v) for v in rect)
    _depth_rect_kernel(np.ascontiguousarray(discs, dtype=float), x0, x1, y0, y1, off, out)
    return float(out[0]) if offsets is None else out


def depth_in_halfplane(discs: np.ndarray, axis: int, edge: float, inward: float, offsets=None):
    """How far the mark reaches past a line's outer edge toward the inside [m] (>= 0: in).

    The inside is where ``inward * (p[axis] - edge) >= 0``.
    """
    off = _offsets(offsets)
    out = np.empty(off.shape[0])
    _depth_half_kernel(np.ascontiguousarray(discs, dtype=float), int(axis), float(edge), float(inward), off, out)
    return float(out[0]) if offsets is None else out
