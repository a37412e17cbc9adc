"""Rigid-body dynamics and the bundled smoke simulation.

* :mod:`~urdftool.facts.dynamics.configurations`: joint ranges and seeded samples within them;
* :mod:`~urdftool.facts.dynamics.coverage`: whether the dynamics of a model mean anything
  (physically invalid inertia, joints Pinocchio cannot hold, several roots);
* :mod:`~urdftool.facts.dynamics.analysis`: mass matrix conditioning and static gravity
  torques with Pinocchio (read by the ``D`` rules);
* :mod:`~urdftool.simulation.run`: the smoke simulation in MuJoCo and PyBullet (read by
  the ``R`` rules and ``urdftool sim``).

Pinocchio, MuJoCo and PyBullet are imported inside the functions that use them,
never when this package is imported. Decisions are written down in
``docs/dynamics.md`` and ``docs/sim.md``.
"""
