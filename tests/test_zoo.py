"""Every method on the scene zoo (tests/zoo.py): it returns, its outputs are
finite, and it agrees with an independent reference within its own stated
error.

Scenes: ``zoo.zoo_scene(seed)`` for seeds 0 .. N_SCENES - 1, every method on
every one (benchmarks/zoo_long.py runs 10,000 and more). What a zoo scene
can be, and why each one is valid, is in the generator's docstring.

Returning. A ``SolverError`` is a failure, except where the exact solution
itself is Zeno-like (infinitely many stick/slip switches accumulating at a
time): then the message must say when (``t = ``), why (``Zeno``) and what to
use instead (``method=``).

Agreement. The error metric is the final pose (x, y, theta) of the object
in the gripper, as a length relative to the object's size L:
``max(|dx|, |dy|, radius |dtheta|) / L`` (zoo.pose_distance; radius the
farthest outline vertex, so an angle error counts as that vertex's
displacement). The final pose is what a user of these scenes asks for and a
continuous function of the trajectory, while velocities, wrenches and stick
flags jump at switches, where every time-stepping error is first order in
the switch time. Scale-free: every run uses tolerances in the scene's own
units (zoo.run), so a 1 mm and a 1 m scene are held to the same standard.

* Reference: the event method (exact Coulomb friction, exact stick, error
  set by its tolerance) at rtol REF_RTOL_TIGHT = 1e-11, output every
  t_end / 64. Its own check: the run at REF_RTOL = 1e-9 with output every
  t_end / 8 is within TOL_EVENT = 1e3 REF_RTOL = 1e-6 of it. The stepper
  keeps the error of each step below rtol (relative) and the global error is
  at most their sum; these scenes take at most a few hundred steps, so the
  1e-9 run lies within ~1e3 rtol of the exact pose, and the 1e-11 run a
  hundred times closer. ``dt`` is only the event method's output grid, so
  the coarse grid must give the same answer as the fine one: a switch
  located at the next output sample instead of where it happens shows here.

* Conditioning. Some valid scenes are near-degenerate: the load touches the
  friction limit, a box balances on a corner. There the final pose is a
  discontinuous (or very steep) function of the data, and every method's
  discretisation, a small perturbation of the dynamics, may land on either
  side. The allowance is measured, not guessed: ``jump``, the largest
  distance between the reference and the reference with gravity scaled by
  1 +- DELTA (1e-6, below the relative error of every method checked). For a
  well-conditioned scene it is ~1e-6 x its condition number and negligible;
  at a threshold it is the size of the discontinuity, the ambiguity of the
  answer itself. Every bound below adds ``jump`` (computed only for scenes
  that exceed their bound without it), the reference's own estimate, and a
  floor of REF_RTOL.

* Implicit (first order in dt) and explicit: runs at h = t_end / 500, h/2
  and h/4, differences D1 = |q(h) - q(h/2)| and D2 = |q(h/2) - q(h/4)|.
  Model of the error: e(h) = h g(h), where g collects the smooth phases'
  first-order term and one term per stick/slip switch or impact inside a
  step, which varies with the switch's position inside its step: g keeps its
  sign and varies within a factor kappa as h changes. Then
  D1 >= h g_min (1 - kappa / 2) and |e(h/4)| <= h g_min kappa / 4, so
  |e(h/4)| <= D1 kappa / (4 - 2 kappa); the same holds with D2 one level
  finer. The bound is S max(D1, D2) with S = 3, which holds for
  kappa <= 1.7 (the switch terms change the error by at most 70 % between
  the three steps). The explicit method never sticks: where the exact
  solution sticks its velocity chatters in a band of width 2 h C / M about 0
  and its pose creeps by at most h C / M per unit time (zoo.creep_speed);
  that creep at h/4 over the reference's stuck time is added.

* Regularised (first order in the smoothing speed eps): runs at eps = EPS L
  / tau (EPS = 1e-2), eps/2 and eps/4 with the same estimate S max(D1, D2)
  at eps/4, plus TOL_EVENT (its own adaptive integration runs at REF_RTOL)
  and its creep: under a load w inside the friction ellipsoid it does not
  stick but creeps at eps |E^-1 w| / sqrt((mu N)^2 - |E^-1 w|^2), summed
  here over the reference's stuck intervals with the reference's wrench
  (zoo.regularised_creep). That law is first order in eps only while the
  creep leaves the configuration nearly unchanged; where the creep at EPS
  exceeds CREEP_REGIME = 0.1 L the method is outside its first-order regime
  at these eps (its error changes the configuration, e.g. a box creeping
  round a stop corner under a load 0.93 of the friction limit), so there it
  must return finite values, and the bound is reported, not asserted
  (test_zoo_regularised_regime bounds how often that happens). Three stiff
  runs per scene are the expensive part of this file: the agreement runs on
  every REG_EVERY-th seed, the single run at EPS on all.

Known defects are marked per (method, seed) with ``xfail(strict=True)`` and
the defect stated; a fix makes them pass, the strict mark then fails, and
the mark must go: the list can only shrink.
"""
import re

import numpy as np
import pytest

import exdex

import zoo

N_SCENES = 200
SEEDS = range(N_SCENES)
#: The regularised method's agreement (three stiff runs) on every REG_EVERY-th
#: seed; it returns on all of them.
REG_EVERY = 2

#: (method, seed) -> the defect; strict xfails.
KNOWN = {}


def _zeno_message_ok(msg):
    return bool(re.search(r"Zeno", msg) and re.search(r"t = ", msg) and re.search(r"method=", msg))


_CACHE = {}


def results(seed):
    """zoo.check_scene of a seed, computed once per test session."""
    if seed not in _CACHE:
        zs = zoo.zoo_scene(seed)
        agree = zoo.METHODS if seed % REG_EVERY == 0 else ("implicit", "event", "explicit")
        _CACHE[seed] = (zs, zoo.check_scene(zs, agree=agree))
    return _CACHE[seed]


def _cases():
    for method in zoo.METHODS:
        for seed in SEEDS:
            marks = []
            if (method, seed) in KNOWN:
                marks.append(pytest.mark.xfail(strict=True, reason=KNOWN[method, seed]))
            yield pytest.param(method, seed, marks=marks, id=f"{method}-{seed}")


@pytest.mark.parametrize("method,seed", list(_cases()))
def test_zoo_scene(method, seed):
    zs, out = results(seed)
    o = out[method]
    if o["error"]:
        assert o["error"].startswith("SolverError") and _zeno_message_ok(o["error"]), (zs, o["error"])
        return
    assert np.all(np.isfinite(o["pose"]))
    ref = out.get("reference")
    if ref is None or "ok" not in o:  # no reference (its own case reports that), or not compared
        return
    assert "jump_error" not in ref, (zs, ref["jump_error"])
    assert o["ok"], (zs, {k: v for k, v in o.items() if k != "pose"}, {k: v for k, v in ref.items() if k != "pose"})


def test_zoo_generator_is_valid_and_covers_the_space():
    """Every scene the tests draw is accepted by the API (it was built),
    starts with no outline vertex inside a stop, is a pure function of its
    seed, and the draws cover each free-coordinate type, motion kind, stop
    count, 1 mm and 1 m scales, the grip range 0.5x-5x and initial
    velocities."""
    seen = {"dof": set(), "motion": set(), "stops": set(), "rotate": set(), "v0": set()}
    Ls, grips = [], []
    for seed in range(600):
        zs = zoo.zoo_scene(seed)
        if zs.scene.stops:
            assert zoo.stop_gaps(zs).min() >= 0.0, seed
        assert zs.t_end > 0.0
        for k in seen:
            seen[k].add(zs.tags[k] if k != "motion" else zs.tags[k].split("-")[0])
        Ls.append(zs.L)
        grips.append(zs.tags["grip_ratio"])
    assert zoo.zoo_scene(7).scene == zoo.zoo_scene(7).scene
    assert seen["dof"] == {"translation", "rotation", "planar"}
    assert seen["motion"] == {"rest", "asym", "trap", "log"}
    assert seen["stops"] == {0, 1, 2}
    assert seen["rotate"] == {True, False} and seen["v0"] == {True, False}
    assert min(Ls) < 2e-3 and max(Ls) > 0.5
    assert min(grips) < 0.6 and max(grips) > 4.5


def test_zoo_regularised_regime():
    """Scenes where the regularised method's creep at EPS exceeds
    CREEP_REGIME (its agreement reported, not asserted) stay a minority
    of the checked ones: the zoo must test that method, not excuse it."""
    checked = outside = 0
    for seed in SEEDS:
        if seed % REG_EVERY:
            continue
        o = results(seed)[1]["regularised"]
        if "regime" in o:
            checked += 1
            outside += not o["regime"]
    assert checked >= N_SCENES // REG_EVERY // 2
    assert outside <= 0.5 * checked, (outside, checked)
