"""The seed's published numbers: Table 1, the peak-spin alphas (fig 5) and the optimum serves (figs 7-9).

Seed 000 (Grosen, Kousted & Treichel 2021), Table 1 and the captions of figs 5, 7, 8, 9.
Ranges are (min, max); angles in degrees, spin in rpm, v in m/s, X and Y in m.
"""

from __future__ import annotations

TABLE1 = {
    "professional": {
        "flat": {
            "beta": (8, 10),
            "alpha": (0, 7),
            "spin_rpm": (0, 1036),
            "speed": (56.5, 56.9),
            "landing_x": (16.39, 18.12),
            "net_height": (0.97, 1.30),
            "launch_angle": (-8.2, -6.1),
            "n": 10,
        },
        "topspin": {
            "beta": (9, 24),
            "alpha": (16, 68),
            "spin_rpm": (3237, 6914),
            "speed": (22.2, 54.9),
            "landing_x": (14.09, 18.31),
            "net_height": (0.95, 2.77),
            "launch_angle": (-6.6, 10.3),
            "n": 223,
        },
    },
    "recreational": {
        "flat": {
            "beta": (6, 9),
            "alpha": (0, 8),
            "spin_rpm": (0, 1150),
            "speed": (42.3, 42.6),
            "landing_x": (16.01, 18.30),
            "net_height": (0.95, 1.43),
            "launch_angle": (-6.7, -3.4),
            "n": 15,
        },
        "topspin": {
            "beta": (9, 22),
            "alpha": (21, 60),
            "spin_rpm": (3237, 5294),
            "speed": (22.2, 40.5),
            "landing_x": (14.23, 18.31),
            "net_height": (0.95, 2.57),
            "launch_angle": (-3.9, 10.3),
            "n": 199,
        },
    },
    "junior": {
        "flat": {
            "beta": (3, 6),
            "alpha": (0, 9),
            "spin_rpm": (0, 1151),
            "speed": (35.2, 35.5),
            "landing_x": (16.00, 18.24),
            "net_height": (0.95, 1.36),
            "launch_angle": (-2.9, 0.3),
            "n": 17,
        },
        "topspin": {
            "beta": (7, 17),
            "alpha": (23, 53),
            "spin_rpm": (3250, 4470),
            "speed": (22.7, 33.6),
            "landing_x": (14.28, 18.31),
            "net_height": (0.96, 2.39),
            "launch_angle": (0.6, 12.3),
            "n": 150,
        },
    },
}

#: alpha of peak spin [deg] (seed fig 5 and abstract)
PEAK_SPIN_ALPHA = {"professional": 36, "recreational": 35, "junior": 34}

#: optimum serves (seed figs 7-9 captions): beta, alpha [deg], gamma [deg], spin [rpm], v [m/s], Y, X [m]
OPTIMUM = {
    "professional": {
        "flat": {
            "beta": 8,
            "alpha": 3,
            "launch_angle": -6.8,
            "spin_rpm": 501,
            "speed": 56.8,
            "net_height": 1.25,
            "landing_x": 18.12,
        },
        "topspin": {
            "beta": 21,
            "alpha": 36,
            "launch_angle": -1.9,
            "spin_rpm": 6914,
            "speed": 48.7,
            "net_height": 1.61,
            "landing_x": 17.91,
        },
    },
    "recreational": {
        "flat": {
            "beta": 7,
            "alpha": 8,
            "launch_angle": -3.4,
            "spin_rpm": 1150,
            "speed": 42.3,
            "net_height": 1.42,
            "landing_x": 18.30,
        },
        "topspin": {
            "beta": 18,
            "alpha": 35,
            "launch_angle": 1.3,
            "spin_rpm": 5294,
            "speed": 36.98,
            "net_height": 1.80,
            "landing_x": 18.18,
        },
    },
    "junior": {
        "flat": {
            "beta": 4,
            "alpha": 9,
            "launch_angle": 0.3,
            "spin_rpm": 1152,
            "speed": 35.2,
            "net_height": 1.37,
            "landing_x": 18.24,
        },
        "topspin": {
            "beta": 14,
            "alpha": 34,
            "launch_angle": 5.3,
            "spin_rpm": 4470,
            "speed": 31.22,
            "net_height": 1.77,
            "landing_x": 18.14,
        },
    },
}

#: beta with the widest range of successful alpha [deg] (seed sec. 3, fig 6)
WIDEST_BETA = {
    "professional": {"flat": 9, "topspin": 21},
    "recreational": {"flat": 8, "topspin": 18},
    "junior": {"flat": 4, "topspin": 14},
}
