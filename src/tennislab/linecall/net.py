"""Did the ball touch the net?  A track that cannot be a free flight over the net plane.

A ball whose samples cross the net plane more than :data:`CORD_ZONE` + :data:`QUICK_MARGIN` above the
tape (+ r) cleared it; otherwise the ball's free flight before the net (the samples more than
:data:`PRE_MARGIN` short of the net plane, before any bounce) is fitted with the physical model
(:func:`~tennislab.linecall.free_flight.fit_free_flight`) and flown on to the net plane (x = 0).  There the
ball centre passes at height z_n and lateral position y_n; the tape is at h(y_n)
(:meth:`tennislab.core.court.Court.net_height`, ITF rule 1), so the ball's surface clears it by

    clearance = z_n - h(y_n) - r.

The samples from :data:`AFTER_START` to :data:`AFTER_SPAN` after that time are compared with the same
flight continued: their median deviation ``deviation``.  Contact is declared when

* the flight passes within :data:`CORD_ZONE` of the tape (clearance < CORD_ZONE) **and** the samples
  after it leave the free flight (deviation > max(:data:`DEV_SIGMA` x noise, :data:`DEV_MIN`)), or
* the flight would pass through the net (clearance < -:data:`BELOW_TOL`) and there are no samples
  after it (the track ends in the net).

A ball that leaves its flight far above the tape was touched by something else (a volley the hit
detection missed): not a net contact.  After a contact the ball ``crossed`` when a later sample is
more than :data:`CROSS_MARGIN` past the net plane (two samples: one could be an outlier); ``resume`` is
the first sample of the flight after the contact (for the bounce fit).  Balls crossing beyond the net
posts (|y| > y_post) never touch it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.core.flight import FlightParams
from tennislab.errors import InputError
from tennislab.linecall.detect import find_bounces
from tennislab.linecall.free_flight import fit_free_flight

PRE_MARGIN = 0.15  #: [m] samples closer than this to the net plane are not used for the flight before it
PRE_SPAN = 0.4  #: [s] the flight before the net is fitted over at most this long
CORD_ZONE = 0.15  #: [m] clearance below which a deflection is put down to the net
QUICK_MARGIN = 0.15  #: [m] a crossing this far above CORD_ZONE in the samples themselves needs no flight fit
BELOW_TOL = 0.02  #: [m] a flight this far below the tape cannot have passed untouched
DEV_SIGMA = 8.0  #: deviation threshold in units of the fit's noise
DEV_MIN = 0.04  #: [m] smallest deviation taken as a deflection
AFTER_START = 0.01  #: [s] samples from this long after the net plane...
AFTER_SPAN = 0.15  #: [s] ...to this long after it are compared with the flight
CROSS_MARGIN = 0.3  #: [m] past the net plane: the ball went over
BELOW_GROUND = 0.05  #: [m] samples lower than this (rolling balls) are not compared with the flight


@dataclass(frozen=True)
class NetCheck:
    """Outcome of :func:`check_net` (SI units; NaN where not determined).

    ``checked``: enough samples before the net to fly it; ``reaches_net``: the flight gets to the net
    plane before landing; ``contact``: the ball touched the net; ``crossed``: and went over;
    ``t, y, z``: time and ball-centre position where the flight meets the net plane (x = 0);
    ``clearance``: of the ball's surface over the tape [m]; ``deviation``: median distance of the
    samples after the net plane from the free flight [m]; ``resume``: index of the first sample after
    the contact (-1 if none); ``note``: why not checked.
    """

    checked: bool
    reaches_net: bool = False
    contact: bool = False
    crossed: bool = True
    t: float = float("nan")
    y: float = float("nan")
    z: float = float("nan")
    clearance: float = float("nan")
    deviation: float = float("nan")
    resume: int = -1
    note: str = ""

    def to_dict(self, t_offset: float = 0.0) -> dict:
        """JSON keys; ``t_offset`` [s] is added to the time (tracks called on a relative clock)."""
        return {
            "checked": self.checked,
            "contact": self.contact,
            "crossed": self.crossed,
            "t": self.t + t_offset,
            "y": self.y,
            "z": self.z,
            "clearance_m": self.clearance,
            "deviation_m": self.deviation,
            "note": self.note,
        }


def _high_crossing(t, xyz, s, court, r) -> NetCheck | None:
    """A check from the samples alone when the ball crosses the net plane far above the tape
    (clearance by linear interpolation between the two samples around the plane above
    :data:`CORD_ZONE` + :data:`QUICK_MARGIN`): no flight fit needed.  None otherwise."""
    k = np.nonzero((s[:-1] < 0) & (s[1:] >= 0))[0]
    if k.size == 0:
        return None
    i = int(k[0])
    if t[i + 1] - t[i] > 0.1:
        return None
    f = -s[i] / (s[i + 1] - s[i])
    tn = float(t[i] + f * (t[i + 1] - t[i]))
    yn, zn = (1 - f) * xyz[i, 1:] + f * xyz[i + 1, 1:]
    h = float(court.net_height(yn))
    clearance = float(zn - h - r) if h > 0 else float("inf")
    if clearance <= CORD_ZONE + QUICK_MARGIN:
        return None
    return NetCheck(True, True, False, True, tn, float(yn), float(zn), clearance, note="clears the tape (samples)")


def check_net(t, xyz, params: FlightParams, direction: float) -> NetCheck:
    """Net contact of one shot's track (from the hit on), travelling along ``direction`` (+1/-1 in x)."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    r = params.ball.radius
    court = params.court
    s = direction * xyz[:, 0]
    if s[0] >= -PRE_MARGIN:
        return NetCheck(False, note="the track starts at or past the net")
    b = find_bounces(t, xyz)
    first_b = b[0] if b else t.size
    stop = int(np.argmax(s >= -PRE_MARGIN)) if np.any(s >= -PRE_MARGIN) else t.size
    if first_b < stop:  # it lands before the net: nothing to check
        return NetCheck(True, reaches_net=False, note="lands before the net")
    quick = _high_crossing(t, xyz, s, court, r)
    if quick is not None:
        return quick
    pre = np.arange(stop)
    pre = pre[t[pre] >= t[pre[-1]] - PRE_SPAN]
    if pre.size < 3:
        return NetCheck(False, note=f"{pre.size} sample(s) before the net")
    try:
        ff = fit_free_flight(t[pre], xyz[pre], params)
    except InputError as exc:  # pragma: no cover - guarded by the count above
        return NetCheck(False, note=str(exc))
    if not np.isfinite(ff.rms):
        return NetCheck(False, note="the flight before the net did not fit")
    tt = t[pre[-1]] + np.arange(1, 1001) * 1e-3
    pos = ff.positions(tt)
    sp = direction * pos[:, 0]
    ok = np.isfinite(sp)
    reach = np.nonzero(ok & (sp >= 0.0))[0]
    land = np.nonzero(ok & (pos[:, 2] <= r))[0]
    if reach.size == 0 or (land.size and land[0] < reach[0]):
        return NetCheck(True, reaches_net=False, note="lands before the net")
    k = int(reach[0])
    if k > 0:  # interpolate to the plane
        f = -sp[k - 1] / (sp[k] - sp[k - 1])
        tn = float(tt[k - 1] + f * (tt[k] - tt[k - 1]))
        yn, zn = (1 - f) * pos[k - 1, 1:] + f * pos[k, 1:]
    else:
        tn, (yn, zn) = float(tt[0]), pos[0, 1:]
    yn, zn = float(yn), float(zn)
    h = float(court.net_height(yn))
    clearance = zn - h - r if h > 0 else float("inf")
    after = np.nonzero((t > max(t[pre[-1]], tn + AFTER_START)) & (t <= tn + AFTER_SPAN))[0]
    after = after[xyz[after, 2] > BELOW_GROUND] if after.size else after
    dev = float("nan")
    if after.size:
        d = np.linalg.norm(ff.positions(t[after]) - xyz[after], axis=1)
        dev = float(np.median(d))
    tol = max(DEV_SIGMA * (ff.noise if np.isfinite(ff.noise) else 0.0), DEV_MIN)
    deflected = np.isfinite(dev) and dev > tol
    contact = (clearance < CORD_ZONE and deflected) or (clearance < -BELOW_TOL and after.size == 0)
    crossed = True
    resume = -1
    if contact:
        later = np.nonzero(t > tn + 0.01)[0]
        crossed = bool(np.count_nonzero(direction * xyz[later, 0] > CROSS_MARGIN) >= 2)
        resume = int(later[0]) if later.size else -1
    return NetCheck(True, True, bool(contact), crossed, tn, yn, zn, float(clearance), dev, resume)
