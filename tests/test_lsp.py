"""``urdftool lsp``: a real client (pygls's LanguageClient) talks to the server over pipes:
diagnostics on open and change, xacro findings on the .xacro line, hover, fixes and
suppressions as quick fixes."""

from __future__ import annotations

import asyncio
import contextlib
import os
import sys
from collections.abc import Awaitable, Callable
from pathlib import Path

import pytest
from lsprotocol import types
from pygls.lsp.client import LanguageClient

from tests.conftest import FIXTURES, ROOT
from urdftool.lsp.analysis import suppression_edit

NUMBERS = FIXTURES / "rules" / "S005" / "bad.urdf"  # invalid-number at 6:13, 19:13, 19:29, 21:26

Queues = dict[str, asyncio.Queue[types.PublishDiagnosticsParams]]
Session = Callable[[LanguageClient, Queues], Awaitable[None]]


def run_session(session: Session) -> None:
    async def main() -> None:
        client = LanguageClient("urdftool-tests", "1")
        queues: Queues = {}

        @client.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def published(params: types.PublishDiagnosticsParams) -> None:
            queues.setdefault(params.uri, asyncio.Queue()).put_nowait(params)

        env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
        await client.start_io(sys.executable, "-m", "urdftool", "lsp", "--no-dynamics", env=env)
        try:
            await client.initialize_async(types.InitializeParams(
                capabilities=types.ClientCapabilities(), root_uri=ROOT.as_uri(),
            ))
            client.initialized(types.InitializedParams())
            await session(client, queues)
        finally:  # also after a failed assertion: a server left running would hang the test
            with contextlib.suppress(Exception):
                await asyncio.wait_for(client.shutdown_async(None), timeout=10)
            client.exit(None)
            await asyncio.wait_for(client.stop(), timeout=10)

    asyncio.run(asyncio.wait_for(main(), timeout=120))


async def diagnostics_for(queues: Queues, uri: str) -> list[types.Diagnostic]:
    while uri not in queues:
        await asyncio.sleep(0.05)
    return (await asyncio.wait_for(queues[uri].get(), timeout=60)).diagnostics


def open_document(client: LanguageClient, path: Path, text: str | None = None) -> str:
    uri = path.as_uri()
    client.text_document_did_open(types.DidOpenTextDocumentParams(types.TextDocumentItem(
        uri=uri, language_id="xml", version=1,
        text=path.read_text(encoding="utf-8") if text is None else text,
    )))
    return uri


def test_open_publishes_findings_and_hover_and_quick_fix() -> None:
    async def session(client: LanguageClient, queues: Queues) -> None:
        uri = open_document(client, NUMBERS)
        found = await diagnostics_for(queues, uri)
        numbers = [d for d in found if d.code == "S005"]
        assert [(d.range.start.line, d.range.start.character) for d in numbers] == [
            (5, 12), (18, 12), (18, 28), (20, 25)
        ]
        first = numbers[0]
        assert first.severity == types.DiagnosticSeverity.Error
        assert first.source == "urdftool"
        assert first.code_description is not None
        assert first.code_description.href.endswith("docs/rules/S005.md")
        assert "2.O" in first.message

        hover = await client.text_document_hover_async(types.HoverParams(
            types.TextDocumentIdentifier(uri), types.Position(5, 0)))
        assert hover is not None and isinstance(hover.contents, types.MarkupContent)
        assert hover.contents.value.startswith("# S005 invalid-number")
        nothing = await client.text_document_hover_async(types.HoverParams(
            types.TextDocumentIdentifier(uri), types.Position(0, 0)))
        assert nothing is None or "S005" not in str(nothing.contents)

        actions = await client.text_document_code_action_async(types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(uri), range=first.range,
            context=types.CodeActionContext(diagnostics=[first])))
        assert actions, "no quick fix offered"
        # the finding's own fix first, the same edit as `check --fix` ("2.O" -> "2.0")
        fix = actions[0]
        assert isinstance(fix, types.CodeAction) and fix.title.startswith("Fix S005")
        assert fix.is_preferred and fix.edit is not None and fix.edit.changes
        (change,) = fix.edit.changes[uri]
        line = NUMBERS.read_text(encoding="utf-8").splitlines()[5]
        start, end = change.range.start, change.range.end
        assert start.line == end.line == 5
        assert line[: start.character] + change.new_text + line[end.character :] == line.replace(
            '"2.O"', '"2.0"'
        )
        [action] = [a for a in actions if isinstance(a, types.CodeAction) and a.title.startswith("Ignore")]
        assert action.edit is not None and action.edit.changes
        (edit,) = action.edit.changes[uri]
        assert edit.range.start == edit.range.end == types.Position(5, 0)
        indent = NUMBERS.read_text(encoding="utf-8").splitlines()[5]
        indent = indent[: len(indent) - len(indent.lstrip())]
        assert edit.new_text == indent + "<!-- urdftool: ignore[S005] -->\n"

    run_session(session)


def test_change_rechecks_the_buffer_and_close_clears(tmp_path: Path) -> None:
    robot = tmp_path / "arm.urdf"
    robot.write_text(NUMBERS.read_text(encoding="utf-8"), encoding="utf-8")
    clean = NUMBERS.read_text(encoding="utf-8").replace('value="2.O"', 'value="2.0"')

    async def session(client: LanguageClient, queues: Queues) -> None:
        uri = open_document(client, robot)
        before = [d.range.start.line for d in await diagnostics_for(queues, uri) if d.code == "S005"]
        assert 5 in before
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            [types.TextDocumentContentChangeWholeDocument(text=clean)]))
        after = [d.range.start.line for d in await diagnostics_for(queues, uri) if d.code == "S005"]
        assert 5 not in after and len(after) == len(before) - 1
        client.text_document_did_close(types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(uri)))
        assert list(await diagnostics_for(queues, uri)) == []

    run_session(session)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.urdf"], "the buffer's copy was left behind"


def test_xacro_findings_land_on_the_xacro_line(tmp_path: Path) -> None:
    robot = tmp_path / "cart.urdf.xacro"
    robot.write_text(
        '<?xml version="1.0"?>\n'
        '<robot name="cart" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="wheel" params="side">\n'
        '    <link name="${side}_wheel">\n'
        '      <inertial><mass value="-1"/>'
        '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>\n'
        '    </link>\n'
        '  </xacro:macro>\n'
        '  <link name="base"/>\n'
        '  <xacro:wheel side="left"/>\n'
        '  <joint name="j" type="fixed"><parent link="base"/><child link="left_wheel"/></joint>\n'
        '</robot>\n',
        encoding="utf-8",
    )

    async def session(client: LanguageClient, queues: Queues) -> None:
        uri = open_document(client, robot)
        found = await diagnostics_for(queues, uri)
        negative = [d for d in found if "negative-mass" in d.message]
        assert negative, [d.message for d in found]
        assert all(d.range.start.line == 4 for d in negative)

    run_session(session)


@pytest.mark.parametrize(
    "lines, line, expected",
    [
        (["<robot>\n", "  <link/>\n"], 1, (1, 1, "  <!-- urdftool: ignore[S005] -->\n")),
        (["  <!-- urdftool: ignore[I001] -->\n", "  <link/>\n"], 1,
         (0, 1, "  <!-- urdftool: ignore[I001,S005] -->\n")),
        (["  <!-- urdftool: ignore[S005] -->\n", "  <link/>\n"], 1,
         (0, 1, "  <!-- urdftool: ignore[S005] -->\n")),
        (["\t<link/>\r\n"], 0, (0, 0, "\t<!-- urdftool: ignore[S005] -->\r\n")),
    ],
)
def test_suppression_edit(lines: list[str], line: int, expected: tuple[int, int, str]) -> None:
    edit = suppression_edit(lines, line, "S005")
    assert (edit.start, edit.end, edit.text) == expected


def test_fix_of_an_edited_buffer_lands_in_the_buffer_text() -> None:
    # unsaved edits above the finding shift it: the fix must be placed in the buffer, not the file
    text = NUMBERS.read_text(encoding="utf-8").replace(
        '<robot name="two_link_arm">',
        '<robot name="two_link_arm">\n  <!-- a note typed in the editor -->'
    )

    async def session(client: LanguageClient, queues: Queues) -> None:
        uri = open_document(client, NUMBERS, text)
        found = await diagnostics_for(queues, uri)
        mass = next(d for d in found if d.code == "S005" and d.range.start.line == 6)
        actions = await client.text_document_code_action_async(types.CodeActionParams(
            text_document=types.TextDocumentIdentifier(uri), range=mass.range,
            context=types.CodeActionContext(diagnostics=[mass])))
        assert actions
        fix = actions[0]
        assert isinstance(fix, types.CodeAction) and fix.edit is not None and fix.edit.changes
        (change,) = fix.edit.changes[uri]
        line = text.splitlines()[6]
        assert change.range.start.line == 6
        patched = line[: change.range.start.character] + change.new_text + line[change.range.end.character :]
        assert patched == line.replace('"2.O"', '"2.0"')

    run_session(session)
