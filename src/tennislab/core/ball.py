"""The tennis ball: mass, radius and moment of inertia.

Defaults are the middle of the ITF ranges for a type-2 (medium pace) ball
(ITF Rules of Tennis, Appendix I): mass 56.0-59.4 g -> 57.7 g; diameter
6.54-6.86 cm -> 6.70 cm (radius 33.5 mm).  The moment of inertia defaults to a
thin-walled sphere, I = 2/3 m r^2, as the seeds use (seed 000 eq 15; seed 002);
Cross (2020) measured a real ball with a ~3 mm wall nearer 0.55 m r^2: pass
``inertia_factor=0.55`` to use it.

References
----------
.. [1] ITF, Rules of Tennis, rule 1 and Appendix I
.. [2] Cross (2020), Sports Eng. 23:9 (moment of inertia of a real ball)
.. [3] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), eq 15
.. [4] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from tennislab.errors import InputError, check_range

ITF_MASS_RANGE = (0.0560, 0.0594)  #: [kg] ITF Rules, Appendix I
ITF_DIAMETER_RANGE = (0.0654, 0.0686)  #: [m] type 2 ball, ITF Rules, Appendix I
THIN_SHELL = 2.0 / 3.0  #: I/(m r^2) for a thin spherical shell
MASS_RANGE = (0.01, 0.5)  #: [kg] allowed masses (physical envelope of balls, not the rules)
RADIUS_RANGE = (0.01, 0.1)  #: [m] allowed radii


@dataclass(frozen=True)
class Ball:
    """A tennis ball.

    Attributes
    ----------
    mass : float
        Mass [kg]; default 0.0577 (ITF range 0.0560-0.0594); allowed 0.01-0.5.
    radius : float
        Radius [m]; default 0.0335 (ITF type-2 diameter 0.0654-0.0686); allowed 0.01-0.1.
    inertia_factor : float
        I / (m r^2) [-]; default 2/3 (thin shell, as in the seeds).
    """

    mass: float = 0.0577
    radius: float = 0.0335
    inertia_factor: float = THIN_SHELL

    def __post_init__(self):
        # Broad physical envelope (junior foam balls are lighter and larger than
        # ITF balls: ITF stage 3 foam, ~25 g and up to 90 mm); use `itf_compliant`
        # for the rules' ranges.  The lower bounds also keep the equations of
        # motion non-stiff (k = rho A / 2m <= 3.2 /m), so that every flight
        # integrates in a bounded number of steps.
        check_range("mass", self.mass, *MASS_RANGE, "kg")
        check_range("radius", self.radius, *RADIUS_RANGE, "m")
        check_range("inertia_factor", self.inertia_factor, 0.0, 1.0, lo_open=True)

    @property
    def area(self) -> float:
        """Cross-sectional area pi r^2 [m^2]."""
        return math.pi * self.radius**2

    @property
    def inertia(self) -> float:
        """Moment of inertia about a diameter [kg m^2]."""
        return self.inertia_factor * self.mass * self.radius**2

    @property
    def itf_compliant(self) -> bool:
        """True when mass and diameter are within the ITF type-2 ranges."""
        d = 2.0 * self.radius
        return (
            ITF_MASS_RANGE[0] <= self.mass <= ITF_MASS_RANGE[1] and ITF_DIAMETER_RANGE[0] <= d <= ITF_DIAMETER_RANGE[1]
        )

    @classmethod
    def from_options(cls, mass=None, radius=None, inertia_factor=None, preset: str = "standard") -> Ball:
        """The ball :meth:`FlightParams.from_options` builds from the same options: the ball of
        ``preset`` (:data:`tennislab.core.names.PRESETS`), each option that is not ``None`` overriding
        it.  It builds no flight physics (no aero model, no compiled kernel): for a computation that
        needs only the ball (the launcher's rollers and power)."""
        from tennislab.core.names import PRESETS

        if preset not in PRESETS:
            raise InputError(f"preset: unknown physics preset {preset!r}; allowed: {', '.join(sorted(PRESETS))}")
        given = {"mass": mass, "radius": radius, "inertia_factor": inertia_factor}
        kw = {k: v for k, v in PRESETS[preset].items() if k in given}
        kw.update({k: v for k, v in given.items() if v is not None})
        return cls(**kw)
