"""GitHub Actions workflow commands (``check --format github``): each finding becomes an
annotation on the pull request's diff.

``::error file=F,line=L,col=C,title=CODE name::message``; ``info`` findings are
``::notice``. Values are escaped as the runner expects: ``%``, CR and LF in messages;
also ``:`` and ``,`` in properties.
"""

from __future__ import annotations

from urdftool.diagnostics import Diagnostic, Report, Severity
from urdftool.render.rule_meta import end_of, files_checked, models_note, relative_path

COMMANDS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def escape_data(value: str) -> str:
    return value.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(value: str) -> str:
    return escape_data(value).replace(":", "%3A").replace(",", "%2C")


def workflow_command(d: Diagnostic, file_path: str) -> str:
    span = d.location
    props: list[tuple[str, str]] = [("file", relative_path(span.path if span else file_path))]
    if span is not None and span.line is not None:
        props.append(("line", str(span.line)))
        end_line, end_column = end_of(span)
        if end_line is not None:
            props.append(("endLine", str(end_line)))
        if span.column is not None:
            props.append(("col", str(span.column)))
        if end_column is not None:
            props.append(("endColumn", str(end_column)))
    props.append(("title", f"{d.code} {d.name}"))
    message = d.message + (f"\nhelp: {d.help}" if d.help else "")
    joined = ",".join(f"{key}={escape_property(value)}" for key, value in props)
    return f"::{COMMANDS[d.severity]} {joined}::{escape_data(message)}"


def render_github(report: Report) -> str:
    lines = [workflow_command(d, f.path) for f in report.files for d in f.diagnostics]
    summary = report.summary()
    lines.append(
        f"urdftool: {files_checked(report)} file(s) checked{models_note(report)}: "
        f"{summary['errors']} error(s), "
        f"{summary['warnings']} warning(s), {summary['infos']} info"
    )
    return "\n".join(lines) + "\n"
