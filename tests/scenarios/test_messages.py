"""Messages a user meets: bad input names the parameter, tables are aligned
without ``nan``, and one exception class for solver failures (the command
line's --version, --no-progress and --help: tests/cli/test_dispatch.py)."""
import re

import numpy as np
import pytest

import exdex
from exdex import _core, _tool
from exdex._table import MISSING

BODY = exdex.Body.box(0.1, (0.06, 0.03, 0.02))
GRASP = exdex.Grasp(mu=0.5, grip_force=2.0)


# ---------------------------------------------------------------- scene messages

def test_stop_inside_object_names_stop_and_depth():
    """A stop that starts inside the object is blamed by index, with the
    penetration depth. Closed form: the default gripper pose maps B's y to
    A's z, so the box's lowest corners (y = -15 mm, theta = 0, q0 y = 2 mm)
    sit at z = -13 mm; a floor at z = -10 mm is 3 mm inside them."""
    ok = exdex.Stop(point=(0, 0, -0.5), normal=(0, 0, 1))
    floor = exdex.Stop(point=(0, 0, -0.010), normal=(0, 0, 1))
    scene = exdex.Scene(body=BODY, grasp=GRASP, q0=(0.0, 0.002, 0.0), stops=(ok, floor))  # may be built
    for run in (lambda: exdex.simulate(scene, 0.01, 1e-3), lambda: exdex.Model(scene),
                lambda: exdex.simulate_batch(scene, 0.01, 1e-3, mu=[0.1, 0.2])):
        with pytest.raises(ValueError) as info:
            run()
        msg = str(info.value)
        assert "Scene.stops[1]" in msg and "q0" in msg
        depth = float(re.search(r"is ([0-9.eE+-]+) m beyond", msg).group(1))
        assert depth == pytest.approx(0.003, rel=1e-6)
    with pytest.raises(ValueError, match=r"batch index 1: Scene\.stops\[1\]"):
        exdex.simulate_batch([exdex.replace(scene, stops=(ok,)), scene], 0.01, 1e-3)


@pytest.mark.parametrize("call", [
    lambda sc: exdex.simulate(sc, t_end=0.01, dt=0.1),
    lambda sc: exdex.Model(sc).simulate(t_end=0.01, dt=0.1),
    lambda sc: exdex.Model(sc).final(t_end=0.01, dt=0.1),
    lambda sc: exdex.simulate_batch(sc, t_end=0.01, dt=0.1),
])
def test_dt_above_t_end_says_so(call):
    sc = exdex.Scene(body=BODY, grasp=GRASP)
    with pytest.raises(ValueError) as info:
        call(sc)
    assert "dt must be <= t_end" in str(info.value) and "[0.1, inf)" not in str(info.value)


def test_batch_result_at_and_indexing():
    sc = exdex.Scene(body=BODY, grasp=GRASP)
    b = exdex.simulate_batch(sc, 0.02, 1e-3, grip_force=[1.0, 2.0, 3.0])
    serial = exdex.simulate(exdex.replace(sc, grasp=exdex.Grasp(mu=0.5, grip_force=2.0)), 0.02, 1e-3)
    for r in (b.at(1), b[1], b[-2], list(b)[1]):
        np.testing.assert_array_equal(r.q, serial.q)
    with pytest.warns(DeprecationWarning, match="at"):
        np.testing.assert_array_equal(b.result(1).q, serial.q)
    with pytest.raises(IndexError):
        b[3]
    with pytest.raises(TypeError):
        b["mu"]


# ---------------------------------------------------------------- exceptions and enums

def test_one_solver_error_class():
    assert _tool.SolverError is _core.SolverError is exdex.SolverError
    assert exdex.tool.ConvergenceError is exdex.SolverError
    assert issubclass(exdex.SolverError, RuntimeError)


def test_c_einval_names_the_parameter():
    spec = exdex.Scene(body=exdex.Body(mass=0.1), grasp=GRASP).to_spec()
    spec["mass"] = -1.0
    with pytest.raises(ValueError, match="'mass'"):
        _core.compile(spec)
    with pytest.raises(ValueError, match="method must be one of 'exact', 'grid', 'qmc'"):
        _tool.volumes(np.zeros((1, 1, 3)), [0, 0, 0], [1, 1, 1], method="monte-carlo")


def test_enums_come_from_the_core():
    """The spec carries the core's enum values; scene.py holds no literal
    enum numbers of its own."""
    from exdex import scene as scene_mod

    sc = exdex.Scene(body=BODY, grasp=GRASP, dof="planar",
                     motion=exdex.TrapezoidalProfile(0.05, 0.5, 0.12))
    spec = sc.to_spec(method="event", friction_solver="brent")
    assert spec["dof"] == _core.DOF_PLANAR and spec["method"] == _core.METHOD_EVENT
    assert spec["friction_solver"] == _core.SOLVER_BRENT and spec["motion_kind"] == _core.MOTION_TRAPEZOID
    src = open(scene_mod.__file__).read()
    assert not re.search(r"motion_kind=\d|\"(implicit|event|regularised|explicit|translation|rotation|planar|"
                         r"scalar|brent|multiroot)\": \d", src)


def test_paper_table_has_units_and_no_nan():
    from exdex import paper

    rows = [dict(case="Fig. 3", quantity="final relative displacement [mm]", paper=20.0, exdex=19.93,
                 difference=-0.07, reference=19.931, max_v_after=0.0, note=""),
            dict(case="Fig. 4", quantity="min stop gap [m]", paper=None, exdex=1e-12, difference=None,
                 reference=float("nan"), max_v_after=None, note="")]
    text = paper.format_table(rows)
    assert "nan" not in text and "None" not in text
    head = text.splitlines()[0]
    assert "unit" in head and "m/s" in text.splitlines()[2]
    assert text.splitlines()[3].count(MISSING) >= 3
