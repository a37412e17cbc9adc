"""The smoke simulation's engine runs (MuJoCo, PyBullet) on urdftool's own exports.

Above the exporters: each engine loads the file that ``urdftool convert``
writes, handed in by the pipeline (:mod:`urdftool.pipeline.simulate`). The
numbers land in :mod:`urdftool.facts.simulation`, where the runtime rules read them.
"""
