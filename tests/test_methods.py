"""The integration methods besides the implicit one (csrc/methods.c) through
the Python API: the paper cases against their closed forms (exdex.paper),
the regularised ODE against an independent stiff integrator (scipy Radau),
an event-driven closed form with a stick event, the explicit scheme's own
closed form and chatter, argument checks, and the numbers the C suite
reports (csrc/tests/test_methods.c) recomputed through Python."""
import math
import re

import numpy as np
import pytest

import exdex
from exdex import paper

G = 9.81
METHODS = ["implicit", "event", "regularised", "explicit"]


def vertical(mass, capacity, motion=exdex.Rest(), **kw):
    """1-DoF vertical scene, two fingers, mu 0.5: capacity [N] = grip force."""
    return exdex.Scene(body=exdex.Body(mass=mass), grasp=exdex.Grasp(mu=0.5, grip_force=capacity),
                       motion=motion, **kw)


FIG3 = vertical(0.1, 1.5, motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))


@pytest.mark.parametrize("method", METHODS)
def test_every_method_runs_the_paper_cases(method):
    for scene, t_end in [(paper.fig3_scene(), 1.5), (paper.fig4_scene(), 1.0), (paper.fig6_scene(), 7.0)]:
        r = exdex.simulate(scene, t_end, 1e-2, method=method)
        assert r.method == method
        assert r.q.shape == (151 if t_end == 1.5 else int(round(t_end / 1e-2)) + 1, 1)
        assert np.all(np.isfinite(r.q)) and np.all(np.isfinite(r.wrench))


def test_event_fig3_fig6_closed_forms():
    """exdex.paper.closed_form: exact 1-DoF Coulomb propagation, written
    independently of the C core. The event method matches it to rounding
    at a coarse output grid, and is exactly still after the rest time."""
    for scene, t_end, tol in [(paper.fig3_scene(), 1.5, 1e-12), (paper.fig6_scene(), 7.0, 1e-9)]:
        cf = paper.closed_form(scene)
        r = exdex.simulate(scene, t_end, 1e-2, method="event")
        assert r.q[-1, 0] - r.q[0, 0] == pytest.approx(cf.final, abs=tol)
        for i in range(0, len(r.t), 7):
            x, v = cf(r.t[i])
            assert r.q[i, 0] - r.q[0, 0] == pytest.approx(x, abs=tol)
            assert r.v[i, 0] == pytest.approx(v, abs=1e3 * tol)
        assert r.drift_after(cf.rest_time + 1e-9) == 0.0
        assert r.stick[r.t > cf.rest_time + 1e-9].all()


def test_event_fig4_stop_force(ref):
    """Fig. 4: while the plates slide past the object held by the stop, the
    stop carries m g + mu N (paper_fig4_stop_force, closed form)."""
    r = exdex.simulate(paper.fig4_scene(), 1.0, 1e-3, method="event")
    cruise = (r.t > 0.1) & (r.t < 0.4)
    assert r.stop_force[cruise, 0] == pytest.approx(ref["paper_fig4_stop_force"], abs=1e-9)
    assert r.q[-1, 0] - r.q[0, 0] == pytest.approx(0.05, abs=1e-12)
    assert r.stats["min_gap"] >= -1e-15


def test_event_inward_throw_in_a_spinning_gripper_sticks_at_the_closed_form():
    """Gripper spinning at w about its plate normal, the object thrown inward
    along a radial line with friction capacity c m: s'' = w^2 s + c until it
    stops at tanh(w t*) = -v0 / (w (s0 + c/w^2)), then sticks (w^2 s* < c).
    s(t) = -c/w^2 + (s0 + c/w^2) cosh(w t) + (v0/w) sinh(w t)."""
    w, s0, c, v0 = 2.0, 0.05, 0.3, -0.1
    scene = exdex.Scene(
        body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=c * 0.1),
        motion=exdex.TrapezoidalProfile(w * 5.0, 5.0, w, axis=(0, -1, 0), rotation=True),
        slide_axis=(1.0, 0.0), q0=(s0, 0.0, 0.0), v0=(v0, 0.0, 0.0), gravity=(0.0, 0.0, 0.0))
    A = s0 + c / w**2
    t_star = math.atanh(-v0 / (w * A)) / w
    s_star = -c / w**2 + A * math.cosh(w * t_star) + v0 / w * math.sinh(w * t_star)
    assert w**2 * s_star < c
    r = exdex.simulate(scene, 1.0, 1e-2, method="event")
    before = r.t < t_star
    exact = -c / w**2 + A * np.cosh(w * r.t[before]) + v0 / w * np.sinh(w * r.t[before])
    assert r.q[before, 0] == pytest.approx(exact, abs=1e-12)
    assert r.q[-1, 0] == pytest.approx(s_star, abs=1e-12)
    assert r.drift_after(t_star + 1e-9) == 0.0


def test_regularised_matches_an_independent_stiff_integrator():
    """The regularised Fig. 3 ODE written here and integrated by scipy's
    Radau (implicit, stiff) must agree with the C method (rk8pd): relative
    up-positive coordinate s, m s'' = -m (g + a_gripper) - C s'/sqrt(s'^2 + eps^2)."""
    solve_ivp = pytest.importorskip("scipy.integrate").solve_ivp
    eps, m, C = 1e-3, 0.1, 1.5
    aH, aL = 2 * 0.1 / (0.9 * 0.25), 2 * 0.1 / (0.1 * 0.25)
    # gripper acceleration, up positive (Eq. 7 downward first)
    phases = [(0.0, 0.45, -aH), (0.45, 0.55, aL), (0.55, 1.0, -aH), (1.0, 1.5, 0.0)]
    y = np.array([0.0, 0.0])
    for t0, t1, a in phases:
        sol = solve_ivp(lambda t, y: [y[1], -(G + a) - C / m * y[1] / math.sqrt(y[1] ** 2 + eps**2)],
                        (t0, t1), y, method="Radau", rtol=1e-12, atol=1e-14)
        y = sol.y[:, -1]
    r = exdex.simulate(FIG3, 1.5, 1e-2, method="regularised", eps=eps, rtol=1e-10, atol=1e-12)
    assert r.q[-1, 0] == pytest.approx(y[0], abs=1e-9)
    assert r.v[-1, 0] == pytest.approx(y[1], abs=1e-9)


def test_explicit_scheme_closed_form_and_chatter():
    """Symplectic Euler free fall: q_n = -g t (t + h)/2. At rest with a load
    inside the capacity the explicit Coulomb velocity never returns to 0 and
    stays in (h (Q - C)/M, h (Q + C)/M] (Q = -m g)."""
    h = 1e-3
    ff = exdex.simulate(exdex.replace(vertical(0.3, 1.0), grasp=exdex.Grasp(mu=0.0, grip_force=1.0)),
                        0.7, h, method="explicit")
    assert ff.q[-1, 0] == pytest.approx(-G * 0.7 * (0.7 + h) / 2, abs=1e-12)
    ratio = 2 + math.sqrt(5)
    r = exdex.simulate(vertical(0.1, ratio * 0.1 * G), 2.0, h, method="explicit")
    v = r.v[2:, 0]
    assert np.all(v != 0.0) and not r.stick[2:].any()
    assert v.min() > h * (-G - ratio * G) * (1 + 1e-9) and v.max() <= h * (-G + ratio * G) * (1 + 1e-9)
    # the implicit and event methods hold it exactly
    for method in ("implicit", "event"):
        s = exdex.simulate(vertical(0.1, ratio * 0.1 * G), 2.0, h, method=method)
        assert s.drift_after(0.0) == 0.0 and s.stick.all()


@pytest.mark.parametrize("method", ["event", "regularised", "explicit"])
def test_planar_scenes_with_stops_need_implicit(method):
    scene = exdex.replace(paper.fig4_scene(), dof="planar")
    with pytest.raises(ValueError, match="stops in planar scenes need 'implicit'"):
        exdex.simulate(scene, 0.1, 1e-3, method=method)
    exdex.simulate(scene, 0.01, 1e-3, method="implicit")


def test_event_zeno_like_toggling_raises_solver_error():
    """A 1 kHz vertical vibration with acceleration amplitude 2 g and
    capacity 1.5 m g crosses the friction limit 2000 times in 1 s: with one
    output interval the event method stops at 1000 events."""
    f = 1000.0
    wf = 2 * math.pi * f
    t = np.arange(int(40 * f) + 1) / (40 * f)
    pos = np.zeros((len(t), 3))
    pos[:, 2] = 2 * G / wf**2 * np.sin(wf * t)
    # R_AB of the default scene (B y up): a quarter turn about A x
    quat = np.tile([math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0], (len(t), 1))
    motion = exdex.SampledTrajectory(times=t, positions=pos, quaternions=quat)
    scene = vertical(0.1, 1.5 * 0.1 * G, motion=motion)
    with pytest.raises(exdex.SolverError):
        exdex.simulate(scene, 1.0, 1.0, method="event")


# --- numbers reported by csrc/tests/test_methods.c, recomputed via Python ---

def _c_values(stdout):
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^VALUE (\S+) (\S+)$", stdout, re.M)}


PYTHON_SIDE = {
    "methods_event_fig3_final_dt1e-2": lambda: exdex.simulate(FIG3, 1.5, 1e-2, method="event").q[-1, 0],
    "methods_reg_slide_1s_eps1e-4": lambda: exdex.simulate(
        vertical(0.2, 0.6 * 0.2 * G), 1.0, 1e-3, method="regularised", eps=1e-4).q[-1, 0],
    "methods_reg_planar_creep_thd": lambda: exdex.simulate(
        exdex.Scene(body=exdex.Body(mass=0.1, inertia=((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1e-3))),
                    grasp=exdex.Grasp(mu=0.5, grip_force=2.0 * 0.1 * G,
                                      patch=exdex.Patch(e_r=0.02, center=(0.004, 0.0))),
                    dof="planar"),
        0.01, 1e-3, method="regularised", eps=1e-4).v[-1, 2],
}


@pytest.mark.parametrize("key", sorted(PYTHON_SIDE))
def test_c_method_numbers_through_python(c_suite, key):
    values = _c_values(c_suite[1])
    assert key in values, f"the C suite no longer reports {key}"
    assert PYTHON_SIDE[key]() == pytest.approx(values[key], rel=1e-12, abs=1e-15)


def test_c_method_tests_pass(c_suite):
    out = c_suite[1]
    names = re.findall(r"^(ok|FAIL) +(methods_\S+)", out, re.M)
    assert len(names) >= 15
    assert all(s == "ok" for s, _ in names), [n for s, n in names if s != "ok"]
