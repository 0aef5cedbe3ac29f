"""3-D impact: reduces exactly to the 2-D model in its plane; spin directions of topspin, slice, kick."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tennislab.core.impact import ImpactParams, impact_batch, to_court
from tennislab.core.impact_3d import face_basis, face_normal, impact_3d, racket_velocity
from tennislab.errors import InputError

P = ImpactParams()
DEG = math.pi / 180


@settings(max_examples=20, deadline=None)
@given(a=st.floats(-80.0, 80.0), b=st.floats(-30.0, 60.0), V=st.floats(10.0, 50.0))
def test_2d_case_equals_2d_model(a, b, V):
    """Normal and racket velocity in the x-z plane: velocity and spin equal the 2-D model's."""
    r3 = impact_3d(racket_velocity(V, a * DEG, b * DEG)[None], face_normal(b * DEG)[None], P)
    r2 = impact_batch(V, a * DEG, P)
    vx, vz = to_court(r2["v_n"], r2["v_t"], b * DEG)
    np.testing.assert_allclose(r3["velocity"][0], [vx[()], 0.0, vz[()]], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(r3["spin"][0], [0.0, r2["omega"][()], 0.0], rtol=1e-12, atol=1e-9)


def test_face_basis_orthonormal():
    n, tu, tl = face_basis(0.3, -0.4)
    M = np.stack([n, tu, tl])
    np.testing.assert_allclose(M @ M.T, np.eye(3), atol=1e-15)


def test_rotation_about_vertical_is_covariant():
    """Turning the whole stroke by an azimuth turns velocity and spin by the same rotation."""
    a, b, psi = 30 * DEG, 12 * DEG, 25 * DEG
    r0 = impact_3d(racket_velocity(40, a, b)[None], face_normal(b)[None], P)
    r1 = impact_3d(racket_velocity(40, a, b, psi)[None], face_normal(b, psi)[None], P)
    c, s = math.cos(psi), math.sin(psi)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    np.testing.assert_allclose(r1["velocity"][0], R @ r0["velocity"][0], atol=1e-10)
    np.testing.assert_allclose(r1["spin"][0], R @ r0["spin"][0], atol=1e-8)


def test_topspin_slice_kick_spin_axes():
    b = 10 * DEG
    n = face_normal(b)[None]
    top = impact_3d(racket_velocity(40, 35 * DEG, b, 0, 0)[None], n, P)["spin"][0]
    sl = impact_3d(racket_velocity(40, 35 * DEG, b, 0, -90 * DEG)[None], n, P)["spin"][0]
    kick = impact_3d(racket_velocity(40, 35 * DEG, b, 0, -45 * DEG)[None], n, P)["spin"][0]
    assert top[1] > 0 and abs(top[0]) < 1e-9 and abs(top[2]) < 1e-9  # topspin: +y
    assert sl[2] > 0 and abs(sl[1]) < 1e-9  # slice: about +z (curves left)
    assert kick[1] > 0 and kick[2] > 0  # kick: both
    # the spin magnitude depends only on the impact angle, not on the brush direction
    assert np.linalg.norm(sl) == pytest.approx(np.linalg.norm(top), rel=1e-12)


def test_ball_velocity_is_a_galilean_shift():
    b = 10 * DEG
    n = face_normal(b)[None]
    Vr = racket_velocity(40, 30 * DEG, b)[None]
    u = np.array([[0.0, 0.5, -3.0]])
    r = impact_3d(Vr, n, P, ball_velocity=u)
    r0 = impact_3d(Vr - u, n, P)
    np.testing.assert_allclose(r["velocity"], r0["velocity"] + u, atol=1e-12)
    np.testing.assert_allclose(r["spin"], r0["spin"], atol=1e-9)


def test_bad_input():
    with pytest.raises(InputError, match="approach"):
        impact_3d(np.array([[-10.0, 0, 0]]), np.array([[1.0, 0, 0]]), P)
    with pytest.raises(InputError, match="normal"):
        impact_3d(np.array([[10.0, 0, 0]]), np.array([[0.0, 0, 0]]), P)
