"""An interactive explorer for Jupyter: sliders for a scene's grip, friction and motion that redraw
its trajectory.

    >>> ex = exdex.explore(scene)      # in a notebook cell: the sliders and the plot
    >>> ex.set(grip_force=1.2)         # the same from code; ex.result is the current run

Each change runs one trajectory with :func:`exdex.simulate_batch` (the scene is compiled once per
run from the varied parameters, no Scene is rebuilt) and redraws the coordinates against time as a
PNG image widget, so it works in any Jupyter front end with ipywidgets. Needs the ``explore``
extra (ipywidgets, matplotlib): ``pip install 'exdex[explore]'``.
"""
from __future__ import annotations

import io
import math
from typing import Any, Dict, Optional, Tuple

import numpy as np

from exdex.batch import simulate_batch
from exdex.scene import AsymmetricProfile, GripSchedule, Scene, TrapezoidalProfile
from exdex.simulate import Method, Result

__all__ = ["Explorer", "explore", "slider_ranges"]


def slider_ranges(scene: Scene) -> Dict[str, Tuple[float, float, float, str]]:
    """The parameters the explorer varies, ``{name: (value, low, high, label)}``: ``grip_force``
    (N per finger, or a factor on a :class:`exdex.GripSchedule`), ``mu``, and the motion's
    ``amplitude``, ``duration``, ``beta`` (:class:`exdex.AsymmetricProfile`) or ``v_max``
    (:class:`exdex.TrapezoidalProfile`); names as in :func:`exdex.simulate_batch`."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    g = scene.grasp
    out: Dict[str, Tuple[float, float, float, str]] = {}
    if isinstance(g.grip_force, GripSchedule):
        out["grip_force"] = (1.0, 0.0, 3.0, "grip (x schedule)")
    else:
        f = float(g.grip_force)
        out["grip_force"] = (f, 0.0, 3.0 * f if f > 0 else 10.0, "grip [N]")
    out["mu"] = (g.mu, 0.0, max(1.5, 2.0 * g.mu), "mu")
    m: Any = scene.motion
    unit = "rad" if getattr(m, "rotation", False) else "m"
    if isinstance(m, (AsymmetricProfile, TrapezoidalProfile)):
        out["amplitude"] = (m.amplitude, 0.1 * m.amplitude, 2.0 * m.amplitude, f"amplitude [{unit}]")
        out["duration"] = (m.duration, 0.2 * m.duration, 3.0 * m.duration, "duration [s]")
    if isinstance(m, AsymmetricProfile):
        out["beta"] = (m.beta, 0.05, 0.95, "beta")
    if isinstance(m, TrapezoidalProfile):
        out["v_max"] = (m.v_max, m.v_max, 3.0 * m.v_max, f"v_max [{unit}/s]")
    return out


class Explorer:
    """Sliders and a plot of one scene's trajectory (see :func:`explore`).

    ``sliders`` maps each parameter name to its ipywidgets FloatSlider, ``image`` is the plot (an
    ipywidgets Image with PNG bytes), ``widget`` the whole box (what Jupyter shows), ``result`` the
    :class:`exdex.Result` of the current values and ``values`` those values.
    """

    def __init__(self, scene: Scene, t_end: Optional[float] = None, dt: float = 1e-3,
                 method: Method = "implicit") -> None:
        from exdex._optional import require

        widgets = require("ipywidgets", "exdex.explore")
        from exdex._optional import pyplot

        pyplot("exdex.explore")
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.scene, self.dt, self.method = scene, float(dt), method
        end = scene.motion.end_time
        self.t_end = float(t_end) if t_end is not None else (1.5 * end if end > 0 else 1.0)
        ranges = slider_ranges(scene)
        self.sliders: Dict[str, Any] = {}
        for name, (value, lo, hi, label) in ranges.items():
            lo, hi = min(lo, hi), max(lo, hi)
            step = (hi - lo) / 200 if hi > lo else 0.01
            self.sliders[name] = widgets.FloatSlider(value=value, min=lo, max=hi, step=step, description=label,
                                                     continuous_update=False, readout_format=".4g",
                                                     style={"description_width": "initial"})
        self.figure = Figure(figsize=(6.0, 3.2), layout="constrained")
        FigureCanvasAgg(self.figure)
        self.axes = self.figure.add_subplot()
        self.image = widgets.Image(format="png")
        self.status = widgets.HTML()
        self.widget = widgets.VBox([widgets.VBox(list(self.sliders.values())), self.image, self.status])
        self.result: Optional[Result] = None
        for s in self.sliders.values():
            s.observe(lambda change: self.redraw(), names="value")
        self.redraw()

    @property
    def values(self) -> Dict[str, float]:
        """The sliders' current values by parameter name."""
        return {k: float(s.value) for k, s in self.sliders.items()}

    def set(self, **values: float) -> None:
        """Move sliders from code (parameter names as in :attr:`sliders`); the plot follows."""
        unknown = sorted(set(values) - set(self.sliders))
        if unknown:
            raise ValueError(f"unknown parameter(s) {', '.join(unknown)}; the sliders are {', '.join(self.sliders)}")
        for k, v in values.items():
            self.sliders[k].value = v

    def redraw(self) -> None:
        """Run the current values and draw the trajectory into :attr:`image`."""
        try:
            options: Dict[str, Any] = dict(threads=1, method=self.method, warn=False, **self.values)
            batch = simulate_batch(self.scene, self.t_end, self.dt, **options)
        except (ValueError, TypeError, ArithmeticError) as exc:
            self.status.value = f"<span style='color:#b00'>{type(exc).__name__}: {exc}</span>"
            return
        res = batch[0]
        self.result = res
        ax = self.axes
        ax.clear()
        names = self.scene.coordinate_names
        for j, name in enumerate(names):
            rot = name == "theta"
            ax.plot(res.t, (180.0 / math.pi if rot else 1e3) * (res.q[:, j] - res.q[0, j]),
                    label=f"{name} [{'deg' if rot else 'mm'}]")
        ax.axvspan(min(self.scene.motion.end_time, self.t_end), self.t_end, color="0.92", lw=0, zorder=0)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("relative to the start")
        ax.legend(loc="best", fontsize="small")
        buf = io.BytesIO()
        self.figure.savefig(buf, format="png", dpi=90)
        self.image.value = buf.getvalue()
        stick = float(np.mean(res.stick[1:])) if len(res.t) > 1 else 1.0
        self.status.value = (f"end: {', '.join(f'{n} = {x:.4g}' for n, x in zip(names, res.q[-1] - res.q[0]))} "
                             f"(m, rad); stick in {stick:.0%} of steps; shaded: gripper at rest")

    def _repr_mimebundle_(self, **kwargs: Any) -> Any:
        return self.widget._repr_mimebundle_(**kwargs)


def explore(scene: Scene, t_end: Optional[float] = None, dt: float = 1e-3, method: Method = "implicit") -> Explorer:
    """An :class:`Explorer` of ``scene`` for Jupyter: sliders for the grip force, mu and the motion's
    parameters (:func:`slider_ranges`), redrawing the trajectory from ``t = 0`` to ``t_end``
    (default 1.5 x the motion's end, or 1 s) in steps of ``dt`` with ``method``. Needs the
    ``explore`` extra (ipywidgets)."""
    return Explorer(scene, t_end=t_end, dt=dt, method=method)
