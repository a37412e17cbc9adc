"""``urdftool lsp``: a language server for editors (pygls, over stdio).

Diagnostics for URDF, xacro and SDF files are published when a file is opened, changed and
saved (xacro findings on the ``.xacro`` line they were written on); hovering a line with a
finding shows the rule's documentation; a quick fix inserts
``<!-- urdftool: ignore[CODE] -->`` on the line before the element.

:mod:`urdftool.lsp.analysis` holds the editor-independent logic; :mod:`urdftool.lsp.server`
wires it to pygls (the ``lsp`` extra).
"""
