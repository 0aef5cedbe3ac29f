"""serve.window_hint: the workflow behind serve-window's hint (the CLI only renders it)."""

from __future__ import annotations

import math

import pytest

from tennislab.errors import InputError
from tennislab.serve import WindowHint, get_player, window, window_hint
from tennislab.serve.hint import box_azimuth_deg
from tennislab.serve.pipeline import default_flight

SERVER = {"target": "deuce", "server_y": -0.5}


@pytest.fixture(scope="module")
def empty():
    """A 3-D window aimed straight down the court (azimuth 0): every serve goes wide of the deuce box."""
    return window(get_player("professional"), step=6.0, **SERVER)


def test_an_empty_window_points_at_the_box_and_counts_what_goes_in_there(empty):
    h = window_hint(empty, step=6.0)
    assert isinstance(h, WindowHint)
    assert sum(h.failures.values()) == empty.success.size and "wide" in h.failures
    # the azimuth from the server toward the box's centre, on the half-degree grid
    x0, x1, y0, y1 = default_flight().court.area_bounds("deuce-box")
    psi = math.degrees(math.atan2(0.5 * (y0 + y1) + 0.5, 0.5 * (x0 + x1) - empty.criteria.server_x))
    assert h.azimuth_deg == round(psi * 2) / 2
    assert h.azimuth_deg == box_azimuth_deg(default_flight(), "deuce", empty.criteria.server_x, -0.5)
    assert h.step_deg == 6.0
    turned = window(get_player("professional"), step=6.0, azimuth_deg=h.azimuth_deg, **SERVER)
    assert h.n_in == int(turned.success.sum()) > 0
    assert window_hint(turned, step=6.0) is None  # some go in: no hint
    d = h.to_dict()
    assert d["azimuth_deg"] == h.azimuth_deg and d["n_in"] == h.n_in


def test_an_unknown_box_is_refused_by_name(empty):
    with pytest.raises(InputError, match="target: unknown 'middle'; choose from deuce, ad"):
        box_azimuth_deg(default_flight(), "middle", empty.criteria.server_x, -0.5)


def test_the_check_is_at_least_two_degrees_coarse_and_2d_has_nothing_to_turn(empty):
    assert window_hint(empty, step=1.0).step_deg == 2.0
    assert window_hint(empty).step_deg == 6.0  # by default the window's own step
    flat = window(get_player("professional"), alpha_deg=[0.0, 6.0], beta_deg=[60.0, 66.0])  # 2-D, all short
    h = window_hint(flat)  # judged as 2-D: no box to turn toward
    assert h.azimuth_deg is None and h.n_in is None and h.failures == dict(flat.failures())


def test_the_window_keeps_what_it_was_flown_with(empty):
    assert empty.setup.target == "deuce" and empty.setup.server_y == -0.5 and empty.azimuth_deg == 0.0
    assert empty.setup.flight == default_flight()
