"""Scenes shared by the tests of different modules (tests/design/test_sequence.py,
tests/cli/test_plan.py, tests/test_simulate.py, tests/cli/test_run.py)."""
import exdex


def planar_box(stops=(), capacity=1.2, pad=0.01):
    """A 60 x 30 mm box (0.1 kg) held through a 10 x 10 mm pad (or pad x pad)
    at its centre of mass, friction capacity 1.2 m g (mu 0.5), plates vertical."""
    m, g = 0.1, 9.81
    grip = capacity * m * g / (0.5 * 2)
    return exdex.Scene(body=exdex.Body.box(m, (0.06, 0.03, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=grip, patch=exdex.Patch.rectangle(pad, pad)),
                       dof="planar", stops=stops)


def falling_box_scenes():
    """A 40 x 60 x 20 mm box (0.1 kg), mu 0.5, 1.5 N per finger, the gripper
    moving down on an asymmetric profile (0.1 s, 0.5 m/s^2, 0.9 s): the same
    scene as a translation, as a rotation about a pivot 10 mm from the centre
    of mass (torsional semi-axis e_r 10 mm), and planar above a stop 90 mm
    below the grip."""
    body = exdex.Body.box(0.1, (0.04, 0.06, 0.02))
    grasp = exdex.Grasp(mu=0.5, grip_force=1.5)
    motion = exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1))
    return {
        "translation": exdex.Scene(body=body, grasp=grasp, motion=motion),
        "rotation": exdex.Scene(body=body, grasp=exdex.Grasp(0.5, 1.5, exdex.Patch(0.01, center=(0.0, 0.01))),
                                motion=motion, dof="rotation"),
        "planar": exdex.Scene(body=body, grasp=grasp, motion=motion, dof="planar",
                              stops=(exdex.Stop((0, 0, -0.09), (0, 0, 1)),)),
    }
