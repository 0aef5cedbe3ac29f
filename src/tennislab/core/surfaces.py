"""Court surfaces as named parameter sets, and the ITF Court Pace Rating.

A :class:`Surface` holds the parameters of the ball-court impact model of
:mod:`tennislab.core.bounce`: the vertical coefficient of restitution ``e``,
the coefficient of sliding friction ``mu`` and the tangential coefficient of
restitution ``e_x`` of a gripping ball (0 = it rolls out, Brody 1984; > 0 =
it leaves overspinning, as Cross 2002 measured).

Court Pace Rating (ITF CS 01/02; ITF Technical Booklet 2015):

    CPR = 100 (1 - mu) + 150 (0.81 - e),
    e  = v_out,z / v_in,z,   mu = (v_in,x - v_out,x) / (v_in,z (1 + e)),

measured with a ball fired at 30 m/s, 16 deg to the surface, spin <= 3 rev/s.
:func:`tennislab.core.bounce.court_pace_rating` simulates that test with the bounce model and applies
the formula to the simulated velocities, so a surface on which the ball grips
gets the lower *apparent* friction the ITF test would measure.  Categories:
slow <= 29, medium-slow 30-34, medium 35-39, medium-fast 40-44, fast >= 45.

Built-in surfaces (their CPR, computed by the model, in brackets; see
docs/bounce.md for the sensitivity d CPR / d mu = -100, d CPR / d e = -150):

``clay``    mu = 0.80, e = 0.90: Cross 2003 (Sports Eng. 6:93) / Cross 2010
            (Sports Technol. 3:112) as quoted in reference-data.md [S,
            unverified]; the ball grips at the ITF angle (apparent mu 0.73).
            [CPR 13: slow; the ITF places most clay courts in category 1].
``grass``   mu = 0.53, e = 0.75: same sources [S, unverified].  [CPR 56: fast;
            the ITF places most natural grass in category 5].
``hard``    mu = 0.65, e = 0.80: a representative acrylic hard court.  No
            primary measurement was available to us; the values sit inside the
            band Carre, Johnson & Haake 2002 (Eng. of Sport 4:200) report for
            acrylic courts between clay and carpet [A].  [CPR 36.5: medium].
``carpet``  mu = 0.50, e = 0.80: indoor carpet gives "fast, shallow rebound"
            (Carre et al. 2002 [A]); values representative, not measured.
            [CPR 51.5: fast].

These are parameter sets, not measurements of a particular court: pass your
own (``Surface("mycourt", e=..., mu=...)`` or ``register_surface``) when a
court has been tested.  ``e`` is held constant; real balls' e falls with
impact speed (Haake, Carre & Goodwill 2003).

References
----------
.. [1] ITF CS 01/02, court pace rating (ITF Technical Booklet 2015)
.. [2] Brody (1984), Phys. Teach. 22:494
.. [3] Cross (2002), Am. J. Phys. 70:1093
.. [4] Cross (2003), Sports Eng. 6:93
.. [5] Cross (2010), Sports Technol. 3:112
.. [6] Carre, Johnson & Haake (2002), The Engineering of Sport 4:200
.. [7] Haake, Carre & Goodwill (2003), J. Sports Sci. 21:839
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from tennislab.errors import InputError, check_range

#: ITF test conditions (ITF CS 01/02): speed [m/s], angle to the surface [rad]
ITF_CPR_SPEED = 30.0
ITF_CPR_ANGLE = math.radians(16.0)

#: CPR category bounds (ITF classification) as (upper bound inclusive, name)
CPR_CATEGORIES = ((29.0, "slow"), (34.0, "medium-slow"), (39.0, "medium"), (44.0, "medium-fast"), (math.inf, "fast"))


@dataclass(frozen=True)
class Surface:
    """A court surface for the bounce model.

    Attributes
    ----------
    name : identifier
    e : vertical coefficient of restitution v_out,z / v_in,z [-] (0-1)
    mu : coefficient of sliding friction [-] (0-2)
    e_x : tangential coefficient of restitution of a gripping ball [-] (0-1):
        the slip of the contact point reverses to -e_x of its incoming value
        (0 = rolls out, Brody 1984; Cross 2002 measured overspin, e_x > 0)
    category : published ITF pace category of this surface type (for checks)
    source : where the numbers come from
    """

    name: str
    e: float
    mu: float
    e_x: float = 0.0
    category: str = ""
    source: str = ""

    def __post_init__(self):
        check_range("surface e", self.e, 0.0, 1.0, lo_open=True)
        check_range("surface mu", self.mu, 0.0, 2.0)
        check_range("surface e_x", self.e_x, 0.0, 1.0)

    def with_(self, **kw) -> Surface:
        """A copy with some parameters replaced (e.g. ``hard.with_(mu=0.7)``)."""
        return replace(self, **kw)


_SURFACES: dict[str, Surface] = {}


def register_surface(surface: Surface) -> Surface:
    """Register a surface under its name (replacing any previous one)."""
    _SURFACES[surface.name] = surface
    return surface


def surface_names() -> list[str]:
    """Names of all registered surfaces."""
    return sorted(_SURFACES)


def get_surface(surface="hard", **overrides) -> Surface:
    """A registered surface by name (or a :class:`Surface` itself), with optional overrides."""
    if isinstance(surface, Surface):
        s = surface
    else:
        if surface not in _SURFACES:
            raise InputError(f"surface: unknown name {surface!r}; allowed: {', '.join(surface_names())}")
        s = _SURFACES[surface]
    kw = {k: v for k, v in overrides.items() if v is not None}
    return s.with_(**kw) if kw else s


register_surface(
    Surface(
        "clay",
        e=0.90,
        mu=0.80,
        category="slow",
        source="Cross 2003 Sports Eng. 6:93; Cross 2010 Sports Technol. 3:112 [S, unverified]",
    )
)
register_surface(
    Surface(
        "grass",
        e=0.75,
        mu=0.53,
        category="fast",
        source="Cross 2003 Sports Eng. 6:93; Cross 2010 Sports Technol. 3:112 [S, unverified]",
    )
)
register_surface(
    Surface(
        "hard",
        e=0.80,
        mu=0.65,
        category="medium",
        source="representative acrylic court; Carre, Johnson & Haake 2002 [A]",
    )
)
register_surface(
    Surface(
        "carpet",
        e=0.80,
        mu=0.50,
        category="fast",
        source="representative indoor carpet; Carre, Johnson & Haake 2002 [A]",
    )
)


def cpr_category(cpr: float) -> str:
    """ITF pace category of a Court Pace Rating."""
    c = round(cpr)
    for hi, name in CPR_CATEGORIES:
        if c <= hi:
            return name
    return "fast"  # pragma: no cover


def cpr_formula(e: float, mu: float) -> float:
    """CPR = 100 (1 - mu) + 150 (0.81 - e) (ITF CS 01/02)."""
    return 100.0 * (1.0 - mu) + 150.0 * (0.81 - e)
