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

Data provenance -- READ THIS.  The speed-by-speed values of Haake et al. (2003)
are only in that paper's figures, which were not accessible when this module
was written.  :data:`RIGID_SURFACE_POINTS` is therefore a *placeholder
transcription*: six points that follow the trends the paper's abstract states
(COR falls, stiffness rises with speed), anchored at the one hard number we
have -- the ITF drop test, COR 0.729-0.761 at 7.06 m/s (ITF Rules of Tennis,
Appendix I) -- and at contact times of 4-5 ms reported for tennis balls on
rigid surfaces (Cross 1999, Sports Eng. 2:23; Goodwill & Haake 2004).  They
must be replaced by a digitisation of Haake et al. (2003) figs 4-5 before any
quantitative claim rests on them; the fitted model below is a power law, so
the swap is a data-only change.  See docs/impact.md ("Ball data").

Model: T_c(v) = T_ref (v/v_ref)^(-p_T),  COR(v) = e_ref (v/v_ref)^(-p_e),
least-squares in log-log over the points (:func:`fit_power_law`).  Above the
data (v > 30 m/s: every serve's normal impact speed) the fit is an
extrapolation.  ``constant`` holds both fixed (the sensitivity case).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from tennislab.errors import InputError, check_range

#: (impact speed [m/s], contact time [s], COR [-]) for a pressurised ball on a
#: rigid surface.  PLACEHOLDER values (see the module docstring), following
#: Haake, Carre & Goodwill 2003 (J. Sports Sci. 21:839) trends; 7 m/s anchored
#: to the ITF rebound test (COR 0.729-0.761 at 7.06 m/s).
RIGID_SURFACE_POINTS = (
    (7.0, 5.2e-3, 0.75),
    (10.0, 5.0e-3, 0.72),
    (15.0, 4.6e-3, 0.68),
    (20.0, 4.35e-3, 0.64),
    (25.0, 4.15e-3, 0.60),
    (30.0, 4.0e-3, 0.57),
)
V_REF = 20.0  #: reference speed of the power laws [m/s]


def fit_power_law(v, y, v_ref: float = V_REF) -> tuple[float, float]:
    """Least-squares fit of y = y_ref (v/v_ref)^(-p) in log-log; returns (y_ref, p)."""
    lv = np.log(np.asarray(v, float) / v_ref)
    ly = np.log(np.asarray(y, float))
    slope, icpt = np.polyfit(lv, ly, 1)
    return float(math.exp(icpt)), float(-slope)


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
    """

    name: str
    tc_ref: float
    tc_exp: float
    cor_ref: float
    cor_exp: float
    v_ref: float = V_REF
    v_min: float = 1.0
    source: str = ""

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

    def spring_damper(self, v, mass: float):
        """(k_b [N/m], c_b [N s/m]) of a ball of ``mass`` [kg] at impact speed v (seed eqs 5-6)."""
        tc = self.contact_time(v)
        e = self.cor(v)
        k = mass * math.pi ** 2 / tc ** 2
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


@register_ball_model("haake2003")
def haake2003() -> BallImpactModel:
    """Power-law fit to :data:`RIGID_SURFACE_POINTS` (placeholder transcription of
    Haake, Carre & Goodwill 2003, J. Sports Sci. 21:839; see module docstring)."""
    v, tc, e = (np.array(c) for c in zip(*RIGID_SURFACE_POINTS))
    tc_ref, tc_exp = fit_power_law(v, tc)
    e_ref, e_exp = fit_power_law(v, e)
    return BallImpactModel("haake2003", tc_ref, tc_exp, e_ref, e_exp,
                           source="Haake, Carre & Goodwill 2003 J. Sports Sci. 21:839 (trend; "
                                  "placeholder points, see tennislab.core.haake2003)")


@register_ball_model("constant")
def constant(contact_time: float = 4.35e-3, cor: float = 0.64) -> BallImpactModel:
    """T_c and COR independent of speed (defaults: the 20 m/s point of the data) [s], [-]."""
    check_range("contact_time", contact_time, 0.0, 0.1, "s", lo_open=True)
    check_range("cor", cor, 0.0, 1.0, lo_open=True)
    return BallImpactModel("constant", contact_time, 0.0, cor, 0.0,
                           source="speed-independent (sensitivity case)")


def get_ball_model(model="haake2003", **params) -> BallImpactModel:
    """Resolve a ball impact model by registered name (or pass a :class:`BallImpactModel`)."""
    if isinstance(model, BallImpactModel):
        return model
    try:
        factory = _REGISTRY[model]
    except KeyError:
        raise InputError(f"ball model: unknown {model!r}; choose from {', '.join(ball_model_names())}") from None
    return factory(**params)
