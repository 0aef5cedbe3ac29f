"""Serve figures frame everything they draw (issue 17: plots frame every bounce and the whole apex)."""

import matplotlib

matplotlib.use("Agg")

from tennislab.core.flight import FlightParams, fly_dense
from tennislab.plot.serve import plot_optimum


def test_optimum_view_holds_a_high_and_a_long_flight():
    p = FlightParams.from_options(preset="seed000")
    lob = fly_dense((-11.885, 0.0, 2.8), (25.0, 0.0, 14.0), (0.0, 0.0, 0.0), p)  # apex far above 3.5 m
    long = fly_dense((-11.885, 0.0, 2.8), (60.0, 0.0, 2.0), (0.0, 0.0, 0.0), p)  # lands beyond the far baseline
    ax = plot_optimum("test", [lob, long], ["lob", "long"]).axes[0]
    for tr in (lob, long):
        for line in ax.get_lines():
            x, z = line.get_xdata(), line.get_ydata()
            assert ax.get_xlim()[0] <= min(x) and max(x) <= ax.get_xlim()[1]
            assert ax.get_ylim()[0] <= min(z) and max(z) <= ax.get_ylim()[1]
        assert tr.apex.z < ax.get_ylim()[1] and tr.landing.x < ax.get_xlim()[1]
