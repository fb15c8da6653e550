"""The friction-model ablation: exdex rerun with the simplifications the engines make
(a cylinder, pyramids, corner contacts instead of the friction ellipsoid; ``ablation``), and the
torque capacity of a patch under each model (``torque_capacity``)."""
from __future__ import annotations

import math

import numpy as np

from exdex.engines._runner import pad_geometry
from exdex.simulate import Result

__all__ = ['ABLATION_MODELS', 'torque_capacity', 'ablation']


# In a 1-DoF scene every maximum-dissipation friction model with a centrally
# symmetric convex friction set per contact reduces *exactly* to one number:
# the largest generalised friction force the contacts can exert against the
# free coordinate (stick: any force up to it; slip: exactly it, opposing the
# motion). For a pivoted rotation about the patch centre the slip twist there
# is a pure spin, so exdex's ellipsoid gives the torque mu N e_r; a model M
# gives mu N e_r(M), and exdex with e_r := e_r(M) *is* that model. For a
# translation the force mu N becomes mu(M) N. The engines' simplifications:
#   pyramid N   : a linearised cone with N facets fixed to the B axes,
#                 inscribed (vertices on the circle, MuJoCo's "pyramidal" with
#                 N = 4) or circumscribed (facets tangent, Bullet without cone
#                 friction, N = 4), applied at every point of the patch;
#   cylinder    : spin limit independent of the tangential one (Bullet's
#                 spinning friction): |f| <= mu N and |m| <= mu N e_r. A pure
#                 spin (pivoted rotation) or a pure slide meets the same limit
#                 as the ellipsoid, so it changes nothing in 1-DoF scenes;
#   corners     : the patch replaced by equal point contacts at its corners
#                 (the engines' box-box manifolds), each with a circular cone.

ABLATION_MODELS = ("ellipsoid", "cylinder", "pyramid4-in", "pyramid4-out", "pyramid8-in", "corners",
                   "corners+pyramid4-in", "corners+pyramid4-out")


def _support(phi, facets, inscribed):
    """Support function of the linearised unit friction disc in direction phi
    (the largest friction a contact can oppose to a slip along phi): 1 for the
    circle (facets=0), else the regular polygon with a vertex (inscribed) or a
    facet normal (circumscribed) on the B x axis."""
    phi = np.asarray(phi, dtype=float)
    if not facets:
        return np.ones_like(phi)
    if inscribed:      # vertices at angles 2 pi k / N on the unit circle
        k = 2 * np.pi * np.arange(facets) / facets
        return np.max(np.cos(phi[..., None] - k), axis=-1)
    # facet normals at 2 pi k / N, facets tangent to the circle: vertices at
    # 2 pi (k + 1/2) / N, a distance 1 / cos(pi / N) out
    k = 2 * np.pi * (np.arange(facets) + 0.5) / facets
    return np.max(np.cos(phi[..., None] - k), axis=-1) / np.cos(np.pi / facets)


def _parse_model(model):
    if model not in ABLATION_MODELS:
        raise ValueError(f"model must be one of {ABLATION_MODELS}, got {model!r}")
    corners = model.startswith("corners")
    facets, inscribed = 0, True
    if "pyramid" in model:
        part = model.split("pyramid")[1]
        facets = int(part.split("-")[0])
        inscribed = part.endswith("-in")
    return corners, facets, inscribed


def torque_capacity(patch, model="ellipsoid", grid=400):
    """Equivalent e_r [m] of ``patch`` under a friction ``model`` for a spin about the patch centre.

    The largest friction torque is mu N e_r(model). Uniform pressure over the
    patch's footprint (disc, rectangle; a patch given by e_r alone is the
    square with that e_r). ``"ellipsoid"`` and ``"cylinder"`` return
    ``patch.e_r``; distributed pyramids are integrated by the midpoint rule on
    a grid x grid mesh (relative error ~1e-5 at 400); corners are exact.
    """
    corners, facets, inscribed = _parse_model(model)
    if not corners and not facets:
        return float(patch.e_r)
    if corners:
        a, b = pad_geometry(patch)
        pts = np.array([(a, b), (-a, b), (-a, -b), (a, -b)])
        r = np.hypot(pts[:, 0], pts[:, 1])
        phi = np.arctan2(pts[:, 1], pts[:, 0]) + np.pi / 2     # slip direction of a positive spin
        return float(np.mean(r * _support(phi, facets, inscribed)))
    if patch.shape == "disc" and patch.dims:
        R = patch.dims[0]
        u = (np.arange(grid) + 0.5) / grid
        x, y = np.meshgrid((2 * u - 1) * R, (2 * u - 1) * R)
        inside = x**2 + y**2 <= R**2
    else:
        a, b = pad_geometry(patch)
        u = (np.arange(grid) + 0.5) / grid
        x, y = np.meshgrid((2 * u - 1) * a, (2 * u - 1) * b)
        inside = np.ones_like(x, dtype=bool)
    r = np.hypot(x, y)[inside]
    phi = np.arctan2(y, x)[inside] + np.pi / 2
    return float(np.mean(r * _support(phi, facets, inscribed)))


def ablation(scene, t_end, dt=1e-3, models=ABLATION_MODELS):
    """Run exdex with each friction ``model`` in place of the ellipsoid.

    1-DoF scenes (the reduction is exact there, see the comment above):
    rotation scenes get the model's equivalent e_r (``torque_capacity``),
    translation scenes the model's equivalent mu (support of the linearised
    cone along the slide axis; corners and the cylinder change nothing).
    Planar scenes get the model's equivalent e_r, as rotation scenes: exact
    for a pure spin about the patch centre, an approximation when the object
    slides and spins at once (the coupling stays the ellipsoid's), and the
    model's mu is kept (the slide direction is not known in advance).
    Returns {model: (exdex.Result, equivalent e_r [m] or mu)}.
    """
    import dataclasses

    from exdex.simulate import simulate

    out = {}
    for model in models:
        corners, facets, inscribed = _parse_model(model)
        if scene.dof in ("rotation", "planar"):
            er = torque_capacity(scene.grasp.patch, model)
            patch = dataclasses.replace(scene.grasp.patch, e_r=er)
            sc = dataclasses.replace(scene, grasp=dataclasses.replace(scene.grasp, patch=patch))
            value = er
        else:
            phi = math.atan2(scene.slide_axis[1], scene.slide_axis[0])
            mu = scene.grasp.mu * float(_support(np.array(phi), facets, inscribed))
            sc = dataclasses.replace(scene, grasp=dataclasses.replace(scene.grasp, mu=mu))
            value = mu
        out[model] = (simulate(sc, t_end, dt=dt), value)
    return out
