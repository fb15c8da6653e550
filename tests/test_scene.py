"""exdex.scene, the scene's inputs: bad input is a TypeError or ValueError
naming the parameter (and its range where it has one); the derived
quantities against their closed forms (a uniform box's and cylinder's
inertia, a disc patch's mean radius 2 R / 3, the capacity mu * fingers * F,
a linear grip schedule's values and slopes, Eq. 7 and the trapezoid
evaluated at their switching times); stops checked against the object's
outline (the depth a stop starts inside it, from the corners' world
coordinates)."""
import math
import re

import numpy as np
import pytest

import exdex

BODY = exdex.Body.box(0.1, (0.06, 0.03, 0.02))
GRASP = exdex.Grasp(mu=0.5, grip_force=2.0)
LOG = ([0.0, 1.0, 2.0, 3.0], [[0.0, 0.0, 0.0]] * 4, [[1.0, 0.0, 0.0, 0.0]] * 4)

BAD = [
    (lambda: exdex.Body(mass=0.0), ValueError, r"Body.mass must be in (0, inf), got 0"),
    (lambda: exdex.Body(mass=0.1, inertia=-1.0), ValueError, r"Body.inertia must be in (0, inf), got -1"),
    (lambda: exdex.Body(mass=0.1, inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), ValueError,
     "Body.inertia must be symmetric"),
    (lambda: exdex.Body(mass=0.1, inertia=np.diag([1.0, -1.0, 1.0])), ValueError,
     "Body.inertia must be positive definite (all principal moments > 0)"),
    (lambda: exdex.Body(mass=0.1, size=(0.1, 0.0, 0.1)), ValueError, "Body.size must be positive (lx, ly, lz > 0) [m]"),
    (lambda: exdex.Body.cylinder(0.1, 0.02, -1.0), ValueError, "Body.cylinder: height must be in (0, inf), got -1"),
    (lambda: exdex.Patch.disc(0.0), ValueError, "Patch.disc: radius must be in (0, inf), got 0"),
    (lambda: exdex.Patch.rectangle(0.01, -1.0), ValueError, "Patch.rectangle: height must be in (0, inf), got -1"),
    (lambda: exdex.Pad(), ValueError, "Pad needs exactly one of vertices (a convex polygon) and radius (a disc)"),
    (lambda: exdex.Grasp(mu=-0.1, grip_force=1.0), ValueError, "Grasp.mu must be in [0, inf), got -0.1"),
    (lambda: exdex.Grasp(mu=0.5, grip_force=-1.0), ValueError, "Grasp.grip_force must be in [0, inf), got -1"),
    (lambda: exdex.Grasp(mu=0.5, grip_force="1"), TypeError,
     "Grasp.grip_force must be a real number [N] or an exdex.GripSchedule, got str"),
    (lambda: exdex.Grasp(mu=0.5, mu_static=0.4, grip_force=1.0), ValueError,
     "Grasp.mu_static must be in [0.5, inf), got 0.4"),
    (lambda: exdex.Grasp(mu=0.5, grip_force=1.0, fingers=3), ValueError, "Grasp.fingers must be 1 or 2, got 3"),
    (lambda: exdex.Grasp(mu=0.5, grip_force=1.0, limit_surface="box"), ValueError,
     "Grasp.limit_surface must be one of 'ellipsoid', 'exact', got 'box'"),
    (lambda: exdex.Grasp(mu=0.5, grip_force=1.0, patch="disc"), TypeError,
     "Grasp.patch must be an exdex.Patch, got str"),
    (lambda: exdex.GripSchedule([0.0, 0.5, 0.5], [1.0, 2.0, 3.0]), ValueError,
     "GripSchedule.times must be strictly increasing: times[2] = 0.5 <= times[1] = 0.5"),
    (lambda: exdex.GripSchedule([0.0, 0.5], [1.0, -2.0]), ValueError, "GripSchedule.forces[1] = -2 must be >= 0 [N]"),
    (lambda: exdex.GripSchedule([0.0, 0.5], [1.0, 2.0, 3.0]), ValueError,
     "GripSchedule.forces must have one force per time: 2 times, 3 forces"),
    (lambda: exdex.GripSchedule([0.0, 0.5], [1.0, 2.0], kind="spline"), ValueError,
     "GripSchedule.kind must be one of ['cubic', 'linear', 'step'], got 'spline'"),
    (lambda: exdex.AsymmetricProfile(0.1, 0.5, 1.0), ValueError, "AsymmetricProfile.beta must be in (0, 1), got 1"),
    (lambda: exdex.AsymmetricProfile(0.1, 0.0, 0.5), ValueError,
     "AsymmetricProfile.duration must be in (0, inf), got 0"),
    (lambda: exdex.AsymmetricProfile(0.1, 0.5, 0.5, axis=(0, 0, 0)), ValueError,
     "AsymmetricProfile.axis must be a non-zero vector"),
    (lambda: exdex.AsymmetricProfile(0.1, 0.5, 0.5, rotation=1), TypeError,
     "AsymmetricProfile.rotation must be True or False"),
    # |X1| / T <= v_max <= 2 |X1| / T: [0.1, 0.2] m/s for 5 cm in 0.5 s
    (lambda: exdex.TrapezoidalProfile(0.05, 0.5, 0.05), ValueError,
     "TrapezoidalProfile.v_max must be in [0.1, 0.2], got 0.05"),
    (lambda: exdex.TrapezoidalProfile(0.0, 0.5, 0.05), ValueError, "TrapezoidalProfile.amplitude must be non-zero"),
    (lambda: exdex.SampledTrajectory(LOG[0][:3], LOG[1][:3], LOG[2][:3]), ValueError,
     "SampledTrajectory.times needs at least 4 samples, got 3"),
    (lambda: exdex.SampledTrajectory([0.0, 1.0, 1.0, 2.0], LOG[1], LOG[2]), ValueError,
     "SampledTrajectory.times must be strictly increasing: times[2] = 1 <= times[1] = 1"),
    (lambda: exdex.SampledTrajectory(LOG[0], [[0.0, 0.0]] * 4, LOG[2]), ValueError,
     "SampledTrajectory.positions must have shape (4, 3), got (4, 2)"),
    (lambda: exdex.Pause(0.0), ValueError, "Pause.duration must be in (0, inf), got 0"),
    (lambda: exdex.Chain([exdex.Rest()]), TypeError,
     "Chain.pieces[0] is a Rest, which has no duration: use exdex.Pause(duration)"),
    (lambda: exdex.Stop((0, 0, 0), (0, 0, 1), mu=-1.0), ValueError, "Stop.mu must be in [0, inf), got -1"),
    (lambda: exdex.Stop((0, 0, 0), (0, 0, 0)), ValueError, "Stop.normal must be a non-zero vector"),
    (lambda: exdex.Obstacle.box((0, 0, 0), (0.1, 0.0, 0.1)), ValueError,
     "Obstacle.box: size must be positive (three side lengths > 0) [m]"),
    (lambda: exdex.Obstacle.box((0, 0), (0.1, 0.1, 0.1)), ValueError,
     "Obstacle.box: center must have shape (3,), got (2,)"),
    (lambda: exdex.Obstacle.box((0, 0, 0), (0.1, 0.1, 0.1), rotation=2 * np.eye(3)), ValueError,
     "Obstacle.box: rotation must be a rotation matrix (orthonormal, det +1)"),
    (lambda: exdex.Obstacle.halfspaces([(0, 0, 0)], [0.0]), ValueError,
     "Obstacle.halfspaces: normals must be non-zero vectors"),
    (lambda: exdex.Obstacle.halfspaces([(0, 0, 1)], [0.0, 1.0]), ValueError,
     "Obstacle.halfspaces: offsets must have shape (1,), got (2,)"),
    (lambda: exdex.Obstacle.cylinder((0, 0, 0), (0, 1, 0), 0.0), ValueError,
     "Obstacle.radius must be in (0, inf), got 0"),
    (lambda: exdex.Obstacle.cylinder((0, 0, 0), (0, 0, 0), 0.1), ValueError, "Obstacle.axis must be a non-zero vector"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, dof="spin"), ValueError,
     "Scene.dof must be one of ['planar', 'rotation', 'translation', 'auto'], got 'spin'"),
    (lambda: exdex.Scene(body="box", grasp=GRASP), TypeError, "Scene.body must be an exdex.Body, got str"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, motion="shake"), TypeError, "Scene.motion must be an exdex motion"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, gripper_rotation=2 * np.eye(3)), ValueError,
     "Scene.gripper_rotation must be a rotation matrix (orthonormal, det +1)"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, q0=(0.0, 0.0)), ValueError, "Scene.q0 must have shape (3,), got (2,)"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, gravity=(0.0, 0.0, math.nan)), ValueError,
     "Scene.gravity must be finite (no NaN or infinity)"),
]


@pytest.mark.parametrize("make, exc, message", BAD, ids=[m for _, _, m in BAD])
def test_bad_input_names_the_parameter_and_its_range(make, exc, message):
    with pytest.raises(exc) as info:
        make()
    assert str(info.value).startswith(message)


def test_box_and_cylinder_inertia_closed_forms():
    lx, ly, lz, m = 0.06, 0.03, 0.02, 0.1
    assert np.allclose(exdex.Body.box(m, (lx, ly, lz)).inertia,
                       np.diag([m * (ly**2 + lz**2) / 12, m * (lx**2 + lz**2) / 12, m * (lx**2 + ly**2) / 12]),
                       rtol=1e-15, atol=0)
    r, h = 0.02, 0.01
    cyl = exdex.Body.cylinder(m, r, h)
    # about a diameter m (3 r^2 + h^2) / 12, about the axis (the plate normal) m r^2 / 2
    assert np.allclose(cyl.inertia, np.diag([m * (3 * r**2 + h**2) / 12] * 2 + [m * r**2 / 2]), rtol=1e-15, atol=0)
    assert cyl.size == (2 * r, 2 * r, h) and cyl.outline_radius == r and cyl.is_disc


def test_disc_patch_mean_radius_and_capacities():
    # the mean distance from the centre of a uniform disc: int_0^R r 2 pi r dr / (pi R^2) = 2 R / 3
    assert exdex.Patch.disc(0.015).e_r == pytest.approx(0.01, rel=1e-15)
    g = exdex.Grasp(mu=0.4, grip_force=2.5)
    assert g.capacity == pytest.approx(0.4 * 2 * 2.5, rel=1e-15) and g.static_capacity == g.capacity
    assert exdex.Grasp(mu=0.4, grip_force=2.5, fingers=1).capacity == pytest.approx(1.0, rel=1e-15)
    assert exdex.Grasp(mu=0.4, mu_static=0.6, grip_force=2.5).static_capacity == pytest.approx(3.0, rel=1e-15)
    assert g.capacity_at(0.3) == g.capacity and np.array_equal(g.capacity_at([0.0, 1.0]), [g.capacity] * 2)


def test_grip_schedule_values_and_slopes():
    gs = exdex.GripSchedule([0.0, 0.5, 1.0], [2.0, 1.0, 3.0])
    # held before the first and after the last point, the line between them
    assert np.allclose(gs([-1.0, 0.25, 0.5, 0.75, 2.0]), [2.0, 1.5, 1.0, 2.0, 3.0], rtol=1e-15, atol=0)
    assert np.allclose(gs.rate([0.25, 0.75]), [-2.0, 4.0], rtol=1e-15, atol=0)
    assert gs.max_force == 3.0 and gs.scaled(0.5).forces == (1.0, 0.5, 1.5)
    grasp = exdex.Grasp(mu=0.5, grip_force=gs)
    assert grasp.capacity == 3.0 and grasp.capacity_at(0.25) == pytest.approx(1.5, rel=1e-15)
    assert grasp.schedule is gs and exdex.Scene(body=BODY, grasp=grasp).end_time == 1.0
    step = exdex.GripSchedule([0.0, 0.5], [2.0, 1.0], kind="step")
    assert list(step([0.0, 0.49, 0.5, 0.6])) == [2.0, 2.0, 1.0, 1.0] and step.rate(0.3) == 0.0   # right-continuous


def test_eq7_and_the_trapezoid_at_their_switching_times():
    X, T, beta = 0.1, 0.5, 0.9
    m = exdex.AsymmetricProfile(X, T, beta, axis=(0, 0, -1))
    a_h, a_l = 2 * X / (beta * T**2), 2 * X / ((beta - 1) * T**2)          # Eq. 9
    assert m.a_high == pytest.approx(a_h, rel=1e-15) and m.a_low == pytest.approx(a_l, rel=1e-15)
    assert m.end_time == 2 * T
    k = m.evaluate([0.5 * beta * T, beta * T, T, 2 * T])
    s, v, a = -k["p"][:, 2], -k["v"][:, 2], -k["a"][:, 2]        # along the axis (0, 0, -1)
    assert s == pytest.approx([a_h * (0.5 * beta * T) ** 2 / 2, a_h * (beta * T) ** 2 / 2, X, 0.0],
                              rel=1e-12, abs=1e-15)
    assert v == pytest.approx([a_h * 0.5 * beta * T, a_h * beta * T, 0.0, 0.0], rel=1e-12, abs=1e-15)
    assert a[0] == pytest.approx(a_h, rel=1e-12)
    tp = exdex.TrapezoidalProfile(0.05, 0.5, 0.12, axis=(1, 0, 0))
    ta = 0.5 - 0.05 / 0.12                                                   # the ramps
    k = tp.evaluate([ta, 0.25, 0.5])
    assert k["p"][:, 0] == pytest.approx([0.5 * 0.12 * ta, 0.025, 0.05], rel=1e-12)
    assert k["v"][:, 0] == pytest.approx([0.12, 0.12, 0.0], rel=1e-12, abs=1e-15)


def test_free_coordinates_and_replace():
    sc = exdex.Scene(body=BODY, grasp=GRASP)
    assert (sc.ndof, sc.coordinate_names) == (1, ("s",))
    assert exdex.replace(sc, dof="rotation").coordinate_names == ("theta",)
    planar = exdex.replace(sc, dof="planar")
    assert (planar.ndof, planar.coordinate_names) == (3, ("x", "y", "theta"))
    assert planar.body == sc.body and planar.grasp == sc.grasp and sc.dof == "translation"


def test_stop_inside_object_random_depths():
    """Seeded random rotations, positions and floor heights: the reported
    depth is the lowest outline corner's distance below the plane, computed
    here from the corners' world coordinates."""
    rng = np.random.default_rng(11)
    for _ in range(40):
        th = rng.uniform(-math.pi, math.pi)
        q0 = (rng.uniform(-0.01, 0.01), rng.uniform(-0.01, 0.01), th)
        c, s = math.cos(th), math.sin(th)
        corners = [(q0[0] + c * x - s * y, q0[1] + s * x + c * y) for x, y in BODY.vertices()]
        low = min(y for _, y in corners)                  # B y = A z in the default pose
        depth = rng.uniform(1e-4, 5e-3)
        stop = exdex.Stop(point=(0, 0, low + depth), normal=(0, 0, 1))
        with pytest.raises(ValueError, match=r"Scene\.stops\[0\]") as info:
            exdex.Scene(body=BODY, grasp=GRASP, dof="planar", q0=q0, stops=stop).check_stops()
        got = float(re.search(r"is ([0-9.eE+-]+) m beyond", str(info.value)).group(1))
        assert got == pytest.approx(depth, rel=1e-5, abs=1e-12)
        # just clear of it: accepted
        exdex.Scene(body=BODY, grasp=GRASP, dof="planar", q0=q0,
                    stops=exdex.Stop(point=(0, 0, low - 1e-6), normal=(0, 0, 1))).check_stops()


def test_single_stop_is_accepted():
    stop = exdex.Stop(point=(0, 0, -0.1), normal=(0, 0, 1))
    one = exdex.Scene(body=BODY, grasp=GRASP, stops=stop)
    assert one.stops == (stop,)
    assert one == exdex.Scene(body=BODY, grasp=GRASP, stops=(stop,))


@pytest.mark.parametrize("bad", [1.0, "floor", object()])
def test_stops_of_wrong_type_name_the_parameter(bad):
    with pytest.raises(TypeError, match="Scene.stops"):
        exdex.Scene(body=BODY, grasp=GRASP, stops=bad)


def test_stops_entry_of_wrong_type_names_the_index():
    stop = exdex.Stop(point=(0, 0, -0.1), normal=(0, 0, 1))
    with pytest.raises(TypeError, match=r"Scene\.stops\[1\] must be an exdex\.Stop"):
        exdex.Scene(body=BODY, grasp=GRASP, stops=[stop, (0, 0, 1)])
