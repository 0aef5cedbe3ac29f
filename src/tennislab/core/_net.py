"""The net cord in compiled code: its height and whether a point of the net plane is net.

The compiled twins of :meth:`tennislab.core.court.Court.net_height` and the net's extent (ITF rule 1;
the cord a straight line from the centre strap to each post, :mod:`tennislab.core.court`), for the
flight kernels (:mod:`tennislab.core.integrators`) and :func:`tennislab.core.flight.with_net`.  Kept
apart from :mod:`tennislab.core.court` so that the court's geometry loads without Numba (the
launcher's database commands read courts and drills but fly nothing).

References
----------
.. [1] ITF, Rules of Tennis, rule 1 and Appendix I
"""

from __future__ import annotations

import numba as nb

from tennislab.core._jit import JIT


@nb.njit(**JIT, inline="always")
def net_height_linear(y, h_center, h_post, y_post):
    """Height of the net cord [m] at lateral position ``y`` [m]; 0 beyond the posts."""
    ay = abs(y)
    if ay > y_post:
        return 0.0
    return h_center + (h_post - h_center) * ay / y_post


@nb.njit(**JIT)
def net_blocks(y, z, h_center, h_post, y_post):
    """True when the point (0, y, z) of the net plane is net: between the posts, at or below the cord.

    The net hangs from the cord down to the ground (ITF rule 1: it must fill the
    space between the posts); a ball touching the plane there meets the net.
    """
    return abs(y) <= y_post and z <= net_height_linear(y, h_center, h_post, y_post)
