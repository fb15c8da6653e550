"""Scenes shared by the tests of different modules (tests/design/test_sequence.py,
tests/cli/test_plan.py)."""
import exdex


def planar_box(stops=(), capacity=1.2, pad=0.01):
    """A 60 x 30 mm box (0.1 kg) held through a 10 x 10 mm pad (or pad x pad)
    at its centre of mass, friction capacity 1.2 m g (mu 0.5), plates vertical."""
    m, g = 0.1, 9.81
    grip = capacity * m * g / (0.5 * 2)
    return exdex.Scene(body=exdex.Body.box(m, (0.06, 0.03, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=grip, patch=exdex.Patch.rectangle(pad, pad)),
                       dof="planar", stops=stops)
