"""The physics has no length, time or mass of its own, and neither may the
numerics: every threshold of the core is a fixed fraction of the scene's own
length, time and force scales (csrc/model.c, model_scales / model_tols).

Scaling laws (derivation). Scale every length by lam, every time by tau and
every mass by mu. Newton's law m a = F with the friction law (a force
mu_c N in the direction of the slip) and unilateral stops is invariant when
    lengths x lam, times x tau, masses x mu,
    velocities x lam/tau (angular: 1/tau), accelerations (gravity) x lam/tau^2,
    forces (grip force, friction, stop forces) x mu lam/tau^2,
    torques x mu lam^2/tau^2, inertia x mu lam^2,
    angles, mu_c, stick flags and counts unchanged;
the friction ellipsoid's e_r is a length (x lam). The numerics scale with it:
the output step dt and t_end are times (x tau), the regularised method's eps
is a slip speed (x lam/tau), rtol and atol are relative (unchanged: the
core applies atol to each state component times that component's own
scale). Then every output scales by
its law: t x tau; q x lam (translation, planar x, y) or unchanged (angles);
v x lam/tau or 1/tau; wrench (f_x, f_y) x mu lam/tau^2, m_z x mu lam^2/tau^2;
stop forces x mu lam/tau^2; stick flags identical; stats.min_gap x lam.

The check: for each scene and method the scaled run's outputs divided by
their factors equal the reference run's to 1e-12 of each array's largest
magnitude (power-of-two factors of lengths and times scale every operation
exactly), and the stick flags are identical; see the test for factors that
change the rounding. Scenes: fixed ones (the
paper's Fig. 3 translation, a planar box on a tilted stop in a turning
gripper, a rotation against a floor) and seeded random valid scenes with
0-2 stops in all three kinds of freedom.
"""
import math

import numpy as np
import pytest

import exdex

FACTORS = [  # (lam, tau, mu)
    (4.0, 1.0, 1.0),
    (1.0 / 1024, 1.0, 1.0),
    (1e-3, 1.0, 1.0),
    (1.0, 2.0, 1.0),
    (1.0, 1.0, 2.0),
    (0.25, 2.0, 2.0),
]
METHODS = ["implicit", "event", "regularised", "explicit", "analytic"]


def box_params(mass, lx, ly, lz=0.02):
    I = mass / 12.0 * np.diag([ly**2 + lz**2, lx**2 + lz**2, lx**2 + ly**2])
    hx, hy = lx / 2, ly / 2
    return dict(mass=mass, inertia=I, outline=[(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)])


def build(p, lam=1.0, tau=1.0, mu=1.0):
    """The scene of parameter set p with lengths x lam, times x tau, masses x mu."""
    acc = lam / tau**2
    force = mu * lam / tau**2
    body = exdex.Body(mass=p["mass"] * mu, inertia=np.asarray(p["inertia"]) * mu * lam**2,
                      outline=tuple((x * lam, y * lam) for x, y in p["outline"]))
    patch = exdex.Patch(e_r=p["e_r"] * lam, center=tuple(c * lam for c in p["pc"]))
    grasp = exdex.Grasp(mu=p["mu"], grip_force=p["grip"] * force, patch=patch)
    m = p["motion"]
    rot = m.get("rotation", False)
    if m["kind"] == "rest":
        motion = exdex.Rest()
    elif m["kind"] == "asym":
        motion = exdex.AsymmetricProfile(m["amp"] * (1.0 if rot else lam), m["T"] * tau, m["beta"],
                                         axis=m["axis"], rotation=rot,
                                         center=tuple(c * lam for c in m.get("center", (0, 0, 0))))
    else:
        motion = exdex.TrapezoidalProfile(m["amp"] * (1.0 if rot else lam), m["T"] * tau,
                                          m["vmax"] * (1.0 if rot else lam) / tau, axis=m["axis"], rotation=rot,
                                          center=tuple(c * lam for c in m.get("center", (0, 0, 0))))
    stops = tuple(exdex.Stop(point=tuple(c * lam for c in s[0]), normal=s[1]) for s in p["stops"])
    q0 = (p["q0"][0] * lam, p["q0"][1] * lam, p["q0"][2])
    v0 = (p["v0"][0] * lam / tau, p["v0"][1] * lam / tau, p["v0"][2] / tau)
    return exdex.Scene(body=body, grasp=grasp, motion=motion, dof=p["dof"], slide_axis=p.get("slide", (0.0, 1.0)),
                       q0=q0, v0=v0, gravity=tuple(g * acc for g in p["g"]),
                       gripper_position=tuple(c * lam for c in p.get("p0", (0, 0, 0))), stops=stops)


def fixed_params():
    out = []
    fig3 = dict(box_params(0.1, 0.03, 0.06), e_r=0.0067, pc=(0.0, 0.0), mu=0.5, grip=1.5, dof="translation",
                g=(0, 0, -9.81), q0=(0, 0, 0), v0=(0, 0, 0), stops=[],
                motion=dict(kind="asym", amp=0.1, T=0.5, beta=0.9, axis=(0, 0, -1)))
    out.append(("fig3", fig3))
    a = math.radians(10)
    planar = dict(box_params(0.1, 0.02, 0.04), e_r=0.0089, pc=(0.004, 0.0), mu=0.5, grip=0.6, dof="planar",
                  g=(0, 0, -9.81), q0=(0, 0, 0), v0=(0, 0, 0),
                  stops=[((0, 0, -0.03), (math.sin(a), 0, math.cos(a)))],
                  motion=dict(kind="asym", amp=0.6, T=0.5, beta=0.7, axis=(0, -1, 0), rotation=True))
    out.append(("planar_stop", planar))
    rot = dict(box_params(0.2, 0.05, 0.03), e_r=0.004, pc=(0.01, 0.005), mu=0.4, grip=1.0, dof="rotation",
               g=(0, 0, -9.81), q0=(0, 0, 0), v0=(0, 0, 0), stops=[((0, 0, -0.03), (0, 0, 1))],
               motion=dict(kind="trap", amp=0.05, T=0.4, vmax=0.05 / 0.4 * 1.5, axis=(0, 0, 1)))
    out.append(("rotation_floor", rot))
    return out


def random_params(seed):
    """A valid scene a user could write: box 1-8 cm, patch off the centre,
    grip 0.5-3x the weight, rest / Eq. 7 / trapezoid along or about an
    arbitrary axis, 0-2 stops touching or near the outline."""
    rng = np.random.default_rng(seed)
    dof = ["translation", "rotation", "planar"][seed % 3]
    mass = float(rng.uniform(0.02, 0.5))
    lx, ly = (float(x) for x in rng.uniform(0.01, 0.08, 2))
    p = box_params(mass, lx, ly)
    p.update(e_r=float(rng.uniform(0.002, 0.01)), pc=tuple(float(x) for x in rng.uniform(-0.3, 0.3, 2) * (lx, ly)),
             mu=float(rng.uniform(0.2, 0.8)), grip=float(mass * 9.81 * rng.uniform(0.5, 3.0)), dof=dof,
             g=(0, 0, -9.81), q0=(0, 0, 0), v0=(0, 0, 0))
    ax = rng.normal(size=3)
    ax = tuple(float(x) for x in ax / np.linalg.norm(ax))
    kind = seed // 3 % 3
    if kind == 0:
        p["motion"] = dict(kind="rest")
        p["v0"] = tuple(float(x) for x in rng.normal(size=3) * (0.05, 0.05, 0.5))
    elif kind == 1:
        rot = bool(rng.integers(2))
        p["motion"] = dict(kind="asym", amp=float(rng.uniform(0.2, 0.8) if rot else rng.uniform(0.05, 0.3)),
                           T=float(rng.uniform(0.2, 0.5)), beta=0.8, axis=ax, rotation=rot,
                           center=tuple(float(x) for x in rng.uniform(-0.05, 0.05, 3)))
    else:
        amp = float(rng.uniform(0.05, 0.3))
        p["motion"] = dict(kind="trap", amp=amp, T=0.4, vmax=amp / 0.4 * 1.5, axis=ax)
    reach = 0.5 * math.hypot(lx, ly) + 1e-3
    stops = []
    n_stops = seed % 3 if dof != "translation" else min(seed % 3, 1)
    if n_stops >= 1:
        ang = float(rng.uniform(-0.3, 0.3))
        stops.append(((0, 0, -reach), (math.sin(ang), 0.0, math.cos(ang))))
    if n_stops == 2:
        stops.append(((reach, 0, 0), (-1.0, 0.0, 0.0)))
    p["stops"] = stops
    return p


CASES = fixed_params() + [(f"random{s}", random_params(s)) for s in range(9)]


def run(p, method, lam=1.0, tau=1.0, mu=1.0):
    t_end = 0.3 * tau
    dt = (2e-4 if method == "explicit" else 2e-3) * tau
    kw = dict(method=method, rtol=1e-8, atol=1e-10)
    if method == "regularised":
        kw["eps"] = 1e-3 * lam / tau
    return exdex.simulate(build(p, lam, tau, mu), t_end, dt=dt, **kw)


def outputs(res, p, lam, tau, mu):
    """The outputs of a run divided by their scaling factors, and its stick flags."""
    nd = res.q.shape[1] if res.q.ndim > 1 else 1
    fq = np.array([lam, lam, 1.0]) if nd == 3 else np.array([1.0 if p["dof"] == "rotation" else lam])
    return {
        "t": res.t / tau,
        "q": res.q / fq,
        "v": res.v / (fq / tau),
        "wrench": res.wrench / np.array([mu * lam / tau**2] * 2 + [mu * lam**2 / tau**2]),
        "stop_force": res.stop_force / (mu * lam / tau**2),
    }, res.stick


def deviation(ref, got):
    """Largest deviation of each array, relative to the array's largest magnitude."""
    out = {}
    for k, a in ref.items():
        scale = np.max(np.abs(a)) if a.size else 0.0
        d = np.max(np.abs(got[k] - a)) if a.size else 0.0
        out[k] = d / scale if scale > 0 else d
    return out


@pytest.mark.parametrize("name,p", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("method", METHODS)
def test_results_scale_with_the_scene(name, p, method):
    """Every output scales by its law to 1e-12 of its scale, stick flags
    identical, for every factor set. A trajectory can be sensitive to
    rounding itself (the explicit method's chatter, an adaptive step accepted
    on one side of its tolerance, an object pinched between stops): factors
    that are not powers of two (1/1000 lengths; sqrt(2) in the mass metric
    for masses x 2) change the rounding, so there the bound is also met when
    the deviation is within four times the largest one the same scene shows
    when its lengths, times and masses are perturbed by 1-30 units of
    rounding (2^-53 relative; six samples estimate the scene's own rounding
    sensitivity, hence the margin), which is not a threshold; a run that counts warnings (the scene drives the object
    through a stop) is outside the model and held to the bound only for the
    factors that scale exactly. A fixed
    threshold shows as a deviation far beyond it (a fixed slip speed in the
    rotation regularisation gave 2e-5 at lengths x 4 against 0 from
    rounding; unit-mixed pivots in the implicit contact solve 4e-9 against
    2e-14)."""
    try:
        ref, ref_stick = outputs(run(p, method), p, 1.0, 1.0, 1.0)
    except (exdex.SolverError, ValueError) as e:
        # a method that cannot run the scene (or, analytic, does not apply
        # to it) must fail the same way at every scale
        for lam, tau, mu in FACTORS:
            with pytest.raises(type(e)):
                run(p, method, lam, tau, mu)
        return
    sens = {k: 0.0 for k in ref}
    sens_stick = False
    for k in (1, -2, 3, -5, 8, -13):
        lam, tau, mu = 1.0 + k * 2.0**-52, 1.0 - 3 * k * 2.0**-53, 1.0 + 5 * k * 2.0**-53
        got, stick = outputs(run(p, method, lam, tau, mu), p, lam, tau, mu)
        for key, d in deviation(ref, got).items():
            sens[key] = max(sens[key], d)
        sens_stick |= not np.array_equal(stick, ref_stick)
    for lam, tau, mu in FACTORS:
        res = run(p, method, lam, tau, mu)
        got, stick = outputs(res, p, lam, tau, mu)
        exact = all(math.frexp(f)[0] == 0.5 for f in (lam, tau))
        if not exact and res.stats["warnings"]:
            # a run that counts warnings is outside the model (the scene
            # drives the object through a stop): there only the exactly
            # representable factors are held to the bound
            continue
        for key, d in deviation(ref, got).items():
            assert d <= max(1e-12, 4.0 * sens[key]), (
                f"{key} at lam={lam}, tau={tau}, mu={mu}: relative deviation {d:.3g}, "
                f"rounding sensitivity {sens[key]:.3g}")
        assert sens_stick or np.array_equal(stick, ref_stick), f"stick flags differ at lam={lam}, tau={tau}, mu={mu}"
