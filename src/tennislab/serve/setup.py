"""The paper's constants, its 2-D success criteria and the impact schemes.

The paper: Grosen, Kousted & Treichel 2021, "2-dimensional tennis serves ..." (the project's
seed 000).  Constants (its sec. 2.3): air density 1.22 kg/m^3, g = 9.82 m/s^2, ball
radius 0.033 m and mass 0.059 kg, racket mass 0.2 kg, string-bed stiffness
50 kN/m, friction 0.35; flight aero = Stepanek (1988) as the seed writes it
(eqs 3-4, registered as ``stepanek1988``).

2-D criteria (seed sec. 2.3): the serve is hit from the baseline (x = -11.885
m in the court frame, y = 0) "down the middle"; it must pass the net with the
ball centre above 0.943 m ("the radius of the ball was added to the height of
the net (0.943 m)") and land no further than 18.318 m from the impact point
(the service line, 11.885 + 6.40 = 18.285 m, plus the radius).  Seed
inconsistency: 0.943 m = 0.91 + 0.033, i.e. the seed used a net of 0.91 m
(worksheet ch. 1: ".91 m at the center"), not the ITF 0.914 m (which would
give 0.947 m).  We keep 0.943 m for the reproduction and use the real net
profile in 3-D.  "Land" = first contact of the ball with the ground (ball
centre at height r), the physical reading; the seed does not say which height
it stopped its flight at (see docs/serve.md for the sensitivity).

Impact schemes (:data:`IMPACT_SCHEMES`, docs/serve.md "Table 1"): ``converged`` (default) is the
physical model -- elasto-plastic friction that never creates energy, the tangential damper that
restitutes 1.04 COR, springs unloaded at first touch, converged RK4; ``seed-literal`` reads the
paper literally -- its friction clamp (eq 20), eq 6 with the ball's mass for the tangential
damper, the racket starting 0.02 m behind the ball with the tangential spring measured from there
(worksheet sec. 2.2, eq 13) and its explicit Euler step of 1e-4 s (sec. 2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tennislab.core.ball import Ball
from tennislab.core.flight import FlightParams
from tennislab.core.impact import ImpactParams
from tennislab.errors import InputError, check_range

SEED_MASS = 0.059  #: ball mass [kg] (seed sec. 2.3)
SEED_RADIUS = 0.033  #: ball radius [m] (seed sec. 2.3)
SEED_AIR_DENSITY = 1.22  #: [kg/m^3] (seed sec. 2.3)
SEED_GRAVITY = 9.82  #: [m/s^2] (seed sec. 2.3)
SEED_RACKET_MASS = 0.2  #: [kg] (seed sec. 2.3)
SEED_STRING_STIFFNESS = 50e3  #: k_k [N/m] (seed sec. 2.3)
SEED_FRICTION = 0.35  #: mu [-] (seed sec. 2.3, eq 20)
BASELINE_X = -11.885  #: the server's impact point in the court frame [m]


def seed_flight_params(**options) -> FlightParams:
    """:class:`FlightParams` with the seed's constants (preset ``seed000``); any option given overrides."""
    return FlightParams.from_options(preset="seed000", **options)


#: Impact schemes: the model readings and the integration of the impact (module docstring).
IMPACT_SCHEMES: dict[str, dict] = {
    "converged": {
        "friction_model": "elastoplastic",
        "tangential_damping": "oscillator",
        "approach_gap": 0.0,
        "method": "rk4",
        "dt": 0.0,
    },
    "seed-literal": {
        "friction_model": "seed-clamp",  # eq 20 read literally
        "tangential_damping": "ball",  # eq 6 with m_b and T_c, COR x 1.04
        "approach_gap": 0.02,  # worksheet sec. 2.2: racket 0.02 m behind the ball
        "method": "euler",  # sec. 2: "a simple time-integration"
        "dt": 1e-4,  # sec. 2: dt = 1e-4 s
    },
}


def _scheme(scheme: str) -> dict:
    try:
        return IMPACT_SCHEMES[scheme]
    except KeyError:
        raise InputError(f"impact_scheme: unknown {scheme!r}; choose from {', '.join(IMPACT_SCHEMES)}") from None


def seed_impact_params(
    ball: Ball | None = None,
    racket_mass=None,
    string_stiffness=None,
    friction=None,
    ball_model=None,
    *,
    impact_scheme: str = "converged",
    friction_model: str | None = None,
    tangential_damping: str | None = None,
    approach_gap: float | None = None,
) -> ImpactParams:
    """:class:`ImpactParams` with the paper's constants and the model readings of ``impact_scheme``
    (:data:`IMPACT_SCHEMES`); any argument given overrides."""
    sch = _scheme(impact_scheme)
    return ImpactParams.from_options(
        racket_mass=SEED_RACKET_MASS if racket_mass is None else racket_mass,
        string_stiffness=SEED_STRING_STIFFNESS if string_stiffness is None else string_stiffness,
        friction=SEED_FRICTION if friction is None else friction,
        ball=ball or Ball(mass=SEED_MASS, radius=SEED_RADIUS),
        ball_model=ball_model,
        friction_model=sch["friction_model"] if friction_model is None else friction_model,
        tangential_damping=sch["tangential_damping"] if tangential_damping is None else tangential_damping,
        approach_gap=sch["approach_gap"] if approach_gap is None else approach_gap,
    )


def scheme_integration(impact_scheme: str = "converged", method: str | None = None, dt: float | None = None):
    """(method, dt [s]) of the impact integration of ``impact_scheme``; a given method/dt overrides."""
    sch = _scheme(impact_scheme)
    m = sch["method"] if method is None else method
    step = sch["dt"] if dt is None else dt
    check_range("dt", step, 0.0, 1e-3, "s")
    return m, float(step)


def integration_caveats(method: str, dt: float) -> list[str]:
    """Caveats of an impact integration (explicit Euler at a coarse step is not converged)."""
    if method == "euler" and (dt <= 0 or dt > 1e-6):
        return [
            f"impact: explicit Euler at dt = {dt:g} s (the paper's scheme) is not converged; ball speed is "
            "about 5 % high at 1e-4 s (docs/impact.md)"
        ]
    return []


def criteria_caveats(target: str | None) -> list[str]:
    """Caveats of the success test: the paper's 2-D criteria are not the real court."""
    if target is None:
        return [
            "criteria: the paper's 2-D test (net 0.91 m + r, service line + r, no sideways direction); "
            "use a deuce/ad target for the real net and service box"
        ]
    return []


#: highest spin-class bound of :class:`SeedCriteria` [rpm] (beyond any serve's spin: Sakurai et al. 2013
#: measure up to ~5000 rpm)
MAX_BAND_RPM = 10000


@dataclass(frozen=True)
class SeedCriteria:
    """The seed's 2-D success test and spin categories.

    Attributes
    ----------
    net_top : the ball centre must pass the net plane above this height [m] (seed: 0.943)
    service_line : the landing point must be at most this far from the impact point [m] (seed: 18.318)
    server_x : x of the impact point in the court frame [m] (baseline, -11.885)
    flat_max_rpm : flat serve below this spin [rpm] (seed: 1200)
    topspin_min_rpm : topspin serve above this spin [rpm] (seed: 3200, after Sakurai et al. 2013)
    """

    net_top: float = 0.943
    service_line: float = 18.318
    server_x: float = BASELINE_X
    flat_max_rpm: float = 1200.0
    topspin_min_rpm: float = 3200.0

    def __post_init__(self):
        check_range("net_top", self.net_top, 0.0, 5.0, "m")
        check_range("service_line", self.service_line, 0.0, 30.0, "m")
        check_range("flat_max_rpm", self.flat_max_rpm, 0, MAX_BAND_RPM, "rpm")
        check_range("topspin_min_rpm", self.topspin_min_rpm, 0, MAX_BAND_RPM, "rpm")
        if self.topspin_min_rpm < self.flat_max_rpm:
            raise InputError(
                f"topspin_min_rpm: the topspin band's start {self.topspin_min_rpm:g} rpm is below the flat band's "
                f"end {self.flat_max_rpm:g} rpm (give the flat band's end first)"
            )

    def category(self, spin_rpm) -> np.ndarray:
        """0 = flat, 1 = topspin, 2 = other (by |spin|)."""
        w = np.abs(np.asarray(spin_rpm, float))
        return np.where(w < self.flat_max_rpm, 0, np.where(w > self.topspin_min_rpm, 1, 2))


CATEGORIES = ("flat", "topspin", "other")


__all__ = [
    "SeedCriteria",
    "IMPACT_SCHEMES",
    "seed_flight_params",
    "seed_impact_params",
    "scheme_integration",
    "integration_caveats",
    "criteria_caveats",
    "CATEGORIES",
    "BASELINE_X",
]
