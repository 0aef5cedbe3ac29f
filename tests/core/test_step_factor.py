"""The step-size controller's factor: 0.9 err^-1/5 within [0.2, 10] (Hairer et al. II.4), its fifth root
formed from the bits of err and Newton steps instead of the library's ``pow``."""

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from tennislab.core.integrators import inv_fifth_root, step_factor


def reference(err: float) -> float:
    return 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err**-0.2))


@given(st.floats(min_value=1e-7, max_value=1e5))
def test_inv_fifth_root_is_the_fifth_root_to_a_few_ulp(x):
    y = inv_fifth_root(x)
    assert abs(y / x**-0.2 - 1.0) < 2e-15


@given(st.one_of(st.just(0.0), st.floats(min_value=5e-324, max_value=1e300)))
def test_step_factor_is_the_classical_formula(err):
    assert math.isclose(step_factor(err), reference(err), rel_tol=2e-15)


def test_step_factor_at_its_clamps_and_limits():
    # 0.9 err^-1/5 = 10 at err = 0.09^5 and 0.2 at 4.5^5: the clamps at 5e-6 and 2000 lie beyond both
    assert step_factor(0.0) == 10.0
    assert step_factor(1e-300) == 10.0
    assert step_factor(0.09**5 * 0.999) == 10.0
    assert step_factor(4.5**5 * 1.001) == 0.2
    assert step_factor(math.inf) == 0.2
    assert math.isclose(step_factor(1.0), 0.9, rel_tol=1e-15)
    assert math.isclose(step_factor(32.0), 0.45, rel_tol=1e-15)  # 32^-1/5 = 1/2


def test_step_factor_is_monotone_over_the_errors_a_step_gives():
    err = np.geomspace(1e-8, 1e4, 20001)
    fac = np.array([step_factor(e) for e in err])
    assert np.all(np.diff(fac) <= 0.0)
