"""exdex.engines.ablation: torque_capacity against the closed forms of each
contact model's spin limit; ablation's reduction exact where the model
cannot matter (bit for bit), and the equivalent e_r of a planar scene."""
import math

import numpy as np
import pytest

import exdex
from exdex import engines
from engine_cases import fig3_scene, fig6_scene


def test_torque_capacity_closed_forms():
    a, b = 0.01, 0.02
    rect = exdex.Patch.rectangle(2 * a, 2 * b)  # half-sides a, b
    disc = exdex.Patch.disc(0.01)
    # ellipsoid and cylinder: the patch's own e_r (pure spin meets both limits alike)
    assert engines.torque_capacity(rect, "ellipsoid") == rect.e_r
    assert engines.torque_capacity(rect, "cylinder") == rect.e_r
    # corners: every corner at the same distance hypot(a, b)
    assert engines.torque_capacity(rect, "corners") == pytest.approx(math.hypot(a, b), rel=1e-12)
    # corners with a 4-facet pyramid on the axes: support |cos| + |sin| (out) or max(|cos|, |sin|) (in)
    phi = math.atan2(b, a) + math.pi / 2
    d = math.hypot(a, b)
    assert engines.torque_capacity(rect, "corners+pyramid4-out") == pytest.approx(
        d * (abs(math.cos(phi)) + abs(math.sin(phi))), rel=1e-12)
    assert engines.torque_capacity(rect, "corners+pyramid4-in") == pytest.approx(
        d * max(abs(math.cos(phi)), abs(math.sin(phi))), rel=1e-12)
    # distributed 4-facet pyramids over a disc: mean support over all directions,
    # 2 sqrt(2) / pi (inscribed) and 4 / pi (circumscribed), times e_r = 2R/3
    assert engines.torque_capacity(disc, "pyramid4-in") == pytest.approx(2 * math.sqrt(2) / math.pi * disc.e_r,
                                                                          rel=2e-3)
    assert engines.torque_capacity(disc, "pyramid4-out") == pytest.approx(4 / math.pi * disc.e_r, rel=2e-3)


def test_ablation_reduction_matches_engine_free_physics():
    # The reduction is exact: a translation scene's pyramid along an axis is the
    # plain cone (support 1), so its result is exdex's to the last bit.
    scene = fig3_scene()
    ab = engines.ablation(scene, 1.0, models=("ellipsoid", "pyramid4-in", "corners"))
    base = ab["ellipsoid"][0].q
    for model in ("pyramid4-in", "corners"):
        assert np.array_equal(ab[model][0].q, base)


def test_planar_ablation_uses_the_equivalent_e_r():
    # planar scenes: each model's equivalent e_r (exact for a pure spin), mu kept;
    # the ellipsoid row is exdex itself, bit for bit
    scene = exdex.replace(fig6_scene(), dof="planar", motion=exdex.AsymmetricProfile(0.5, 0.5, 0.7, axis=(0, -1, 0),
                                                                                      rotation=True))
    ab = engines.ablation(scene, 1.0, models=("ellipsoid", "corners"))
    assert np.array_equal(ab["ellipsoid"][0].q, exdex.simulate(scene, 1.0, dt=1e-3).q)
    a, b = engines.pad_geometry(scene.grasp.patch)
    assert ab["corners"][1] == pytest.approx(math.hypot(a, b), rel=1e-12)
    assert ab["corners"][0].scene.grasp.mu == scene.grasp.mu


def test_torque_capacity_bad_model_is_named():
    with pytest.raises(ValueError, match="model"):
        engines.torque_capacity(exdex.Patch.disc(0.01), "cone")
