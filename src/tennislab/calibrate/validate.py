"""The validation study: measured serves flown through their net points by every aero model.

:func:`validate_serves` flies the usable serves of a CourtVision set (:func:`~.serves.check_serves`)
with each aero model, under one spin-axis assumption, and summarises the bounce misses (median,
90th percentile, length and width bias) overall, on the two parts of a split and per group (serve
type, tour, tournament, event).  With ``spin_axis="fitted"`` the axis of each serve family is a
nuisance fitted per model on the *fit* part of the split only (:mod:`~.engine`), so the held-out
part measures the model, not the fit.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from tennislab.calibrate.engine import ServeFit
from tennislab.calibrate.predict import Prediction, SpinAxis, predict_bounces
from tennislab.calibrate.serves import REASONS, Serves, check_serves, load_serves, split_serves
from tennislab.calibrate.stats import by_group, summarize
from tennislab.core.aero import AeroModel, aero_model_names, get_aero_model
from tennislab.core.flight import FlightParams
from tennislab.errors import InputError
from tennislab.results import Table, jsonable

GROUPS = ("serve_type", "family", "tour", "tournament", "event")  #: default groupings of the summaries


def as_serves(serves) -> Serves:
    """A :class:`Serves` set as is, or read from a CourtVision serves CSV path."""
    return serves if isinstance(serves, Serves) else load_serves(serves)


def usable(serves: Serves, params: FlightParams) -> tuple[Serves, dict]:
    """(the serves that pass :func:`check_serves`, {reason: count} of those left out)."""
    why = check_serves(serves, params.court, params.ball.radius)
    counts = {r: int(np.sum(why == r)) for r in REASONS if np.any(why == r)}
    ok = why == ""
    if not ok.any():
        raise InputError(f"serves: no serves left after the checks (left out: {counts})")
    return serves.subset(ok), counts


def registered_models() -> list[str]:
    """Every registered aero model once (aliases and ``table``, which needs data, left out)."""
    seen: dict[str, str] = {}
    for name in aero_model_names():
        if name == "table":
            continue
        canonical = get_aero_model(name).name
        seen.setdefault(canonical, name)
    return sorted(seen)


def _resolve(models, aero_table) -> list[tuple[str, AeroModel]]:
    names = list(models) if models is not None else registered_models()
    out = []
    for m in names:
        model = m if isinstance(m, AeroModel) else get_aero_model(m)
        out.append((model.name if isinstance(m, AeroModel) else str(m), model))
    if aero_table is not None:
        sp, w, cd, cl = aero_table
        out.append(("table", get_aero_model("table", speed=sp, spin=w, cd=cd, cl=cl)))
    if not out:
        raise InputError("models: no aero model to validate")
    return out


def with_aero(base: FlightParams, aero: AeroModel) -> FlightParams:
    """``base`` with another aero model."""
    return dataclasses.replace(base, aero=aero)


@dataclass(frozen=True)
class ModelValidation:
    """One model's misses: ``overall``, ``fit`` and ``held_out`` summaries (:func:`~.stats.summarize`),
    ``groups`` {grouping: {label: summary}} over all serves, the spin ``axis`` used."""

    model: str
    axis: SpinAxis
    overall: dict
    fit: dict
    held_out: dict
    groups: dict
    prediction: Prediction = field(repr=False)

    def to_dict(self) -> dict:
        return {
            "model": self.model,
            "spin_axis": self.axis.to_dict(),
            "overall": self.overall,
            "fit": self.fit,
            "held_out": self.held_out,
            "groups": self.groups,
        }


@dataclass(frozen=True)
class ValidationResult(Table):
    """The validation study (:func:`validate_serves`).

    ``to_dict()`` keys: ``n_read``, ``n_used``, ``excluded`` {reason: count}, ``excluded_reasons``
    {reason: text}, ``spin_axis`` (the assumption asked for), ``split`` (description), ``n_fit``,
    ``n_held_out``, ``conventions`` (signs of length and width), ``physics`` (ball, air), ``models``
    (list of {``model``, ``spin_axis``, ``overall``, ``fit``, ``held_out``, ``groups``}; each summary
    with ``n``, ``miss_median_m``, ``miss_p90_m``, ``length_median_m``, ``width_median_m``,
    ``length_mean_m``, ``width_mean_m``, ``length_mad_m`` and, overall and per part, 95 % cluster
    bootstrap intervals ``*_ci95_m``).  :meth:`rows` gives one row per serve and model.
    """

    n_read: int
    n_used: int
    excluded: dict
    spin_axis: str
    split: str
    models: tuple[ModelValidation, ...]
    physics: dict
    serves: Serves = field(repr=False)
    fit_mask: np.ndarray = field(repr=False)

    def to_dict(self) -> dict:
        return jsonable(
            {
                "n_read": self.n_read,
                "n_used": self.n_used,
                "excluded": self.excluded,
                "excluded_reasons": {k: REASONS[k] for k in self.excluded},
                "spin_axis": self.spin_axis,
                "split": self.split,
                "n_fit": int(self.fit_mask.sum()),
                "n_held_out": int((~self.fit_mask).sum()),
                "conventions": {
                    "length": "predicted minus measured bounce along the flight (impact to bounce, seen from "
                    "above); > 0 long",
                    "width": "across the flight; > 0 the prediction lands left of the measured bounce (seen "
                    "from the server), < 0 right",
                    "height": "the prediction is carried to the measured bounce height (ball centre z ~ 0.03 m)",
                },
                "physics": legacy_physics(self.physics),
                "models": [m.to_dict() for m in self.models],
            }
        )

    def rows(self) -> list[dict]:
        s = self.serves
        out = []
        for m in self.models:
            p = m.prediction
            for i in range(len(s)):
                out.append(
                    {
                        "model": m.model,
                        "match": s.match[i],
                        "point_ID": s.point_id[i],
                        "serve_num": int(s.serve_num[i]),
                        "serve_type": s.serve_type[i],
                        "part": "fit" if self.fit_mask[i] else "held_out",
                        "speed_kmh": float(s.speed[i] * 3.6),
                        "spin_rpm": float(s.spin[i] * 30.0 / np.pi),
                        "bounce_x_m": float(s.bounce[i, 0]),
                        "bounce_y_m": float(s.bounce[i, 1]),
                        "pred_x_m": float(p.bounce[i, 0]),
                        "pred_y_m": float(p.bounce[i, 1]),
                        "length_m": float(p.length[i]),
                        "width_m": float(p.width[i]),
                        "miss_m": float(p.miss[i]),
                    }
                )
        return out


def legacy_physics(physics: dict) -> dict:
    """A study's ``physics`` (:meth:`FlightParams.to_dict`) with the keys its JSON had before
    (``mass_kg``, ``radius_m``: kept working, CHANGELOG.md)."""
    return {**physics, "mass_kg": physics["mass"], "radius_m": physics["radius"]}


def validate_serves(
    serves,
    *,
    models: Sequence | None = None,
    aero_table=None,
    spin_axis="topspin",
    split: str = "parity",
    physics: dict | None = None,
    groups: Sequence[str] = GROUPS,
    progress: Callable[[str], None] | None = None,
) -> ValidationResult:
    """Fly measured serves through their net points with each aero model and summarise the bounce misses.

    Parameters
    ----------
    serves : a :class:`~.serves.Serves` set or the path of a CourtVision serves CSV
    models : aero model names (or :class:`AeroModel`); default every registered model
    aero_table : optional (speed [m/s], spin [rad/s], cd, cl) arrays, validated as model ``table``
    spin_axis : ``topspin`` (default), ``none``, an axis name or angle [deg] (:class:`~.predict.SpinAxis`),
        or ``fitted`` (per serve family, fitted per model on the fit part of ``split``)
    split : :func:`~.serves.split_serves` (default ``parity``)
    physics : other :meth:`FlightParams.from_options` options (mass, radius, air_density, gravity, ...)
    groups : groupings of the per-group summaries (:meth:`~.serves.Serves.group`)
    progress : called with a line of text as each model is done
    """
    base = FlightParams.from_options(**(physics or {}))
    allset = as_serves(serves)
    used, excluded = usable(allset, base)
    fit_mask, _, split_desc = split_serves(used, split)
    fitted = isinstance(spin_axis, str) and spin_axis.strip().lower() == "fitted"
    if fitted and not fit_mask.any():
        raise InputError("split: the fit part is empty; a fitted spin axis needs serves to fit")
    axis_fixed = None if fitted else SpinAxis.parse(spin_axis)
    for g in groups:
        used.group(g)  # validates the grouping names
    cluster = used.match
    out = []
    for name, model in _resolve(models, aero_table):
        params = with_aero(base, model)
        if fitted:
            fit = ServeFit(used.subset(fit_mask), params, free=(), values={}, axis=None, aero=model)
            axis = fit.solve().axis
        else:
            assert axis_fixed is not None
            axis = axis_fixed
        pred = predict_bounces(used, params, axis)
        L, W = pred.length, pred.width
        held = ~fit_mask
        mv = ModelValidation(
            model=name,
            axis=axis,
            overall=summarize(L, W, cluster),
            fit=summarize(L[fit_mask], W[fit_mask], cluster[fit_mask]),
            held_out=summarize(L[held], W[held], cluster[held]),
            groups={g: by_group(L, W, used.group(g)) for g in groups},
            prediction=pred,
        )
        out.append(mv)
        if progress is not None:
            o = mv.overall
            progress(
                f"{name}: median miss {o['miss_median_m']:.3f} m, length bias {o['length_median_m']:+.3f} m, "
                f"width bias {o['width_median_m']:+.3f} m"
            )
    return ValidationResult(
        n_read=len(allset),
        n_used=len(used),
        excluded=excluded,
        spin_axis=spin_axis if isinstance(spin_axis, str) else spin_axis.name,
        split=split_desc,
        models=tuple(out),
        physics=base.to_dict(),
        serves=used,
        fit_mask=fit_mask,
    )
