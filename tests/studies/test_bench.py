"""exdex.studies.bench: the reference machinery (the ``exdex bench --quick`` run is
tested in tests/cli/test_bench.py).

No timing is asserted anywhere (speed is measured in the benchmark only).
Where an expected number comes from is said at each test: hand-derived closed
forms (the Fig. 3 event times of exdex.paper.fig3_grip_force's derivation,
plane geometry, rotation chords), the paper (20 mm, 50 mm), or exact rational
arithmetic (fractions) for the step grids.
"""
import math
import types
from fractions import Fraction

import numpy as np
import pytest

import exdex
from exdex import paper
from exdex.studies import bench
from optional_packages import need_mujoco


# ------------------------------------------------------------------ smoke run


# ------------------------------------------------------------------ references and grids

def test_references_reproduce_the_paper_numbers():
    # the paper: 20 mm down (Fig. 3, by the closed-form grip force), 50 mm up (Fig. 4, the trapezoid),
    # Fig. 6: 2 theta1 (2 beta - 1) / beta = 800/7 deg (exdex.paper.fig6_rotation_bound, by hand), for a
    # grasp FIG6_MARGIN = 1e-9 (relative) stronger than the bound's, hence the relative 1e-8
    assert bench.make_case("fig3").ref[-1, 0] == pytest.approx(-0.020, abs=1e-12)
    assert bench.make_case("fig4").ref[-1, 0] == pytest.approx(0.050, abs=1e-12)
    assert bench.make_case("fig6").ref[-1, 0] == pytest.approx(math.radians(800.0 / 7.0), rel=1e-8)


def test_step_grids_hit_the_common_grid_and_switch_times():
    # exact rational arithmetic: every dyadic step divides the grid spacing 2^-6 s and the horizons,
    # and misses the Eq. 7 switching time 0.45 s; the aligned step 1/320 s divides the grid and
    # every switching time of Figs. 3, 6 and the planar case
    grid = Fraction(1, 64)
    for k in range(6, 17):
        dt = Fraction(1, 2 ** k)
        assert (grid / dt).denominator == 1
        assert (Fraction(3, 2) / dt).denominator == 1 and (Fraction(8) / dt).denominator == 1
        assert (Fraction(9, 20) / dt).denominator != 1
    al = Fraction(1, 320)
    assert Fraction(bench.make_case("fig3").aligned_dt).limit_denominator(10 ** 6) == al
    assert (grid / al).denominator == 1
    for t in ("0.45", "0.55", "1.0", "2.1", "3.9", "6.0", "0.4", "0.6"):
        assert (Fraction(t) / al).denominator == 1


def test_planar_scene_geometry():
    # plane geometry by hand: the lowest corner (-30 mm, -15 mm) lies 8 mm cos 10deg - 30 mm sin 10deg
    # above the stop tilted by 10 deg (checked with exdex.paper.stop_gaps, a geometric check)
    sc = bench.planar_scene()
    a = math.radians(10.0)
    res = exdex.simulate(sc, 0.01, dt=0.005)
    assert paper.stop_gaps(res)[0, 0] == pytest.approx(0.008 * math.cos(a) - 0.030 * math.sin(a), abs=1e-15)
    assert sc.grasp.capacity == pytest.approx(1.1 * 0.1 * 9.81, rel=1e-15)


@pytest.mark.warns_by_design("impact")
def test_planar_reference_uncertainty_is_small():
    # the tight reference agrees with itself one notch looser far below the chart's errors
    c = bench.make_case("planar", methods=bench.available_methods()[0], quick=True)
    assert 0.0 < c.ref_uncertainty < 1e-5
    assert c.ref.shape == (len(c.grid), 3)


def test_vertex_error_closed_forms():
    sc = bench.planar_scene()
    q0 = np.zeros((1, 3))
    # a pure translation moves every vertex by the same vector
    assert bench.vertex_error(sc, np.array([[3e-3, -4e-3, 0.0]]), q0)[0] == pytest.approx(5e-3, rel=1e-14)
    # a rotation by phi about the centre of mass: chord 2 r sin(phi / 2), r = the half-diagonal
    phi = 0.3
    r = math.hypot(0.03, 0.015)
    assert bench.vertex_error(sc, np.array([[0.0, 0.0, phi]]), q0)[0] == pytest.approx(2 * r * math.sin(phi / 2),
                                                                                       rel=1e-14)


def test_errors_and_grid_interpolation():
    sc = paper.fig3_scene()
    grid = np.array([0.0, 0.5, 1.0])
    ref = np.array([[0.0], [1.0], [2.0]])
    assert bench.final_and_max_error(sc, np.array([[0.0], [1.5], [1.9]]), ref) == pytest.approx((0.1, 0.5))
    assert bench.final_and_max_error(sc, np.array([[0.0], [np.nan], [2.0]]), ref) == (math.inf, math.inf)
    # on_grid: exact at samples, linear between, displacement from the first sample
    res = types.SimpleNamespace(t=np.array([0.0, 0.25, 1.0]), q=np.array([[1.0], [2.0], [5.0]]))
    assert bench.on_grid(res, grid)[:, 0] == pytest.approx([0.0, 2.0, 4.0])


def test_observed_order_recovers_synthetic_slopes():
    dt = 2.0 ** -np.arange(4, 12)
    assert bench.observed_order(dt, 3.0 * dt**2, 1e-30) == pytest.approx(2.0, abs=1e-12)
    # points at or below the floor are left out (a rounding plateau does not bend the slope)
    err = np.maximum(0.5 * dt, 1e-3)
    assert bench.observed_order(dt, err, 1e-3) == pytest.approx(1.0, abs=1e-12)
    assert math.isnan(bench.observed_order(dt, np.zeros_like(dt), 1e-16))


# ------------------------------------------------------------------ the stability classifier

def test_stick_intervals_of_fig3():
    # hand derivation (exdex.paper.fig3_grip_force): stick on [0, beta T) = [0, 0.45), slip for
    # tau = 0.1 s, then u tau / (D - u) = 0.045 s of deceleration: stick again from 0.595 s
    cf = paper.closed_form(paper.fig3_scene())
    iv = bench.stick_intervals(cf, 1.5)
    assert len(iv) == 2
    assert iv[0] == pytest.approx((0.0, 0.45), abs=1e-12)
    assert iv[1] == pytest.approx((0.595, 1.5), abs=1e-12)


def _fake(t, x, v, stats=None):
    return types.SimpleNamespace(t=t, q=x[:, None].copy(), v=v[:, None].copy(), stats=stats or {})


def test_classify_synthetic_runs():
    sc = paper.fig3_scene()
    cf = paper.closed_form(sc)
    dt = 2.0 ** -10
    t = np.arange(int(1.5 / dt) + 1) * dt
    x, v = cf(t)
    end = sc.motion.end_time
    args = (cf, 1.5, dt, "translation", end)
    assert bench.classify(_fake(t, x, v), *args)[0] == "ok"
    # alternating velocity inside the first stick interval: chatter
    vc = v.copy()
    sel = (t > 0.1) & (t < 0.3)
    vc[sel] = 1e-6 * (-1.0) ** np.arange(np.count_nonzero(sel))
    cls, det = bench.classify(_fake(t, x, vc), *args)
    assert cls == "chatter" and det["chatter_sign_changes"] > 10
    # a slow creep after the motion: drift, with its rate
    xd, vd = x.copy(), v.copy()
    after = t > end
    vd[after] = -1e-7
    xd[after] += -1e-7 * (t[after] - end)
    cls, det = bench.classify(_fake(t, xd, vd), *args)
    assert cls == "drift" and det["creep_rate"] == pytest.approx(1e-7, rel=1e-6)
    # non-finite state, or an error larger than the whole motion: blow-up
    xn = x.copy()
    xn[5] = np.nan
    assert bench.classify(_fake(t, xn, v), *args)[0] == "blow-up"
    assert bench.classify(_fake(t, x + 0.05 * np.sin(40 * t), v), *args)[0] == "blow-up"
    # a raised solver error, or more events than the budget: step collapse
    assert bench.classify(exdex.SolverError("no convergence"), *args)[0] == "collapse"
    assert bench.classify(_fake(t, x, v, dict(events=bench.EVENT_BUDGET + 1)), *args)[0] == "collapse"


@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("ratio", [0.5, 1.1, 2.0, 10.0])
def test_classify_implicit_runs_hold_exact_stick(ratio):
    # the implicit method (exact stick) classified "ok" across capacities (the maximum-dissipation step: no chatter,
    # no drift), at a step that does not divide the switching times
    make, t_end, _, dof, _ = bench._family("fig3")
    sc = make(ratio)
    dt = 2.0 ** -9
    res = exdex.simulate(sc, t_end, dt=dt)
    cls, det = bench.classify(res, paper.closed_form(sc), t_end, dt, dof, sc.motion.end_time)
    assert cls == "ok", det


def test_method_available():
    assert bench.method_available("implicit") == (True, "")
    ok, reason = bench.method_available("no-such-method")
    assert not ok and "method" in reason


def test_mujoco_bare_step_time_runs():
    need_mujoco()
    secs = bench.mujoco_bare_step_time(paper.fig3_scene(), 0.05, 2.0 ** -8, "pads")
    assert math.isfinite(secs) and secs > 0.0


# ------------------------------------------------------------------ figures

def _capture_figures(monkeypatch):
    """Figures passed to savefig (kept open), to inspect what a plot function drew."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.figure
    import matplotlib.pyplot as plt

    figs = []
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", lambda self, *a, **k: figs.append(self))
    monkeypatch.setattr(plt, "close", lambda *a, **k: None)
    return figs


def _inside(fig, artist):
    fig.canvas.draw()
    bb = artist.get_window_extent(fig.canvas.get_renderer())
    W, H = fig.canvas.get_width_height()
    return bb.x0 >= -0.5 and bb.y0 >= -0.5 and bb.x1 <= W + 0.5 and bb.y1 <= H + 0.5


def test_work_precision_panel_of_rounding_noise_is_said_in_words(monkeypatch):
    # a case whose every error is below ROUNDING x max|reference| (as Fig. 4's
    # 5e-18..7e-18 m against a 50 mm slip) gets no plot of the noise, a text instead;
    # a case with real errors keeps its lines, on axes spanning >= 4 decades with
    # labels on the decades only
    figs = _capture_figures(monkeypatch)
    cases = {"a": types.SimpleNamespace(scale=0.05, unit="m", title="noise", ref_label="closed form",
                                        ref_uncertainty=0.0, ref_uncertainty_max=0.0, unsupported=()),
             "b": types.SimpleNamespace(scale=0.05, unit="m", title="real", ref_label="closed form",
                                        ref_uncertainty=0.0, ref_uncertainty_max=0.0, unsupported=())}
    rows = []
    for case, errs in (("a", (5e-18, 6e-18, 7e-18)), ("b", (1e-3, 1e-4, 3e-5))):
        for k, e in enumerate(errs):
            rows.append(dict(case=case, method="implicit", line="implicit", status="ok", run_time_s=1e-4 * (k + 1),
                             final_error=e, max_error=e, dt=None))
    bench.plot_work_precision(rows, cases, "unused.png", "test machine", {})
    fig = figs[-1]
    axes = fig.axes
    noise = [ax for ax in axes if any("exact to rounding" in t.get_text() for t in ax.texts)]
    assert len(noise) == 2 and all(not ax.lines for ax in noise)
    real = [ax for ax in axes if ax.lines]
    assert len(real) == 2
    for ax in real:
        lo, hi = ax.get_ylim()
        assert hi / lo >= 1e4 * (1 - 1e-9)
        fig.canvas.draw()
        labels = [t for t in ax.get_yticklabels(minor=True) if t.get_text()]
        assert not labels                        # no minor labels to overlap
    for ax in axes:
        assert _inside(fig, ax.title)


def test_stability_map_titles_fit_the_figure(monkeypatch):
    figs = _capture_figures(monkeypatch)
    rows = []
    for method in bench.METHODS:
        for axis in ("ratio",) + (("eps",) if method == "regularised" else ()):
            for dt in (2.0 ** -5, 2.0 ** -11):
                for y in (1.1, 10.0):
                    rows.append(dict(family="fig3", method=method, axis=axis, y=y, dt=dt, cls="ok",
                                     y_label="capacity / weight", creep_rate="",
                                     y_label_ratio="the paper's grasp, ratio 1.53428943123"))
    bench.plot_maps(rows, "fig3", "unused.png", "test machine, 2 cores", {})
    fig = figs[-1]
    for ax in fig.axes:
        assert _inside(fig, ax.title), ax.get_title()
