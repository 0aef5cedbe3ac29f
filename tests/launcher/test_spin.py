"""The compiled spin variants of the aim's search against their NumPy reference."""

import numpy as np
import pytest

from tennislab.launcher import _spin
from tennislab.launcher.machine import DEFAULT_SPEC
from tennislab.launcher.preferences import Tolerances


@pytest.mark.parametrize(
    "asked,tol",
    [
        ((1000.0, 0.0), Tolerances()),
        ((300.4, 12.6), Tolerances()),
        ((40.0, 180.0), Tolerances()),  # a slow spin: the disc holds every axis (the axes near each optimum)
        ((0.0, 0.0), Tolerances(3.0, 100.0, 0.0)),
        ((1500.0, -45.0), Tolerances(3.0, 0.0, 10.0)),
        ((1995.0, 170.0), Tolerances(3.0, 250.0, 30.0)),  # the rate's upper bound, the axis wrapping
        ((500.0, 0.0), Tolerances(0.0, 0.0, 0.0)),
    ],
)
def test_compiled_variants_are_the_reference(asked, tol):
    rng = np.random.default_rng(3)
    n = 200
    L0 = np.column_stack([rng.uniform(5, 12, n), rng.uniform(-4, 4, n)])
    J = rng.normal(0.0, 2e-4, (n, 2, 2))
    J[:5] = 0.0  # no sensitivity: the asked rate
    om = np.column_stack([rng.uniform(-2000, 2000, n), rng.uniform(-500, 500, n)])
    T = (8.7, 1.3)
    got = _spin.variants(L0, J, om, T, asked, tol, DEFAULT_SPEC.spin, DEFAULT_SPEC.spin_axis)
    ref = _spin.variants_reference(L0, J, om, T, asked, tol, DEFAULT_SPEC.spin, DEFAULT_SPEC.spin_axis)
    assert np.array_equal(got[0], ref[0]) and np.array_equal(got[1], ref[1])
    assert np.array_equal(np.isinf(got[2]), np.isinf(ref[2]))
    fin = np.isfinite(ref[2])
    assert fin.any() and np.allclose(got[2][fin], ref[2][fin], rtol=1e-12, atol=1e-12)
