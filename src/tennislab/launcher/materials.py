"""Ball material parameters for the roller model (seed 002 section 5): Young's modulus and friction.

Young's modulus (seed 002 section 5.1, eq 13 read backwards): a ball of
diameter 2r pressed between flat plates by a load F deforms by dl (diameter
reduction); the seed defines E = F 2r / (s dl), with s the contact area.

What the seed implies about s: it never states it, but every row of its
Tables 1 and 2 gives the same F / (E dl) = 3.175 mm (to the tables' rounding,
+-0.5 %), so s / (2 r) = 3.175 mm: the seed used one constant area,
s = 2.12 cm^2 for its r = 33.3 mm (a disc 16.4 mm across), for every load.
A real contact patch grows with the load (a flattened sphere has
s ~ pi r dl: 0.5 cm^2 at 0.5 mm, 3.8 cm^2 at 3.6 mm), so the seed's E is a
secant "stiffness modulus" of the ball at a nominal area, not a material
modulus of the rubber; that is how we use it (eq 13 with the same s).
The spread of Table 1's E (2.83-4.50 MPa) then just reflects the curvature of
the load-deformation curve.

Seed figures checked: every row of Tables 1-2 gives s / 2r within 0.4 % of
3.175 mm except Table 1's 4.95 kg row, whose printed 4.50 MPa would need
dl = 3.4 mm: with the printed dl = 3.6 mm it is 4.24 MPa (6 % lower).  Hence
the seed's Table 1 mean 3.63 MPa (the mean of its printed column) becomes
3.59 MPa recomputed, its maximum 4.50 becomes 4.24 MPa, and its text's
"variability range 1.60 MPa" is neither its printed 4.50 - 2.83 = 1.67 MPa nor
the recomputed 1.41 MPa.  Table 2 mean 4.20 MPa and range 1.68 MPa are
reproduced (4.19, 1.67).

ITF deformation limits (Table 2; ITF Rules of Tennis, Appendix I, at an
8.165 kg = 18 lb load): type 1 (fast) forward 0.495-0.597 cm, types 2 and 3
forward 0.559-0.737 cm (seed's Table 2 lists 0.559; ITF's is 0.56).

Friction (seed 002 section 5.2, eq 10): mu = tan(eta) for a friction angle eta
on an inclined plane (Table 3).  The seed adopts mu = 2.05 (roller segment,
35 mm contact length, eta = 64 deg).  Table 3's other coefficients are tan(eta) to
the printed rounding except the plane's 39 deg row: tan 39 deg = 0.81, printed 0.80.

References
----------
.. [1] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), sec. 5, eqs 10 and 13,
    Tables 1-3
.. [2] ITF, Rules of Tennis, rule 1 and Appendix I (deformation limits)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tennislab.errors import InputError, check_range
from tennislab.results import Table

#: Standard gravity used to turn a load in kg into a force [m/s^2] (CGPM 1901).
G0 = 9.80665
#: F / (E dl) implied by seed 002 Tables 1-2 [m]; s = this x 2r.
SEED_AREA_PER_DIAMETER = 3.175e-3
#: Ball radius the seed uses (section 3, "0,333 m", a typo for 0.0333 m) [m].
SEED_BALL_RADIUS = 0.0333
#: Contact area implied by the seed [m^2] (= 3.175 mm x 66.6 mm).
SEED_CONTACT_AREA = 2.12e-4

#: Seed 002 Table 1: loading weight [kg], deformation [m], seed's E [MPa].
SEED_TABLE1 = (
    (0.55, 0.0005, 3.40),
    (1.10, 0.0011, 3.09),
    (1.65, 0.0018, 2.83),
    (2.20, 0.0021, 3.24),
    (2.75, 0.0025, 3.40),
    (3.30, 0.0029, 3.52),
    (3.85, 0.0030, 3.96),
    (4.40, 0.0033, 4.12),
    (4.95, 0.0036, 4.50),
    (5.50, 0.0040, 4.25),
)
#: ITF forward-deformation limits at 8.165 kg (seed 002 Table 2): (type, min [m], max [m], seed's E [MPa] at min, max).
ITF_DEFORMATION_LIMITS = (
    ("fast", 0.00495, 0.00597, 5.10, 4.22),
    ("medium", 0.00559, 0.00737, 4.51, 3.42),
    ("slow", 0.00559, 0.00737, 4.51, 3.42),
)
ITF_LOAD_KG = 8.165
#: Seed 002 Table 3: configuration -> rows (contact length [m], friction angle [deg], seed's mu).
SEED_TABLE3 = {
    "plane": (
        (0.008, 32, 0.63),
        (0.010, 34, 0.67),
        (0.015, 37, 0.75),
        (0.020, 39, 0.80),
        (0.025, 41, 0.87),
        (0.030, 43, 0.93),
        (0.035, 44, 0.97),
    ),
    "roller": (
        (0.005, 30, 0.58),
        (0.010, 34, 0.67),
        (0.015, 40, 0.84),
        (0.020, 46, 1.04),
        (0.025, 53, 1.33),
        (0.030, 59, 1.66),
        (0.035, 64, 2.05),
    ),
}


@dataclass(frozen=True)
class YoungResult(Table):
    """Per-row moduli [Pa], their mean, min, max, and the least-squares slope modulus [Pa]; ``rows()`` /
    ``to_frame()`` one row per load (the JSON's ``rows``)."""

    COLUMNS = ("load_n", "deformation_m", "young_modulus_mpa")

    load: np.ndarray
    deformation: np.ndarray
    modulus: np.ndarray
    mean: float
    minimum: float
    maximum: float
    slope_modulus: float
    contact_area: float
    diameter: float

    def rows(self) -> list[dict]:
        return [
            {"load_n": float(f), "deformation_m": float(d), "young_modulus_mpa": float(e) / 1e6}
            for f, d, e in zip(self.load, self.deformation, self.modulus)
        ]

    def to_dict(self) -> dict:
        return {
            "rows": self.rows(),
            "mean_mpa": self.mean / 1e6,
            "min_mpa": self.minimum / 1e6,
            "max_mpa": self.maximum / 1e6,
            "range_mpa": (self.maximum - self.minimum) / 1e6,
            "slope_modulus_mpa": self.slope_modulus / 1e6,
            "contact_area_m2": self.contact_area,
            "diameter_m": self.diameter,
        }


def _arrays(*named):
    out = []
    n = None
    for name, v in named:
        a = np.atleast_1d(np.asarray(v, dtype=float))
        if a.ndim != 1 or a.size == 0:
            raise InputError(f"{name}: expected a non-empty list of numbers")
        if not np.isfinite(a).all():
            raise InputError(f"{name}: row {int(np.argmax(~np.isfinite(a))) + 1}: must be a finite number")
        if n is not None and a.size != n:
            raise InputError(f"{name}: {a.size} values, expected {n} (one per row)")
        n = a.size
        out.append(a)
    return out


MAX_LOAD_N = 10_000.0  #: largest load of a material test row [N]
MIN_DEFORMATION_M = 1e-6  #: smallest deformation of a material test row [m]


def young_modulus(
    load_n, deformation_m, diameter: float = 2 * SEED_BALL_RADIUS, contact_area: float = SEED_CONTACT_AREA
) -> YoungResult:
    """Young's modulus E = F 2r / (s dl) [Pa] per row (seed 002 section 5.1, eq 13), mean and slope fit.

    ``load_n`` F [N] and ``deformation_m`` dl [m] (diameter reduction) per row; ``diameter``
    2r [m]; ``contact_area`` s [m^2] (default: the 2.12 cm^2 implied by the seed's tables).
    The slope modulus uses the least-squares slope k of F against dl through the origin
    (the seed's Fig. 8 reading): E = k 2r / s.
    """
    diameter = check_range("diameter", diameter, 0, 0.2, "m", lo_open=True)
    f, dl = _arrays(("load_n", load_n), ("deformation_m", deformation_m))
    # physical ranges: a ball press loads a ball with tens to hundreds of newtons (the ITF test: 8.165 kg,
    # 80 N), and no press resolves less than a micrometre of deformation
    bad_f = (f <= 0) | (f > MAX_LOAD_N)
    if bad_f.any():
        bad = int(np.argmax(bad_f))
        raise InputError(f"load_n: row {bad + 1}: {f[bad]:g} N is outside the allowed range (0, {MAX_LOAD_N:g}] N")
    bad_dl = (dl < MIN_DEFORMATION_M) | (dl >= diameter)
    if bad_dl.any():
        bad = int(np.argmax(bad_dl))
        raise InputError(
            f"deformation_m: row {bad + 1}: {dl[bad]:g} m is outside the allowed range "
            f"[{MIN_DEFORMATION_M:g}, {diameter:g}) m"
        )
    if not (math.isfinite(contact_area) and 1e-6 <= contact_area < 0.01):  # 1 mm^2 to 100 cm^2
        raise InputError(f"contact_area_m2: {contact_area:g} m^2 is outside the allowed range [1e-06, 0.01) m^2")
    e = f * diameter / (contact_area * dl)
    k = float(np.sum(f * dl) / np.sum(dl * dl))
    return YoungResult(
        f,
        dl,
        e,
        float(e.mean()),
        float(e.min()),
        float(e.max()),
        k * diameter / contact_area,
        float(contact_area),
        float(diameter),
    )


def implied_contact_area(load_n, deformation_m, modulus_pa, diameter: float = 2 * SEED_BALL_RADIUS) -> np.ndarray:
    """The contact area s = F 2r / (E dl) [m^2] behind a table of moduli (what the seed implies)."""
    f, dl, e = _arrays(("load_n", load_n), ("deformation_m", deformation_m), ("modulus_pa", modulus_pa))
    return f * diameter / (e * dl)


def itf_young_moduli(diameter: float = 2 * SEED_BALL_RADIUS, contact_area: float = SEED_CONTACT_AREA) -> YoungResult:
    """Seed 002 Table 2: moduli at the ITF deformation limits under 8.165 kg (fast, medium, slow)."""
    dl = [d for _, lo, hi, *_ in ITF_DEFORMATION_LIMITS for d in (lo, hi)]
    return young_modulus([ITF_LOAD_KG * G0] * len(dl), dl, diameter, contact_area)


@dataclass(frozen=True)
class FrictionResult(Table):
    """mu = tan(eta) per row, with optional contact lengths [m]; mean and maximum; ``rows()`` /
    ``to_frame()`` one row per measurement (the JSON's ``rows``)."""

    COLUMNS = ("friction_angle_deg", "friction_coefficient", "contact_length_m")

    angle_deg: np.ndarray
    mu: np.ndarray
    contact_length: np.ndarray | None
    mean: float
    maximum: float

    def rows(self) -> list[dict]:
        rows = []
        for i, (a, m) in enumerate(zip(self.angle_deg, self.mu)):
            r = {"friction_angle_deg": float(a), "friction_coefficient": float(m)}
            if self.contact_length is not None:
                r["contact_length_m"] = float(self.contact_length[i])
            rows.append(r)
        return rows

    def to_dict(self) -> dict:
        return {"rows": self.rows(), "mean": self.mean, "max": self.maximum}


def friction_coefficient(angle_deg, contact_length_m=None) -> FrictionResult:
    """Friction coefficient mu = tan(eta) from friction angles eta [deg] (seed 002 eq 10, Table 3)."""
    (a,) = _arrays(("friction_angle_deg", angle_deg))
    if ((a < 0) | (a >= 90)).any():
        bad = int(np.argmax((a < 0) | (a >= 90)))
        raise InputError(f"friction_angle_deg: row {bad + 1}: {a[bad]:g} deg is outside the allowed range [0, 90) deg")
    cl = None
    if contact_length_m is not None:
        (cl,) = _arrays(("contact_length_m", contact_length_m))
        if cl.size != a.size:
            raise InputError(f"contact_length_m: {cl.size} values, expected {a.size} (one per row)")
        if (cl < 0).any():
            raise InputError("contact_length_m: must be >= 0 (allowed [0, inf) m)")
    mu = np.tan(np.radians(a))
    return FrictionResult(a, mu, cl, float(mu.mean()), float(mu.max()))


def friction_angle(mu: float) -> float:
    """Friction angle eta = atan(mu) [rad] (seed 002 eq 10)."""
    return math.atan(mu)
