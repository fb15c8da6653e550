"""Tests of exdex.tool (paper Section 3): cone rows, volumes, tool optimisation.

Expected values come from closed forms (derived in the comments), symmetry
identities, tests/data/reference.dat, or independent methods: scipy's
half-space intersection + convex hull (qhull), randomised QMC, brute-force
scans in NumPy. Uses exdex._tool only.
"""
import math
import os
import re

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from exdex import tool as T

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # tests/
SQRT2 = math.sqrt(2.0)


def ref(key):
    with open(os.path.join(HERE, "data", "reference.dat")) as f:
        for line in f:
            parts = line.split("#")[0].split()
            if len(parts) == 2 and parts[0] == key:
                return float(parts[1])
    raise KeyError(key)


EQ13 = T.Box.eq13()
rows3 = st.lists(st.floats(-1, 1, allow_nan=False), min_size=3, max_size=3).filter(
    lambda r: np.linalg.norm(r) > 1e-3)


# ------------------------------------------------------------ closed forms

@settings(max_examples=60, deadline=None, derandomize=True)
@given(rows3)
def test_half_space_through_centre_is_half_the_box(row):
    # closed form: central symmetry of the centred box
    assert T.cone_volume(np.array([row])) == pytest.approx(0.5, abs=1e-12)
    box = T.Box(0.3, 2.0, 5.0)
    assert T.cone_volume(np.array([row]), box) == pytest.approx(1.5, abs=1e-12)


def test_octant_is_one_eighth():
    # closed form: the octant of a centred box
    assert T.cone_volume(np.eye(3)) == pytest.approx(0.125, abs=1e-12)
    assert T.cone_volume(np.eye(3), T.Box(1, 2, 3)) == pytest.approx(6 / 8, abs=1e-12)


@pytest.mark.parametrize("k", [0.0, 0.3, 1.75, 2.0, 7.0])
def test_wedge_closed_form(k):
    # closed form: Vy >= k |Vx| in |Vx| <= a, |Vy| <= b, |wz| <= c has
    # cross-section 2ab - k a^2 (k a <= b) or b^2 / k (k a >= b), times 2c
    a, b, c = 0.4, 0.7, 1.3
    box = T.Box(2 * a, 2 * b, 2 * c)
    area = 2 * a * b - k * a * a if k * a <= b else b * b / k
    rows = np.array([[-k, 1, 0], [k, 1, 0]])
    assert T.cone_volume(rows, box) == pytest.approx(area * 2 * c, abs=1e-12)


def test_square_in_corner_and_on_floor_closed_forms():
    # closed forms in reference.dat (derivations there and in test_cone.c)
    prob = T.ToolProblem(phi=[0.0])
    v = T.objective(prob, T.Tool(theta=math.pi / 2))
    assert v == pytest.approx(ref("tool_corner_square_eq13"), abs=1e-12)
    assert v == pytest.approx(1 / (12 * SQRT2), abs=1e-12)
    floor = T.tool_rows(prob, T.Tool(theta=0.0), 0.0)
    # theta = 0: both surfaces are the floor, the edge contact twice
    assert floor.shape == (4, 3)
    assert T.cone_volume(floor) == pytest.approx(ref("tool_floor_edge_eq13"), abs=1e-12)


def test_empty_and_whole():
    assert T.cone_volume(np.array([[1, 0, 0], [-0.5, 1, 0], [-0.5, -1, 0]])) == \
        pytest.approx(0, abs=1e-12)
    assert T.cone_volume(np.zeros((0, 3))) == pytest.approx(1.0, abs=1e-12)
    assert T.cone_volume(np.zeros((3, 3))) == pytest.approx(1.0, abs=1e-12)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(rows3, rows3)
def test_symmetry_identity(a1, a2):
    # closed form: V(a1, a2) + V(a1, -a2) = V(a1) = box / 2 (centred box)
    a1, a2 = np.array(a1), np.array(a2)
    box = T.Box(0.6, 2.2, 1.6)
    v = T.cone_volume(np.array([a1, a2]), box) + T.cone_volume(np.array([a1, -a2]), box)
    assert v == pytest.approx(box.volume / 2, abs=1e-12)


# ------------------------------------------------------------ independent methods

def _qhull_volume(rows, box):
    """Independent: scipy's half-space intersection (qhull) and hull volume:
    (volume, inradius). For slivers (inradius below 1e-6) qhull cannot place
    an interior point: (None, inradius)."""
    from scipy.optimize import linprog
    from scipy.spatial import ConvexHull, HalfspaceIntersection
    lo, hi = box.lo, box.hi
    # halfspaces as A x + b <= 0
    A = [-r for r in rows] + [np.eye(3)[j] for j in range(3)] + [-np.eye(3)[j] for j in range(3)]
    b = [0.0] * len(rows) + list(-hi) + list(lo)
    A, b = np.array(A, dtype=float), np.array(b)
    norm = np.linalg.norm(A, axis=1)
    # Chebyshev centre: max t s.t. A x + t |A_i| <= -b
    res = linprog(np.r_[0, 0, 0, -1.0], A_ub=np.c_[A, norm], b_ub=-b,
                  bounds=[(None, None)] * 3 + [(0, None)])
    if not res.success:
        return 0.0, 0.0      # empty (infeasible LP)
    if res.x[3] < 1e-6:
        return None, res.x[3]   # too thin for qhull: only the inradius is known
    hs = HalfspaceIntersection(np.c_[A, b], res.x[:3])
    return ConvexHull(hs.intersections).volume, res.x[3]


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.lists(rows3, min_size=1, max_size=6),
       st.tuples(st.floats(-0.4, 0.4), st.floats(-0.4, 0.4), st.floats(-0.4, 0.4)))
def test_exact_matches_qhull(rows, centre):
    pytest.importorskip("scipy")
    rows = np.array(rows)
    box = T.Box(1.0, 0.7, 1.6, centre=centre)
    v = T.cone_volume(rows, box)
    ref_v, r_in = _qhull_volume(rows, box)
    if ref_v is not None:
        assert v == pytest.approx(ref_v, abs=1e-9)
    else:
        # a convex body of inradius r has V = int_0^r S(K_-t) dt <= r S(K) <= r S(box)
        # (inner parallel bodies; surface area is monotone on convex sets); the
        # LP's radius is good to its tolerance (1e-8 allowed)
        s_box = 2 * (1.0 * 0.7 + 1.0 * 1.6 + 0.7 * 1.6)
        assert 0.0 <= v <= (r_in + 1e-8) * s_box


def test_exact_matches_sliver_closed_form():
    """The wedge -1e-7 y <= x <= 0 (rows (1, 1e-7, 0), (-1, 0, 0); Hypothesis'
    case where qhull cannot help): V = 1e-7 * (0.35^2 / 2) * 1.6 = 9.8e-9 in the
    centred 1 x 0.7 x 1.6 box (the wedge exists for y > 0 only)."""
    box = T.Box(1.0, 0.7, 1.6)
    v = T.cone_volume(np.array([[1.0, 1e-7, 0.0], [-1.0, 0.0, 0.0]]), box)
    assert v == pytest.approx(1e-7 * 0.35**2 / 2 * 1.6, rel=1e-9)


def test_qmc_1e7_points_within_its_error():
    # Independent: randomised QMC, 16 Cranley-Patterson shifts x 625000 Sobol
    # points = 10^7 points; error estimate = sample sd over the shifts / 4.
    # Agreement within 5 standard errors (t, 15 dof: P(|t| > 5) < 2e-4).
    rng = np.random.default_rng(3)
    phi, theta = rng.uniform(0, 1.4, 3), rng.uniform(0.3, 2.9, 3)
    rows = T.paper_rows(phi, theta)
    exact, _ = T.cone_volumes(rows)
    vq, err = T.cone_volumes(rows, method="qmc", qmc_points=625000, qmc_shifts=16, seed=11)
    assert np.all(err > 0) and np.all(err < 3e-5)
    assert np.all(np.abs(vq - exact) <= 5 * err)


def test_grid_converges_to_exact():
    # The paper's grid: the error must stay within the geometric bound
    # m * 2 * S * diag (see test_cone.c) and shrink at least like 1/n
    # (median over 40 random cones).
    rng = np.random.default_rng(5)
    rows = T.paper_rows(rng.uniform(0, 1.5, 40), rng.uniform(0.2, 3.0, 40))
    exact, _ = T.cone_volumes(rows)
    d = np.array([EQ13.dVx, EQ13.dVy, EQ13.dwz])
    S = math.sqrt((d[0] * d[1]) ** 2 + (d[1] * d[2]) ** 2 + (d[2] * d[0]) ** 2)
    med = {}
    for n in (16, 64, 256):
        vg, _ = T.cone_volumes(rows, method="grid", grid_n=n)
        err = np.abs(vg - exact)
        assert np.all(err <= 2 * 2 * S * np.linalg.norm(d) / n)
        med[n] = np.median(err)
    assert med[64] < med[16] / 4
    assert med[256] < med[64] / 4


# ------------------------------------------------------------ rows

def test_paper_rows_are_eqs_10_11():
    # Eqs. 10-11 written out in NumPy
    phi, theta = np.array([0.1, 0.7, 1.2]), np.array([1.5, 2.0, 1.3])
    r = T.paper_rows(phi, theta)
    p = theta - phi
    np.testing.assert_allclose(r[:, 0], np.c_[np.sin(phi), np.cos(phi), -(1 - np.sin(phi)) / 2],
                               atol=1e-15)
    np.testing.assert_allclose(r[:, 1], np.c_[-np.sin(p), np.cos(p), -(1 - np.sin(p)) / 2],
                               atol=1e-15)


@pytest.mark.parametrize("phi_deg,theta_deg", [(10, 60), (30, 90), (45, 100), (70, 120)])
def test_compare_rows_derivation(phi_deg, theta_deg):
    # derived by hand (see compare_rows): same translational parts, wz
    # coefficients -(cos phi - sin phi)/2 and +(cos psi - sin psi)/2
    phi, theta = math.radians(phi_deg), math.radians(theta_deg)
    psi = theta - phi
    paper, derived = T.compare_rows(phi, theta)
    assert derived.shape == (2, 3)
    np.testing.assert_allclose(derived[:, :2], paper[:, :2], atol=1e-15)
    assert derived[0, 2] == pytest.approx(-(math.cos(phi) - math.sin(phi)) / 2, abs=1e-15)
    assert derived[1, 2] == pytest.approx((math.cos(psi) - math.sin(psi)) / 2, abs=1e-15)


def test_contact_rows_and_vectorised_volumes_agree():
    prob = T.ToolProblem(phi=np.radians([5, 20, 40]),
                         shapes=(T.UNIT_SQUARE, T.rectangle(1.2, 0.6), T.regular_polygon(5)))
    tools = [T.Tool(theta=1.2), T.Tool(theta=2.1, alpha1=0.3)]
    v = T.tool_volumes(prob, tools)
    assert v.shape == (2, 3, 3)
    for i, t in enumerate(tools):
        for s in range(3):
            for k, phi in enumerate(prob.phi):
                r = T.tool_rows(prob, t, phi, shape=s)
                assert v[i, s, k] == pytest.approx(T.cone_volume(r), abs=1e-15)


def test_plunger_row():
    # by hand: square wedged in the square corner, centre (-1/2, 1/2); a
    # plunger at x = -0.25 touches (-0.25, 1): r = (0.25, 0.5), n = (0, -1)
    r = T.tool_rows(T.ToolProblem(phi=[0.0]), T.Tool(theta=math.pi / 2, s=-0.25), 0.0)
    np.testing.assert_allclose(r[-1], [0, -1, -0.25], atol=1e-15)


# ------------------------------------------------------------ friction

def test_friction_mu_zero_is_frictionless():
    pts = np.array([[0.3, -0.5], [-0.2, 0.4]])
    nrm = np.array([[0.6, 0.8], [0.0, -1.0]])
    rows0 = T.permitted_rows(pts, nrm, mu=0.0)
    rowsf = T.permitted_rows(pts, nrm, mu=1e-300)
    assert rowsf.shape == (4, 3)
    assert T.cone_volume(rowsf) == pytest.approx(T.cone_volume(rows0), abs=1e-15)
    prob0 = T.ToolProblem(phi=np.radians([3, 17, 44]))
    probf = T.ToolProblem(phi=np.radians([3, 17, 44]), mu=1e-300)
    assert T.objective(probf, T.Tool(1.9)) == pytest.approx(T.objective(prob0, T.Tool(1.9)),
                                                            abs=1e-14)


@pytest.mark.parametrize("mu", [0.2, 1.0, 50.0, 1e6])
def test_friction_closed_form_and_pinning(mu):
    # closed form: contact at r = 0, n = (0, 1): Vy >= mu |Vx| (the wedge
    # above); mu -> infinity pins the contact point: volume b^2/mu 2c -> 0
    a, b, c = 0.4, 0.7, 1.3
    box = T.Box(2 * a, 2 * b, 2 * c)
    rows = T.permitted_rows([[0.0, 0.0]], [[0.0, 1.0]], mu)
    area = 2 * a * b - mu * a * a if mu * a <= b else b * b / mu
    assert T.cone_volume(rows, box) == pytest.approx(area * 2 * c, abs=1e-12)


def test_friction_offset_contact_against_qmc():
    # independent: QMC for a contact off the reference point, mu = 0.7
    rows = T.permitted_rows([[0.3, -0.5]], [[0.0, 1.0]], 0.7)
    v = T.cone_volume(rows)
    vq, err = T.cone_volumes(rows, method="qmc", qmc_points=1 << 17, qmc_shifts=16, seed=2)
    assert abs(vq[0] - v) <= 5 * err[0]
    assert v < 0.5  # friction removes twists from the frictionless half-space


def test_push_into_corner_is_held():
    # by hand: -P = (-1, 1, 0) is 1/2 the sum of the four corner contact
    # wrenches, so P . x <= 0 on the cone: only a null set stays
    pts = [[-0.5, -0.5], [0.5, -0.5], [0.5, -0.5], [0.5, 0.5]]
    nrm = [[0, 1], [0, 1], [-1, 0], [-1, 0]]
    assert T.cone_volume(T.permitted_rows(pts, nrm, push=[1, -1, 0])) == pytest.approx(0, abs=1e-12)
    assert T.cone_volume(T.permitted_rows(pts, nrm, mu=0.5, push=[1, -1, 0])) == \
        pytest.approx(0, abs=1e-12)
    assert T.cone_volume(T.permitted_rows(pts, nrm, push=[-1, -1, 0])) > 1e-3
    prob = T.ToolProblem(phi=[0.0], push=(1, -1, 0))
    assert T.objective(prob, T.Tool(math.pi / 2)) == pytest.approx(0, abs=1e-12)


# ------------------------------------------------------------ optimisation

def test_optimise_theta_matches_dense_numpy_scan():
    # independent: brute force over 3001 theta values
    prob = T.ToolProblem(phi=T.phi_set(0, 45, 5.0), model="paper")
    res = T.optimise_theta(prob, n_scan=37)
    th = np.linspace(math.radians(1), math.radians(179), 3001)
    f = T.theta_curve(prob, th)
    assert res.bracketed
    assert res.objective <= f.min() + 1e-12
    assert abs(res.theta - th[f.argmin()]) <= th[1] - th[0]
    assert np.all(res.objective <= res.scan_objective + 1e-15)


def test_optimise_theta_rejects_unresolvable_angles():
    """Angles beyond 1e6 rad leave no resolution for theta in alpha2 =
    alpha1 + theta (the fuzzer's alpha1 = -8.3e128 lost theta entirely): a
    ValueError naming the parameter and the range, not a wrong optimum."""
    prob = T.ToolProblem(phi=T.phi_set(0, 45, 15.0), model="paper")
    with pytest.raises(ValueError, match=r"alpha1.*1e\+06"):
        T.optimise_theta(prob, n_scan=5, alpha1=-8.3e128)
    with pytest.raises(ValueError, match=r"theta_hi.*1e\+06"):
        T.optimise_theta(prob, theta_range=(0.5, 2e6), n_scan=5)
    res = T.optimise_theta(prob, n_scan=5, alpha1=2.0 * math.pi * 1000)   # within the bound
    assert math.radians(1) <= res.theta <= math.radians(179)


def test_multimin_one_parameter_matches_brent():
    prob = T.ToolProblem(phi=T.phi_set(0, 45, 5.0), model="paper")
    res = T.optimise_theta(prob)
    r = T.optimise_tool(prob, T.Tool(theta=res.theta + 0.05), free=("alpha2",), step=(0.1,) * 3,
                        size_tol=1e-10)
    assert r.objective == pytest.approx(res.objective, abs=1e-9)
    assert r.tool.alpha1 == 0.0


def test_multimin_more_parameters_not_worse():
    shapes = (T.UNIT_SQUARE, T.rectangle(1.2, 0.6))
    prob = T.ToolProblem(phi=T.phi_set(0, 60, 10.0), shapes=shapes)
    base = T.optimise_theta(prob)
    r = T.optimise_tool(prob, T.Tool(theta=base.theta), free=("alpha1", "alpha2"))
    assert r.objective <= base.objective + 1e-12
    assert T.objective(prob, r.tool) == pytest.approx(r.objective, abs=1e-12)


def test_rotating_tool_and_phi_together_is_invariant():
    # geometry: rotating the tool by alpha1 and every object by alpha1 leaves
    # the contacts (in the object frame) unchanged
    phi = np.radians([10, 25, 40])
    a = 0.37
    v1 = T.objective(T.ToolProblem(phi=phi), T.Tool(theta=1.7))
    v2 = T.objective(T.ToolProblem(phi=phi + a), T.Tool(theta=1.7, alpha1=a))
    assert v2 == pytest.approx(v1, abs=1e-12)


# ------------------------------------------------------------ rod (Fig. 11)

def test_rod_rotation_closed_form():
    height, xr = 1.0, 0.25  # unit square: half-height b = 0.5
    pmax = T.rod_max_rotation(height, xr)
    assert pmax == pytest.approx(math.radians(30), abs=1e-15)  # asin(rod_x / b) = asin(1/2)
    psi, d, u = T.rod_rotation(0.99 * pmax, 1.0, height, xr, steps=4000)
    np.testing.assert_allclose(d, T.rod_descent_closed_form(psi, height, xr), atol=1e-9)
    # initial rate: dpsi/dd = 1/rod_x (lever arm of the rod about the grasp);
    # the forward difference over one step h errs by ~ h b / (2 rod_x) ~ 1.3e-4
    assert (psi[1] - psi[0]) / (d[1] - d[0]) == pytest.approx(1 / xr, rel=1e-3)
    assert u[0] == pytest.approx(xr) and abs(u[-1]) < 0.05 * xr


def test_rod_alone_is_half_the_box():
    # one contact: a half-space through the centre (paper: the rod does not
    # constrain the object fully)
    rows = T.contact_rows([[0.25, -0.5]], [[0.0, 1.0]])
    assert T.cone_volume(rows) == pytest.approx(0.5, abs=1e-12)


# ------------------------------------------------------------ errors

@pytest.mark.parametrize("call,exc,words", [
    (lambda: T.cone_volumes(np.zeros((1, 2, 4))), ValueError, "rows"),
    (lambda: T.cone_volumes("abc"), TypeError, "rows"),
    (lambda: T.cone_volumes(np.eye(3), method="mc"), ValueError, "method"),
    (lambda: T.cone_volumes(np.eye(3), method="grid", grid_n=0), ValueError, "grid_n"),
    (lambda: T.cone_volumes(np.eye(3), method="grid", grid_n=2.5), TypeError, "grid_n"),
    (lambda: T.cone_volumes(np.eye(3), method="qmc", qmc_shifts=0), ValueError, "qmc_shifts"),
    (lambda: T.cone_volumes(np.zeros((1, 200, 3))), ValueError, "136"),
    (lambda: T.cone_volumes([[np.nan, 0, 0]]), ValueError, "finite"),
    (lambda: T.Box(dVx=0), ValueError, "dVx"),
    (lambda: T.Box(dwz="2"), TypeError, "dwz"),
    (lambda: T.ToolProblem(phi=[]), ValueError, "phi"),
    (lambda: T.ToolProblem(phi=[0.1], mu=-1), ValueError, "mu"),
    (lambda: T.ToolProblem(phi=[0.1], shapes=(np.zeros((2, 2)),)), ValueError, "shapes[0]"),
    (lambda: T.ToolProblem(phi=[0.1], shapes=(np.zeros((4, 2)),)), ValueError, "area"),
    (lambda: T.ToolProblem(phi=[0.1], model="exact"), ValueError, "model"),
    (lambda: T.contact_rows([[0, 0]], [[0, 2.0]]), ValueError, "unit"),
    (lambda: T.contact_rows([[0, 0]], [[0, 1.0]], mu=-0.1), ValueError, "mu"),
    (lambda: T.optimise_theta(T.ToolProblem(phi=[0.1]), theta_range=(2, 1)), ValueError,
     "theta_range"),
    (lambda: T.optimise_tool(T.ToolProblem(phi=[0.1]), T.Tool(), free=("s",)), ValueError, "s"),
    (lambda: T.rod_rotation(1.0), ValueError, "psi_end"),
    (lambda: T.regular_polygon(2), ValueError, "n"),
])
def test_bad_input_names_parameter(call, exc, words):
    with pytest.raises(exc, match=None) as info:
        call()
    assert words in str(info.value)


def test_c_module_messages_name_parameter_and_range():
    from exdex import _tool
    with pytest.raises(ValueError, match=r"grid_n must be in \[1, 100000\]"):
        _tool.volumes(np.zeros((1, 1, 3)), EQ13.lo, EQ13.hi, "grid", grid_n=10 ** 6)
    with pytest.raises(ValueError, match="hi must exceed lo"):
        _tool.volumes(np.zeros((1, 1, 3)), EQ13.hi, EQ13.lo)
    with pytest.raises(TypeError, match="mu must be a real number"):
        _tool.contact_rows([[0, 0]], [[0, 1]], mu="a")


# ------------------------------------------------------------ command line


def test_tool_figures_label_every_axis_with_units():
    """Every axis of the ``exdex tool`` figures names its unit in brackets
    (cone volumes in (m/s)^2 rad/s, angles in deg, box sides in m/s)."""
    import matplotlib.pyplot as plt

    study = T.theta_study(ranges={"0-90": (0, 90)}, n_scan=7, step_deg=15.0, progress=False)
    sweep = [dict(a=a, model=m, theta_star_deg=100.0) for a in (0.5, 1.0) for m in ("paper", "contact")]
    psi = np.linspace(0, 0.5, 200)
    figs = [T.figure_theta_curves(study), T.figure_box_aspect(sweep),
            T.figure_rod(psi * 0.1, psi, psi * 0.1, 1.0, 0.25)]
    unit = re.compile(r"\[[^\]]+\]")
    for fig in figs:
        for ax in fig.axes:
            assert unit.search(ax.get_xlabel()), ax.get_xlabel()
            if ax.get_ylabel() or ax is fig.axes[0]:
                assert unit.search(ax.get_ylabel()), ax.get_ylabel()
    assert "(m/s)$^2$ rad/s" in figs[0].axes[0].get_ylabel()
    assert "[m/s]" in figs[1].axes[0].get_xlabel()
    plt.close("all")
