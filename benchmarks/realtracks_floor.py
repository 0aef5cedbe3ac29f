"""How close can a physical flight come to a tracked one?  The whole-flight residual of real 50 Hz tracks,
split into the part a cubic-stored track forces on any physical flight and the part the model misses.

The tracker stores every flight between a hit and its bounce as one cubic in time (the data's README).
For a fitted physical flight P and the track D (a cubic), with Pi the least-squares projection onto cubics
at the sample times, the residual splits exactly (Pythagoras, since D = Pi D):

    |P - D|^2 = |P - Pi P|^2 + |Pi P - D|^2
                floor          gap

*floor*: the flight's distance from its own best cubic, which no physical flight avoids (drag and
Magnus make a flight's jerk vary; a cubic's is constant); *gap*: the best cubic of the physical flight
against the track's cubic, what a better model of the ball could remove.  Each flight (hit to first
bounce, on-grid samples, :func:`tennislab.calibrate.flights.flights_from_points`, as ``calibrate
tracks`` cuts them) is fitted with the line-call fit's free-flight model (core's right-hand side and
``sweep_positions``): launch state, spin vector, drag and lift scales all free, by SciPy's
``least_squares`` from three spin starts; then the gap alone is minimised (the best any flight of the
family could do).  Reported per aero model: medians over flights (3-D RMS, mm), and the share of the
residual's sum of squares in the Legendre orders 0-2, 3 (the cubic term: the jerk) and 4+.

    .venv/bin/python benchmarks/realtracks_floor.py [FOLDER] [--every K] [--hypotheses]

(FOLDER: a folder of point JSON, default set 1 of the 50 Hz match in ``../shared/realdata/``, found as
``bench_realtracks.py`` finds it; ``--every K`` fits every K-th flight; about 10 minutes on 2 shared
cores for set 1.  ``--hypotheses`` adds, for the second model, what the gap is: parameters added per
shot (spin decay, C_D slope in speed, C_L exponent, C_D against S, time scale) or globally (gravity
tilt and size, time scale, axis scales, wind, C_D slope) with their residuals, best gaps and fitted
values, and a check of the track's own jerk against drag and Magnus (``_realtracks_gap.py``; about
4 CPU minutes with ``--every 4``).  Not a timing: an analysis of real tracks, beside the benchmark that
calls them.)
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from tennislab.calibrate.flights import flights_from_points
from tennislab.core.aero import get_aero_model
from tennislab.core.flight import FlightParams
from tennislab.core.surfaces import get_surface
from tennislab.io.hawkeye import read_points
from tennislab.linecall import model as M

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_realtracks import default_folder

MODELS = {
    "choppin2018": FlightParams(),
    "tennislab2026 + decay 0.174/s": FlightParams.from_options(aero=get_aero_model("tennislab2026"), spin_decay=0.174),
}
SCALE = np.r_[[1.0] * 3, [10.0] * 3, [100.0] * 3, 0.2, 0.2]  #: x_scale of the fit (m, m/s, rad/s, -, -)
SPIN_STARTS = ((0.0, 200.0, 0.0), (0.0, -200.0, 0.0), (0.0, 0.0, 0.0))  #: [rad/s]


def _rms_mm(r: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(r.reshape(-1, 3) ** 2, axis=1))) * 1000.0)


def fit_flight(t: np.ndarray, xyz: np.ndarray, params: FlightParams) -> dict:
    """Residual, floor, gap [mm] and Legendre shares of one flight's physical fit."""
    t = t - t[0]
    consts = M.make_consts(params, get_surface("hard"), 0.0045, 16e-3)
    kern, ap = M.kernel_arg(params), params.aero.params
    w, pos = np.ones(t.size), np.empty((t.size, 3))
    res = np.empty(3 * t.size)

    def direct(q):
        M.free_residuals(np.ascontiguousarray(q), 0.0, t, xyz, w, kern, ap, consts, res, pos)
        return res.copy()

    v0 = (xyz[2] - xyz[0]) / (t[2] - t[0])
    best = None
    for spin in SPIN_STARTS:
        r = least_squares(direct, np.r_[xyz[0], v0, spin, 1.0, 1.0], x_scale=SCALE, max_nfev=400)
        if best is None or r.cost < best.cost:
            best = r
    vander = np.vander((t - t.mean()) / (t[-1] - t[0]), 4)
    proj = vander @ np.linalg.pinv(vander)
    M.free_positions(np.ascontiguousarray(best.x), 0.0, t, kern, ap, consts, pos)
    floor = pos - proj @ pos
    gap = proj @ pos - xyz

    def gap_only(q):
        M.free_positions(np.ascontiguousarray(q), 0.0, t, kern, ap, consts, pos)
        return (proj @ pos - xyz).ravel()

    g = least_squares(gap_only, best.x, x_scale=SCALE, max_nfev=400)
    leg = np.polynomial.legendre.legvander(2 * t / t[-1] - 1, 6)
    co = np.linalg.lstsq(leg, best.fun.reshape(-1, 3), rcond=None)[0]
    e = (co**2).sum(axis=1) / (2 * np.arange(7) + 1)
    e = e / e.sum()
    return {
        "residual": _rms_mm(best.fun),
        "floor": _rms_mm(floor),
        "gap": _rms_mm(gap),
        "best_gap": _rms_mm(g.fun),
        "shares": (e[:3].sum(), e[3], e[4:].sum()),
    }


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?", help="folder of point JSON (default: set 1 of the 50 Hz match)")
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--hypotheses", action="store_true", help="test what the gap is (_realtracks_gap.py)")
    args = ap.parse_args(argv)
    warnings.filterwarnings("ignore", category=RuntimeWarning)
    folder = args.folder or default_folder()
    if folder is None:
        print("realtracks_floor: skipped (no real tracker data: ../shared/realdata/match50hz-set1 is absent)")
        return
    flights = flights_from_points(read_points(folder))[:: max(1, args.every)]
    if not flights:
        sys.exit(f"realtracks_floor: no flights in {folder}")
    data_cubic = []
    for f in flights:
        tt = f.t - f.t[0]
        c = np.vstack([np.polyval(np.polyfit(tt, f.xyz[:, i], 3), tt) for i in range(3)]).T
        data_cubic.append(_rms_mm(c - f.xyz))
    n_serve = sum(1 for f in flights if f.kind == "serve")
    print(f"{len(flights)} flights ({n_serve} serves); the track against its own best cubic: median "
          f"{np.median(data_cubic):.2f} mm (3-D RMS)")  # fmt: skip
    print(f"{'model':30s} | residual: all / serve / rally | floor | gap | best gap | residual in P0-2 / P3 / P4+")
    for name, params in MODELS.items():
        rows = [fit_flight(f.t, f.xyz, params) for f in flights]
        r = np.array([x["residual"] for x in rows])
        s = np.array([f.kind == "serve" for f in flights])
        sh = np.median(np.array([x["shares"] for x in rows]), axis=0)
        print(
            f"{name:30s} | {np.median(r):.2f} / {np.median(r[s]):.2f} / {np.median(r[~s]):.2f} mm"
            f" | {np.median([x['floor'] for x in rows]):.2f} mm | {np.median([x['gap'] for x in rows]):.2f} mm"
            f" | {np.median([x['best_gap'] for x in rows]):.2f} mm"
            f" | {sh[0]:.0%} / {sh[1]:.0%} / {sh[2]:.0%}"
        )
    if args.hypotheses:
        from _realtracks_gap import report

        name = list(MODELS)[-1]
        report(flights, MODELS[name], SCALE, SPIN_STARTS, name)


if __name__ == "__main__":
    main()
