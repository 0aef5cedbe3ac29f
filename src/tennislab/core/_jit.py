"""Compiler options shared by every Numba kernel of tennislab (one statement of them).

``FASTMATH`` allows the floating-point rewrites that do not change what a finite
computation means: no signed zeros (``nsz``), reciprocal instead of division
(``arcp``), fused multiply-add (``contract``) and approximate library functions
(``afn``).  It leaves out ``nnan`` and ``ninf``, so that ``math.isfinite`` and NaN
checks keep working inside kernels (the integrators rely on them to stop on a
non-finite state), and reassociation (``reassoc``): with it LLVM ordered the same
sums differently in a loop's SIMD body and in its scalar remainder, so that a shot's
bits in the lockstep kernel (:mod:`tennislab.core.lockstep`) depended on the lane it
flew in (1e-14 m; tests/core/test_lockstep.py).  Leaving it out cost nothing measurable.

Use as ``@nb.njit(**JIT)`` (add ``parallel=True``, ``inline="always"`` or a
signature where needed).  Do not mutate ``FASTMATH``: Numba keeps the set it is
given.
"""

from __future__ import annotations

import warnings

from numba.core.errors import NumbaIRAssumptionWarning

# The aero formulas are inlined into their callers' Numba IR (core.aero: so that LLVM vectorises the
# lockstep kernel); Numba's internal pedantic check then reports the renamed variables of the inlined
# branches as "not in scope" (its own note: an internal check, not a user error): silenced for these only.
warnings.filterwarnings("ignore", message=r"variable '.*' is not in scope", category=NumbaIRAssumptionWarning)

#: LLVM fast-math flags of every compiled kernel (Numba wants a ``set``)
FASTMATH: set[str] = {"nsz", "arcp", "contract", "afn"}

#: ``numba.njit`` options of every kernel: cached on disk, NumPy's error model (a
#: division by zero gives inf/NaN, no exception), :data:`FASTMATH`
JIT: dict = {"cache": True, "error_model": "numpy", "fastmath": FASTMATH}

#: the same for functions compiled at run time (a user's aero callable): not cacheable on disk
JIT_DYNAMIC: dict = {"error_model": "numpy", "fastmath": FASTMATH}

__all__ = ["FASTMATH", "JIT", "JIT_DYNAMIC"]
