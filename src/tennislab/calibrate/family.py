"""The calibrated aerodynamic family and its table (the ``--aero table`` format every command reads).

Family (the spin ratio S = r w / v, r the ball radius, w = |omega|, v the air speed)::

    C_D = cd + cd_s min(S, S_DRAG_MAX)     (S_DRAG_MAX = 0.5: held beyond the data)
    C_L = min(cl S, cl_max)

* ``cd``: drag of a non-spinning ball; in-flight measurements give 0.507 +- 0.024 for new balls at
  15-30 m/s (Cross & Lindsey 2014, Sports Eng. 17:89) and effective 0.579 (new) / 0.603 (used)
  from 9,224 Hawk-Eye serves (Choppin et al. 2018, Proceedings 2:265).
* ``cd_s``: growth of drag with spin (Stepanek 1988's C_D rises from 0.55 with S; Cross & Lindsey
  found none); 0 unless fitted.
* ``cl``: lift slope; C_L = 0.6 S in Cross 2020 (Sports Eng. 23:9), the launcher paper's form
  (seed 002 eq 3).  ``cl_max`` caps it where the linear law would run away at low speed and high
  spin: 0.5, the limit of Stepanek's C_L = 1/(2 + 1/S) as S grows (seed 000 eq 3).

:func:`family_table` tabulates the family on the grid of :data:`SPEED_GRID` x :data:`SPIN_GRID`
(C_D and C_L are linear in w, so the table is exact along the spin axis; along speed the 1/v of S is
interpolated on a geometric grid of ratio 1.08, an error below 0.1 % of C_L).  The calibration
fits the model through this very table, so the table written is the model fitted.  Outside the
grid the table clamps (speed above 90 m/s, spin above 10,000 rpm).

References
----------
.. [1] Cross & Lindsey (2014), Sports Eng. 17:89
.. [2] Choppin et al. (2018), Proceedings 2:265
.. [3] Stepanek (1988), Am. J. Phys. 56:138
.. [4] Cross (2020), Sports Eng. 23:9
.. [5] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), eq 3
.. [6] Wojcicki, Pucilowski & Kulesza (2010), Acta Mechanica et Automatica (seed 002), eq 3
"""

from __future__ import annotations

import io

import numpy as np

from tennislab.core.aero import AeroModel, get_aero_model
from tennislab.errors import InputError
from tennislab.units import RPM

#: speed grid [m/s]: geometric, 2 to 90 m/s (ratio ~1.08)
SPEED_GRID = np.unique(np.round(np.geomspace(2.0, 90.0, 50), 4))
#: spin grid [rpm]: 0 to 10,000 every 250
SPIN_GRID = np.arange(0.0, 10_000.0 + 1.0, 250.0)
CL_MAX = 0.5  #: cap of C_L (Stepanek's C_L = 1/(2 + 1/S) tends to 1/2 as S grows)
PARAMS = ("cd", "cl", "cd_s")  #: the family's parameters
FORMULA = "C_D = cd + cd_s min(S, 0.5), C_L = min(cl S, 0.5), S = r w / v"  #: the family, in words
#: spin ratio beyond which the drag term is held (the serves that calibrate it have S <= 0.35; beyond
#: the data a linear term is an extrapolation, and at 2 m/s and 8,000 rpm it would leave any physical range)
S_DRAG_MAX = 0.5
#: allowed ranges of the parameters (wide: any physical ball lies inside)
BOUNDS = {"cd": (0.05, 2.0), "cl": (-1.0, 3.0), "cd_s": (-2.0, 5.0)}


def family_coefficients(speed, spin, *, cd: float, cl: float, cd_s: float = 0.0, radius: float, cl_max=CL_MAX):
    """(C_D, C_L) of the family at speed(s) [m/s] and spin rate(s) [rad/s] of a ball of radius [m]."""
    v = np.asarray(speed, dtype=float)
    w = np.asarray(spin, dtype=float)
    s = radius * w / np.maximum(v, 1e-9)
    return cd + cd_s * np.minimum(s, S_DRAG_MAX), np.minimum(cl * s, cl_max)


def family_table(cd: float, cl: float, cd_s: float = 0.0, *, radius: float, cl_max: float = CL_MAX):
    """(speed [m/s] (n,), spin [rad/s] (m,), C_D (n, m), C_L (n, m)) of the family on the grid."""
    v = SPEED_GRID
    w = SPIN_GRID * RPM
    c_d, c_l = family_coefficients(v[:, None], w[None, :], cd=cd, cl=cl, cd_s=cd_s, radius=radius, cl_max=cl_max)
    return v.copy(), w.copy(), c_d, c_l


def family_model(cd: float, cl: float, cd_s: float = 0.0, *, radius: float, cl_max: float = CL_MAX) -> AeroModel:
    """The family as a ``table`` aero model (what ``--aero table --aero-table FILE`` rebuilds)."""
    for name, val in (("cd", cd), ("cl", cl), ("cd_s", cd_s)):
        lo, hi = BOUNDS[name]
        if not (np.isfinite(val) and lo <= val <= hi):
            raise InputError(f"{name}: {val:g} is outside the allowed range [{lo:g}, {hi:g}]")
    v, w, c_d, c_l = family_table(cd, cl, cd_s, radius=radius, cl_max=cl_max)
    if np.any(c_d <= 0.0):
        raise InputError("cd_s: drag would turn negative on the grid; raise cd or cd_s")
    return get_aero_model("table", speed=v, spin=w, cd=c_d, cl=c_l)


def aero_table_csv(speed, spin, cd, cl) -> str:
    """CSV text of an aero table (columns ``speed_ms, spin_rpm, cd, cl``; one row per grid point),
    the format :func:`tennislab.io.aero_table.read_aero_table` reads (it takes no comment lines:
    the provenance is in the calibration's JSON).  ``speed`` [m/s], ``spin`` [rad/s]."""
    buf = io.StringIO()
    buf.write("speed_ms,spin_rpm,cd,cl\n")
    cd = np.asarray(cd, dtype=float)
    cl = np.asarray(cl, dtype=float)
    for i, vi in enumerate(np.asarray(speed, dtype=float)):
        for j, wj in enumerate(np.asarray(spin, dtype=float)):
            buf.write(f"{vi:.6g},{wj / RPM:.6g},{cd[i, j]:.6f},{cl[i, j]:.6f}\n")
    return buf.getvalue()
