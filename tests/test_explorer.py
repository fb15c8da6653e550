"""exdex.explore: sliders for grip, mu and the motion redraw the trajectory, built here without a
display (the plot is a PNG image widget). The run behind the plot is checked against
exdex.simulate of the scene with the slider's values put in by exdex.replace (simulate_batch
promises bit-identical trajectories), the sliders' ranges against the scene's values."""
import numpy as np
import pytest

import exdex

pytest.importorskip("ipywidgets")
pytest.importorskip("matplotlib")

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture
def scene():
    return exdex.paper.fig3_scene()


def test_sliders_for_grip_mu_and_the_motion(scene):
    ex = exdex.explore(scene, dt=1e-3)
    assert list(ex.sliders) == ["grip_force", "mu", "amplitude", "duration", "beta"]
    m = scene.motion
    assert ex.values == pytest.approx({"grip_force": scene.grasp.grip_force, "mu": scene.grasp.mu,
                                       "amplitude": m.amplitude, "duration": m.duration, "beta": m.beta})
    s = ex.sliders["grip_force"]
    assert s.min == 0.0 and s.max == pytest.approx(3 * scene.grasp.grip_force) and s.description == "grip [N]"
    assert ex.t_end == pytest.approx(1.5 * m.end_time)
    assert bytes(ex.image.value).startswith(PNG)


def test_moving_a_slider_reruns_and_redraws(scene):
    ex = exdex.explore(scene, dt=1e-3)
    before = bytes(ex.image.value)
    ex.set(mu=0.45, beta=0.85)
    ref = exdex.simulate(exdex.replace(scene, grasp=exdex.replace(scene.grasp, mu=0.45),
                                       motion=exdex.replace(scene.motion, beta=0.85)), ex.t_end, 1e-3)
    assert np.array_equal(ex.result.q, ref.q) and np.array_equal(ex.result.t, ref.t)
    (line,) = ex.axes.get_lines()
    assert np.array_equal(line.get_ydata(), 1e3 * (ref.q[:, 0] - ref.q[0, 0]))
    assert bytes(ex.image.value) != before and bytes(ex.image.value).startswith(PNG)
    assert "stick in" in ex.status.value


def test_bad_names_and_a_schedule(scene):
    ex = exdex.explore(scene, dt=1e-3)
    with pytest.raises(ValueError, match="unknown parameter.*grip_force"):
        ex.set(gravity=1.0)
    sched = exdex.replace(scene, grasp=exdex.replace(scene.grasp, grip_force=exdex.GripSchedule([0.0, 1.0], [2.0, 1.0])))
    assert exdex.explorer.slider_ranges(sched)["grip_force"] == (1.0, 0.0, 3.0, "grip (x schedule)")
    with pytest.raises(TypeError, match="scene must be an exdex.Scene"):
        exdex.explorer.slider_ranges("fig3")
