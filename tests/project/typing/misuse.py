"""Wrong calls that the type hints must reject (mypy reports one error per marked line)."""
import exdex

scene = exdex.paper.fig3_scene()
exdex.simulate(scene, t_end="1.5")                          # E: t_end is a float
exdex.simulate(scene, 1.5, method="rk4")                    # E: unknown method
exdex.Model(scene, friction_solver="newton")                # E: unknown friction solver
exdex.Patch.rectangle("1 cm", 0.02)                         # E: width is a float
slip: str = exdex.simulate(scene, 1.5).drift_after(1.0)     # E: a float, not a str
exdex.tool.rod_rotation(0.1, height=None)                   # E: height is a float
exdex.paper.fig3_scene(grip_force="strong")                 # E: a float or None
