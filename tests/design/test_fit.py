"""exdex.sensitivity and exdex.identify against closed forms and synthetic logs.

The Fig. 3 closed form (exdex.paper.fig3_grip_force's derivation) gives the
final slip s = -u tau^2 D / (2 (D - u)) with u = g + |a_L| - c and
c = mu * 2 F / m, so
    ds/dF = ds/du du/dF = [-tau^2 D^2 / (2 (D - u)^2)] [-2 mu / m]
          = tau^2 D^2 mu / (m (D - u)^2),
and the same with mu and F exchanged for ds/dmu.
"""
import dataclasses

import numpy as np
import pytest

import exdex
from exdex import paper


def fig3(**grasp):
    s = paper.fig3_scene()
    return dataclasses.replace(s, grasp=dataclasses.replace(s.grasp, **grasp)) if grasp else s


def ds_dF_closed(F, mu):
    a_h, a_l = paper.eq7_accelerations(0.1, 0.5, 0.9)
    a_l = abs(a_l)
    c = mu * 2 * F / paper.MASS
    u = paper.G + a_l - c
    D = a_h + a_l
    tau = 0.1
    return tau**2 * D**2 * mu / (paper.MASS * (D - u) ** 2)


@pytest.mark.parametrize("method", ["auto", "event"])
@pytest.mark.parametrize("F", [1.3, 1.50514, 1.7])
def test_sensitivity_matches_closed_form(method, F):
    s = exdex.sensitivity(fig3(grip_force=F), ["grip_force", "mu"], t_end=1.5, method=method)
    # d(final slip)/dF and /dmu: the slip is -s in the coordinate (downward)
    assert s["grip_force"][0] == pytest.approx(ds_dF_closed(F, 0.5), rel=1e-7)
    assert s["mu"][0] == pytest.approx(ds_dF_closed(F, 0.5) * F / 0.5, rel=1e-7)
    # the error estimate is honest: within it of the closed form (and small)
    assert abs(s["grip_force"][0] - ds_dF_closed(F, 0.5)) <= max(10 * s.error[0, 0], 1e-9 * abs(s.dq[0, 0]))
    assert s.error[0, 0] <= 1e-6 * abs(s.dq[0, 0])


def test_sensitivity_of_a_stuck_object_is_zero():
    """With a grip that holds through the whole motion (capacity above
    g + |a_L|), nothing moves, for any nearby grip: the derivative is 0."""
    s = exdex.sensitivity(fig3(grip_force=3.0), ["grip_force"], t_end=1.5)
    assert s.dq[0, 0] == 0.0 and s.dv[0, 0] == 0.0


def synthetic_log(mu, sigma, seed, n=151):
    scene = fig3(mu=mu)
    t = np.linspace(0.0, 1.5, n)
    r = exdex.simulate(scene, 1.5, 0.01, method="analytic")
    rng = np.random.default_rng(seed)
    return t, r.q[:, 0] + rng.normal(0.0, sigma, n)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_identify_recovers_mu_within_its_interval(seed):
    """Synthetic tracker log (0.1 mm noise, 151 samples) of Fig. 3 with
    mu = 0.46; fit mu from the start 0.5: the truth lies within 3 standard
    errors and the reported sigma matches the noise."""
    t, y = synthetic_log(0.46, 1e-4, seed)
    fit = exdex.identify(fig3(), t, y, {"mu": (0.3, 0.7)})
    assert fit.success and fit.identifiable
    assert abs(fit.values["mu"] - 0.46) <= 3 * fit.stderr["mu"]
    assert 0 < fit.stderr["mu"] < 0.01
    assert fit.sigma == pytest.approx(1e-4, rel=0.3)
    lo, hi = fit.interval["mu"]
    assert lo < fit.values["mu"] < hi
    assert "mu" in fit.report()


def test_identify_reports_what_the_data_cannot_fix():
    """mu and the grip force enter only as the capacity mu * 2 F: a log fixes
    the product and never both; the fit says so and gives no finite interval."""
    t, y = synthetic_log(0.46, 1e-4, 5)
    fit = exdex.identify(fig3(), t, y, {"mu": (0.3, 0.7), "grip_force": (1.0, 2.5)})
    assert not fit.identifiable
    comb, _ = fit.unidentifiable[0]
    assert abs(comb["mu"]) > 0.1 and abs(comb["grip_force"]) > 0.1
    assert np.isinf(fit.stderr["mu"]) and np.isinf(fit.stderr["grip_force"])
    # the capacity it found is the true one
    cap = fit.values["mu"] * fit.values["grip_force"]
    assert cap == pytest.approx(0.46 * paper.fig3_grip_force(), rel=1e-3)
    assert "not identifiable" in fit.report()


@pytest.mark.parametrize("kw, match", [
    (dict(times=[0.0]), "times"),
    (dict(observed=np.zeros((3, 2))), "observed must have shape"),
    (dict(params={"colour": None}), "cannot vary"),
    (dict(params={"mu": (0.6, 0.7)}), "start"),
])
def test_identify_bad_input(kw, match):
    args = dict(times=[0.0, 0.5, 1.0], observed=[0.0, 0.0, 0.0], params={"mu": (0.3, 0.7)})
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        exdex.identify(fig3(), args["times"], args["observed"], args["params"])


# ------------------------------------------------------------- event times

def stop_closed(F, mu):
    """End of the Fig. 3 slip: it starts at t1 = beta T = 0.45 s (the switch
    to a_L, when the drive first exceeds the capacity), grows at u = g +
    |a_L| - c until t2 = (2 - beta) T = 0.55 s (tau = 0.1 s), then decays at
    D - u (D = a_H + |a_L|): t_stop = t2 + u tau / (D - u), and
    d t_stop / dF = tau D / (D - u)^2 du/dF = -2 mu tau D / (m (D - u)^2)."""
    a_h, a_l = paper.eq7_accelerations(0.1, 0.5, 0.9)
    a_l = abs(a_l)
    c = mu * 2 * F / paper.MASS
    u = paper.G + a_l - c
    D = a_h + a_l
    tau = 0.1
    return 0.55 + u * tau / (D - u), -2 * mu * tau * D / (paper.MASS * (D - u) ** 2)


@pytest.mark.parametrize("method", ["auto", "event"])
def test_event_times_and_their_sensitivities_match_closed_forms(method):
    """Onset at the Eq. 7 switch beta T: d onset / dF = 0, d onset / d beta
    = T = 0.5 s exactly; the stop time and d stop / dF from stop_closed."""
    F, mu = 1.5, 0.5
    sc = fig3(grip_force=F, mu=mu)
    t_stop, dstop_dF = stop_closed(F, mu)
    e = exdex.design.fit.event_times(sc, 1.5, method=method)
    assert e.onset == pytest.approx(0.45, abs=1e-12)
    assert e.stop == pytest.approx(t_stop, abs=1e-12)
    s = exdex.design.fit.event_sensitivity(sc, ["grip_force", "beta"], 1.5, method=method)
    assert s.donset[0] == pytest.approx(0.0, abs=1e-6) and s.donset[1] == pytest.approx(0.5, abs=1e-6)
    assert s.dstop[0] == pytest.approx(dstop_dF, rel=1e-6)
    assert abs(s.dstop[0] - dstop_dF) <= max(10 * s.stop_error[0], 1e-8)


def test_event_times_of_a_held_object_and_of_one_still_moving():
    held = fig3(grip_force=3.0)   # capacity above every drive: no slip
    e = exdex.design.fit.event_times(held, 1.5)
    assert np.isnan(e.onset) and np.isnan(e.stop)
    e = exdex.design.fit.event_times(fig3(grip_force=1.5), 0.5)   # t_end inside the slip (0.45 .. 0.59 s)
    assert e.onset == pytest.approx(0.45, abs=1e-12) and e.stop == np.inf
    with pytest.raises(ValueError, match="n_grid"):
        exdex.design.fit.event_times(held, 1.5, n_grid=1)


def test_exact_event_derivatives_match_closed_form_and_differences():
    """The forward-mode derivatives (exact=True) against the closed form of
    stop_closed (d stop / dF), T for d onset / d beta, and the Richardson
    differences (exact_if_possible=False) for every parameter, within their
    stated error."""
    F, mu = 1.5, 0.5
    sc = fig3(grip_force=F, mu=mu)
    names = ["grip_force", "mu", "mass", "beta", "duration", "amplitude"]
    ex = exdex.design.fit.event_sensitivity(sc, names, 1.5)
    fd = exdex.design.fit.event_sensitivity(sc, names, 1.5, exact_if_possible=False)
    assert ex.exact and not fd.exact and np.all(ex.stop_error == 0)
    assert ex.dstop[0] == pytest.approx(stop_closed(F, mu)[1], rel=1e-12)
    assert ex.donset[3] == pytest.approx(0.5, rel=1e-14)   # onset = beta T
    assert ex.donset[4] == pytest.approx(0.9, rel=1e-14)   # d (beta T) / dT = beta
    for i in range(len(names)):
        assert abs(ex.donset[i] - fd.donset[i]) <= 10 * fd.onset_error[i] + 1e-8
        assert abs(ex.dstop[i] - fd.dstop[i]) <= 10 * fd.stop_error[i] + 1e-8 * abs(ex.dstop[i])


def test_exact_event_derivatives_flag_a_threshold():
    """exdex.paper.fig6_scene sits 1e-9 above the stick threshold of the
    gentle phases (torque capacity = I_zz a_H (1 + 1e-9)): a slightly weaker
    grasp slips from t = 0, so the derivative is one-sided: the error is inf."""
    s = exdex.design.fit.event_sensitivity(paper.fig6_scene(), ["grip_force"], 8.0)
    assert s.exact and np.isinf(s.stop_error[0])


def _exact_planar(mu=0.5, grip=2.0):
    """A planar box on a 20 mm pad beside its centre of mass (inside the
    face) with the exact surface under the Fig. 3 motion (it slides and
    turns)."""
    return exdex.Scene(body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
                       grasp=exdex.Grasp(mu=mu, grip_force=grip, limit_surface="exact",
                                         pad=exdex.Pad.rectangle(0.02, 0.02, center=(0.008, 0.0))),
                       motion=paper.fig3_scene().motion, dof="planar")


def test_sensitivity_with_the_exact_surface_matches_central_differences():
    """d q(t_end) / d grip_force of the exact surface of pad & face against central
    differences of event runs at rtol 1e-12 (h = 1e-4 N: truncation ~ h^2
    q''' ~ 1e-8 relative), to 1e-4 relative."""
    sc, F, h = _exact_planar(), 2.0, 1e-4
    s = exdex.sensitivity(sc, ["grip_force"], t_end=1.5, method="event")
    qs = [exdex.simulate(dataclasses.replace(sc, grasp=dataclasses.replace(sc.grasp, grip_force=f)), 1.5, 1.5,
                         method="event", rtol=1e-12, atol=1e-14).q[-1] for f in (F - h, F + h)]
    fd = (qs[1] - qs[0]) / (2 * h)
    assert np.max(np.abs(fd)) > 1e-3
    np.testing.assert_allclose(s["grip_force"], fd, rtol=1e-4, atol=1e-4 * np.max(np.abs(fd)))


def test_identify_recovers_mu_with_the_exact_surface():
    """A synthetic log (0.1 mm noise on x, y; 151 samples) of the exact surface
    of pad & face with mu = 0.46: fitting mu from 0.5 finds it within 3 standard
    errors."""
    sc = _exact_planar(mu=0.46)
    t = np.linspace(0.0, 1.5, 151)
    r = exdex.simulate(sc, 1.5, 0.01, method="event", rtol=1e-12, atol=1e-14)
    rng = np.random.default_rng(7)
    y = r.q + rng.normal(0.0, 1e-4, r.q.shape) * np.array([1.0, 1.0, 0.0])
    fit = exdex.identify(_exact_planar(), t, y, {"mu": (0.3, 0.7)})
    assert fit.success and fit.identifiable
    assert abs(fit.values["mu"] - 0.46) <= 3 * fit.stderr["mu"]
    assert 0 < fit.stderr["mu"] < 0.01
