"""Calibration figures: histograms of the landing misses of served balls per model (``tennislab calibrate
serves --plot``, ``calibrate validate --plot``).  The misses come from :mod:`tennislab.calibrate`."""

from __future__ import annotations

import numpy as np

#: the misses drawn lie within +-MISS_RANGE_M [m]; larger ones are counted in the end bins
MISS_RANGE_M = 1.5


def plot_misses(series: dict, title: str):
    """Length and width misses [m] of served balls, one histogram line per model: ``series`` maps a
    label to (length misses, width misses) arrays (> 0 long; > 0 left of the measured bounce)."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    bins = np.linspace(-MISS_RANGE_M, MISS_RANGE_M, 61)
    for label, (length, width) in series.items():
        n = len(length)
        axes[0].hist(np.clip(length, -MISS_RANGE_M, MISS_RANGE_M), bins=bins, histtype="step", label=f"{label} ({n})")
        axes[1].hist(np.clip(width, -MISS_RANGE_M, MISS_RANGE_M), bins=bins, histtype="step", label=f"{label} ({n})")
    axes[0].set_xlabel(f"length miss [m] (> 0 long; beyond ±{MISS_RANGE_M:g} m in the end bins)")
    axes[1].set_xlabel("width miss [m] (> 0 left of the bounce)")
    for ax in axes:
        ax.axvline(0.0, color="k", lw=0.6)
        ax.set_ylabel("serves")
    axes[0].legend(fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    return fig
