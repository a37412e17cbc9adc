"""The pygls server behind ``urdftool lsp``."""

from __future__ import annotations

import os
from typing import Any

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

from urdftool.lsp.analysis import (
    Placed,
    check_document,
    fix_edits,
    hover_markdown,
    is_checkable,
    place,
    severity_rank,
    suppression_edit,
)
from urdftool.pipeline.check import CheckOptions
from urdftool.render.rule_meta import rule_help_uri
from urdftool.version import __version__

SOURCE = "urdftool"


class UrdftoolServer(LanguageServer):
    """A language server that checks robot descriptions with *options*."""

    def __init__(self, options: CheckOptions, fast_options: CheckOptions | None = None) -> None:
        super().__init__("urdftool", __version__, text_document_sync_kind=types.TextDocumentSyncKind.Full)
        self.options = options
        #: used while typing (no dynamics pass), to keep the editor responsive
        self.fast_options = fast_options or options
        #: the findings last published, per document URI
        self.placed: dict[str, list[Placed]] = {}

    def validate(self, uri: str, typing: bool = False) -> None:
        path = to_fs_path(uri)
        if path is None or not is_checkable(path):
            return
        document = self.workspace.get_text_document(uri)
        text = document.source if os.path.exists(path) or document.source else None
        found = check_document(path, text, self.fast_options if typing else self.options)
        placed = place(found, path, list(document.lines))
        self.placed[uri] = placed
        self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(
            uri=uri, version=document.version, diagnostics=[lsp_diagnostic(p) for p in placed],
        ))

    def forget(self, uri: str) -> None:
        self.placed.pop(uri, None)
        self.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


def lsp_diagnostic(p: Placed) -> types.Diagnostic:
    d = p.diagnostic
    message = d.message + (f"\nhelp: {d.help}" if d.help else "")
    return types.Diagnostic(
        range=types.Range(types.Position(p.line, p.start), types.Position(p.line, p.end)),
        message=f"{d.name}: {message}",
        severity=types.DiagnosticSeverity(severity_rank(d.severity)),
        code=d.code,
        code_description=types.CodeDescription(href=rule_help_uri(d.code)),
        source=SOURCE,
        data={"code": d.code, "name": d.name},
    )


def create_server(options: CheckOptions | None = None) -> UrdftoolServer:
    import dataclasses

    options = options or CheckOptions()
    fast = dataclasses.replace(options, rule_options={**options.rule_options, "dynamics": False})
    server = UrdftoolServer(options, fast)

    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: UrdftoolServer, params: types.DidOpenTextDocumentParams) -> None:
        ls.validate(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: UrdftoolServer, params: types.DidChangeTextDocumentParams) -> None:
        ls.validate(params.text_document.uri, typing=True)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    def did_save(ls: UrdftoolServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.validate(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: UrdftoolServer, params: types.DidCloseTextDocumentParams) -> None:
        ls.forget(params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_HOVER)
    def hover(ls: UrdftoolServer, params: types.HoverParams) -> types.Hover | None:
        text = hover_markdown(ls.placed.get(params.text_document.uri, []), params.position.line)
        if text is None:
            return None
        return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text))

    @server.feature(
        types.TEXT_DOCUMENT_CODE_ACTION,
        types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]),
    )
    def code_action(ls: UrdftoolServer, params: types.CodeActionParams) -> list[types.CodeAction]:
        uri = params.text_document.uri
        document = ls.workspace.get_text_document(uri)
        lines = list(document.lines)
        actions = []
        for diagnostic in params.context.diagnostics:
            if diagnostic.source != SOURCE or not isinstance(diagnostic.code, str):
                continue
            data: Any = diagnostic.data
            name = data.get("name", "") if isinstance(data, dict) else ""
            fix = _fix_action(ls, uri, document.source, diagnostic)
            if fix is not None:
                actions.append(fix)
            edit = suppression_edit(lines, diagnostic.range.start.line, diagnostic.code)
            text_edit = types.TextEdit(
                range=types.Range(types.Position(edit.start, 0), types.Position(edit.end, 0)),
                new_text=edit.text,
            )
            actions.append(types.CodeAction(
                title=f"Ignore {diagnostic.code} {name}".rstrip() + " here (inline comment)",
                kind=types.CodeActionKind.QuickFix,
                diagnostics=[diagnostic],
                edit=types.WorkspaceEdit(changes={uri: [text_edit]}),
            ))
        return actions

    return server


def _fix_action(
    ls: UrdftoolServer, uri: str, buffer: str, diagnostic: types.Diagnostic
) -> types.CodeAction | None:
    """The finding's own fix as a quick fix (the same edits as ``check --fix``), or ``None``."""
    path = to_fs_path(uri)
    start = diagnostic.range.start
    placed = next(
        (p for p in ls.placed.get(uri, [])
         if p.diagnostic.code == diagnostic.code and p.line == start.line and p.start == start.character
         and p.diagnostic.fix is not None),
        None,
    )
    if path is None or placed is None or placed.diagnostic.fix is None:
        return None
    fix = placed.diagnostic.fix
    edits = fix_edits(fix, path, buffer)
    if not edits:
        return None
    changes: dict[str, list[types.TextEdit]] = {}
    for edit in edits:
        target = uri if os.path.abspath(edit.path) == os.path.abspath(path) else from_fs_path(edit.path)
        if target is None:
            return None
        changes.setdefault(target, []).append(types.TextEdit(
            range=types.Range(types.Position(*edit.start), types.Position(*edit.end)),
            new_text=edit.text,
        ))
    safe = fix.applicability.value == "safe"
    return types.CodeAction(
        title=f"Fix {diagnostic.code}: {fix.message}" + ("" if safe else " (unsafe: changes physics)"),
        kind=types.CodeActionKind.QuickFix,
        diagnostics=[diagnostic],
        is_preferred=safe,
        edit=types.WorkspaceEdit(changes=changes),
    )


def serve(options: CheckOptions | None = None) -> None:
    """Run the server over standard input and output until the editor closes it."""
    create_server(options).start_io()
