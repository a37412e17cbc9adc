"""Safe XML reading with positions.

Robot descriptions arrive from CAD exporters, the internet and colleagues, so
the reader treats them as untrusted: no DTD loading, no entity declarations
(they are refused outright: libxml2 still expands internal entities in
attributes even with entity resolution off), no network, a size cap, and
libxml2's nesting cap of 256 levels. Every refusal is a located ``xml-syntax``
diagnostic, never an exception.

After parsing, every element gets a :data:`~urdftool.source.SRC_ATTRIBUTE`
recording where its start tag was written, so spans survive any later
transformation (xacro expansion, extraction of ``<gazebo>`` blocks). A reader
that only walks the document once (the URDF and SRDF readers) asks for a
position table instead (``table=True``): the same positions, looked up only
when a span is read (:mod:`urdftool.parse.locate`).
"""

from __future__ import annotations

import functools
import re
import sys
import threading
from collections.abc import Callable

from lxml import etree

from urdftool.catalogue.syntax import XmlSyntax
from urdftool.catalogue.xacro import XacroInUrdf
from urdftool.diagnostics import Diagnostic, Severity
from urdftool.parse.locate import PositionTable, span_of, stamp_positions
from urdftool.records import record
from urdftool.safe_files import DEFAULT_LIMITS, human, limit, read_up_to
from urdftool.source import BOMS, DECLARED_ENCODING, UTF8_NAMES, Span, deferred_span, sniff_encoding

#: Larger inputs are refused by default (the largest corpus URDF is about 1 MB);
#: ``--max-file-size`` raises the cap (see :mod:`urdftool.safe_files`).
MAX_BYTES = DEFAULT_LIMITS["model"]

_KIND_WORDS = {"model": "robot descriptions", "include": "included xacro files"}

def to_utf8(data: bytes, path: str) -> tuple[bytes, Diagnostic | None]:
    """*data* as UTF-8 with its declaration saying so; a diagnostic when it cannot be decoded."""
    encoding = sniff_encoding(data)
    if encoding is not None:
        bom = next((b for b, name in BOMS if name == encoding and data.startswith(b)), b"")
        try:
            data = data[len(bom):].decode(encoding).encode("utf-8")
        except UnicodeDecodeError as exc:
            return data, XmlSyntax.diagnostic(
                f"file looks like {encoding.upper()} but does not decode as it: {exc.reason}",
                Span(path, 1, 1),
                help="save the file as UTF-8",
            )
    elif data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    match = DECLARED_ENCODING.match(data)
    if match is None:
        return data, None
    declared = match.group(2).decode("ascii").lower()
    if encoding is not None or declared in UTF8_NAMES:
        if declared not in UTF8_NAMES:  # the text is UTF-8 now: say so
            data = data[: match.start(2)] + b"UTF-8" + data[match.end(2):]
        return data, None
    try:
        text = data.decode(declared)
    except LookupError:
        return data, XmlSyntax.diagnostic(
            f"the XML declaration names an unknown encoding \"{declared}\"",
            Span(path, 1, 1),
            help='save the file as UTF-8 and write <?xml version="1.0" encoding="UTF-8"?>',
        )
    except UnicodeDecodeError as exc:
        return data, XmlSyntax.diagnostic(
            f"file is not valid {declared} as its XML declaration says: {exc.reason}",
            Span(path, 1, 1),
            help="save the file as UTF-8",
        )
    if not text.lstrip().startswith("<?xml"):  # EBCDIC and the like: not an XML declaration any more
        return data, XmlSyntax.diagnostic(
            f"the XML declaration's encoding \"{declared}\" does not fit the file's bytes",
            Span(path, 1, 1),
            help="save the file as UTF-8",
        )
    data = text.encode("utf-8")
    match = DECLARED_ENCODING.match(data)
    if match is not None:
        data = data[: match.start(2)] + b"UTF-8" + data[match.end(2):]
    return data, None

_ENTITY_DECL = re.compile(rb"<!ENTITY", re.IGNORECASE)


#: One parser per thread, used again for every file: lxml parsers may be reused one document
#: at a time, not shared between threads (``check_many`` may run files in threads).
_PARSERS = threading.local()


def _parser() -> etree.XMLParser:
    parser: etree.XMLParser | None = getattr(_PARSERS, "parser", None)
    if parser is None:
        parser = _PARSERS.parser = etree.XMLParser(
            resolve_entities=False,
            no_network=True,
            load_dtd=False,
            dtd_validation=False,
            huge_tree=False,
            remove_blank_text=False,
            remove_comments=True,
            remove_pis=True,
        )
    return parser


@record(frozen=False, eq=False)  # one run's state, equal only to itself
class XmlDocument:
    """A parsed document whose elements carry their source positions.

    The positions are either stamped on every element (:data:`SRC_ATTRIBUTE`) or,
    for a document read with ``table=True``, kept in :attr:`table` (see
    :mod:`urdftool.parse.locate`): then :meth:`span` gives deferred spans, and
    :meth:`mark` marks the elements that outlive the reading (the model's
    ``Extension.element`` subtrees), so that :func:`span_of` finds those later.
    """

    root: etree._Element
    path: str
    #: the positions, when they are not stamped on the elements
    table: PositionTable | None = None
    #: the text could put an element in xacro's namespace: it names ``wiki/xacro`` or holds a
    #: character reference (which could spell it); when false, :func:`xacro_in_urdf` has nothing to find
    may_use_xacro: bool = True
    #: the text names ``urdftool:``, as an inline suppression comment does; when false, the
    #: suppression pass need not read the file again
    may_hold_suppressions: bool = True

    def span(self, element: etree._Element) -> Span | None:
        """Where *element*'s start tag was written: from the table, else from the stamps."""
        if self.table is not None:
            return self.table.span(element)
        return span_of(element)

    def locator(self) -> Callable[[etree._Element], Span | None]:
        """:meth:`span` as the cheapest callable, for a reader that asks once per element."""
        if self.table is not None:
            return functools.partial(deferred_span, self.path, self.table.locate)
        return span_of

    def mark(self, element: etree._Element) -> None:
        """Make *element* and everything below it findable by :func:`span_of` after the reading
        (no-op for a stamped document)."""
        if self.table is not None:
            self.table.mark(element)


def line_of(data: bytes, offset: int) -> int:
    return data.count(b"\n", 0, offset) + 1


def parse_bytes(
    data: bytes, path: str, stamp: bool = True, kind: str = "model", table: bool = False
) -> tuple[XmlDocument | None, list[Diagnostic]]:
    """Parse *data* read from *path*; return the document or the diagnostics that stop it.

    With *stamp*, every element records its position in *data* (with *table*, in
    the document's position table instead of an attribute); without, the
    document is taken to carry positions already (xacro output).
    """
    cap = limit(kind)
    if len(data) > cap:
        return None, [
            XmlSyntax.diagnostic(
                f"file is {len(data) / 1e6:.0f} MB; urdftool reads {_KIND_WORDS.get(kind, kind)} up to "
                f"{human(cap)}",
                Span(path, 1, 1),
                help=f"split the description, check that this is the file you meant, or raise the cap "
                f"with --max-file-size {kind}=SIZE",
            )
        ]
    # Every guard below reads bytes: text in UTF-16/32 (by BOM or by its first
    # characters) or in a declared non-UTF-8 encoding is turned into UTF-8 first,
    # so that no encoding hides an entity declaration from them.
    data, problem = to_utf8(data, path)
    if problem is not None:
        return None, [problem]
    # Entity declarations can only stand in a document type declaration, which can only stand
    # in the prolog, after the XML declaration, comments and processing instructions. A
    # document that has one is refused if "<!ENTITY" appears anywhere after it: robot
    # descriptions have no DOCTYPE, and a comment holding markup must not hide one.
    start = _prolog_end(data)
    if data[start:start + len(b"<!DOCTYPE")].upper() == b"<!DOCTYPE":
        entity = _ENTITY_DECL.search(data, start)
        if entity:
            return None, [_entities_refused(path, line_of(data, entity.start()))]
    data, warnings = _tolerate_quirks(data, path)
    root, refusal = _parse_root(data, path)
    if refusal is not None:
        # libxml2 refuses `--` inside a comment, which TinyXML-based loaders read: mended here,
        # after a failed parse, so that the documents without one pay no scan for it.
        mended = _hyphens_in_comments(data, path, warnings)
        if mended is data:
            return None, [refusal]
        data = mended
        root, refusal = _parse_root(data, path)
        if refusal is not None:
            return None, [refusal]
    if root is None:
        return None, [XmlSyntax.diagnostic("document has no root element", Span(path, 1, 1))]
    dtd = root.getroottree().docinfo.internalDTD
    if dtd is not None and next(iter(dtd.iterentities()), None) is not None:
        # The guard above missed one (libxml2 bounds the expansion while parsing): still refused.
        return None, [_entities_refused(path, line_of(data, start))]
    # (a one-byte search runs at memchr's speed; most files hold no '&' at all)
    may_use_xacro = ((b"&" in data and b"&#" in data)
                     or (b"wiki/xacro" in data and _may_name_xacro_elements(data)))
    may_hold_suppressions = b"urdftool:" in data
    if stamp and table:
        path = sys.intern(path)
        return XmlDocument(root, path, PositionTable(root, data, path), may_use_xacro,
                           may_hold_suppressions), warnings
    if stamp:
        stamp_positions(root, data, path)
    return XmlDocument(root, path, None, may_use_xacro, may_hold_suppressions), warnings


#: a prefix bound to xacro's namespace, and xacro's namespace made the default one
_XACRO_PREFIX = re.compile(rb"""xmlns:([^\s=/>]+)\s*=\s*["'][^"']*wiki/xacro""")
_XACRO_DEFAULT = re.compile(rb"""xmlns\s*=\s*["'][^"']*wiki/xacro""")


def _may_name_xacro_elements(data: bytes) -> bool:
    """Whether an element of *data* can be in xacro's namespace: a tag starts with a prefix bound
    to it, or it is made the default namespace. Files that xacro wrote declare the namespace on
    ``<robot>`` and use it nowhere; the search of every element for it is then skipped."""
    if _XACRO_DEFAULT.search(data):
        return True
    return any(b"<" + prefix + b":" in data for prefix in _XACRO_PREFIX.findall(data))


_DECLARED_VERSION = re.compile(rb"^(\s*<\?xml[^>]*?version\s*=\s*[\"'])([^\"']*)([\"'])")


_PREFIXED_TAG = re.compile(rb"</?([A-Za-z_][\w.-]*):[A-Za-z_]")
#: a prefixed attribute (``gz:type="…"``) inside a start tag
_PREFIXED_ATTRIBUTE = re.compile(rb"<[A-Za-z_][^<>]*?\s([A-Za-z_][\w.-]*):[A-Za-z_][\w.-]*\s*=")
_DECLARED_PREFIX = re.compile(rb"xmlns:([A-Za-z_][\w.-]*)\s*=")


def _declare_prefixes(data: bytes, path: str, warnings: list[Diagnostic]) -> bytes:
    """Declare namespace prefixes that elements use without a declaration (TinyXML ignores namespaces).

    SDF files carry custom elements such as ``<my_ns:sensor>`` and attributes
    such as ``gz:type="…"`` without ``xmlns:my_ns``; libsdformat reads them. The missing declarations are
    added on the root element, on its own line, so positions do not move.
    """
    if b":" not in data:
        return data
    prefixes = set(_PREFIXED_TAG.findall(data)) | set(_PREFIXED_ATTRIBUTE.findall(data))
    used = prefixes - set(_DECLARED_PREFIX.findall(data)) - {b"xml", b"xmlns"}
    if not used:
        return data
    root = re.search(rb"<[A-Za-z_][\w.:-]*", data[_first_element(data):])
    if root is None:
        return data
    at = _first_element(data) + root.end()
    declarations = b"".join(b" xmlns:" + p + b'="urn:undeclared:' + p + b'"' for p in sorted(used))
    names = ", ".join(p.decode("ascii", "replace") for p in sorted(used))
    warnings.append(
        XmlSyntax.diagnostic(
            f"namespace prefix{'es' if len(used) > 1 else ''} {names} used without an xmlns declaration; "
            "read as custom elements",
            Span(path, line_of(data, at), 1),
            severity=Severity.INFO,
            help="declare the prefix on the root element: xmlns:PREFIX=\"http://example.org/PREFIX\"",
        )
    )
    return data[:at] + declarations + data[at:]


_SCOPED_TAG = re.compile(rb"(</?[A-Za-z_][\w.-]*)::(?=[A-Za-z_])")


def _scoped_tags(data: bytes, path: str, warnings: list[Diagnostic]) -> bytes:
    """Element names with ``::`` (gz-sim's ``<gz::system_priority>``), read as ``__``.

    TinyXML2 takes any name; for libxml2 a name holds at most one ``:``. The
    two bytes keep their place, so no position moves.
    """
    found = _SCOPED_TAG.search(data)
    if found is None:
        return data
    warnings.append(
        XmlSyntax.diagnostic(
            "element names with '::' (e.g. <gz::system_priority>) are not XML names; read with "
            "'__' in their place, as sdformat reads them as written",
            Span(path, line_of(data, found.start()), 1),
            severity=Severity.INFO,
        )
    )
    return _SCOPED_TAG.sub(lambda m: m.group(1) + b"__", data)


def _hyphens_in_comments(data: bytes, path: str, warnings: list[Diagnostic]) -> bytes:
    """Comments holding ``--`` (XML forbids it): the hyphens read as ``~``, byte for byte.

    gz-sim's own example worlds write shell commands (``gz service --timeout``)
    in comments; sdformat and urdfdom (TinyXML2) read them, libxml2 and Python's
    expat (xacro, urdf_parser_py) refuse them. Only comment text changes, so no
    position moves. Returns *data* itself when no comment needs mending.
    """
    # Comment by comment with find(), not a regular expression: a lazy match of each "<!--" up
    # to its "-->" is quadratic in a text of many unclosed comments (64 kB took 2.7 s). A comment
    # with no "-->" after it ends the search: no later one can close either.
    parts: list[bytes] = []
    first: int | None = None
    done = searched = 0
    while (start := data.find(b"<!--", searched)) >= 0:
        end = data.find(b"-->", start + 4)
        if end < 0:
            break
        body = data[start + 4:end]
        mended = body.replace(b"--", b"~~")
        if mended.endswith(b"-"):
            mended = mended[:-1] + b"~"
        if mended != body:
            first = start if first is None else first
            parts += (data[done:start + 4], mended)
            done = end
        searched = end + 3
    if first is None:
        return data  # the same object: nothing was mended
    mended = b"".join((*parts, data[done:]))
    sdf = path.lower().endswith((".sdf", ".world"))
    warnings.append(
        XmlSyntax.diagnostic(
            "a comment holds '--', which XML forbids; read as if it did not"
            + ("" if sdf else " (xacro and other expat-based tools refuse the file)"),
            Span(path, line_of(mended, first), 1),
            severity=Severity.INFO if sdf else Severity.WARNING,
            help="write the hyphens apart, or move the text out of the comment",
        )
    )
    return mended


def _parse_root(data: bytes, path: str) -> tuple[etree._Element | None, Diagnostic | None]:
    """The root element of *data* parsed by libxml2, or the located refusal."""
    try:
        return etree.fromstring(data, _parser()), None
    except etree.XMLSyntaxError as exc:
        line, column = exc.position if exc.position else (1, 1)
        message = str(exc.msg or exc).split(", line ")[0]
        message, hint = _explain(message, data)
        return None, XmlSyntax.diagnostic(message, Span(path, max(line, 1), max(column, 1)), help=hint)
    except ValueError as exc:  # e.g. unsupported encoding declarations
        return None, XmlSyntax.diagnostic(str(exc), Span(path, 1, 1))


_LEADING_SPACE = re.compile(rb"[ \t\r\n]*")
_NOT_A_BREAK = re.compile(rb"[^\r\n]")


def _blank(text: bytes) -> bytes:
    """*text* with every byte but its line breaks turned into a space."""
    return _NOT_A_BREAK.sub(b" ", text)


def _tolerate_quirks(data: bytes, path: str) -> tuple[bytes, list[Diagnostic]]:
    """Accept, with a warning, harmless defects that TinyXML-based loaders accept.

    (``--`` inside comments is mended after libxml2 has refused the text: see
    :func:`_hyphens_in_comments`.)

    * blank lines before the XML declaration;
    * an XML declaration with a version other than 1.0/1.1 (``version="0.0"``,
      written by several exporters), read as 1.0;
    * NUL bytes after the root element (padding left by some editors), ignored.
    """
    warnings: list[Diagnostic] = []
    match = _DECLARED_VERSION.match(data)
    if match and match.group(2) not in (b"1.0", b"1.1"):
        version = match.group(2).decode("ascii", "replace")
        data = data[: match.start(2)] + b"1.0" + data[match.end(2) :]
        warnings.append(
            XmlSyntax.diagnostic(
                f"XML declaration has version \"{version}\"; read as 1.0",
                Span(path, line_of(data, match.start(2)), 1),
                severity=Severity.WARNING,
                help='write <?xml version="1.0"?>',
            )
        )
    leading = _LEADING_SPACE.match(data).end()  # type: ignore[union-attr]  # (lstrip copied the text)
    close = data.find(b"?>", leading) if leading and data.startswith(b"<?xml", leading) else -1
    if close >= 0:
        warnings.append(
            XmlSyntax.diagnostic(
                "the XML declaration is not at the very start of the file; read as if it were",
                Span(path, line_of(data, leading), 1),
                severity=Severity.WARNING,
                help="remove the blank lines before <?xml ...?>",
            )
        )
        # The declaration is blanked where it stands (its line breaks kept), so every element
        # keeps its line and column; moving the blank lines behind it shifted the columns of
        # whatever followed it on its line. Without a declaration libxml2 reads UTF-8, which
        # the text is by now (to_utf8).
        end = close + 2
        data = data[:leading] + _blank(data[leading:end]) + data[end:]
    if path.lower().endswith((".sdf", ".world")):
        data = _scoped_tags(data, path, warnings)
        data = _declare_prefixes(data, path, warnings)
    stripped = data.rstrip(b"\0\r\n\t ") if b"\0" in data else data  # (rstrip copies the text)
    if b"\0" in data[len(stripped) :]:
        warnings.append(
            XmlSyntax.diagnostic(
                "file ends with NUL bytes after the root element; they are ignored",
                Span(path, line_of(data, len(stripped)), 1),
                severity=Severity.WARNING,
                help="remove the trailing NUL bytes",
            )
        )
        data = stripped + b"\n"
    return data, warnings


_BINARY = re.compile(rb"[\x00-\x08\x0e-\x1f]")


def _explain(message: str, data: bytes) -> tuple[str, str | None]:
    """libxml2's message in the user's terms, and a hint, for the commonest failures."""
    if not data.strip():
        return "file is empty", "a URDF starts with <robot name=\"...\">"
    head = data[:4096]
    binary = _BINARY.search(head)
    first_tag = head.find(b"<")
    if binary and (first_tag < 0 or binary.start() < first_tag or len(_BINARY.findall(head)) >= 8):
        offset = binary.start()
        return (
            f"file is binary data, not XML (control byte 0x{data[offset]:02x} at byte {offset})",
            "check that this is the robot description and not a mesh or an archive",
        )
    if message.startswith("Excessive depth"):
        return (
            "elements nest deeper than 256 levels; urdftool refuses such documents",
            "a robot description nests a few levels deep: look for unclosed or runaway elements",
        )
    if "Invalid bytes in character encoding" in message or "not proper UTF-8" in message:
        return (
            "file is not valid UTF-8 here: " + message,
            'save the file as UTF-8, or declare its encoding: <?xml version="1.0" encoding="ISO-8859-1"?>',
        )
    if "Premature end of data" in message or _ends_early(data):
        return f"file ends before the document is complete (truncated?): {message}", None
    return message, None


def _ends_early(data: bytes) -> bool:
    """True when the text does not end with a closing tag (a cut-off file)."""
    return not data.rstrip().endswith(b">") or data.rstrip().endswith(b"<")


#: what may stand in the prolog before a document type declaration: a byte order mark, space,
#: the XML declaration and processing instructions, comments
_PROLOG_ITEM = re.compile(rb"\xef\xbb\xbf|\s+|<\?.*?\?>|<!--.*?-->", re.S)


def _prolog_end(data: bytes) -> int:
    """Where the prolog's space, declaration, processing instructions and comments end: a
    document type declaration, if any, starts there."""
    position = 0
    while (match := _PROLOG_ITEM.match(data, position)) is not None and match.end() > position:
        position = match.end()
    return position


def _entities_refused(path: str, line: int) -> Diagnostic:
    return XmlSyntax.diagnostic(
        "entity declarations are not allowed in robot descriptions (they can expand "
        "without bound or read other files)",
        Span(path, line, 1),
        help="replace entities with xacro properties, or write the values out",
    )


def _first_element(data: bytes) -> int:
    match = re.search(rb"<[A-Za-z_]", data)
    return match.start() if match else len(data)


def read_file(
    path: str, kind: str = "model", table: bool = False
) -> tuple[XmlDocument | None, list[Diagnostic]]:
    """Read and parse *path* (positions in a table with *table*, see :class:`XmlDocument`).
    Raises :class:`OSError` when the file cannot be read
    (:class:`~urdftool.safe_files.UnsafeFile` when it is not a regular file)."""
    data = read_up_to(path, kind)
    return parse_bytes(data, path, kind=kind, table=table)


def xacro_in_urdf(
    root: etree._Element, locate: Callable[[etree._Element], Span | None] = span_of
) -> Diagnostic | None:
    """A ``xacro-in-urdf`` finding when the URDF document *root* uses xacro elements
    (*locate* gives an element's span: :meth:`XmlDocument.span` for a tabled document)."""
    # The first element, in document order, whose namespace is xacro's; XPath walks the tree in C.
    found = _XACRO_ELEMENT(root)
    if isinstance(found, list) and found and isinstance(found[0], etree._Element):
        element = found[0]
        tag = etree.QName(element).localname
        return XacroInUrdf.diagnostic(
            f"this .urdf file uses xacro (<xacro:{tag}>): xacro and the loaders that read it "
            "directly (urdfdom, PyBullet, MuJoCo, which skip xacro elements and read ${…} as text) "
            "can read it differently",
            locate(element),
            help="rename it to .urdf.xacro, or ship the expanded URDF",
            data={"element": f"xacro:{tag}"},
        )
    return None


_XACRO_ELEMENT = etree.XPath("descendant-or-self::*[contains(namespace-uri(), 'wiki/xacro')][1]")


def uses_substitution(root: etree._Element) -> bool:
    """Whether an attribute or a text (not a comment) of *root*'s document holds a xacro
    substitution, ``$(…)`` or ``${…}``."""
    return bool(_SUBSTITUTION(root))


_SUBSTITUTION = etree.XPath("(//@*[contains(., '$(') or contains(., '${')]"
                            " | //text()[contains(., '$(') or contains(., '${')])[1]")
