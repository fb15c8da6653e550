"""Warnings name the user's line; error messages name their class and, for
sequences, the first offending index."""
import warnings

import numpy as np
import pytest

import exdex
from exdex import paper


def off_the_box():
    """An 8 cm box that slides off its 2 cm pad: every run of it warns."""
    f3 = paper.fig3_scene()
    return exdex.replace(f3, body=exdex.Body.box(0.1, (0.08, 0.08, 0.08)),
                         grasp=exdex.replace(f3.grasp, grip_force=0.8, patch=exdex.Patch.rectangle(0.02, 0.02)))


def moving_log():
    """A robot log that starts at speed: a GripperJumpWarning at its start."""
    t = np.linspace(0.0, 1.0, 11)
    p = np.stack([np.zeros(11), np.zeros(11), -0.1 * t], axis=1)
    q = np.tile([1.0, 0.0, 0.0, 0.0], (11, 1))
    return exdex.replace(off_the_box(), motion=exdex.SampledTrajectory(t + 0.1, p, q))


def _caught(fn):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        fn()
    return rec


@pytest.mark.parametrize("call", ["simulate", "Model.simulate", "simulate_batch", "log", "plan"])
def test_warnings_name_the_line_that_called_exdex(call):
    sc = off_the_box()
    runs = {
        "simulate": lambda: exdex.simulate(sc, 1.0, 1e-3),
        "Model.simulate": lambda: exdex.Model(sc).simulate(1.0, 1e-3),
        "simulate_batch": lambda: exdex.simulate_batch(sc, 1.0, 1e-3, grip_force=np.array([0.8, 0.9])),
        "log": lambda: exdex.simulate(moving_log(), 1.0, 1e-3),
        "plan": lambda: exdex.plan.solve(exdex.replace(paper.fig3_scene(), body=exdex.replace(
            paper.fig3_scene().body, size=(0.03, 1.0, 0.03))), {"slip": -0.35}, {"grip_force": (1.0, 1.2)},
            t_end=1.5),
    }
    rec = _caught(runs[call])
    assert rec, "the scene is built to warn"
    line = runs[call].__code__.co_firstlineno    # the lambda's line: the call into exdex
    for w in rec:
        assert (w.filename, w.lineno) == (__file__, line), (w.category.__name__, w.filename, w.lineno)


def test_a_jump_warning_from_a_log_names_the_line():
    model = exdex.Model(moving_log())
    run = lambda: model.simulate(1.0, 1e-3)  # noqa: E731
    rec = _caught(run)
    assert any(issubclass(w.category, exdex.GripperJumpWarning) for w in rec)
    assert all((w.filename, w.lineno) == (__file__, run.__code__.co_firstlineno) for w in rec)


@pytest.mark.parametrize("make, text", [
    (lambda: exdex.Body.box(0.1, (0.1, 0.1)), "Body.box: size must have shape (3,), got (2,)"),
    (lambda: exdex.Patch.rectangle(0.0, 0.01), "Patch.rectangle: width must be in (0, inf)"),
    (lambda: exdex.Patch.disc(-1.0), "Patch.disc: radius must be in (0, inf)"),
    (lambda: exdex.Pad.rectangle(0.02, 0.0), "Pad.rectangle: height must be in (0, inf)"),
    (lambda: exdex.Body.cylinder(0.1, 0.02, 0.0), "Body.cylinder: height must be in (0, inf)"),
    (lambda: exdex.SampledTrajectory([0.0, 0.1, 0.2, 0.2, 0.3], np.zeros((5, 3)), np.tile([1.0, 0, 0, 0], (5, 1))),
     "SampledTrajectory.times must be strictly increasing: times[3] = 0.2"),
])
def test_errors_name_their_class_and_index(make, text):
    with pytest.raises(ValueError) as ei:
        make()
    assert text in str(ei.value)


def test_unknown_extension_names_the_ways_to_give_the_format(tmp_path):
    path = tmp_path / "scene.yaml"
    path.write_text("")
    with pytest.raises(ValueError, match="--scene-format") as ei:
        exdex.load_scene(path)
    assert "format='toml'" in str(ei.value)
