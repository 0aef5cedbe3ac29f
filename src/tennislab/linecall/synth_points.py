"""Synthetic tracker points with known truth: serves, rallies, net cords, lets, volleys, double bounces.

Made to test the line caller on what real play throws at it, with a flight model that is not quite the
fit's default: the truth flies with ``cross2014`` at C_D = 0.6, C_L = 0.6 S uncapped (:data:`TRUTH_AERO`;
the fit uses the default ``choppin2018``, C_D 0.60 and C_L capped at 0.5, with free drag and lift scales
under priors; benchmarks/bench_linecall.py also flies the shots with ``stepanek1988``), spins about every
axis (topspin, sidespin, spin along the path), a contact time of 4.0 ms (the fit's contact model assumes
4.5 ms), and samples like a tracker's: 50 or 340 Hz with a random clock phase, Gaussian noise, random
dropouts, a gap after each hit (the racket hides the ball) and a gross outlier or two.  Synthetic truth
proves the code, not the physics.

Shots are flown by the reference integrator (:func:`tennislab.core.flight.fly_dense`, DOP853) and chained
through the bounce model (:func:`tennislab.core.rally.bounce_at`).  The net is an obstacle here: a ball
whose centre reaches the net plane below the tape + r touches it (:func:`tennislab.core.flight.fly_dense`'s
net crossing); a glancing touch (clearance > -0.6 r) is a net cord that goes over with 45-80 % of its
speed along the court and 20-80 % of its vertical speed plus a kick of -0.5 to 1.5 m/s, a deeper one
is stopped and drops on the hitter's side with a tenth of its speed.

:func:`synthetic_point` returns a point in the tracker JSON format read by
:func:`tennislab.io.hawkeye.parse_points` and the truth of each shot; :func:`synthetic_match` many.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tennislab.core.flight import FlightParams, fly_dense
from tennislab.core.launch import describe_spin, launch_velocity, spin_vector
from tennislab.core.mark import MarkParams
from tennislab.core.rally import bounce_at
from tennislab.core.shoot import shoot
from tennislab.core.surfaces import get_surface
from tennislab.linecall.decide import call_mark
from tennislab.units import RPM

TRUTH_AERO: dict[str, Any] = {
    "aero": "cross2014",
    "cd": 0.6,
    "cl": 0.6,
}  #: the truth's aero model (not the fit's default)
TRUTH_CONTACT = MarkParams(contact_time=4.0e-3)  #: the truth's contact time [s] (the fit assumes 4.5 ms)


def truth_params() -> FlightParams:
    """Flight physics of the synthetic truth (:data:`TRUTH_AERO`)."""
    return FlightParams.from_options(**TRUTH_AERO)


@dataclass
class ShotTruth:
    """One simulated shot: its flight pieces ``(t0, t1, sol or None)`` (None: on the ground during a
    contact, linear between its ends), the bounces, the net contact and the true call."""

    t_hit: float
    pieces: list = field(default_factory=list)
    bounces: list = field(default_factory=list)
    net: dict | None = None
    serve: bool = False
    target: str = ""
    call: str = ""
    distance_mm: float = float("nan")
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    spin: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @property
    def t_end(self) -> float:
        return self.pieces[-1][1]

    def position(self, t) -> np.ndarray:
        """True ball-centre positions (N, 3) at times t within the shot (NaN outside)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.full((t.size, 3), np.nan)
        for t0, t1, sol in self.pieces:
            m = (t >= t0) & (t <= t1)
            if not m.any():
                continue
            if callable(sol):
                out[m] = sol(t[m])[:3].T
            else:
                a, b = sol
                f = ((t[m] - t0) / max(t1 - t0, 1e-12))[:, None]
                out[m] = (1 - f) * a + f * b
        return out


def simulate_shot(
    position,
    velocity,
    spin,
    t0: float,
    params: FlightParams,
    *,
    surface="hard",
    mark_params: MarkParams = TRUTH_CONTACT,
    t_stop: float | None = None,
    max_bounces: int = 3,
    rng: np.random.Generator | None = None,
) -> ShotTruth:
    """Fly a shot from (position, velocity, spin) at t0 through the net (as an obstacle) and up to
    ``max_bounces`` bounces, until ``t_stop`` [s] (default: 1.5 s after the first bounce)."""
    s = get_surface(surface)
    r = params.ball.radius
    st = ShotTruth(t_hit=t0, velocity=np.asarray(velocity, float), spin=np.asarray(spin, float))
    pos, vel, w, t = np.asarray(position, float), np.asarray(velocity, float), np.asarray(spin, float), t0
    d = 1.0 if vel[0] >= 0 else -1.0
    stop = math.inf if t_stop is None else t_stop
    for _ in range(max_bounces + 2):
        tr = fly_dense(pos, vel, w, params, t0=t, rtol=1e-10)
        t_land = tr.landing.t if tr.landing is not None else t + params.t_max
        if st.net is None and not st.bounces and tr.net.result == "net" and tr.net.t < t_land:
            tn = tr.net.t
            y = tr.sol(tn)  # type: ignore[operator]
            st.pieces.append((t, tn, tr.sol))
            clear = float(tr.net.clearance)
            over = clear > -0.6 * r
            st.net = {"t": float(tn), "y": float(y[1]), "z": float(y[2]), "clearance": clear, "crossed": over}
            if over:  # net cord: slowed along the court, deflected up or down
                keep, fz, kick = (
                    (0.6, 0.5, 0.5)
                    if rng is None
                    else (rng.uniform(0.45, 0.8), rng.uniform(0.2, 0.8), rng.uniform(-0.5, 1.5))
                )
                vel = np.array([keep * y[3], 0.9 * y[4], fz * y[5] + kick])
                pos = np.array([d * 0.002, y[1], max(y[2], r)])
            else:  # stopped by the mesh: drops on the hitter's side, most of its energy gone
                vel = np.array([-0.1 * y[3], 0.1 * y[4], -0.2 * abs(y[5]) - 0.3])
                pos = np.array([-d * (r + 0.01), y[1], max(y[2], r)])
                stop = min(stop, tn + 1.2)
            w = 0.5 * y[6:9] if over else np.zeros(3)  # the mesh takes the spin of a stopped ball
            st.pieces.append((tn, tn + 1e-3, (y[:3].copy(), pos.copy())))
            t = tn + 1e-3
            continue
        if tr.landing is None or t_land >= stop:
            st.pieces.append((t, min(t_land, stop if math.isfinite(stop) else t_land), tr.sol))
            break
        st.pieces.append((t, t_land, tr.sol))
        b = bounce_at(tr.landing, s, params, mark_params)
        st.bounces.append(b)
        if len(st.bounces) == 1 and t_stop is None:
            stop = b.t + 1.5
        tc = mark_params.contact_time
        p_out = np.array([b.x + b.mark.displacement[0], b.y + b.mark.displacement[1], r])
        st.pieces.append((b.t, b.t + tc, (np.array([b.x, b.y, r]), p_out)))
        if len(st.bounces) >= max_bounces or b.velocity_out[2] < 0.3:
            break
        pos, vel, w, t = p_out, b.velocity_out, b.spin_out, b.t + tc
        if t >= stop:
            break
    return st


#: Elevations scanned for a synthetic shot's low branch [rad] (-20 to 35 deg: every rally shot and serve)
SCAN_ELEVATIONS = np.radians(np.arange(-20.0, 35.5, 1.0))


def aim(position, speed: float, spin_rpm, target_xy, params: FlightParams, *, clearance: float | None = None):
    """(velocity, spin) of a shot from ``position`` at ``speed`` [m/s] with spin components
    (topspin, sidespin, along-path) [rpm] that lands at ``target_xy`` [m] (or, with ``clearance`` [m],
    crosses the net plane with that clearance over the tape on the straight line to ``target_xy``).

    The aiming primitive :func:`tennislab.core.shoot.shoot` (low branch, or ``at="net"``); a shot
    that cannot reach its target keeps the scan's nearest elevation (the longest or shortest flight).
    """
    p0 = np.asarray(position, float)
    tx, ty = map(float, target_xy)
    comps = np.asarray(spin_rpm, float) * RPM
    if clearance is None:
        s = shoot(p0, speed, (tx, ty), params, spin=comps, branch="low", grid=SCAN_ELEVATIONS)
    else:
        y_net = p0[1] + (ty - p0[1]) * (0.0 - p0[0]) / (tx - p0[0])
        z_net = float(params.court.net_height(y_net)) + params.ball.radius + clearance
        s = shoot(p0, speed, (y_net, z_net), params, spin=comps, at="net")
    el, hd = float(s.elevation[0]), float(s.heading[0])
    if not s.converged[0] and s.scan is not None:
        el = float(s.scan.nearest[0])
    v = launch_velocity(speed, el, hd)
    return v, spin_vector(el, hd, *comps)


MIN_CLEARANCE = 0.05  #: [m] a shot meant to clear the net is slowed until it clears it by this much


def aim_clear(p0, speed, spin, tgt, params, clearance):
    """:func:`aim`; a shot meant to clear the net (``clearance`` None) is slowed by 3 m/s at a time
    (at most 6 times) until it clears the tape by :data:`MIN_CLEARANCE`."""
    v, w = aim(p0, speed, spin, tgt, params, clearance=clearance)
    if clearance is not None:
        return v, w
    for _ in range(6):
        tr = fly_dense(p0, v, w, params, rtol=1e-7, atol=1e-9)
        if not np.isfinite(tr.net.clearance) or tr.net.clearance >= MIN_CLEARANCE:
            break
        speed -= 3.0
        v, w = aim(p0, speed, spin, tgt, params)
    return v, w


def _serve_target_box(server_x: float, server_y: float) -> str:
    far = server_x < 0
    sy = -1.0 if server_y > 0 else 1.0
    if far:
        return "deuce-box" if sy > 0 else "ad-box"
    return "near-deuce-box" if sy < 0 else "near-ad-box"


def _truth_call(st: ShotTruth, court) -> None:
    if st.net is not None and not st.net["crossed"]:
        st.call = "net"
        return
    if not st.bounces:
        st.call = "none"
        return
    dec = call_mark(st.bounces[0].mark, court=court, target=st.target)
    st.distance_mm = dec["distance_mm"]
    st.call = dec["call"]
    if st.serve and st.net is not None and st.call == "in":
        st.call = "let"


def synthetic_point(
    rng: np.random.Generator,
    *,
    server_near: bool = True,
    deuce: bool = True,
    rally_len: int = 4,
    params: FlightParams | None = None,
    kind: str = "normal",
    volley_prob: float = 0.15,
    out_prob: float = 0.1,
) -> list[ShotTruth]:
    """The shots of one point (truth only).  ``kind``: ``normal``, ``let`` (serve clips the tape and
    goes over), ``net-fault`` (serve into the net), ``net-cord`` (a rally shot clips the tape)."""
    params = params or truth_params()
    court = params.court
    s = -1.0 if server_near else 1.0  # the server's half
    ys = (-1.0 if deuce else 1.0) * s * rng.uniform(0.3, 1.0)
    p0 = np.array([s * rng.uniform(11.3, 11.7), ys, rng.uniform(2.7, 3.0)])
    box = court.area_bounds(_serve_target_box(p0[0], p0[1]))
    tgt = (rng.uniform(box[0] + 0.6, box[1] - 0.2), rng.uniform(box[2] + 0.3, box[3] - 0.3))
    if rng.random() < out_prob:  # a fault long or wide, or a close call
        tgt = (tgt[0] + (-s) * rng.uniform(-0.5, 1.0), tgt[1]) if rng.random() < 0.5 else tgt
    serve_spin = (rng.uniform(300, 2500), rng.uniform(-2000, 2000), rng.uniform(-1500, 1500))
    speed = rng.uniform(38.0, 58.0)
    clearance = None
    if kind == "let":
        clearance = rng.uniform(-0.015, -0.004)
    elif kind == "net-fault":
        clearance = rng.uniform(-0.25, -0.06)
    v, w = aim_clear(p0, speed, serve_spin, tgt, params, clearance)
    shots = []
    t = 0.0
    st = simulate_shot(p0, v, w, t, params, rng=rng)
    st.serve, st.target = True, _serve_target_box(p0[0], p0[1])
    shots.append(st)
    hitter = -s  # the receiver hits next
    for k in range(rally_len):
        prev = shots[-1]
        _truth_call(prev, court)
        if prev.call != "in" or not prev.bounces:
            break
        # the next hitter meets the ball after its bounce (or volleys it)
        volley = rng.random() < volley_prob and not prev.serve
        t_hit = None
        if volley:
            ts = np.linspace(prev.t_hit + 0.1, prev.bounces[0].t - 0.02, 200)
            pos = prev.position(ts)
            ok = np.nonzero((hitter * pos[:, 0] > 2.0) & (hitter * pos[:, 0] < 5.0) & (pos[:, 2] > 0.4))[0]
            if ok.size:
                t_hit = float(ts[ok[0]])
        if t_hit is None:
            b0 = prev.bounces[0]
            ts = np.linspace(b0.t + 0.05, b0.t + 1.0, 300)
            pos = prev.position(ts)
            ok = np.nonzero((pos[:, 2] < 1.1) & (np.gradient(pos[:, 2]) < 0) & np.isfinite(pos[:, 2]))[0]
            t_hit = float(ts[ok[0]]) if ok.size else float(b0.t + 0.45)
        hp = prev.position([t_hit])[0]
        if not np.all(np.isfinite(hp)) or hp[2] < 0.2:
            break
        # trim the previous shot at the hit
        prev.pieces = [(a, min(b, t_hit), sol) for a, b, sol in prev.pieces if a < t_hit]
        prev.bounces = [b for b in prev.bounces if b.t < t_hit]
        if not prev.bounces:  # volleyed: nothing to call
            prev.call = "none"
        opp = -hitter  # the ball goes to this half
        area = court.area_bounds("singles" if opp > 0 else "near-singles")
        tgt = (rng.uniform(area[0] + 1.0, area[1] - 0.3), rng.uniform(area[2] + 0.3, area[3] - 0.3))
        if rng.random() < out_prob:
            tgt = (tgt[0] + opp * rng.uniform(0.5, 1.5), tgt[1]) if rng.random() < 0.5 else (tgt[0], tgt[1] * 1.25)
        spin = (rng.uniform(-2500, 3500), rng.uniform(-800, 800), rng.uniform(-600, 600))
        speed = rng.uniform(18.0, 36.0) if not volley else rng.uniform(12.0, 25.0)
        clr = rng.uniform(-0.02, -0.005) if (kind == "net-cord" and k == 0) else None
        v, w = aim_clear(hp, speed, spin, tgt, params, clr)
        st = simulate_shot(hp, v, w, t_hit, params, rng=rng)
        st.target = "singles" if opp > 0 else "near-singles"
        shots.append(st)
        hitter = opp
    _truth_call(shots[-1], court)
    for st in shots:
        if not st.call:
            _truth_call(st, court)
    return shots


def sample_point(
    shots: list[ShotTruth],
    rng: np.random.Generator,
    *,
    rate: float = 50.0,
    sigma: float = 3e-3,
    dropout: float = 0.03,
    hit_gap: tuple[int, int] = (0, 3),
    outliers: int = 1,
    events: bool = True,
    shot_records: bool = True,
    sequences: dict | None = None,
    t_offset: float = 0.0,
) -> dict:
    """A tracker point JSON document (plain dict) from the shots' truth (module docstring)."""
    t_end = shots[-1].t_end
    t = shots[0].t_hit + rng.uniform(0, 1.0 / rate) + np.arange(0.0, t_end - shots[0].t_hit, 1.0 / rate)
    pos = np.full((t.size, 3), np.nan)
    owner = np.full(t.size, -1)
    for k, st in enumerate(shots):
        nxt = shots[k + 1].t_hit if k + 1 < len(shots) else math.inf
        m = (t >= st.t_hit) & (t < nxt)
        pos[m] = st.position(t[m])
        owner[m] = k
    keep = np.all(np.isfinite(pos), axis=1)
    keep &= rng.random(t.size) > dropout
    for st in shots[1:]:  # the racket hides the ball for a few frames after a hit
        i = int(np.searchsorted(t, st.t_hit))
        keep[i + 1 : i + 1 + int(rng.integers(hit_gap[0], hit_gap[1] + 1))] = False
    noisy = pos + rng.normal(0.0, sigma, pos.shape)
    for _ in range(outliers):
        cand = np.nonzero(keep)[0]
        if cand.size:
            j = int(rng.choice(cand))
            noisy[j] += rng.normal(0.0, 0.4, 3)
    samples: list[dict[str, Any]] = [
        {"time": round(float(t[i]) + t_offset, 5), "ball": {"pos": dict(zip("xyz", np.round(noisy[i], 4).tolist()))}}
        for i in np.nonzero(keep)[0]
    ]
    if events:
        for st in shots:
            samples.append(
                {
                    "time": round(st.t_hit + t_offset, 5),
                    "ball": {"pos": dict(zip("xyz", np.round(st.position([st.t_hit])[0], 4).tolist()))},
                    "event": "hit",
                }
            )
            if st.bounces:
                b = st.bounces[0]
                samples.append(
                    {
                        "time": round(b.t + t_offset, 5),
                        "ball": {"pos": {"x": round(b.x, 4), "y": round(b.y, 4), "z": 0.033}},
                        "event": "bounce",
                    }
                )
        samples.sort(key=lambda smp: float(smp["time"]))
    recs = []
    if shot_records:
        for k, st in enumerate(shots):
            top = float(_spin_parts(st)[0])
            recs.append(
                {
                    "shot_no": k + 1,
                    "team": 1 + (k % 2),
                    "stroke": "serve" if st.serve else "forehand",
                    "time": round(st.t_hit + t_offset, 5),
                    "speed_ms": round(float(np.linalg.norm(st.velocity)), 2),
                    "spin": {"type": "topspin" if top >= 0 else "backspin", "rpm": round(top, 1)},
                    "call": st.call if st.call in ("in", "out") else None,
                    "distance": None if not np.isfinite(st.distance_mm) else round(st.distance_mm / 1000.0, 4),
                }
            )
    return {
        "match": {"season": 2026, "tournament_id": "SYNTH", "players": [{"team": 1}, {"team": 2}]},
        "sequences": sequences or {},
        "shots": recs,
        "samples": samples,
        "events": [],
    }


def _spin_parts(st: ShotTruth) -> np.ndarray:
    d = describe_spin(st.spin, st.velocity)
    return np.array([d["topspin"], d["sidespin"], d["along_path"]]) / RPM


def synthetic_match(
    n_points: int,
    seed: int = 0,
    *,
    rate: float = 50.0,
    sigma: float = 3e-3,
    kinds: dict | None = None,
    **sample_kw,
) -> tuple[list[dict], list[list[ShotTruth]]]:
    """``n_points`` points (documents, truths): games of alternating servers and sides; ``kinds``
    maps point kinds to probabilities (default: 80 % normal, 5 % let, 5 % net fault, 10 % net cord)."""
    rng = np.random.default_rng(seed)
    kinds = kinds or {"normal": 0.8, "let": 0.05, "net-fault": 0.05, "net-cord": 0.1}
    names = list(kinds)
    probs = np.array([kinds[k] for k in names], dtype=float)
    docs, truths = [], []
    for i in range(n_points):
        kind = str(rng.choice(names, p=probs / probs.sum()))
        shots = synthetic_point(
            rng,
            server_near=(i // 6) % 2 == 0,
            deuce=i % 2 == 0,
            rally_len=int(rng.integers(0, 9)),
            kind=kind,
        )
        seq = {"set": 1, "game": 1 + i // 6, "point": 1 + i % 6, "serve": 1, "rally": 1}
        docs.append(sample_point(shots, rng, rate=rate, sigma=sigma, sequences=seq, **sample_kw))
        truths.append(shots)
    return docs, truths
