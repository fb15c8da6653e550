"""A typed user script: what a user of exdex writes, checked by mypy (zero errors)
and also executed by tests/project/test_typing.py."""
from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

import exdex
from exdex import tool as T


def make_scene(grip_force: float) -> exdex.Scene:
    return exdex.Scene(
        body=exdex.Body.box(0.1, (0.02, 0.04, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=grip_force, patch=exdex.Patch.rectangle(0.01, 0.02)),
        motion=exdex.AsymmetricProfile(amplitude=0.1, duration=0.5, beta=0.9, axis=(0, 0, -1)),
        stops=(exdex.Stop(point=(0.0, 0.0, -0.05), normal=(0.0, 0.0, 1.0)),),
    )


def final_slip(scene: exdex.Scene) -> float:
    res: exdex.Result = exdex.simulate(scene, t_end=1.5, dt=1e-3, method="implicit", friction_solver="scalar")
    disp: NDArray[np.float64] = res.displacement
    return float(disp[-1, 0])


def compiled(scene: exdex.Scene) -> bool:
    model = exdex.Model(scene, method="event")
    q, v, stick = model.final(t_end=1.5, dt=1e-2)
    return stick and len(q) == model.ndof == len(v)


def batch(scene: exdex.Scene) -> NDArray[np.float64]:
    b: exdex.BatchResult = exdex.simulate_batch(scene, t_end=1.5, dt=1e-3, record="final",
                                                grip_force=np.linspace(1.2, 1.8, 5)[:, None], beta=[[0.8, 0.9]])
    s = exdex.sweep(scene, {"mu": [0.4, 0.5]}, t_end=1.5, dt=1e-3, progress=False)
    assert s.gridded("final_displacement").shape == (2, 1)
    return b.gridded("final_displacement")


def paper_and_tool() -> float:
    fig3 = exdex.paper.fig3_scene()
    cf = exdex.paper.closed_form(fig3)
    f: float = exdex.paper.fig3_grip_force()
    prob = T.ToolProblem(phi=T.phi_set(0, 45, 5.0), box=T.Box.eq13())
    best: T.ThetaResult = T.optimise_theta(prob)
    v: float = T.cone_volume(T.tool_rows(prob, T.Tool(theta=best.theta), 0.3))
    psi, d, u = T.rod_rotation(0.1, width=1.0, height=1.0, rod_x=0.25)
    return cf.final + f + v + float(d[-1]) + float(psi[-1]) + float(u[0])


def main() -> None:
    scene = make_scene(1.5)
    heavier = dataclasses.replace(scene, body=exdex.Body(mass=0.2, inertia=np.diag([1e-4, 1e-4, 2e-4])))
    variant = exdex.replace(scene, dof="planar")
    print(final_slip(scene), final_slip(heavier), final_slip(variant), compiled(scene))
    print(batch(scene).shape, paper_and_tool())


if __name__ == "__main__":
    main()
