"""exdex: in-hand manipulation by extrinsic dexterity.

Exact relative dynamics of an object held in a moving parallel-plate gripper
(gravity, inertial forces, friction ellipsoid with maximum dissipation,
external stops), after "In-hand manipulation using extrinsic dexterity and
simple assistive tools" (paper Eqs. 3-6), with a C core and NumPy arrays out.

    >>> import exdex
    >>> scene = exdex.Scene(body=exdex.Body(mass=0.1),
    ...                     grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
    ...                     motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))
    >>> res = exdex.simulate(scene, t_end=1.5, dt=1e-3)

Units are SI; frames are described in :mod:`exdex.scene`. ``import exdex``
needs only NumPy; plotting and progress bars need the ``plot`` extra
(matplotlib, tqdm), the engine cross-checks the ``engines`` extra.
"""
from exdex.scene import (AsymmetricProfile, Body, Chain, Grasp, GripSchedule, Obstacle, Pad, Patch, Pause, Rest,
                         SampledTrajectory, Scene, Shake, Stop, TrapezoidalProfile, quaternion_from_matrix, replace)
from exdex.diagnostics import NoisyLogWarning, PlausibilityWarning, ReductionWarning
from exdex.simulate import GripperJumpWarning, PhysicsWarning, Result, SolverError, simulate
from exdex.stepper import GripperPose, Model, Stepper, StepperSnapshot, StepperState  # noqa: E402  (feedback control)
from exdex.batch import BatchResult, simulate_batch, sweep  # noqa: E402
from exdex.io import load_scene, save_scene  # noqa: E402  (scenes as TOML or JSON files)
from exdex.explorer import Explorer, explore  # noqa: E402  (Jupyter sliders; ipywidgets imported when used)
from exdex import design, studies  # noqa: E402  (subpackages: inverse design; the paper and benchmark studies)
from exdex.studies import paper  # noqa: E402  (the paper's case studies, Figs. 3, 4, 6)
from exdex.design import tool  # noqa: E402  (assistive-tool design, paper Section 3)
from exdex.design import plan  # noqa: E402  (inverse design: motion and grip for a target outcome)
from exdex.design.plan import UnreachableTargetError  # noqa: E402  (a plan's target out of reach)
from exdex.design import sequence  # noqa: E402  (planar pose targets by sequences of motion primitives)
from exdex.design.fit import (EventSensitivity, EventTimes, Identification, Sensitivity, event_sensitivity,  # noqa: E402
                              event_times, identify, sensitivity)
from exdex import diagnostics  # noqa: E402  (physics warnings)
from exdex._optional import MissingExtraError  # noqa: E402
from exdex import _moved  # noqa: E402  (old module paths, e.g. exdex.cli_run, with a DeprecationWarning)

_moved.install()


def __getattr__(name):
    """Old module attributes (exdex.fit, exdex.bench, exdex.hold, exdex.cli_run, ...): the moved
    module, with a DeprecationWarning naming its new path."""
    old = f"exdex.{name}"
    if old in _moved.MOVED:
        import importlib

        _moved.warn(old, 2)
        return importlib.import_module(_moved.MOVED[old])
    raise AttributeError(f"module 'exdex' has no attribute {name!r}")


__version__ = "0.1.0"

__all__ = [
    "AsymmetricProfile", "Body", "Grasp", "GripSchedule", "Obstacle", "Pad", "Patch", "Rest", "SampledTrajectory", "Scene",
    "Stop",
    "TrapezoidalProfile", "Shake", "Pause", "Chain", "replace", "quaternion_from_matrix", "Model", "Result", "SolverError", "PhysicsWarning", "ReductionWarning", "NoisyLogWarning", "PlausibilityWarning",
    "GripperJumpWarning", "Stepper", "StepperState", "StepperSnapshot", "GripperPose",
    "MissingExtraError", "simulate", "BatchResult", "simulate_batch", "sweep", "load_scene", "save_scene", "explore", "Explorer", "paper",
    "tool", "plan", "sequence", "UnreachableTargetError", "sensitivity", "Sensitivity", "event_times", "EventTimes", "event_sensitivity",
    "EventSensitivity", "identify", "Identification", "__version__",
]
