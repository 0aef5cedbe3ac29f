"""Line calling on synthetic tracks whose truth flies with another model than the fit's (issues 4, 13).

Truth: ``cross2014`` with C_D = 0.6 and C_L = 0.6 S, spin about every axis (topspin, sidespin, spin along
the path), contact time 4.0 ms (:mod:`tennislab.linecall.synth_points`); the fit: the default aero model
(:data:`tennislab.core.aero.DEFAULT_AERO`, named in the output) with its drag and lift scales free under
priors, contact time 4.5 ms.  That truth is close to some of the models the fit may default to (it
differs from ``choppin2018``, C_D 0.60 and C_L = smooth min(0.6 S, 0.5), only by the lift cap), so the
same shots are also flown by a second truth with another drag *shape*: ``stepanek1988`` (C_D 0.55-0.75
rising with spin, C_L = 1/(2 + 1/S)), each re-aimed so that its mark lands as far from its line as
under the first truth.  Synthetic truth proves the code, not the physics: real tracks are the test of the physics
(docs/linecall.md).

Part 1, shots: serves (flat, slice, kick), groundstrokes and lobs, each aimed so that its true mark
lands a random distance in [-30, +30] mm from a line, sampled at 50 Hz and at 340 Hz with 3-D noise
sigma, fitted with sigma unknown (``call_track``).  Printed per rate and truth: bounce-point error
(median, p90, max, mean, bias along the path), calls correct beyond 5 mm from the line, reviews, time per
call, the fitted effective C_D at the bounce against the truth's; the same tracks under other fit
settings (the approach and the bounce fitted jointly, aero scales fixed); the baseline of a quadratic
extrapolation of the last 0.1 s to z = r; and, for reference, a truth flown with the fit's own model
(self-consistent).

Part 2, a match: ``--points`` points (about two shots each: serves, rallies, volleys, net cords, lets,
net faults, double bounces; dropouts, a gap after each hit, an outlier per point) at 50 Hz, flown by the
first truth, called by ``call_rally`` with 1 and 2 workers: calls per second on the 2 cores (ratio
against one reference ``fly`` measured in the same run) and the calls against the truth.

    .venv/bin/python benchmarks/bench_linecall.py [--n 40] [--points 400] [--sigma 0.003] [--seed 1]

(about 2 minutes on 2 shared cores with the defaults, 2026-12-01; ``--points 0`` skips part 2, ``--n 0``
part 1.)
"""

from __future__ import annotations

import argparse
import json
import time
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq

from tennislab.core.aero import DEFAULT_AERO
from tennislab.core.flight import FlightParams, fly_dense
from tennislab.core.mark import MarkParams
from tennislab.core.rally import fly_bounces
from tennislab.io.hawkeye import parse_points
from tennislab.linecall import call_rally, call_track
from tennislab.linecall.decide import call_mark
from tennislab.linecall.synth_points import (
    TRUTH_CONTACT,
    ShotTruth,
    simulate_shot,
    synthetic_match,
    truth_params,
)
from tennislab.units import RPM

#: the second truth: another drag shape than the first truth's and the fit's (spin-dependent C_D)
ALT_TRUTH_AERO = "stepanek1988"

CONFIGS = {
    "default": {},
    "joint approach + bounce": {"post": "joint"},
    "aero scales fixed": {"drag": "fixed", "lift": "fixed"},
}


def random_shot(rng):
    """(kind, position, velocity, spin, target) of a random shot toward the far half, near a line."""
    kind = rng.choice(["serve", "rally", "lob"], p=[0.4, 0.4, 0.2])
    if kind == "serve":
        side = rng.choice([-1.0, 1.0])
        pos = (-11.6, side * rng.uniform(0.2, 1.0), rng.uniform(2.6, 2.95))
        sub = rng.choice(["flat", "slice", "kick"])
        if sub == "flat":
            v = (rng.uniform(45, 58), 0.0, rng.uniform(-5.5, -3.5))
            w = (rng.uniform(-80, 80), rng.uniform(0, 100), rng.uniform(-80, 80))
        elif sub == "slice":
            v = (rng.uniform(38, 46), 0.0, rng.uniform(-3.0, -1.5))
            w = (rng.uniform(-100, 100), rng.uniform(50, 150), -side * rng.uniform(150, 300))
        else:
            v = (rng.uniform(32, 38), 0.0, rng.uniform(0.3, 1.2))
            w = (side * rng.uniform(50, 150), rng.uniform(200, 320), side * rng.uniform(50, 150))
        target = "ad-box" if side > 0 else "deuce-box"
        box = {"deuce-box": (0.0, 6.4, -0.025, 4.115), "ad-box": (0.0, 6.4, -4.115, 0.025)}[target]
        line = rng.choice(["service", "side"])
        aim = (6.4 - 0.3, 0.5 * (box[2] + box[3])) if line == "service" else (4.8, box[3] if side < 0 else box[2])
    else:
        pos = (rng.uniform(-12.5, -9.5), rng.uniform(-3, 3), rng.uniform(0.6, 1.1))
        if kind == "rally":
            v = (rng.uniform(24, 36), 0.0, rng.uniform(3.0, 6.5))
            wy = rng.choice([-1, 1, 1]) * rng.uniform(500, 3000) * RPM
            w = (rng.uniform(-300, 300) * RPM, wy, rng.uniform(-600, 600) * RPM)
        else:
            v = (rng.uniform(12, 16), 0.0, rng.uniform(9.5, 13.0))
            w = (rng.uniform(-300, 300) * RPM, rng.uniform(-800, 2000) * RPM, rng.uniform(-300, 300) * RPM)
        target = "singles"
        line = rng.choice(["baseline", "side"])
        ys = rng.choice([-1, 1]) * 4.115
        aim = (11.885 - 0.5, rng.uniform(-3, 3)) if line == "baseline" else (rng.uniform(7, 11), ys)
    d = np.array(aim) - np.array(pos[:2])
    sp = np.hypot(v[0], v[1])
    v = (sp * d[0] / np.hypot(*d), sp * d[1] / np.hypot(*d), v[2])
    return kind, pos, v, w, target


def aim_distance(pos, v, w, target, want_mm, params, mark_params):
    """Scale the speed so that the true mark reaches want_mm into the target (None if impossible)."""

    def dist(s):
        r = fly_bounces(pos, np.array(v) * s, w, params, bounces=1, mark_params=mark_params, rtol=1e-9, atol=1e-11)
        if not r.bounces:
            return np.nan
        return call_mark(r.bounces[0].mark, target=target)["distance_mm"] - want_mm

    try:
        if not (dist(0.85) * dist(1.15) < 0):
            return None
        return brentq(dist, 0.85, 1.15, xtol=1e-10)
    except (ValueError, RuntimeError):
        return None


def poly_baseline(t, xyz, r):
    """Quadratic extrapolation of the last 0.1 s before the lowest point to z = r."""
    i = int(np.argmin(xyz[:, 2]))
    sel = (t <= t[i]) & (t >= t[i] - 0.1)
    if sel.sum() < 3:
        sel = np.arange(max(0, i - 3), i + 1)
    tt = t[sel] - t[i]
    cz = np.polyfit(tt, xyz[sel, 2], 2)
    roots = np.roots(cz - [0, 0, r])
    roots = np.real(roots[np.isreal(roots)])
    tau = roots[np.argmin(np.abs(roots))] if roots.size else 0.0
    return np.polyval(np.polyfit(tt, xyz[sel, 0], 2), tau), np.polyval(np.polyfit(tt, xyz[sel, 1], 2), tau)


class Shot(NamedTuple):
    kind: str
    st: ShotTruth  # the truth
    target: str
    true_mm: float  # the true mark's distance into the target [mm]
    phase: float  # the sampling clock's phase [frames]
    seed: int  # of the track noise
    pos: tuple  # where the shot was hit [m]


def make_shots(n, seed, params, mark_params):
    rng = np.random.default_rng(seed)
    shots, tries = [], 0
    while len(shots) < n and tries < 6 * n:
        tries += 1
        kind, pos, v, w, target = random_shot(rng)
        s = aim_distance(pos, v, w, target, rng.uniform(-30, 30), params, mark_params)
        if s is None:
            continue
        st = simulate_shot(pos, np.array(v) * s, w, 0.0, params, mark_params=mark_params, max_bounces=2)
        if st.net is not None or not st.bounces:
            continue
        true_mm = call_mark(st.bounces[0].mark, target=target)["distance_mm"]
        shots.append(Shot(kind, st, target, true_mm, rng.uniform(), int(rng.integers(1 << 30)), pos))
    return shots


def reaim_shots(shots, params, mark_params):
    """The same shots (position, direction, spin, sampling) flown by another truth, the speed scaled
    so that each mark lands as far from its line as before (shots that cannot be re-aimed are left out)."""
    out = []
    for sh in shots:
        v, w = sh.st.velocity, sh.st.spin
        s = aim_distance(sh.pos, v, w, sh.target, sh.true_mm, params, mark_params)
        if s is None:
            continue
        st = simulate_shot(sh.pos, v * s, w, 0.0, params, mark_params=mark_params, max_bounces=2)
        if st.net is not None or not st.bounces:
            continue
        true_mm = call_mark(st.bounces[0].mark, target=sh.target)["distance_mm"]
        out.append(sh._replace(st=st, true_mm=true_mm))
    return out


def sample(st, rate, sigma, phase, seed):
    rng = np.random.default_rng(seed)
    b = st.bounces[0]
    t = phase / rate + np.arange(0.0, b.t + 0.3, 1.0 / rate)
    x = st.position(t)
    ok = np.all(np.isfinite(x), axis=1)
    return t[ok], x[ok] + rng.normal(0.0, sigma, (ok.sum(), 3))


def truth_cd(shots, params):
    """C_D of the truth at each shot's bounce (its incoming speed and spin)."""
    r = params.ball.radius
    out = []
    for sh in shots:
        b = sh.st.bounces[0]
        out.append(params.aero.coefficients(np.linalg.norm(b.velocity_in), np.linalg.norm(b.spin_in), r)[0])
    return np.array(out)


def report_fits(shots, rate, sigma, cd_truth):
    """One line per fit setting (:data:`CONFIGS`) and the quadratic baseline over ``shots``; ``cd_truth``:
    the truth's C_D at each shot's bounce (:func:`truth_cd`)."""
    for name, opts in CONFIGS.items():
        err, along, ok, far, rev, cpu, cde = [], [], [], [], 0, [], []
        dcd = []
        for sh, cd_true in zip(shots, cd_truth):
            t, x = sample(sh.st, rate, sigma, sh.phase, sh.seed)
            c0 = time.process_time()
            res = call_track(t, x, target=sh.target, **opts)
            cpu.append((time.process_time() - c0) * 1000)
            b = sh.st.bounces[0]
            if res.bounce is None:
                rev += 1
                continue
            cde.append(res.fit.get("cd_effective") or np.nan)
            dcd.append(cde[-1] - cd_true)
            dx, dy = res.bounce["x"] - b.x, res.bounce["y"] - b.y
            h = b.velocity_in[:2] / np.hypot(*b.velocity_in[:2])
            err.append(1000 * np.hypot(dx, dy))
            along.append(1000 * (dx * h[0] + dy * h[1]))
            rev += res.call == "review"
            if abs(sh.true_mm) > 5:
                far.append(True)
                ok.append(res.call == ("in" if sh.true_mm >= 0 else "out") or res.call == "review")
        e = np.array(err)
        wrong = len(ok) - int(np.sum(ok))
        print(
            f"   {name:24s} bounce error median {np.median(e):5.2f} mm, p90 {np.percentile(e, 90):5.2f}, "
            f"max {e.max():5.1f}, mean {e.mean():5.2f}, bias along the path {np.median(along):+5.2f} mm; "
            f"wrong calls beyond 5 mm {wrong}/{len(far)}; review {rev}; {np.median(cpu):.0f} ms CPU per call; "
            f"effective C_D at the bounce median {np.nanmedian(cde):.3f} (truth {np.median(cd_truth):.3f}; "
            f"fit - truth per shot median {np.nanmedian(dcd):+.3f}, |.| p90 {np.nanpercentile(np.abs(dcd), 90):.3f})"
        )
    pe = []
    for sh in shots:
        t, x = sample(sh.st, rate, sigma, sh.phase, sh.seed)
        bx, by = poly_baseline(t, x, 0.0335)
        pe.append(1000 * np.hypot(bx - sh.st.bounces[0].x, by - sh.st.bounces[0].y))
    print(
        f"   {'quadratic baseline':24s} bounce error median {np.median(pe):5.1f} mm, p90 {np.percentile(pe, 90):5.1f}"
    )


def part_shots(n, seed, sigma):
    truth, mp = truth_params(), TRUTH_CONTACT
    alt = FlightParams.from_options(aero=ALT_TRUTH_AERO)
    shots = make_shots(n, seed, truth, mp)
    alt_shots = reaim_shots(shots, alt, mp)
    ref = make_shots(max(n // 2, 10), seed + 1, FlightParams(), MarkParams())
    kinds = ", ".join(f"{k} {sum(s.kind == k for s in shots)}" for k in ("serve", "rally", "lob"))
    print(
        f"Part 1: {len(shots)} shots ({kinds}) near lines; fit: default aero model {DEFAULT_AERO}, scales under "
        f"priors, T_c 4.5 ms; truth A: cross2014 C_D 0.6, C_L 0.6 S, T_c 4.0 ms; truth B: the same shots "
        f"re-aimed under {ALT_TRUTH_AERO} (C_L 1/(2 + 1/S)), T_c 4.0 ms: {len(alt_shots)} of {len(shots)}"
    )
    cd_a, cd_b = truth_cd(shots, truth), truth_cd(alt_shots, alt)
    print(f"   truth B's C_D at the bounces: {cd_b.min():.3f}-{cd_b.max():.3f}, median {np.median(cd_b):.3f}")
    for rate in (50.0, 340.0):
        print(f"-- {rate:.0f} Hz, noise {sigma * 1000:.1f} mm per axis, sigma estimated")
        print(f"  truth A (cross2014, {len(shots)} shots)")
        report_fits(shots, rate, sigma, cd_a)
        print(f"  truth B ({ALT_TRUTH_AERO}, {len(alt_shots)} shots)")
        report_fits(alt_shots, rate, sigma, cd_b)
        re = []
        for sh in ref:
            t, x = sample(sh.st, rate, sigma, sh.phase, sh.seed)
            res = call_track(t, x, target=sh.target)
            if res.bounce is not None:
                b = sh.st.bounces[0]
                re.append(1000 * np.hypot(res.bounce["x"] - b.x, res.bounce["y"] - b.y))
        print(
            f"   {'self-consistent truth':24s} bounce error median {np.median(re):5.2f} mm, "
            f"p90 {np.percentile(re, 90):5.2f} ({len(re)} shots flown with the fit's own model)"
        )


def part_match(n_points, seed, sigma):
    t0 = time.perf_counter()
    docs, truths = synthetic_match(n_points, seed=seed, rate=50.0, sigma=sigma)
    points = parse_points(json.dumps(docs), "synthetic match")
    n_shots = sum(len(s) for s in truths)
    print(
        f"Part 2: a synthetic match of {n_points} points, {n_shots} shots at 50 Hz "
        f"({time.perf_counter() - t0:.0f} s to make)"
    )
    t1 = time.perf_counter()
    for _ in range(20):
        fly_dense((-11.9, 0.4, 2.85), (50, 1, -4.4), (0, 60, 80), FlightParams())
    fly_ms = (time.perf_counter() - t1) / 20 * 1000
    results = {}
    for workers in (1, 2):
        c0 = time.process_time()
        res = call_rally(points, workers=workers)
        cpu = time.process_time() - c0  # this process only: the CPU of the calls with 1 worker
        results[workers] = res
        sm = res.summary
        cpu_note = f", {1000 * cpu / max(len(res.shots), 1):.1f} ms CPU per call" if workers == 1 else ""
        print(
            f"   workers {workers}: {sm['seconds']:.1f} s, {sm['calls_per_second']:.1f} calls per second{cpu_note} "
            f"({1000 / sm['calls_per_second']:.1f} ms per call = {1000 / sm['calls_per_second'] / fly_ms:.1f} x one "
            f"reference fly of {fly_ms:.1f} ms)"
        )
    res = results[1]
    by: dict = {}
    for s in res.shots:
        by.setdefault(s["point"], []).append(s)
    conf: dict = {}
    errs = []
    for p, shots in zip(points, truths):
        for g, t in zip(by.get(p.name, []), shots):
            key = (t.call, g["call"])
            conf[key] = conf.get(key, 0) + 1
            if t.bounces and g["bounce"]["x"] is not None and (t.net is None or t.net["crossed"]):
                errs.append(1000 * np.hypot(g["bounce"]["x"] - t.bounces[0].x, g["bounce"]["y"] - t.bounces[0].y))
    print("   calls (truth -> ours): " + ", ".join(f"{a}->{b} {c}" for (a, b), c in sorted(conf.items())))
    e = np.array(errs)
    print(f"   bounce error median {np.median(e):.2f} mm, p90 {np.percentile(e, 90):.2f} mm over {e.size} bounces")
    sm = res.summary
    print(
        f"   against the tracker's own records: {sm['tracker_calls_agree']}/{sm['tracker_calls_compared']} "
        "calls agree; "
        f"bounce distance median {sm['bounce_distance_mm_all']['median']:.2f} mm"
    )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=40, help="shots of part 1")
    ap.add_argument("--points", type=int, default=400, help="points of the match of part 2 (0: skip)")
    ap.add_argument("--sigma", type=float, default=3e-3, help="track noise per axis [m]")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args([] if argv is None else argv)  # run_all.py calls main() with its own argv
    if a.n:
        part_shots(a.n, a.seed, a.sigma)
    if a.points:
        part_match(a.points, a.seed, a.sigma)


if __name__ == "__main__":
    import sys

    main(sys.argv[1:])
