"""Rule definitions that readers and exporters report: codes, names, severities and documentation.

The lowest layer that knows about rules. Readers (:mod:`urdftool.parse`) and
exporters (:mod:`urdftool.export`) create findings of the rules defined here;
the checks of a loaded robot are in :mod:`urdftool.rules` and register into the
same table (:data:`~urdftool.catalogue.registry.REGISTRY`).
"""
