"""exdex.simulate: simulate's bad input named; a box held below the grip it
needs slides at the closed-form constant acceleration a = g - 2 mu F / m
(s = -a t^2 / 2 along the plate axis, down), above it stays exactly still:
the analytic, event and implicit methods to rounding, the explicit method's
error exactly proportional to its step (first order) at a constant
acceleration, the regularised friction's creep at its closed-form speed;
then the Result's ways out (to_dict, save / load, to_dataframe, repr)."""
import csv
import sys

import numpy as np
import pytest

import exdex
from expected_warnings import by_design
from scenes import falling_box_scenes

M, G, MU = 0.1, 9.81, 0.5


def _held(grip):
    return exdex.Scene(body=exdex.Body.box(M, (0.04, 0.2, 0.02)), grasp=exdex.Grasp(mu=MU, grip_force=grip))


def test_bad_input_names_the_parameter():
    sc = _held(1.0)
    for call, exc, message in [
            (lambda: exdex.simulate("scene", 1.0), TypeError, "scene must be an exdex.Scene, got str"),
            (lambda: exdex.simulate(sc, 1.0, method="rk4"), ValueError,
             "method must be one of ['analytic', 'event', 'explicit', 'implicit', 'regularised', 'auto'], got 'rk4'"),
            (lambda: exdex.simulate(sc, 1.0, friction_solver="x"), ValueError,
             "friction_solver must be one of ['brent', 'multiroot', 'scalar'], got 'x'"),
            (lambda: exdex.simulate(sc, -1.0), ValueError, "t_end must be in (0, inf), got -1"),
            (lambda: exdex.simulate(sc, float("nan")), ValueError, "t_end must be finite, got nan"),
            (lambda: exdex.simulate(sc, 1.0, dt=0.0), ValueError, "dt must be in (0, inf), got 0")]:
        with pytest.raises(exc) as info:
            call()
        assert str(info.value).startswith(message)


@pytest.mark.parametrize("method", ["analytic", "event", "implicit", "auto"])
def test_below_the_grip_needed_the_box_slides_at_the_closed_form_acceleration(method):
    F = 0.5 * M * G / (2 * MU)                  # half the grip needed, m g / (2 mu)
    a = G - 2 * MU * F / M
    t_end, dt = 0.05, 1e-3
    r = exdex.simulate(_held(F), t_end, dt, method=method)
    assert r.t[0] == 0.0 and r.t[-1] == pytest.approx(t_end, rel=1e-15) and len(r.t) == 51
    assert r.method == ("analytic" if method == "auto" else method) and r.dt == dt and r.scene == _held(F)
    assert r.q[-1, 0] == pytest.approx(-0.5 * a * t_end**2, rel=1e-12)
    assert r.v[-1, 0] == pytest.approx(-a * t_end, rel=1e-12)
    assert not np.any(r.stick[1:])


@pytest.mark.parametrize("method", ["analytic", "event", "implicit"])
def test_above_the_grip_needed_the_box_stays_exactly_still(method):
    r = exdex.simulate(_held(1.05 * M * G / (2 * MU)), 0.05, 1e-3, method=method)
    assert np.all(r.q == 0.0) and np.all(r.v == 0.0) and np.all(r.stick)


def test_the_regularised_friction_creeps_at_its_closed_form_speed():
    """w = -C u / sqrt(u^2 + eps^2) holds the weight m g = r C (r = 1 / 1.05
    here) at the slip speed u = eps r / sqrt(1 - r^2), reached at once (the
    object starts at rest, the speed settles within a few eps m / C)."""
    r = 1 / 1.05
    res = exdex.simulate(_held(M * G / (2 * MU * r)), 0.05, 1e-3, method="regularised", eps=1e-4)
    assert res.v[10:, 0] == pytest.approx(np.full(41, -1e-4 * r / np.sqrt(1 - r * r)), rel=1e-9)


def test_the_explicit_method_is_first_order_at_a_constant_acceleration():
    F = 0.5 * M * G / (2 * MU)
    a, t_end = G - 2 * MU * F / M, 0.05
    err = [exdex.simulate(_held(F), t_end, dt, method="explicit").q[-1, 0] + 0.5 * a * t_end**2
           for dt in (1e-3, 5e-4, 2.5e-4)]
    # error C h: halving the step halves it, to rounding
    assert err[0] / err[1] == pytest.approx(2.0, rel=1e-9) and err[1] / err[2] == pytest.approx(2.0, rel=1e-9)


COLUMNS = {
    "translation": ["t", "s", "v_s", "f_x", "f_y", "m_z", "stick"],
    "rotation": ["t", "theta", "v_theta", "f_x", "f_y", "m_z", "stick"],
    "planar": ["t", "x", "y", "theta", "v_x", "v_y", "v_theta", "f_x", "f_y", "m_z", "stick", "stop_force_0"],
}


@pytest.fixture(scope="module")
def results():
    with by_design("impact", "outline"):  # the planar scene drops onto its stop
        return {k: exdex.simulate(sc, 1.2, 1e-3) for k, sc in falling_box_scenes().items()}


@pytest.mark.warns_by_design("impact", "outline")
@pytest.mark.parametrize("dof", list(COLUMNS))
def test_to_dict_columns(results, dof):
    r = results[dof]
    d = r.to_dict()
    assert list(d) == COLUMNS[dof]
    assert list(r.units) == COLUMNS[dof]
    assert all(len(v) == len(r.t) for v in d.values())
    names = r.scene.coordinate_names
    for i, n in enumerate(names):
        assert np.array_equal(d[n], r.q[:, i]) and np.array_equal(d[f"v_{n}"], r.v[:, i])
    assert np.array_equal(np.column_stack([d["f_x"], d["f_y"], d["m_z"]]), r.wrench)
    assert r.units["m_z"] == "N m" and r.units["t"] == "s"


@pytest.mark.parametrize("dof", list(COLUMNS))
def test_save_csv_is_exact(results, dof, tmp_path):
    r = results[dof]
    path = r.save(tmp_path / "r.csv")
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == COLUMNS[dof]
    assert len(rows) == len(r.t) + 1
    table = np.array([[float(x) for x in row] for row in rows[1:]])
    for j, (name, col) in enumerate(r.to_dict().items()):
        assert np.array_equal(table[:, j], np.asarray(col, dtype=float)), name
    assert set(row[rows[0].index("stick")] for row in rows[1:]) <= {"0", "1"}


@pytest.mark.parametrize("dof", list(COLUMNS))
def test_save_npz_round_trip(results, dof, tmp_path):
    r = results[dof]
    back = exdex.Result.load(r.save(tmp_path / "r.npz"))
    for name in ("t", "q", "v", "wrench", "stick", "stop_force"):
        a, b = getattr(r, name), getattr(back, name)
        assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), name
    assert back.scene == r.scene and back.method == r.method and back.dt == r.dt
    assert back.stats == r.stats
    with pytest.raises(ValueError, match=r"\.npz or \.csv.*'\.xlsx'"):
        r.save(tmp_path / "r.xlsx")


def test_to_dataframe(results, monkeypatch):
    r = results["planar"]
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if pandas were not installed
    with pytest.raises(ImportError, match="needs pandas"):
        r.to_dataframe()
    monkeypatch.undo()
    pd = pytest.importorskip("pandas")
    df = r.to_dataframe()
    assert isinstance(df, pd.DataFrame) and list(df.columns) == COLUMNS["planar"] and len(df) == len(r.t)
    assert np.array_equal(df["y"].to_numpy(), r.q[:, 1]) and df.attrs["units"]["y"] == "m"


@pytest.mark.warns_by_design("impact", "outline")
def test_repr_is_short_and_says_what_matters(results):
    r = exdex.simulate(falling_box_scenes()["planar"], 20.0, 1e-4)  # 200,001 samples
    text = repr(r)
    assert "\n" not in text and len(text) < 250, text
    assert "method='implicit'" in text and "200001 samples" in text and "t = 0..20 s" in text
    assert f"y = {r.q[-1, 1]:.6g} m" in text
    # stick share of the steps, from the stick flags
    assert f"stick in {np.mean(r.stick[1:]):.0%} of steps" in text
    assert "[" not in text  # no arrays
