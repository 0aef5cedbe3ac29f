"""Speed-dependent ball contact time and COR, and the ball's spring and damper (seed 000 eqs 5-6).

Seed 000 (section 2.2) models the ball as a spring k_b and damper c_b in
parallel, computed from the contact time T_c and the coefficient of
restitution COR of a ball impact (Goodwill & Haake 2001, Proc. IMechE C 215:1331):

    k_b = m_b pi^2 / T_c^2                       (seed eq 5)
    c_b = -(2 m_b / T_c) ln(COR)                 (seed eq 6)

(eq 5 is the half-period of an undamped mass-spring, eq 6 the logarithmic
decrement of the lightly damped one).  T_c and COR depend on the impact speed;
the seed takes them from Haake, Carre & Goodwill (2003), J. Sports Sci. 21:839
(its ref [14]): on a rigid surface the COR of a pressurised ball falls and its
dynamic stiffness rises (T_c falls) with impact speed.

Data provenance -- READ THIS (:data:`DATA_STATUS` = ``"placeholder"``)
-----------------------------------------------------------------------
The speed-by-speed values of Haake et al. (2003) are only in that paper's
figures.  Neither they nor any other tabulated contact time / COR of a
pressurised ball versus impact speed could be obtained for this module (a first
attempt, then the literature search of 2026-11-24 recorded below), so
:data:`RIGID_SURFACE_POINTS` remains a *placeholder*: six points that follow the
trends the paper's abstract states (COR falls, stiffness rises with speed),
anchored at the one hard number we have -- the ITF drop test -- and at contact
times of 4-5 ms.  Per point:

* 7.0 m/s, COR 0.75: inside the ITF band e = 0.729-0.761 at 7.06 m/s
  (ITF Rules of Tennis, Appendix I: 254 cm drop, 135-147 cm rebound; e =
  sqrt(h_out/h_in), computed [C]).  T_c 5.2 ms: placeholder.
* 10-30 m/s: placeholders following the trend of Haake et al. 2003 [abstract
  only], T_c within the 4-5 ms "on the court" range (Brody, second-hand [S]).

Known defect of the placeholder fit: at the ITF test speed (7.06 m/s) the power
law gives COR 0.764, 0.003 above the ITF band (the 7 m/s point itself is
inside); residuals of the fit are <= 2.4 % in COR and <= 1.4 % in T_c.

What the searches found (value, speed, surface, how it was read):

* Haake, Carre & Goodwill 2003, J. Sports Sci. 21:839-850 -- abstract only [A]:
  six ball types on a force platform (rigid surface) and on rigidly clamped
  rackets (high-speed video); COR falls with velocity; pressurised balls have
  the highest COR and stiffness; puncturing lowers COR by 20 % and stiffness
  by 35 %; pressureless balls approach punctured ones at high speed.  No
  numbers per speed.
* Dignall & Haake 2000 (Tennis Science & Technology 1, "Analytical modelling
  of the impact of tennis balls on court surfaces") -- abstract only [A]: balls
  projected at 6.7-20 m/s onto a rigid surface; spring and damper in parallel
  fitted to the data.  No values.
* Cross 1999, Sports Eng. 2:23-33 ("Dynamic properties of tennis balls") --
  abstract and introduction only [A]: force plate; force rises to half its
  peak in the first 200 us, then the wall buckles and the ball softens;
  impact duration, compression and COR are given *as functions of speed in
  its figures*.  A game-development repository quotes it as "COR ~0.75 at
  5 m/s, ~0.65 at 15 m/s" [S, unverified, anonymous notes: NOT used].
* Davies (Loughborough PhD thesis, "Determination and analysis of dimensions
  of 'feel' in tennis ball impacts") -- abstract only [A]: stiffness, damping,
  peak force and contact time of a single-degree-of-freedom viscoelastic ball
  reported for 16-66 m/s (the only source found that covers serve speeds).
* Glynn, King & Mitchell 2011, Sports Eng. 13:65-72 -- abstract [A]:
  visco-elastic point-mass ball, racket impacts at 16-27 m/s; no ball table
  in the accessible text.
* Vallatta, Casolo & Caffi (ISBS proceedings, "On the coefficient of
  restitution of tennis rackets") -- abstract [A]: their fig 1 is COR of a
  ball vs impact velocity on a rigid wall; figure not accessible.
* Goodwill & Haake 2001 (seed ref [11]), Goodwill & Haake 2004 (Proc. IMechE
  C 218, rigid surface), Goodwill, Kirk & Haake 2005 (Sports Eng. 8:145, seed
  ref [12]) -- abstracts/citations only; no per-speed numbers found.
* Contact time on strings ~3.5 ms (Kawazoe, 20,000 fps) [P, per
  /work/shared/reference-data.md]; not a rigid-surface value, not used.

What a real transcription needs (data-only change, see :func:`model_from_points`):
digitise Haake et al. 2003's COR-vs-inbound-velocity and stiffness-vs-inbound-
velocity curves for a *new pressurised* ball on the force platform (rigid
surface), 5-10 points each over the measured range; record the ball's mass;
check how the paper defines "dynamic stiffness" -- if it is Goodwill & Haake's
k = m pi^2 / T_c^2 (seed eq 5), convert with :func:`contact_time_from_stiffness`
using the *tested* ball's mass; list each point with its figure number.  Cross
1999 (figs of impact duration and COR vs speed) or Davies' thesis (16-66 m/s)
would be independent checks; the latter would also remove the extrapolation
above 30 m/s.

Model: T_c(v) = T_ref (v/v_ref)^(-p_T),  COR(v) = e_ref (v/v_ref)^(-p_e),
least-squares in log-log over the points (:func:`fit_power_law`).  Above the
data (v > 30 m/s: every professional serve's normal impact speed) the fit is an
extrapolation.  ``constant`` holds both fixed (the sensitivity case); the
effect of +-15 % in T_c and +-0.05 in COR on the seed's Table 1 is in
docs/serve.md ("Sensitivity to the ball data").

References
----------
.. [1] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), sec. 2.2, eqs 5-6
.. [2] Goodwill & Haake (2001), Proc. IMechE C 215:1331
.. [3] Haake, Carre & Goodwill (2003), J. Sports Sci. 21:839
.. [4] ITF, Rules of Tennis, rule 1 and Appendix I (the drop test)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from tennislab.errors import InputError, check_range

#: Provenance of :data:`RIGID_SURFACE_POINTS`: ``"placeholder"`` until a digitisation
#: of Haake et al. (2003) replaces them (module docstring).
DATA_STATUS = "placeholder"

#: (impact speed [m/s], contact time [s], COR [-]) for a pressurised ball on a
#: rigid surface.  PLACEHOLDER values (see the module docstring), following the
#: Haake, Carre & Goodwill 2003 (J. Sports Sci. 21:839) trends [abstract]; the
#: 7 m/s COR lies in the ITF rebound band (0.729-0.761 at 7.06 m/s, ITF Rules of
#: Tennis App. I, computed); every other number is a placeholder.
RIGID_SURFACE_POINTS = (
    (7.0, 5.2e-3, 0.75),  # COR: ITF band [C]; T_c: placeholder
    (10.0, 5.0e-3, 0.72),  # placeholder (trend of Haake et al. 2003)
    (15.0, 4.6e-3, 0.68),  # placeholder
    (20.0, 4.35e-3, 0.64),  # placeholder
    (25.0, 4.15e-3, 0.60),  # placeholder
    (30.0, 4.0e-3, 0.57),  # placeholder
)
V_REF = 20.0  #: reference speed of the power laws [m/s]


def fit_power_law(v, y, v_ref: float = V_REF) -> tuple[float, float]:
    """Least-squares fit of y = y_ref (v/v_ref)^(-p) in log-log; returns (y_ref, p)."""
    lv = np.log(np.asarray(v, float) / v_ref)
    ly = np.log(np.asarray(y, float))
    slope, icpt = np.polyfit(lv, ly, 1)
    return float(math.exp(icpt)), float(-slope)


def contact_time_from_stiffness(stiffness, mass: float):
    """T_c = pi sqrt(m / k) [s]: seed eq 5 inverted, for data given as a dynamic stiffness k [N/m]
    of a ball of ``mass`` [kg] (valid only if the source defines k as m pi^2 / T_c^2, as
    Goodwill & Haake 2001 do)."""
    k = np.asarray(stiffness, float)
    if np.any(~np.isfinite(k)) or np.any(k <= 0):
        raise InputError("stiffness: must be finite and > 0 N/m")
    check_range("mass", mass, 0.0, 1.0, "kg", lo_open=True)
    return math.pi * np.sqrt(mass / k)


@dataclass(frozen=True)
class BallImpactModel:
    """Contact time and COR of the ball as power laws of the normal impact speed.

    Attributes
    ----------
    name : registry name
    tc_ref : contact time at ``v_ref`` [s]
    tc_exp : exponent p_T of T_c = tc_ref (v/v_ref)^-p_T [-]
    cor_ref : COR at ``v_ref`` [-]
    cor_exp : exponent p_e of COR = cor_ref (v/v_ref)^-p_e [-]
    v_ref : reference speed [m/s]
    v_min : speeds below this are evaluated at v_min [m/s] (avoids T_c -> inf)
    source : citation
    data_status : provenance of the numbers: ``"placeholder"`` (not measured values: the model
        carries a caveat, :meth:`caveat`), ``"digitised"``/``"measured"``, or ``""`` (user-given)
    """

    name: str
    tc_ref: float
    tc_exp: float
    cor_ref: float
    cor_exp: float
    v_ref: float = V_REF
    v_min: float = 1.0
    source: str = ""
    data_status: str = ""

    def __post_init__(self):
        check_range("tc_ref", self.tc_ref, 0.0, 0.1, "s", lo_open=True)
        check_range("cor_ref", self.cor_ref, 0.0, 1.0, lo_open=True)
        check_range("tc_exp", self.tc_exp, -2.0, 2.0)
        check_range("cor_exp", self.cor_exp, -2.0, 2.0)

    def contact_time(self, v):
        """T_c(v) [s] for normal impact speed v [m/s]."""
        v = np.maximum(np.abs(np.asarray(v, float)), self.v_min)
        return self.tc_ref * (v / self.v_ref) ** (-self.tc_exp)

    def cor(self, v):
        """COR(v) [-] for normal impact speed v [m/s] (capped at 1)."""
        v = np.maximum(np.abs(np.asarray(v, float)), self.v_min)
        return np.minimum(self.cor_ref * (v / self.v_ref) ** (-self.cor_exp), 1.0)

    def caveat(self) -> str | None:
        """A one-sentence caveat for results built on this model, or None."""
        if self.data_status == "placeholder":
            return (
                f"impact: ball contact time and COR ({self.name}) are placeholder values that follow the trends of "
                "Haake et al. 2003, not measured data; expect ~2 % in speed and spin (docs/impact.md)"
            )
        return None

    def spring_damper(self, v, mass: float):
        """(k_b [N/m], c_b [N s/m]) of a ball of ``mass`` [kg] at impact speed v (seed eqs 5-6)."""
        tc = self.contact_time(v)
        e = self.cor(v)
        k = mass * math.pi**2 / tc**2
        c = -2.0 * mass / tc * np.log(e)
        return k, c


_REGISTRY: dict[str, Callable[..., BallImpactModel]] = {}


def register_ball_model(name: str):
    """Decorator registering a factory ``f(**params) -> BallImpactModel``."""

    def deco(factory):
        _REGISTRY[name] = factory
        return factory

    return deco


def ball_model_names() -> list[str]:
    return sorted(_REGISTRY)


def model_from_points(name: str, points, source: str, v_ref: float = V_REF, data_status: str = "") -> BallImpactModel:
    """Power-law :class:`BallImpactModel` fitted to ``points`` = ((v [m/s], T_c [s], COR [-]), ...).

    The way to register a transcribed data set (module docstring): at least two distinct
    speeds, T_c in (0, 0.1] s, COR in (0, 1]."""
    pts = np.asarray(points, float)
    if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] < 2:
        raise InputError("points: need >= 2 rows of (speed [m/s], contact time [s], COR)")
    v, tc, e = pts.T
    if np.any(~np.isfinite(pts)) or np.any(v <= 0) or np.unique(v).size < 2:
        raise InputError("points: speeds must be finite, > 0 m/s and at least two distinct")
    if np.any(tc <= 0) or np.any(tc > 0.1):
        raise InputError("points: contact time must be in (0, 0.1] s")
    if np.any(e <= 0) or np.any(e > 1):
        raise InputError("points: COR must be in (0, 1]")
    tc_ref, tc_exp = fit_power_law(v, tc, v_ref)
    e_ref, e_exp = fit_power_law(v, e, v_ref)
    return BallImpactModel(name, tc_ref, tc_exp, e_ref, e_exp, v_ref=v_ref, source=source, data_status=data_status)


@register_ball_model("haake2003")
def haake2003() -> BallImpactModel:
    """Power-law fit to :data:`RIGID_SURFACE_POINTS` (placeholder transcription of
    Haake, Carre & Goodwill 2003, J. Sports Sci. 21:839; see module docstring):
    T_c = 4.34 ms (v/20)^-0.185, COR = 0.629 (v/20)^-0.187."""
    return model_from_points(
        "haake2003",
        RIGID_SURFACE_POINTS,
        source="Haake, Carre & Goodwill 2003 J. Sports Sci. 21:839 (trend; "
        f"{DATA_STATUS} points, see tennislab.core.haake2003)",
        data_status=DATA_STATUS,
    )


@register_ball_model("constant")
def constant(contact_time: float = 4.35e-3, cor: float = 0.64) -> BallImpactModel:
    """T_c and COR independent of speed (defaults: the 20 m/s point of the data) [s], [-]."""
    check_range("contact_time", contact_time, 0.0, 0.1, "s", lo_open=True)
    check_range("cor", cor, 0.0, 1.0, lo_open=True)
    return BallImpactModel("constant", contact_time, 0.0, cor, 0.0, source="speed-independent (sensitivity case)")


def get_ball_model(model="haake2003", **params) -> BallImpactModel:
    """Resolve a ball impact model by registered name (or pass a :class:`BallImpactModel`)."""
    if isinstance(model, BallImpactModel):
        return model
    try:
        factory = _REGISTRY[model]
    except KeyError:
        raise InputError(f"ball_model: unknown {model!r}; choose from {', '.join(ball_model_names())}") from None
    return factory(**params)
