"""exdex._obstacle_hint: the SolverError of a rotation run (dof="rotation")
that cannot clear an obstacle says why (the pivot inside the obstacle, or
that the rotation model may be unable to clear it) and names the remedy
(dof="planar" or "auto"); runs that clear are the core's run unchanged.
References: the pivot's depth inside the obstacle computed here from the
scene's own geometry (its face planes), and planar runs of the same scenes."""
import math
import warnings

import numpy as np
import pytest

import exdex

def _zoo_scene_with_obstacle(seed):
    # test_auto_against_planar_on_zoo_scenes_with_obstacles's scene of `seed`
    import zoo

    zs = zoo.zoo_scene(seed)
    rng = np.random.default_rng(1000 + seed)
    ob, _ = zoo.obstacle(rng, zs, float(rng.choice([0.0, 0.5])))
    return zs, exdex.replace(zs.scene, obstacles=(ob,))


KW = dict(method="event", rtol=1e-10, atol=1e-12)


def _rotation_failure(seed):
    """Zoo scene `seed` with its obstacle as dof="rotation": (zoo scene,
    scene, dt, the SolverError exdex.simulate raises)."""
    zs, sc = _zoo_scene_with_obstacle(seed)
    sc = exdex.replace(sc, dof="rotation")
    dt = zs.t_end / 200
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(exdex.SolverError) as info:
            exdex.simulate(sc, zs.t_end, dt, **KW)
    return zs, sc, dt, info.value


def _pivot_depth(sc, t):
    """How deep [m] the grasp point (the rotation model's pivot, fixed in B)
    lies inside the scene's one box or wedge obstacle at time t (> 0 inside):
    the smallest distance from the obstacle's face planes."""
    pc = np.array(sc.grasp.patch.center)
    th0 = sc.q0[2]
    pivot = np.array(sc.q0[:2]) + np.array([math.cos(th0) * pc[0] - math.sin(th0) * pc[1],
                                            math.sin(th0) * pc[0] + math.cos(th0) * pc[1]])
    kin = sc.motion.evaluate([t], sc.gripper_rotation, sc.gripper_position)
    x = kin["p"][0] + kin["R"][0] @ np.array([pivot[0], pivot[1], 0.0])
    ob = sc.obstacles[0]
    return min(-(x - np.array(p)) @ np.array(n) for p, n in zip(ob.face_points, ob.face_normals))


@pytest.mark.parametrize("seed", [5, 17, 19, 27])
def test_rotation_runs_that_cannot_clear_an_obstacle_say_so(seed):
    # Zoo scenes 5, 17, 19 and 27 with the obstacle of the test above, run as
    # dof="rotation" (event): the state leaves the finite range against the
    # obstacle. At 5, 17 and 27 the pivot is then inside it (checked here from
    # the face planes and the gripper's pose at SolverError.time, by more than
    # 1e-6 L), so the object, whose outline holds the pivot, overlaps it at
    # every angle: the message says so and names the obstacle. At 19 the
    # pivot is outside (by more than 1e-6 L): the message says the model may
    # be unable to clear the obstacles. Both name dof='planar', with which
    # the scene runs to t_end.
    zs, sc, dt, exc = _rotation_failure(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        planar = exdex.simulate(exdex.replace(sc, dof="planar"), zs.t_end, dt, **KW)
    assert planar.t[-1] == pytest.approx(zs.t_end, rel=1e-12)
    assert exc.cause == "nonfinite" and exc.time is not None
    msg = str(exc)
    assert "use dof='planar' (or dof='auto'" in msg
    depth = _pivot_depth(sc, exc.time)
    if seed == 19:
        assert depth < -1e-6 * zs.L
        assert "the rotation model (the object turning about the grasp point, pinned in the gripper) may be " \
               "unable to clear them" in msg
    else:
        assert depth > 1e-6 * zs.L
        assert "the rotation model cannot clear Scene.obstacles[0]: its pivot (the grasp point, pinned in the " \
               "gripper) is inside the obstacle then, so no angle of the object clears it" in msg
        assert "check the scene's scales" not in msg


@pytest.mark.parametrize("seed", [1, 4, 10, 29])
def test_rotation_runs_that_clear_an_obstacle_are_the_core_run(seed):
    # Zoo scenes with the obstacle of the test above that the rotation model
    # runs to t_end (a rod, boxes, a wedge): exdex.simulate's arrays are the
    # extension's own run of the same spec, bit for bit.
    from exdex.simulate import scene_spec

    zs, sc = _zoo_scene_with_obstacle(seed)
    sc = exdex.replace(sc, dof="rotation")
    dt = zs.t_end / 200
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = exdex.simulate(sc, zs.t_end, dt, method="event", rtol=1e-10, atol=1e-12)
    out = exdex._core.simulate(scene_spec(sc, "event", "scalar", 1e-4, 1e-10, 1e-12), zs.t_end, dt)
    assert res.t[-1] == pytest.approx(zs.t_end, rel=1e-12)
    for k in ("t", "q", "v", "wrench", "stick", "stop_force"):
        assert np.array_equal(getattr(res, k), out[k]), k


@pytest.mark.parametrize("seed", [5, 19])
def test_batch_says_what_simulate_says_where_rotation_cannot_clear_an_obstacle(seed):
    # simulate_batch's SolverError is simulate's with the batch index in
    # front, the obstacle hint included: zoo scene 5 (the pivot inside the
    # obstacle) and 19 (outside) as dof="rotation" at index 1, after a scene
    # that clears (zoo scene 1 as dof="rotation").
    _, ok = _zoo_scene_with_obstacle(1)
    zs, bad, dt, s = _rotation_failure(seed)
    ok = exdex.replace(ok, dof="rotation")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(exdex.SolverError) as info:
            exdex.simulate_batch([ok, bad], zs.t_end, dt, threads=1, record="final", **KW)
    e = info.value
    assert "use dof='planar'" in str(s)
    assert e.args == (f"batch index 1: {s.args[0]}", s.status)
    assert (e.index, e.time, e.cause) == (1, s.time, s.cause)


@pytest.mark.parametrize("seed", [5, 19])
def test_model_says_what_simulate_says_where_rotation_cannot_clear_an_obstacle(seed):
    # exdex.Model's simulate and final raise simulate's SolverError (the
    # obstacle hint included) for zoo scenes 5 and 19 as dof="rotation".
    zs, sc, dt, serial = _rotation_failure(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = exdex.Model(sc, **KW)
        for run in (model.simulate, model.final):
            with pytest.raises(exdex.SolverError) as info:
                run(zs.t_end, dt)
            assert info.value.args == serial.args and "use dof='planar'" in str(info.value)


@pytest.mark.parametrize("seed", [5, 19])
def test_stepper_says_what_simulate_says_where_rotation_cannot_clear_an_obstacle(seed):
    # exdex.Stepper stepped on simulate's grid (dt = t_end / 200, the scene's
    # motion) fails at simulate's time with its message, the obstacle hint
    # included (zoo scenes 5: the pivot inside, and 19: outside).
    zs, sc, dt, serial = _rotation_failure(seed)
    st = exdex.Stepper(sc, **KW)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(exdex.SolverError) as info:
            for _ in range(200):
                st.step(dt)
    e = info.value
    assert (e.args, e.time, e.cause) == (serial.args, serial.time, serial.cause)
    assert "use dof='planar'" in str(e)


def test_stepper_given_poses_gives_the_hedged_hint():
    # Zoo scene 5 stepped with the gripper's poses and twists, sampled from
    # the scene's own motion: given poses replace the scene's motion, so the
    # pivot's place is not taken from it (here the two agree, and the
    # scene's motion has the pivot inside the obstacle at the failure: a
    # hint that read the motion would name it). The message is the hedged
    # form with the remedy.
    zs, sc, dt, _ = _rotation_failure(5)
    st = exdex.Stepper(sc, **KW)
    kin = sc.motion.evaluate(np.arange(1, 201) * dt, sc.gripper_rotation, sc.gripper_position)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(exdex.SolverError) as info:
            for i in range(200):
                st.step(dt, gripper=exdex.GripperPose(kin["p"][i], kin["R"][i], kin["v"][i], kin["w"][i]))
    msg = str(info.value)
    assert info.value.cause == "nonfinite"
    assert "may be unable to clear them: use dof='planar'" in msg
    assert "is inside the obstacle" not in msg
