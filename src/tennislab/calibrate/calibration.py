"""Calibration of the aero coefficients on measured serves, and the sensitivity of the misses.

:func:`calibrate_serves` fits the family of :mod:`~.family` (C_D = cd + cd_s min(S, 0.5), C_L = min(cl S,
0.5)) to the *fit* part of a split of the usable serves (:mod:`~.engine`: nearly least absolute
deviations of the length and width misses, match-clustered uncertainties) and reports the misses
before (the baseline model, by default :data:`~tennislab.core.aero.DEFAULT_AERO`, under the same
spin-axis assumption) and after, on the fit part and on the held-out part.  The fitted model is a
full ``speed x spin`` table (:meth:`CalibrationResult.table_csv`) that every command reads with
``--aero table --aero-table FILE``.

:func:`sensitivity_serves` maps the misses over a grid of (cd, cl) and spin-axis assumptions.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from tennislab.calibrate.engine import GLOBALS, ServeFit
from tennislab.calibrate.family import CL_MAX, FORMULA, aero_table_csv, family_model, family_table
from tennislab.calibrate.predict import Prediction, SpinAxis, predict_bounces
from tennislab.calibrate.serves import REASONS, Serves, split_serves
from tennislab.calibrate.stats import by_group, summarize
from tennislab.calibrate.validate import as_serves, legacy_physics, usable, with_aero
from tennislab.core.aero import DEFAULT_AERO, get_aero_model
from tennislab.core.flight import FlightParams
from tennislab.errors import InputError, check_range
from tennislab.results import Table, jsonable

#: starting (or fixed) values: cd between the in-flight and Hawk-Eye measurements, cl of Cross 2020
START = {"cd": 0.6, "cl": 0.6, "cd_s": 0.0, "speed_scale": 1.0}


def _axis_option(spin_axis) -> SpinAxis | None:
    if isinstance(spin_axis, str) and spin_axis.strip().lower() == "fitted":
        return None
    return SpinAxis.parse(spin_axis)


def _fit_tuple(fit) -> tuple[str, ...]:
    names = tuple(s.strip() for s in (fit.split(",") if isinstance(fit, str) else fit) if s.strip())
    bad = [n for n in names if n not in GLOBALS]
    if bad:
        raise InputError(f"fit: unknown parameter {bad[0]!r}; allowed: {', '.join(GLOBALS)}")
    if len(set(names)) != len(names):
        raise InputError("fit: a parameter is listed twice")
    return names


@dataclass(frozen=True)
class CalibrationResult(Table):
    """Aero coefficients calibrated on measured serves (:func:`calibrate_serves`).

    ``to_dict()`` keys: ``family`` (the formula), ``values`` {cd, cl, cd_s, speed_scale}, ``free``
    (fitted names), ``sd`` {name: standard error, match-clustered}, ``correlation`` {"a:b": r},
    ``n_clusters`` (matches in the fit), ``spin_axis`` (assumed or fitted per family: fractions
    and angles), ``split``, ``n_read``, ``n_used``, ``excluded``, ``n_fit``, ``n_held_out``,
    ``baseline`` (model name), ``before`` / ``after`` {``fit``, ``held_out``: summaries as in
    :func:`~.stats.summarize`}, ``held_out_groups`` {grouping: {label: summary}} after calibration,
    ``table`` {``rows``, ``speed_ms`` [min, max], ``spin_rpm`` [min, max], ``radius_m``, ``cl_max``},
    ``physics``, ``cost``, ``evaluations``.  :meth:`rows` gives one row per serve.
    """

    values: dict
    free: tuple[str, ...]
    sd: dict
    correlation: dict
    n_clusters: int
    spin_axis: SpinAxis
    baseline_axis: SpinAxis
    split: str
    n_read: int
    n_used: int
    excluded: dict
    baseline: str
    before: dict
    after: dict
    held_out_groups: dict
    physics: dict
    cost: float
    evaluations: int
    table: tuple = field(repr=False)
    serves: Serves = field(repr=False)
    fit_mask: np.ndarray = field(repr=False)
    pred_before: Prediction = field(repr=False)
    pred_after: Prediction = field(repr=False)

    def to_dict(self) -> dict:
        v, w, cd, cl = self.table
        return jsonable(
            {
                "family": FORMULA,
                "values": self.values,
                "free": list(self.free),
                "sd": self.sd,
                "correlation": self.correlation,
                "n_clusters": self.n_clusters,
                "spin_axis": self.spin_axis.to_dict(),
                "baseline_spin_axis": self.baseline_axis.to_dict(),
                "split": self.split,
                "n_read": self.n_read,
                "n_used": self.n_used,
                "excluded": self.excluded,
                "excluded_reasons": {k: REASONS[k] for k in self.excluded},
                "n_fit": int(self.fit_mask.sum()),
                "n_held_out": int((~self.fit_mask).sum()),
                "baseline": self.baseline,
                "before": self.before,
                "after": self.after,
                "held_out_groups": self.held_out_groups,
                "table": {
                    "rows": int(cd.size),
                    "speed_ms": [float(v[0]), float(v[-1])],
                    "spin_rpm": [float(w[0] * 30 / np.pi), float(w[-1] * 30 / np.pi)],
                    "radius_m": self.physics["radius"],
                    "cl_max": CL_MAX,
                },
                "physics": legacy_physics(self.physics),
                "cost": self.cost,
                "evaluations": self.evaluations,
            }
        )

    def table_csv(self) -> str:
        """The calibrated model as an aero-table CSV (``speed_ms, spin_rpm, cd, cl``)."""
        return aero_table_csv(*self.table)

    def rows(self) -> list[dict]:
        s = self.serves
        b, a = self.pred_before, self.pred_after
        return [
            {
                "match": s.match[i],
                "point_ID": s.point_id[i],
                "serve_num": int(s.serve_num[i]),
                "serve_type": s.serve_type[i],
                "part": "fit" if self.fit_mask[i] else "held_out",
                "speed_kmh": float(s.speed[i] * 3.6),
                "spin_rpm": float(s.spin[i] * 30.0 / np.pi),
                "length_before_m": float(b.length[i]),
                "width_before_m": float(b.width[i]),
                "miss_before_m": float(b.miss[i]),
                "length_m": float(a.length[i]),
                "width_m": float(a.width[i]),
                "miss_m": float(a.miss[i]),
            }
            for i in range(len(s))
        ]


def _parts(pred: Prediction, serves: Serves, fit_mask: np.ndarray) -> dict:
    L, W, c = pred.length, pred.width, serves.match
    return {
        "fit": summarize(L[fit_mask], W[fit_mask], c[fit_mask]),
        "held_out": summarize(L[~fit_mask], W[~fit_mask], c[~fit_mask]),
    }


def calibrate_serves(
    serves,
    *,
    fit: Sequence[str] | str = ("cd",),
    cd: float | None = None,
    cl: float | None = None,
    cd_s: float | None = None,
    speed_scale: float | None = None,
    spin_axis="fitted",
    split: str = "parity",
    baseline: str = DEFAULT_AERO,
    physics: dict | None = None,
    groups: Sequence[str] = ("serve_type", "tour", "event"),
    progress: Callable[[str], None] | None = None,
) -> CalibrationResult:
    """Fit the aero family to measured serves (module docstring).

    Parameters
    ----------
    serves : a :class:`~.serves.Serves` set or the path of a CourtVision serves CSV
    fit : the free parameters among ``cd``, ``cl``, ``cd_s``, ``speed_scale`` (default ``cd``)
    cd, cl, cd_s, speed_scale : start (free) or fixed (not free) values; defaults :data:`START`
        (cl = 0.6: Cross 2020)
    spin_axis : ``fitted`` (default: per serve family, a nuisance fitted with the coefficients; then
        ``cl`` must stay fixed), or an assumption (``topspin``, ``none``, an angle [deg])
    split : :func:`~.serves.split_serves` (default ``parity``: odd matches fitted, even held out)
    baseline : the model the "before" figures use (default :data:`DEFAULT_AERO`)
    physics : other :meth:`FlightParams.from_options` options (mass, radius, air_density, ...)
    groups : groupings of the held-out summaries after calibration
    progress : called with a line of text per optimiser evaluation
    """
    free = _fit_tuple(fit)
    values = dict(START)
    for name, val in (("cd", cd), ("cl", cl), ("cd_s", cd_s), ("speed_scale", speed_scale)):
        if val is not None:
            values[name] = check_range(name, val, -10.0, 10.0)
    base = FlightParams.from_options(**(physics or {}))
    allset = as_serves(serves)
    used, excluded = usable(allset, base)
    fit_mask, _, split_desc = split_serves(used, split)
    if not fit_mask.any():
        raise InputError("split: no serves left in the fit part")
    axis = _axis_option(spin_axis)
    if axis is None and "cl" in free:
        raise InputError(
            "fit: cl and a fitted spin axis cannot both be free (only cl x axis fraction reaches the flight); "
            "fix cl or assume an axis"
        )
    for g in groups:
        used.group(g)
    fitset = used.subset(fit_mask)
    say = progress or (lambda _msg: None)

    # before: the baseline model, its own axis fitted on the same part when the axis is fitted
    base_model = get_aero_model(baseline)
    base_params = with_aero(base, base_model)
    if axis is None:
        say(f"fitting the spin axis of the baseline {baseline}")
        b_axis = ServeFit(fitset, base_params, free=(), values={}, axis=None, aero=base_model).solve().axis
    else:
        b_axis = axis
    pred_before = predict_bounces(used, base_params, b_axis)

    say(f"fitting {', '.join(free) or 'nothing'} on {len(fitset)} serves ({split_desc})")
    problem = ServeFit(fitset, base, free=free, values=values, axis=axis)
    outcome = problem.solve(axis0=b_axis if axis is None else None, progress=say)
    vals = outcome.values
    params = problem.params(vals)
    pred_after = predict_bounces(used, params, outcome.axis, speed_scale=vals["speed_scale"])
    table = family_table(vals["cd"], vals["cl"], vals["cd_s"], radius=base.ball.radius)
    held = ~fit_mask
    return CalibrationResult(
        values=vals,
        free=free,
        sd=outcome.sd(),
        correlation=outcome.correlation(),
        n_clusters=outcome.n_clusters,
        spin_axis=outcome.axis,
        baseline_axis=b_axis,
        split=split_desc,
        n_read=len(allset),
        n_used=len(used),
        excluded=excluded,
        baseline=baseline,
        before=_parts(pred_before, used, fit_mask),
        after=_parts(pred_after, used, fit_mask),
        held_out_groups={
            g: by_group(pred_after.length[held], pred_after.width[held], used.group(g)[held]) for g in groups
        },
        physics=base.to_dict(),
        cost=outcome.cost,
        evaluations=outcome.nfev,
        table=table,
        serves=used,
        fit_mask=fit_mask,
        pred_before=pred_before,
        pred_after=pred_after,
    )


@dataclass(frozen=True)
class SensitivityResult(Table):
    """Misses over a grid of (cd, cl, spin axis, speed scale) (:func:`sensitivity_serves`).

    ``to_dict()`` keys: ``family``, ``split``, ``n_fit``, ``n_held_out``, ``grid`` (list of {``cd``,
    ``cl``, ``spin_axis``, ``speed_scale``, ``fit``, ``held_out``: summaries without intervals,
    ``axis``: the fractions used}).  :meth:`rows` flattens the grid (one row per point and part).
    """

    split: str
    n_fit: int
    n_held_out: int
    grid: tuple

    def to_dict(self) -> dict:
        return jsonable(
            {
                "family": FORMULA,
                "split": self.split,
                "n_fit": self.n_fit,
                "n_held_out": self.n_held_out,
                "grid": list(self.grid),
            }
        )

    def rows(self) -> list[dict]:
        out = []
        for g in self.grid:
            for part in ("fit", "held_out"):
                s = g[part]
                out.append(
                    {
                        "cd": g["cd"],
                        "cl": g["cl"],
                        "spin_axis": g["spin_axis"],
                        "speed_scale": g["speed_scale"],
                        "part": part,
                        **{
                            k: s.get(k)
                            for k in ("n", "miss_median_m", "miss_p90_m", "length_median_m", "width_median_m")
                        },
                    }
                )
        return out


def sensitivity_serves(
    serves,
    *,
    cd: Sequence[float] = (0.5, 0.6, 0.7, 0.8, 0.9),
    cl: Sequence[float] = (0.0, 0.3, 0.6, 0.9),
    spin_axes: Sequence = ("topspin", "fitted"),
    speed_scale: Sequence[float] = (1.0,),
    split: str = "parity",
    physics: dict | None = None,
    progress: Callable[[str], None] | None = None,
) -> SensitivityResult:
    """Median and p90 miss and length/width bias for every (cd, cl, axis, speed scale) of the grid.

    A ``fitted`` axis is fitted per grid point on the fit part of ``split``; the held-out part is
    then a fair measure.  The family is that of :func:`calibrate_serves` (cl_s = 0).
    """
    for name, seq in (("cd", cd), ("cl", cl), ("speed_scale", speed_scale)):
        if len(seq) == 0 or len(seq) > 50:
            raise InputError(f"{name}: give 1 to 50 values")
    base = FlightParams.from_options(**(physics or {}))
    used, _ = usable(as_serves(serves), base)
    fit_mask, _, split_desc = split_serves(used, split)
    fitset = used.subset(fit_mask)
    grid = []
    combos = list(itertools.product(cd, cl, spin_axes, speed_scale))
    for k, (c_d, c_l, ax, vs) in enumerate(combos, start=1):
        c_d = check_range("cd", c_d, 0.05, 2.0)
        c_l = check_range("cl", c_l, -1.0, 3.0)
        vs = check_range("speed_scale", vs, 0.5, 1.5)
        model = family_model(c_d, c_l, radius=base.ball.radius)
        params = with_aero(base, model)
        axis = _axis_option(ax)
        if axis is None and c_l == 0.0:
            axis = SpinAxis.parse("topspin")  # no lift: the axis does not reach the flight
        if axis is None:
            if not fit_mask.any():
                raise InputError("split: the fit part is empty; a fitted spin axis needs serves to fit")
            axis = ServeFit(fitset, params, free=(), values={"speed_scale": vs}, axis=None, aero=model).solve().axis
        pred = predict_bounces(used, params, axis, speed_scale=vs)
        L, W = pred.length, pred.width
        point: dict = {
            "cd": c_d,
            "cl": c_l,
            "spin_axis": str(ax),
            "speed_scale": vs,
            "axis": axis.to_dict(),
            "fit": summarize(L[fit_mask], W[fit_mask], ci=False),
            "held_out": summarize(L[~fit_mask], W[~fit_mask], ci=False),
        }
        grid.append(point)
        if progress is not None:
            h: dict = point["held_out"] if point["held_out"]["n"] else point["fit"]
            progress(
                f"[{k}/{len(combos)}] cd {c_d:g} cl {c_l:g} axis {ax} speed x{vs:g}: median miss "
                f"{h['miss_median_m']:.3f} m, length bias {h['length_median_m']:+.3f} m"
            )
    return SensitivityResult(split_desc, int(fit_mask.sum()), int((~fit_mask).sum()), tuple(grid))
