"""Calibration on timed tracks: identify a ball's aerodynamics from real flights (``calibrate tracks``).

Input: CSV tracks (:class:`tennislab.io.track.Track`, each one free flight) and/or tracker points
(Hawk-Eye-style point JSON, :func:`tennislab.io.hawkeye.read_points`), cut into hit-to-first-bounce
flights (:mod:`~.flights`).  Two fits:

* **The curves** (default): the global curves of one ball type, C_D against speed and spin, C_L
  against the spin parameter, the spin decay (and optionally the wind), jointly with every flight's
  launch state, spin vector and drag scale (:mod:`~.identify`: method, priors, uncertainties).  The
  flights are split (``split``): ``parity`` fits the odd games' flights and reports on the even ones
  (flights without a game, CSV tracks: the odd-numbered fitted, the even held out), ``parity:even`` the
  other way round, ``none`` fits all, ``holdout=`` gives the held-out flights explicitly.  Residuals
  before (the ``baseline`` model, each flight with the same freedoms) and after are reported per part
  and kind (serve, rally, track) with 95 % bootstrap intervals over flights, beside each flight's
  *cubic floor* (the fitted flight's distance from its own best cubic in time: what a tracker that
  stores a flight as a cubic leaves of a perfect model; :func:`~.identify.cubic_floor_mm`).
* **The family** (``fit`` among ``cd, cl, cd_s``, or a known ``spin_rpm``): the three coefficients of
  :mod:`~.family` on tracks of a known spin (a launcher's setting) or none (:mod:`._family_fit`).

Both write the model as an ``--aero table`` CSV (:meth:`TrackCalibrationResult.table_csv`) and the
spin decay, which every command takes (``--aero table --aero-table FILE --spin-decay RATE``, or the
``[physics]`` table of :meth:`TrackCalibrationResult.config_toml`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tennislab.calibrate._family_fit import FAMILY_PARAMS, family_options, fit_family
from tennislab.calibrate.family import FORMULA, SPEED_GRID, SPIN_GRID, aero_table_csv
from tennislab.calibrate.flights import Detector, Flight, flights_from_points, flights_from_tracks
from tennislab.calibrate.identify import (
    CL_ANCHOR_SLOPE,
    GROUPS,
    MAX_SPIN,
    Curves,
    Identification,
    ShotFit,
    baseline_ext,
    consts_of,
    cubic_floor_mm,
    fit_shots,
    identify,
)
from tennislab.core.aero import DEFAULT_AERO, get_aero_model
from tennislab.core.flight import FlightParams
from tennislab.core.launch import spin_axis_angle
from tennislab.errors import InputError, check_range
from tennislab.io.hawkeye import Point
from tennislab.io.track import Track
from tennislab.results import Table, jsonable
from tennislab.units import RPM

MAX_TRACKS = 5000  #: most flights in one calibration
MIN_POINTS = 8  #: fewest samples of a track in the curves fit
SPLITS = ("parity", "parity:even", "none")  #: the splits (``holdout=`` makes another, "holdout")
CURVES_FORMULA = "C_D = s_D (cd(v) + cd_s min(S, 0.5)), C_L = cl(S), dw/dt = -decay w, S = r w / v"
DEFAULT_FIT = ("cd_v", "cl_s", "decay")  #: the curves' free groups by default (docs/validation.md: why not cd_s)
BOOTSTRAP = 1000  #: resamples of the 95 % intervals over flights
KINDS = ("serve", "rally", "track")


@dataclass(frozen=True)
class TrackCalibrationResult(Table):
    """Aero model identified from tracks (:func:`calibrate_tracks`).

    ``to_dict()`` keys: ``family`` (the model's formula), ``model`` (``curves`` or ``family``),
    ``values`` {name: value} and ``sd`` {name: standard error} of the free parameters, ``free``,
    ``correlation`` (pairs; for the curves those beyond 0.5), ``n_tracks`` (flights used),
    ``n_points``, ``spin`` (the spin assumption), ``baseline``, ``rms_before_mm`` / ``rms_after_mm``
    (residual RMS per coordinate over all points of the held-out flights, else of the fitted ones),
    ``chi2_dof``, ``tracks`` (per flight: ``name, kind, part, n, duration_s, speed_ms, spin_rpm,
    tracker_spin_rpm, drag_scale, weight, rms_before_mm, rms_after_mm, cubic_floor_mm``, after ``track``,
    its number, fitted flights first).  The
    curves add ``curves`` {``speed_ms, cd, cd_sd, s, cl, cl_sd, cd_s, cd_s_sd, spin_decay_per_s,
    spin_decay_sd, wind_ms``}, ``split`` {``name, n_fit, n_held_out``}, ``fit_part`` and ``held_out``
    ({kind: {``n``, ``before``/``after``/``cubic_floor`` {``median_mm, p90_mm, median_ci95_mm,
    p90_ci95_mm``}, ``excess_median_mm``}}, kinds ``all, serve, rally, track``), ``drag_scale``
    {``sigma_prior``, ``p10, p50, p90``}, ``excluded`` (flights not used, by reason), ``convergence``
    {``iterations``, ``stopped``: ``converged``, ``no_descent``, ``max_iter`` or ``nothing_free``} and
    ``spin_decay_per_s`` (what ``--spin-decay`` takes).
    """

    #: the curves' row keys (the family's rows have ``track, name, n, speed_ms, rms_before_mm, rms_after_mm``)
    COLUMNS = (
        "track",
        "name",
        "kind",
        "part",
        "n",
        "duration_s",
        "speed_ms",
        "spin_rpm",
        "tracker_spin_rpm",
        "drag_scale",
        "weight",
        "rms_before_mm",
        "rms_after_mm",
        "cubic_floor_mm",
    )

    model: str
    values: dict
    free: tuple[str, ...]
    sd: dict
    correlation: dict
    n_tracks: int
    n_points: int
    spin: dict
    baseline: str
    rms_before_mm: float
    rms_after_mm: float
    chi2_dof: float
    per_track: tuple
    table: tuple
    spin_decay_per_s: float = 0.0
    curves: dict | None = None
    split: dict | None = None
    fit_part: dict | None = None
    held_out: dict | None = None
    drag_scale: dict | None = None
    excluded: dict | None = None
    convergence: dict | None = None

    def to_dict(self) -> dict:
        out = {
            "family": CURVES_FORMULA if self.model == "curves" else FORMULA,
            "model": self.model,
            "values": self.values,
            "free": list(self.free),
            "sd": self.sd,
            "correlation": self.correlation,
            "n_tracks": self.n_tracks,
            "n_points": self.n_points,
            "spin": self.spin,
            "baseline": self.baseline,
            "rms_before_mm": self.rms_before_mm,
            "rms_after_mm": self.rms_after_mm,
            "chi2_dof": self.chi2_dof,
            "spin_decay_per_s": self.spin_decay_per_s,
            "tracks": list(self.per_track),
        }
        if self.model == "curves":
            for key in ("curves", "split", "fit_part", "held_out", "drag_scale", "excluded", "convergence"):
                out[key] = getattr(self, key)
        return jsonable(out)

    def rows(self) -> list[dict]:
        return [dict(r) for r in self.per_track]

    def table_csv(self) -> str:
        """The model as an aero table (``--aero table --aero-table FILE``)."""
        return aero_table_csv(*self.table)

    def config_toml(self, table_path: str) -> str:
        """A ``tennislab.toml`` ``[physics]`` table flying the model: the table at ``table_path``
        (as written by :meth:`table_csv`) and the spin decay."""
        path = table_path.replace("\\", "\\\\").replace('"', '\\"')
        return (
            "# written by tennislab calibrate tracks\n[physics]\n"
            f'aero = "table"\naero_table = "{path}"\nspin_decay = {self.spin_decay_per_s:.6g}\n'
        )


def _fit_names(fit) -> tuple[str, ...] | None:
    if fit is None:
        return None
    names = tuple(s.strip() for s in (fit.split(",") if isinstance(fit, str) else fit) if s.strip())
    allowed = (*FAMILY_PARAMS, *GROUPS)
    for n in names:
        if n not in allowed:
            raise InputError(f"fit: unknown parameter {n!r} for tracks; allowed: {', '.join(dict.fromkeys(allowed))}")
    return names


def _gather(tracks, points, find_hits, find_bounces, excluded: dict) -> list[Flight]:
    flights = flights_from_tracks(tracks)
    if points:
        flights += flights_from_points(points, find_hits=find_hits, find_bounces=find_bounces, skipped=excluded)
    return flights


def calibrate_tracks(
    tracks: Sequence[Track] = (),
    *,
    points: Sequence[Point] = (),
    holdout_tracks: Sequence[Track] = (),
    holdout_points: Sequence[Point] = (),
    fit: Sequence[str] | str | None = None,
    cd: float | None = None,
    cl: float | None = None,
    cd_s: float | None = None,
    spin_rpm: float | None = None,
    spin_axis="topspin",
    baseline: str = DEFAULT_AERO,
    physics: dict | None = None,
    split: str = "parity",
    drag_sigma: float | None = 0.15,
    speed_knots: Sequence[float] | None = None,
    s_knots: Sequence[float] | None = None,
    max_iter: int = 20,
    find_hits: Detector | None = None,
    find_bounces: Detector | None = None,
    progress: Callable[[str], None] | None = None,
) -> TrackCalibrationResult:
    """Identify the aero model of the ball of ``tracks`` and ``points`` (module docstring).

    Parameters
    ----------
    tracks : CSV tracks, each one free flight
    points : tracker points (cut into hit-to-first-bounce flights; without hit/bounce events the
        detectors ``find_hits`` / ``find_bounces`` find them, e.g. those of :mod:`tennislab.linecall`)
    holdout_tracks, holdout_points : flights held out instead of a ``split``
    fit : the curves' free groups among ``cd_v`` (C_D against speed), ``cd_s`` (against S), ``cl_s`` (C_L
        against S), ``decay``, ``wind`` (default ``cd_v, cl_s, decay``), or the family's
        parameters ``cd``, ``cl``, ``cd_s`` (then ``spin_rpm`` / ``spin_axis`` give the tracks' spin)
    cd, cl, cd_s : the family's start (free) or fixed values (defaults 0.6, 0.6, 0); giving one
        (or ``spin_rpm``) chooses the family fit
    spin_rpm : the tracks' spin rate [rpm] (the family fit; None: no spin)
    spin_axis : its axis relative to each track's initial direction (name or angle [deg])
    baseline : the model of the "before" residuals (default :data:`DEFAULT_AERO`)
    physics : other :meth:`FlightParams.from_options` options (ball, air)
    split : ``parity``, ``parity:even`` or ``none`` (curves; ignored with ``holdout_*``)
    drag_sigma : prior sigma of every flight's drag scale about 1 (None or 0: no drag scale)
    speed_knots : [m/s] knots of cd(v) (default :data:`~.identify.SPEED_KNOTS`)
    s_knots : knots of cl(S) (default :data:`~.identify.S_KNOTS`; the first is anchored)
    max_iter : most iterations of the globals
    """
    names = _fit_names(fit)
    given = any(v is not None for v in (cd, cl, cd_s, spin_rpm))
    family = given or (names is not None and set(names) <= set(FAMILY_PARAMS) and len(names) > 0)
    base = FlightParams.from_options(**(physics or {}))
    say = progress or (lambda _m: None)
    excluded: dict = {}
    flights = _gather(tracks, points, find_hits, find_bounces, excluded)
    held = _gather(holdout_tracks, holdout_points, find_hits, find_bounces, excluded)
    if not flights:
        raise InputError("tracks: no tracks given" if not points else "points: no hit-to-bounce flight in the points")
    if len(flights) + len(held) > MAX_TRACKS:
        raise InputError(f"tracks: {len(flights) + len(held)} tracks, more than the {MAX_TRACKS} allowed")
    for f in (*flights, *held):
        if f.duration > 10.0:
            raise InputError(f"tracks: {f.name} lasts {f.duration:g} s; a free flight lasts < 10 s")
    if family:
        return _family(flights, names, cd, cl, cd_s, spin_rpm, spin_axis, baseline, base, say)
    groups = names if names is not None else DEFAULT_FIT
    bad = [g for g in groups if g not in GROUPS]
    if bad:
        raise InputError(f"fit: {bad[0]} is a parameter of the family fit; the curves take {', '.join(GROUPS)}")
    if split not in SPLITS:
        raise InputError(f"split: unknown split {split!r}; allowed: {', '.join(SPLITS)}")
    sigma = None if not drag_sigma else check_range("drag_sigma", drag_sigma, 0.0, 2.0, lo_open=True)
    check_range("max_iter", max_iter, 1, 200)
    for f in (*flights, *held):
        if len(f) < MIN_POINTS:
            raise InputError(f"tracks: {f.name} has {len(f)} points; the curves need at least {MIN_POINTS} per flight")
    start = _start_curves(speed_knots, s_knots)
    fit_part, held_part, split_name = _split(flights, held, split)
    say(f"{len(fit_part)} flights fitted, {len(held_part)} held out ({split_name})")
    ident = identify(fit_part, base, start=start, free=groups, drag_sigma=sigma, max_iter=int(max_iter), progress=say)
    return _curves_result(ident, fit_part, held_part, split_name, groups, sigma, baseline, base, excluded, say)


def _start_curves(speed_knots, s_knots) -> Curves:
    c = Curves()
    if speed_knots is not None:
        v = tuple(float(x) for x in speed_knots)
        c = Curves(speed=v, cd=(0.6,) * len(v), s=c.s, cl=c.cl)
    if s_knots is not None:
        s = tuple(float(x) for x in s_knots)
        c = Curves(speed=c.speed, cd=c.cd, s=s, cl=tuple(min(CL_ANCHOR_SLOPE * x, 0.5) for x in s))
    c.model()  # checks the knots
    return c


def _split(flights: list[Flight], held: list[Flight], split: str) -> tuple[list[Flight], list[Flight], str]:
    if held:
        return flights, held, "holdout"
    if split == "none":
        return flights, [], "none"
    want = 0 if split == "parity:even" else 1
    fitted = [(f.game if f.game is not None else i + 1) % 2 == want for i, f in enumerate(flights)]
    fit_part = [f for f, o in zip(flights, fitted) if o]
    held_part = [f for f, o in zip(flights, fitted) if not o]
    a, b = ("even", "odd") if want == 0 else ("odd", "even")
    if not fit_part:
        raise InputError(f"split: no flight in the fitted part ({a} games); use split none")
    unit = "games" if any(f.game is not None for f in flights) else "flights"
    return fit_part, held_part, f"{split} ({a} {unit} fitted, {b} held out)"


def _stats(vals: np.ndarray, rng: np.random.Generator) -> dict:
    if vals.size == 0:
        return {"median_mm": None, "p90_mm": None, "median_ci95_mm": None, "p90_ci95_mm": None}
    boot = rng.choice(vals, size=(BOOTSTRAP, vals.size), replace=True)
    med = np.median(boot, axis=1)
    p90 = np.percentile(boot, 90, axis=1)
    return {
        "median_mm": float(np.median(vals)),
        "p90_mm": float(np.percentile(vals, 90)),
        "median_ci95_mm": [float(np.percentile(med, 2.5)), float(np.percentile(med, 97.5))],
        "p90_ci95_mm": [float(np.percentile(p90, 2.5)), float(np.percentile(p90, 97.5))],
    }


def _summary(rows: list[dict], part: str) -> dict:
    rng = np.random.default_rng(20)
    out = {}
    for kind in ("all", *KINDS):
        sel = [r for r in rows if r["part"] == part and (kind == "all" or r["kind"] == kind)]
        if not sel:
            continue
        b = np.array([r["rms_before_mm"] for r in sel])
        a = np.array([r["rms_after_mm"] for r in sel])
        fl = np.array([r["cubic_floor_mm"] for r in sel])
        out[kind] = {
            "n": len(sel),
            "before": _stats(b, rng),
            "after": _stats(a, rng),
            "cubic_floor": _stats(fl, rng),
            "excess_median_mm": float(np.median(np.sqrt(np.maximum(a * a - fl * fl, 0.0)))),
        }
    return out


def _pooled(rows: list[dict], key: str, part: str) -> float:
    sel = [r for r in rows if r["part"] == part] or rows
    n = np.array([r["n"] for r in sel], dtype=float)
    v = np.array([r[key] for r in sel]) / math.sqrt(3.0)  # 3-D RMS -> per coordinate
    return float(np.sqrt(np.sum(v * v * n) / n.sum()))


def _curves_result(
    ident: Identification, fit_part, held_part, split_name, groups, sigma, baseline, base, excluded, say
):
    curves = ident.curves
    consts = consts_of(base)
    bmodel = get_aero_model(baseline)
    bext = baseline_ext(bmodel, base.spin_decay, base.atmosphere.wind)
    kern = curves.model().kernel
    ext = curves.ext()
    say(f"fitting the {len(fit_part) + len(held_part)} flights with the baseline {baseline}")
    before = [ShotFit(f, consts, drag_sigma=sigma) for f in (*fit_part, *held_part)]
    fit_shots(before, bmodel.kernel, bext, say)
    say(f"fitting the {len(held_part)} held-out flights with the identified curves")
    after_held = [ShotFit(f, consts, drag_sigma=sigma) for f in held_part]
    fit_shots(after_held, kern, ext, say)
    after = [*ident.shots, *after_held]
    weights = [*ident.weights, *([None] * len(held_part))]
    rows = []
    for i, (sb, sa, w) in enumerate(zip(before, after, weights)):
        f = sa.flight
        pos = sa.positions(kern, ext)
        rows.append(
            {
                "track": i + 1,
                "name": f.name,
                "kind": f.kind,
                "part": "fit" if w is not None else "held_out",
                "n": len(f),
                "duration_s": f.duration,
                "speed_ms": float(np.linalg.norm(sa.p[3:6])),
                "spin_rpm": sa.spin_rpm,
                "tracker_spin_rpm": f.spin_rpm,
                "drag_scale": sa.drag_scale,
                "weight": None if w is None else float(w),
                "rms_before_mm": sb.rms_mm(bmodel.kernel, bext),
                "rms_after_mm": sa.rms_mm(kern, ext),
                "cubic_floor_mm": cubic_floor_mm(f.t, pos),
            }
        )
    sd_all = np.sqrt(np.clip(np.diag(ident.cov), 0.0, None)) if ident.values.size else np.zeros(0)
    values = {n: float(v) for n, v in zip(ident.names, ident.values)}
    sd = {n: float(s) for n, s in zip(ident.names, sd_all)}
    corr = {}
    for i in range(len(ident.names)):
        for j in range(i + 1, len(ident.names)):
            if sd_all[i] > 0 and sd_all[j] > 0:
                r = float(ident.cov[i, j] / (sd_all[i] * sd_all[j]))
                if abs(r) > 0.5:
                    corr[f"{ident.names[i]}:{ident.names[j]}"] = r
    ds = np.array([s.drag_scale for s in after])
    held = "held_out" if held_part else "fit"
    n_pts = sum(len(s.flight) for s in after)
    dof = max(3 * n_pts - sum(s.np for s in after) - len(ident.values), 1)
    return TrackCalibrationResult(
        model="curves",
        values=values,
        free=tuple(groups),
        sd=sd,
        correlation=corr,
        n_tracks=len(after),
        n_points=n_pts,
        spin={"assumption": "fitted per flight, perpendicular to its path (two components)", "max_rpm": MAX_SPIN / RPM},
        baseline=baseline,
        rms_before_mm=_pooled(rows, "rms_before_mm", held),
        rms_after_mm=_pooled(rows, "rms_after_mm", held),
        chi2_dof=float(ident.cost / dof),
        per_track=tuple(rows),
        table=_table(curves, base.ball.radius),
        spin_decay_per_s=max(curves.decay, 0.0),
        curves=_curves_entry(curves, ident),
        split={"name": split_name, "n_fit": len(fit_part), "n_held_out": len(held_part)},
        fit_part=_summary(rows, "fit"),
        held_out=_summary(rows, "held_out"),
        drag_scale={
            "sigma_prior": sigma,
            "p10": float(np.percentile(ds, 10)),
            "p50": float(np.median(ds)),
            "p90": float(np.percentile(ds, 90)),
        },
        excluded={k: v for k, v in excluded.items() if v},
        convergence={"iterations": ident.iterations, "stopped": ident.stopped},
    )


def _curves_entry(c: Curves, ident: Identification) -> dict:
    """The ``curves`` entry of the JSON: the identified curves and their 1-sigma."""
    sd = dict(zip(ident.names, np.sqrt(np.clip(np.diag(ident.cov), 0.0, None)))) if ident.values.size else {}
    return {
        "speed_ms": list(c.speed),
        "cd": list(c.cd),
        "cd_sd": [sd.get(f"cd@{v:g}") for v in c.speed],
        "s": list(c.s),
        "cl": list(c.cl),
        "cl_sd": [None] + [sd.get(f"cl@{v:g}") for v in c.s[1:]],
        "cl_anchor_slope": CL_ANCHOR_SLOPE,
        "cd_s": c.cd_s,
        "cd_s_sd": sd.get("cd_s"),
        "spin_decay_per_s": c.decay,
        "spin_decay_sd": sd.get("decay"),
        "wind_ms": list(c.wind),
    }


def _table(c: Curves, radius: float) -> tuple:
    """The curves on the grid of :mod:`~.family` (speed [m/s], spin [rad/s], C_D, C_L)."""
    v = SPEED_GRID.copy()
    w = SPIN_GRID * RPM
    c_d, c_l = c.model().coefficients(v[:, None], w[None, :], radius)
    return v, w, np.asarray(c_d), np.asarray(c_l)


def _family(flights, names, cd, cl, cd_s, spin_rpm, spin_axis, baseline, base, say) -> TrackCalibrationResult:
    names_, values, rate = family_options(names, cd, cl, cd_s, spin_rpm)
    tracks = [Track(f.t, f.xyz, f.sigma) for f in flights]
    for f in flights:
        if len(f) < 4:
            raise InputError(f"tracks: {f.name} has {len(f)} points; need at least 4")
    res = fit_family(tracks, names_, values, rate, spin_axis, base, baseline, say)
    npts = np.array([len(tr) for tr in tracks])
    all_b = float(np.sqrt(np.sum(np.array(res.rms_before) ** 2 * npts) / npts.sum()))
    all_a = float(np.sqrt(np.sum(np.array(res.rms_after) ** 2 * npts) / npts.sum()))
    per = tuple(
        {
            "track": i + 1,
            "name": f.name,
            "n": int(len(f)),
            "speed_ms": res.speeds[i],
            "rms_before_mm": 1000 * res.rms_before[i],
            "rms_after_mm": 1000 * res.rms_after[i],
        }
        for i, f in enumerate(flights)
    )
    return TrackCalibrationResult(
        model="family",
        values=res.values,
        free=names_,
        sd=res.sd,
        correlation=res.correlation,
        n_tracks=len(tracks),
        n_points=int(npts.sum()),
        spin={"rpm": rate / RPM, "axis_deg": _axis_deg(spin_axis) if rate else None},
        baseline=baseline,
        rms_before_mm=1000 * all_b,
        rms_after_mm=1000 * all_a,
        chi2_dof=res.chi2_dof,
        per_track=per,
        table=res.table,
        spin_decay_per_s=base.spin_decay,
    )


def _axis_deg(spin_axis) -> float:
    return float(np.degrees(spin_axis_angle(spin_axis)))
