"""Air and gravity: density from weather, standard gravity, constant wind.

Air density is computed from the ideal-gas law for a mixture of dry air and
water vapour (e.g. Picard et al. 2008, Metrologia 45:149, the CIPM-2007 formula
without the compressibility factor, which changes rho by < 0.05 %):

    rho = (p_d M_d + p_v M_v) / (R T),   p_v = RH * p_sat(T)

with p_sat from the Buck (1981) equation, J. Appl. Meteorol. 20:1527 (eq 8):
p_sat = 611.21 exp((18.678 - T/234.5) (T/(257.14 + T))) [Pa], T in deg C.
Pressure from altitude uses the ISA barometric formula (ICAO 1993):
p = 101325 (1 - 2.25577e-5 h)^5.25588.

Defaults: 20 deg C, sea level (101325 Pa), 50 % relative humidity, giving
rho = 1.199 kg/m^3; standard gravity 9.80665 m/s^2 (CGPM 1901).  The seeds'
values (rho = 1.22, g = 9.82; seed 000 section 2.3) are reproduced by passing
them: ``Atmosphere(density=1.22, gravity=9.82)``.

References
----------
.. [1] Picard, Davis, Glaser & Fujii (2008), Metrologia 45:149 (CIPM-2007 air density)
.. [2] Buck (1981), J. Appl. Meteorol. 20:1527, eq 8 (saturation vapour pressure)
.. [3] ICAO (1993), Manual of the ICAO Standard Atmosphere (barometric formula)
.. [4] CGPM (1901), 3rd General Conference on Weights and Measures (standard gravity)
.. [5] Grosen, Kousted & Treichel (2021), 2-dimensional tennis serves show similar successful mechanical
    parameter across physiological differences, Aalborg University (seed 000), sec. 2.3
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from tennislab.errors import check_range, check_vector

R_GAS = 8.314462618  #: molar gas constant [J/(mol K)]
M_DRY = 0.0289652  #: molar mass of dry air [kg/mol]
M_VAP = 0.018016  #: molar mass of water vapour [kg/mol]
G_STANDARD = 9.80665  #: standard gravity [m/s^2]
P_SEA_LEVEL = 101325.0  #: ISA sea-level pressure [Pa]


def saturation_vapour_pressure(temperature_c: float) -> float:
    """Saturation vapour pressure over water [Pa] (Buck 1981, eq 8)."""
    t = temperature_c
    return 611.21 * math.exp((18.678 - t / 234.5) * (t / (257.14 + t)))


def pressure_at_altitude(altitude_m: float) -> float:
    """ISA pressure [Pa] at geometric altitude [m] (troposphere, ICAO 1993)."""
    return P_SEA_LEVEL * (1.0 - 2.25577e-5 * altitude_m) ** 5.25588


def air_density(
    temperature_c: float = 20.0,
    pressure_pa: float | None = None,
    altitude_m: float = 0.0,
    relative_humidity: float = 0.5,
) -> float:
    """Density of moist air [kg/m^3].

    Parameters
    ----------
    temperature_c : air temperature [deg C], -40..60
    pressure_pa : station pressure [Pa]; if None, from ``altitude_m`` (ISA)
    altitude_m : altitude above sea level [m], -500..5000 (used only without pressure)
    relative_humidity : 0..1 [-]

    Returns
    -------
    rho : (p_d M_d + p_v M_v) / (R T) [kg/m^3], p_v = RH p_sat(T) (module docstring)

    References
    ----------
    .. [1] Picard, Davis, Glaser & Fujii (2008), Metrologia 45:149 (the CIPM-2007 formula, without the
       compressibility factor).
    .. [2] Buck (1981), J. Appl. Meteorol. 20:1527, eq 8.
    .. [3] ICAO (1993), Manual of the ICAO Standard Atmosphere.
    """
    t = check_range("temperature_c", temperature_c, -40.0, 60.0, "degC")
    rh = check_range("relative_humidity", relative_humidity, 0.0, 1.0)
    if pressure_pa is None:
        h = check_range("altitude_m", altitude_m, -500.0, 5000.0, "m")
        p = pressure_at_altitude(h)
    else:
        p = check_range("pressure_pa", pressure_pa, 30000.0, 110000.0, "Pa")
    pv = rh * saturation_vapour_pressure(t)
    pd = p - pv
    return (pd * M_DRY + pv * M_VAP) / (R_GAS * (t + 273.15))


@dataclass(frozen=True)
class Atmosphere:
    """Air density, gravity and a constant wind.

    Attributes
    ----------
    density : air density [kg/m^3]; default 1.199 (20 deg C, 101325 Pa, 50 % RH)
    gravity : gravitational acceleration [m/s^2]; default 9.80665
    wind : constant wind velocity (x, y, z) [m/s] in the court frame; default still air
    """

    density: float = 1.199
    gravity: float = G_STANDARD
    wind: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self):
        check_range("air_density", self.density, 0.0, 2.0, "kg/m^3")
        check_range("gravity", self.gravity, 0.0, 30.0, "m/s^2")
        object.__setattr__(self, "wind", check_vector("wind", self.wind))
        for w in self.wind:
            check_range("wind", w, -60.0, 60.0, "m/s")

    @classmethod
    def from_weather(
        cls,
        temperature_c: float = 20.0,
        pressure_pa: float | None = None,
        altitude_m: float = 0.0,
        relative_humidity: float = 0.5,
        gravity: float = G_STANDARD,
        wind=(0.0, 0.0, 0.0),
    ) -> Atmosphere:
        """Atmosphere with density from :func:`air_density`."""
        rho = air_density(temperature_c, pressure_pa, altitude_m, relative_humidity)
        return cls(density=rho, gravity=gravity, wind=tuple(wind))
