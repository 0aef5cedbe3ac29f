"""What a raw ball track shows before any fit: hits, bounces, direction of travel and noise.

* :func:`find_hits` - racket contacts: a jump of the velocity between consecutive frame pairs far
  above what gravity and drag change in one frame (|dv| > :data:`HIT_DV` and > 6x the track's median),
  with the ball in the air (z > :data:`BOUNCE_Z`), away from the net (|x| > :data:`NET_ZONE`), and the
  ball turned back along the court or sped up (a serve out of the toss).
* :func:`find_bounces` - ground contacts: a local minimum of z below :data:`BOUNCE_Z` where the ball
  comes down and goes up again (by at least 2 cm within 0.15 s on each side).
* :func:`noise_from_differences` - the per-axis noise of the track without any model: third
  differences of equally spaced samples cancel a quadratic (drag changes the acceleration by
  ~100 m/s^3, i.e. < 1 mm at 50 Hz), and Var(p_i+3 - 3 p_i+2 + 3 p_i+1 - p_i) = 20 sigma^2 for white
  noise; the median absolute value (1.4826 MAD) keeps hits and bounces out.
* :func:`travel_direction` - +1 when the ball moves toward +x, -1 otherwise.
"""

from __future__ import annotations

import numpy as np

HIT_DV = 8.0  #: [m/s] smallest velocity jump taken as a hit
BOUNCE_Z = 0.3  #: [m] a ground contact has its lowest sample below this height (ball centre)
NET_ZONE = 1.0  #: [m] velocity jumps this close to the net plane are net contacts, not hits
MAX_GAP = 0.12  #: [s] frame pairs further apart than this are not used to detect a jump
MERGE = 0.06  #: [s] jumps closer than this are one event


def _velocities(t, xyz):
    dt = np.diff(t)
    v = np.diff(xyz, axis=0) / dt[:, None]
    return dt, v


def velocity_jumps(t, xyz) -> np.ndarray:
    """|v_after - v_before| at each interior sample (0 at the ends and across gaps) [m/s]."""
    n = t.size
    out = np.zeros(n)
    if n < 3:
        return out
    dt, v = _velocities(t, xyz)
    ok = (dt[:-1] <= MAX_GAP) & (dt[1:] <= MAX_GAP)
    out[1:-1] = np.where(ok, np.linalg.norm(v[1:] - v[:-1], axis=1), 0.0)
    return out


def _merge(idx: np.ndarray, t: np.ndarray, score: np.ndarray) -> list[int]:
    """One index per cluster of candidates closer than :data:`MERGE` (the highest score)."""
    out: list[int] = []
    for i in idx:
        if out and t[i] - t[out[-1]] < MERGE:
            if score[i] > score[out[-1]]:
                out[-1] = int(i)
        else:
            out.append(int(i))
    return out


def find_hits(t, xyz) -> list[int]:
    """Sample indices where a racket hit starts a new shot (see the module docstring)."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    n = t.size
    if n < 4:
        return []
    jump = velocity_jumps(t, xyz)
    thr = max(HIT_DV, 6.0 * float(np.median(jump[1:-1])))
    cand = np.nonzero(jump > thr)[0]
    dt, v = _velocities(t, xyz)
    hits = []
    for i in _merge(cand, t, jump):
        if not 1 <= i <= n - 2:
            continue
        vb, vf = v[i - 1], v[i]
        if xyz[i, 2] < BOUNCE_Z or abs(xyz[i, 0]) < NET_ZONE:
            continue
        turned = np.sign(vb[0]) != np.sign(vf[0]) and abs(vf[0]) > 2.0
        faster = np.linalg.norm(vf) > np.linalg.norm(vb) + HIT_DV
        if turned or faster:
            hits.append(i)
    return hits


def find_bounces(t, xyz, rise: float = 0.02, span: float = 0.15) -> list[int]:
    """Sample indices of ground contacts (lowest sample of each), in time order."""
    t = np.asarray(t, dtype=float)
    z = np.asarray(xyz, dtype=float)[:, 2]
    n = t.size
    out: list[int] = []
    for i in range(1, n - 1):
        if z[i] >= BOUNCE_Z or z[i] > z[i - 1] or z[i] > z[i + 1]:
            continue
        before = (t >= t[i] - span) & (t < t[i])
        after = (t > t[i]) & (t <= t[i] + span)
        if not before.any() or not after.any():
            continue
        if z[before].max() - z[i] < rise or z[after].max() - z[i] < rise:
            continue
        if out and t[i] - t[out[-1]] < MERGE:
            if z[i] < z[out[-1]]:
                out[-1] = i
            continue
        out.append(i)
    return out


def bounce_estimate(t, xyz, i: int, radius: float = 0.033) -> tuple[float, float, float]:
    """(t, x, y) where the last <= 5 samples before sample ``i`` (and ``i``) reach z = radius
    (quadratic in z, linear in x and y); the sample itself when that fails."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    sel = np.arange(max(0, i - 5), i + 1)
    if sel.size >= 3:
        t0 = t[i]
        cz = np.polyfit(t[sel] - t0, xyz[sel, 2], 2)
        roots = np.roots(cz - np.array([0.0, 0.0, radius]))
        roots = np.real(roots[np.abs(np.imag(roots)) < 1e-9])
        roots = roots[(roots > -0.05) & (roots < 0.05)]
        if roots.size:
            tau = float(roots.min())
            cx = np.polyfit(t[sel] - t0, xyz[sel, 0], 1)
            cy = np.polyfit(t[sel] - t0, xyz[sel, 1], 1)
            return t0 + tau, float(np.polyval(cx, tau)), float(np.polyval(cy, tau))
    return float(t[i]), float(xyz[i, 0]), float(xyz[i, 1])


def noise_from_differences(t, xyz, tol: float = 0.1) -> float:
    """Per-axis noise [m] from third differences of equally spaced samples (NaN if < 4 usable)."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    if t.size < 8:
        return float("nan")
    dt = np.diff(t)
    w = np.lib.stride_tricks.sliding_window_view(dt, 3)
    even = (w.max(axis=1) - w.min(axis=1)) <= tol * w.mean(axis=1)
    d3 = xyz[3:] - 3 * xyz[2:-1] + 3 * xyz[1:-2] - xyz[:-3]
    d3 = d3[even]
    if d3.shape[0] < 4:
        return float("nan")
    comp = d3.ravel()
    return float(1.4826 * np.median(np.abs(comp - np.median(comp))) / np.sqrt(20.0))


def travel_direction(t, xyz) -> float:
    """+1 when the ball travels toward +x over its first samples (up to 0.1 s), else -1."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(xyz, dtype=float)[:, 0]
    sel = np.nonzero(t <= t[0] + 0.1)[0]
    if sel.size < 2:
        sel = np.arange(min(2, t.size))
    dx = x[sel[-1]] - x[sel[0]]
    if dx == 0 and t.size > 1:
        dx = x[-1] - x[0]
    return 1.0 if dx >= 0 else -1.0
