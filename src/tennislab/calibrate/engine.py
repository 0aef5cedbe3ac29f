"""Robust least squares of the serves' bounce misses over aero coefficients and nuisance parameters.

Unknowns (any subset free, the others fixed):

* the aero family's ``cd``, ``cl``, ``cd_s`` (:mod:`tennislab.calibrate.family`), unless a fixed
  aero model is given (then only nuisances are fitted: the validation study's fitted axis);
* ``speed_scale``: a common factor on the tracker's speeds (a sensitivity: it trades off against
  ``cd`` almost exactly, so fit it only with ``cd`` fixed);
* with a *fitted* spin axis, per serve family (flat, slice, kick, pronated, other) the fractions
  (f_top, f_side) of the rate about the topspin and sidespin axes (:mod:`~.predict`).  With the
  linear lift law only the products cl f_top and cl f_side reach the flight, so ``cl`` and a fitted
  axis cannot both be free (refused).

Residuals: the length and width misses of every serve [m] (:func:`~.predict.predict_bounces`),
with the soft-L1 loss at a scale :data:`F_SCALE` far below their spread: nearly least absolute
deviations, whose optimum sets the *median* misses to zero (the target of a bias-free model) and
which the few serves with poor summary points cannot steer.  With a free global parameter, each
serve's misses are divided by its length's sensitivity to the first one (at the start, relative to
the median sensitivity, clipped to 0.2-5): the fit then reads each miss as the parameter change
that would cancel it, and its optimum is the median of those votes, so that every serve counts
once in the median (slow serves, whose length is the most sensitive to drag, would otherwise
weigh most).  Minimised by SciPy's trust-region reflective ``least_squares`` with a
forward-difference Jacobian built here: a global parameter costs one batch of flights, and all
families' axis fractions are stepped together (a family's fractions move only its own serves), so a
Jacobian costs (globals + 2) batches of N aimed flights, each aim warm-started from the last.

Uncertainty: a sandwich covariance clustered by match (serves of a match share balls, air and
tracker; Liang & Zeger 1986, Biometrika 73:13; Cameron & Miller 2015, J. Human Resources 50:317)
from the M-estimator's score and Hessian at the solution (Huber 1967), scaled by G / (G - 1) for G
matches.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from tennislab.calibrate.family import BOUNDS, family_model
from tennislab.calibrate.predict import Prediction, SpinAxis, predict_bounces
from tennislab.calibrate.serves import FAMILIES, Serves
from tennislab.core.aero import AeroModel
from tennislab.core.flight import FlightParams
from tennislab.errors import InputError

F_SCALE = 0.02  #: [m] soft-L1 scale: far below the ~0.3 m spread of the misses, so the fit is nearly L1 (medians)
GLOBALS = ("cd", "cl", "cd_s", "speed_scale")
GLOBAL_BOUNDS = {**BOUNDS, "speed_scale": (0.5, 1.5)}
STEP = 1e-3  #: forward-difference step of every parameter (coefficients, scale and fractions alike)
MAX_NFEV = 40  #: most evaluations of the optimiser (each a batch of aimed flights)


@dataclass(frozen=True)
class FitOutcome:
    """The solution of a fit: values of every parameter (free and fixed), the covariance of the free
    ones, the fitted spin axis and the prediction on the fitted serves."""

    values: dict
    free: tuple[str, ...]
    cov: np.ndarray
    axis: SpinAxis
    prediction: Prediction
    cost: float
    nfev: int
    n_clusters: int

    def sd(self) -> dict:
        d = np.sqrt(np.clip(np.diag(self.cov), 0.0, None)) if self.cov.size else np.array([])
        return {k: float(s) for k, s in zip(self.free, d)}

    def correlation(self) -> dict:
        out = {}
        sd = self.sd()
        for i, a in enumerate(self.free):
            for j, b in enumerate(self.free):
                if j > i and sd[a] > 0 and sd[b] > 0:
                    out[f"{a}:{b}"] = float(self.cov[i, j] / (sd[a] * sd[b]))
        return out


class ServeFit:
    """One least-squares problem over a set of serves (module docstring)."""

    def __init__(
        self,
        serves: Serves,
        base: FlightParams,
        *,
        free: tuple[str, ...],
        values: dict,
        axis: SpinAxis | None,
        aero: AeroModel | None = None,
    ):
        bad = [p for p in free if p not in GLOBALS]
        if bad:
            raise InputError(f"fit: unknown parameter {bad[0]!r}; allowed: {', '.join(GLOBALS)}")
        if aero is not None and any(p in ("cd", "cl", "cd_s") for p in free):
            raise InputError("fit: a fixed aero model has no free coefficients")
        if axis is None and "cl" in free:
            raise InputError(
                "fit: cl and a fitted spin axis cannot both be free (only cl x axis fraction reaches the flight); "
                "fix cl or assume an axis"
            )
        if len(serves) == 0:
            raise InputError("serves: no serves left to fit")
        self.serves = serves
        self.base = base
        self.free = tuple(free)
        self.values = {"cd": 0.6, "cl": 0.6, "cd_s": 0.0, "speed_scale": 1.0, **values}
        self.aero = aero
        self.fixed_axis = axis
        present = sorted(set(serves.family.tolist()), key=FAMILIES.index)
        self.families = present if axis is None else []
        self.fam_index = np.array([FAMILIES.index(f) for f in serves.family])
        self._start: tuple[np.ndarray, np.ndarray] | None = None
        self._last: tuple[np.ndarray, Prediction] | None = None
        self.weight = np.ones(2 * len(serves))
        self.n = len(serves)

    # ------------------------------------------------------------------ parameter vector
    def names(self) -> list[str]:
        return list(self.free) + [f"top_{f}" for f in self.families] + [f"side_{f}" for f in self.families]

    def x0(self, axis0: SpinAxis | None = None) -> np.ndarray:
        ax = axis0 or SpinAxis.angle(60.0)
        top = [ax.top[FAMILIES.index(f)] for f in self.families]
        side = [ax.side[FAMILIES.index(f)] for f in self.families]
        return np.array([self.values[p] for p in self.free] + top + side, dtype=float)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lo = [GLOBAL_BOUNDS[p][0] for p in self.free] + [-1.0] * (2 * len(self.families))
        hi = [GLOBAL_BOUNDS[p][1] for p in self.free] + [1.0] * (2 * len(self.families))
        return np.array(lo), np.array(hi)

    def unpack(self, x) -> tuple[dict, SpinAxis]:
        vals = dict(self.values)
        for p, v in zip(self.free, x[: len(self.free)]):
            vals[p] = float(v)
        if self.fixed_axis is not None:
            return vals, self.fixed_axis
        k = len(self.free)
        nf = len(self.families)
        top = [1.0] * len(FAMILIES)
        side = [0.0] * len(FAMILIES)
        for i, f in enumerate(self.families):
            t, s = float(x[k + i]), float(x[k + nf + i])
            r = max(1.0, float(np.hypot(t, s)))
            top[FAMILIES.index(f)], side[FAMILIES.index(f)] = t / r, s / r
        return vals, SpinAxis("fitted", tuple(top), tuple(side))

    def params(self, vals: dict) -> FlightParams:
        aero = self.aero or family_model(vals["cd"], vals["cl"], vals["cd_s"], radius=self.base.ball.radius)
        return dataclasses.replace(self.base, aero=aero)

    # ------------------------------------------------------------------ evaluation
    def predict(self, x, *, remember: bool = True) -> Prediction:
        """Predicted bounces at parameters ``x`` (the last base evaluation is cached)."""
        x = np.asarray(x, dtype=float)
        if remember and self._last is not None and np.array_equal(self._last[0], x):
            return self._last[1]
        vals, axis = self.unpack(x)
        pred = predict_bounces(self.serves, self.params(vals), axis, start=self._start, speed_scale=vals["speed_scale"])
        if remember:
            self._start = (pred.elevation.copy(), pred.heading.copy())
            self._last = (x.copy(), pred)
        return pred

    def _raw(self, pred: Prediction) -> np.ndarray:
        r = np.concatenate([pred.length, pred.width]) / self.weight
        return np.where(np.isfinite(r), r, 0.0)

    def _set_weights(self, x) -> None:
        """Per-serve weights: the length's sensitivity to the first free global parameter (docstring)."""
        self.weight = np.ones(2 * self.n)
        if not self.free:
            return
        base = self.predict(x, remember=False).length
        xp = np.array(x, dtype=float)
        _, hi = self.bounds()
        h = 10 * STEP if xp[0] + 10 * STEP <= hi[0] else -10 * STEP
        xp[0] += h
        sens = np.abs((self.predict(xp, remember=False).length - base) / h)
        ok = np.isfinite(sens) & (sens > 0)
        if not ok.any():
            return
        sens = np.where(ok, sens, np.median(sens[ok]))
        rel = np.clip(sens / np.median(sens), 0.2, 5.0)
        self.weight = np.concatenate([rel, rel])

    def residuals(self, x) -> np.ndarray:
        return self._raw(self.predict(x))

    def jacobian(self, x) -> np.ndarray:
        """Forward-difference Jacobian of :meth:`residuals` (module docstring)."""
        x = np.asarray(x, dtype=float)
        r0 = self._raw(self.predict(x))
        n2 = r0.size
        jac = np.zeros((n2, x.size))
        _, hi = self.bounds()
        k = len(self.free)
        nf = len(self.families)
        for i in range(k):
            h = STEP if x[i] + STEP <= hi[i] else -STEP
            xp = x.copy()
            xp[i] += h
            jac[:n2, i] = (self._raw(self.predict(xp, remember=False)) - r0) / h
        fam_rows = np.concatenate([self.fam_index, self.fam_index])
        for block in range(2 if nf else 0):
            cols = np.arange(k + block * nf, k + (block + 1) * nf)
            steps = np.where(x[cols] + STEP <= hi[cols], STEP, -STEP)
            xp = x.copy()
            xp[cols] += steps
            d = self._raw(self.predict(xp, remember=False)) - r0
            for c, hc, f in zip(cols.tolist(), steps.tolist(), self.families):
                jac[:n2, c] = np.where(fam_rows == FAMILIES.index(f), d / hc, 0.0)
        return jac

    # ------------------------------------------------------------------ solve
    def solve(self, axis0: SpinAxis | None = None, progress: Callable[[str], None] | None = None) -> FitOutcome:
        x0 = self.x0(axis0)
        lo, hi = self.bounds()
        x0 = np.clip(x0, lo + 1e-9, hi - 1e-9)
        self._set_weights(x0)
        calls = {"n": 0}

        def fun(x):
            calls["n"] += 1
            if progress is not None:
                progress(f"fit evaluation {calls['n']}: " + ", ".join(f"{n}={v:.4f}" for n, v in zip(self.names(), x)))
            return self.residuals(x)

        if x0.size == 0:
            pred = self.predict(x0)
            vals, axis = self.unpack(x0)
            return FitOutcome(vals, (), np.zeros((0, 0)), axis, pred, float("nan"), 1, 0)
        sol = least_squares(
            fun,
            x0,
            jac=lambda x: self.jacobian(x),
            bounds=(lo, hi),
            loss="soft_l1",
            f_scale=F_SCALE,
            x_scale="jac",
            max_nfev=MAX_NFEV,
            xtol=1e-6,
            ftol=1e-7,
        )
        x = sol.x
        pred = self.predict(x)
        vals, axis = self.unpack(x)
        jac = self.jacobian(x)
        cov_all, g = self._covariance(x, pred, jac)
        k = len(self.free)
        return FitOutcome(vals, self.free, cov_all[:k, :k], axis, pred, float(sol.cost), int(sol.nfev), g)

    def _covariance(self, x, pred: Prediction, jac: np.ndarray) -> tuple[np.ndarray, int]:
        r = self._raw(pred)
        z = (r / F_SCALE) ** 2
        # cost 1/2 sum f^2 rho(r^2/f^2), rho(z) = 2 (sqrt(1 + z) - 1): score rho'(z) r J with
        # rho'(z) = (1 + z)^-1/2, and the Gauss-Newton Hessian weight rho' + 2 z rho'' = (1 + z)^-3/2
        jd = jac
        bread = jd.T @ (((1.0 + z) ** -1.5)[:, None] * jd)
        score = ((1.0 + z) ** -0.5 * r)[:, None] * jd
        labels = np.concatenate([self.serves.match, self.serves.match]).astype(str)
        _, inv = np.unique(labels, return_inverse=True)
        g = int(inv.max()) + 1
        sums = np.zeros((g, jd.shape[1]))
        np.add.at(sums, inv, score)
        meat = sums.T @ sums * (g / max(g - 1, 1))
        try:
            binv = np.linalg.pinv(bread)
        except np.linalg.LinAlgError:  # pragma: no cover - pinv rarely fails
            return np.full(bread.shape, np.nan), g
        return binv @ meat @ binv, g
