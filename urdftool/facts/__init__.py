"""Facts: one stage per expensive question about a model, computed once and cached on the context.

* :mod:`~urdftool.facts.meshes`: where the robot uses mesh files, where they
  resolved, their formats and contents;
* :mod:`~urdftool.facts.dynamics`: the Pinocchio pass (mass matrix conditioning,
  gravity torques);
* :mod:`~urdftool.facts.simulation`: the smoke simulation's numbers (run by the
  pipeline's simulator, read by the runtime rules).

Rules read facts; they never load, resolve or simulate anything themselves.
Engines are imported inside the backends that use them, on first use.
"""

from urdftool.facts.context import CheckContext

__all__ = ["CheckContext"]
