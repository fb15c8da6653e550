"""exdex._rotations.quat_from_matrix against the axis-angle closed form:
R = rotation by angle a about the unit axis u has the quaternion
(cos a/2, u sin a/2), up to its sign. Angles up to pi (the trace-negative
branches of Shepperd's method) and the identity."""
import math

import numpy as np
import pytest

from exdex._rotations import quat_from_matrix


def _rotation(u, a):
    """Rodrigues' formula."""
    u = np.asarray(u, dtype=float) / np.linalg.norm(u)
    K = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K


@pytest.mark.parametrize("seed", range(20))
def test_axis_angle_closed_form(seed):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    a = rng.uniform(0.0, math.pi) if seed % 4 else math.pi * (1 - 1e-9 * seed)   # near pi: trace < 0
    q = quat_from_matrix(_rotation(u, a))
    ref = np.concatenate([[math.cos(a / 2)], u * math.sin(a / 2)])
    s = 1.0 if q @ ref >= 0 else -1.0
    assert np.allclose(s * q, ref, atol=1e-12)
    assert abs(np.linalg.norm(q) - 1.0) < 1e-12


def test_identity_and_half_turns():
    assert np.allclose(quat_from_matrix(np.eye(3)), [1, 0, 0, 0])
    for i in range(3):
        R = -np.eye(3)
        R[i, i] = 1.0   # half turn about axis i
        q = quat_from_matrix(R)
        e = np.zeros(3)
        e[i] = 1.0
        assert np.allclose(np.abs(q), np.concatenate([[0.0], e]), atol=1e-15)


@pytest.mark.parametrize("seed", range(8))
def test_public_quaternion_from_matrix_is_the_axis_angle_quaternion(seed):
    """exdex.quaternion_from_matrix: the closed form (cos a/2, u sin a/2) with w >= 0 (a <= pi), and a
    SampledTrajectory given it reproduces the matrix."""
    import exdex

    rng = np.random.default_rng(100 + seed)
    u = rng.normal(size=3)
    u /= np.linalg.norm(u)
    a = rng.uniform(0.0, math.pi)
    R = _rotation(u, a)
    q = exdex.quaternion_from_matrix(R)
    assert np.allclose(q, np.concatenate([[math.cos(a / 2)], u * math.sin(a / 2)]), atol=1e-12)
    traj = exdex.SampledTrajectory([0.0, 1.0, 2.0, 3.0], np.zeros((4, 3)), np.tile(q, (4, 1)))
    assert np.allclose(traj.evaluate([0.5], np.eye(3))["R"][0], R, atol=1e-12)


def test_public_quaternion_from_matrix_refuses_non_rotations():
    import exdex

    for bad in (np.diag([1.0, 1.0, -1.0]), 2 * np.eye(3)):
        with pytest.raises(ValueError, match="rotation must be a rotation matrix"):
            exdex.quaternion_from_matrix(bad)
    with pytest.raises(ValueError, match="rotation"):
        exdex.quaternion_from_matrix(np.eye(2))
