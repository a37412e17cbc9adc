"""One path from an input to a result, used by every command and by the Python API.

* :mod:`~urdftool.pipeline.load`: a path and its options become the models in it;
* :mod:`~urdftool.pipeline.check`: the model rules over a model, a file or many files;
* :mod:`~urdftool.pipeline.convert`: the structural gate, the exporter, the atomic write;
* :mod:`~urdftool.pipeline.simulate`: the smoke simulation of exactly what ``convert`` writes;
* :mod:`~urdftool.pipeline.info` and :mod:`~urdftool.pipeline.discover`: the summary, and
  which files a directory check reads.

``check``, ``convert``, ``graph``, ``sim``, ``info`` and the API are thin calls
into these modules, so they agree by construction. Nothing is imported here:
the commands import the stage they need.
"""
