"""Studies made with exdex: fixed scenes chosen to reproduce or to probe.

* :mod:`exdex.studies.paper`: the paper's case studies (Figs. 3, 4, 6) and
  their closed forms (also ``exdex.paper``; ``exdex paper``);
* :mod:`exdex.studies.bench`: work-precision and stability maps of the
  integration methods (``exdex bench``);
* :mod:`exdex.studies.hold`: drift of a held object in exdex and in the
  engines' settings (``exdex hold``).
"""
