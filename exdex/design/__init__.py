"""Design with exdex: from the outcome you want back to the scene that gives it.

* :mod:`exdex.design.plan`: the motion or grip for a target slip or turn
  (also ``exdex.plan``);
* :mod:`exdex.design.sequence`: a planar pose by a sequence of motion
  primitives (also ``exdex.sequence``);
* :mod:`exdex.design.fit`: sensitivities, event times and the fit of scene
  parameters to an observed motion (``exdex.identify`` and friends);
* :mod:`exdex.design.tool`: assistive-tool design, twist cones (also
  ``exdex.tool``).
"""
