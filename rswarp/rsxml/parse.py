"""Safe XML and number parsing for the RSXML family.

The document is parsed with entities, DTDs and network off, from a regular file within the size
limit. No DTD may supply, remove or change a value: a DOCTYPE that declares anything (an element,
an attribute list with its defaults, an entity, a notation) is refused at its line, and so is a
reference to any entity but XML's five, in content or in an attribute value, where a parser would
drop it without a word. Both are decided on the document's text decoded in its own encoding, with
comments and CDATA sections left out, so every encoding is judged alike and a comment that mentions
``<!ENTITY`` is harmless. Numbers are plain ASCII decimals, as RobotStudio writes them.
"""

from __future__ import annotations

import codecs
import math
import re
from pathlib import Path

from lxml import etree

from ..errors import Diagnostic, RsxmlError
from ..files import read_regular

NON_FINITE = ("nan", "+nan", "-nan", "inf", "+inf", "-inf", "infinity", "+infinity", "-infinity")
MAX_NUMBER = 1e30  # any number beyond this is out of range (float32 overflows past 3.4e38)


def number(text: str) -> float:
    """An RSXML number: a plain ASCII decimal within ±1e30; ``ValueError`` saying why otherwise."""
    text = text.strip()
    # float() alone would also take "1_80", non-ASCII digits ("١٨٠"), "nan" and "inf"
    if text.isascii() and "_" not in text:
        try:
            value = float(text)
        except ValueError:
            raise ValueError(f"a bad number '{text}'") from None
        if abs(value) <= MAX_NUMBER:
            return value
        if math.isnan(value) or (math.isinf(value) and text.lower() in NON_FINITE):
            raise ValueError(f"a non-finite number '{text}'")
        raise ValueError(f"a number out of range '{text}'")
    raise ValueError(f"a bad number '{text}'")


def _parser(recover: bool = False) -> etree.XMLParser:
    return etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False, load_dtd=False,
                           dtd_validation=False, remove_pis=True, remove_comments=False,  # kept for save
                           remove_blank_text=True,  # whitespace between elements costs a node each
                           recover=recover)


def parse_xml(path: str | Path) -> etree._Element:
    """Parse an XML file safely; raise RsxmlError(file:line: ...) when it is not usable XML."""
    file = str(path)
    try:
        data = read_regular(path)
    except OSError as exc:
        raise RsxmlError(Diagnostic(file, 0, f"cannot read file: {exc.strerror or exc}")) from None
    try:
        root = etree.fromstring(data, _parser(), base_url=None)
    except etree.XMLSyntaxError as exc:
        _refuse_entities(_recovered(data), data, file)  # an entity may be why it failed: say so
        line = exc.lineno or 0
        msg = exc.msg.split(f", line {line}")[0] if exc.msg else "not well-formed XML"
        if "amplification" in msg:  # libxml2 stopped an entity bomb inside an attribute
            raise RsxmlError(Diagnostic(file, line, "entity expansion too large: entities are refused")) from None
        raise RsxmlError(Diagnostic(file, line, f"XML syntax error: {msg}")) from None
    _refuse_entities(root, data, file)
    _refuse_dtd(data, root.getroottree().docinfo.encoding, file)
    return root


def _recovered(data: bytes) -> etree._Element | None:
    """What libxml2's recovery mode makes of a broken document (same safe settings), or None."""
    try:
        return etree.fromstring(data, _parser(recover=True), base_url=None)
    except etree.XMLSyntaxError:
        return None


def _refuse_entities(root: etree._Element | None, data: bytes, file: str) -> None:
    """External-entity and entity-bomb attacks start with a declaration or a reference: refuse both."""
    if root is None:
        return
    tree = root.getroottree()
    dtd = tree.docinfo.internalDTD
    declared = list(dtd.iterentities()) if dtd is not None else []
    if declared:
        first = declared[0]
        kind = "external entity" if first.system_url else "entity"
        line = _declaration_line(data, tree.docinfo.encoding, first.name)
        raise RsxmlError(Diagnostic(file, line, f"{kind} '{first.name}' declared in the DOCTYPE: entities are refused"))
    for node in root.iter(etree.Entity):
        raise RsxmlError(Diagnostic(file, node.sourceline or 0,
                                    f"entity reference {node.text} to an external DTD: entities are refused"))


PREDEFINED = frozenset({"amp", "lt", "gt", "quot", "apos"})
_HIDDEN = re.compile(r"<!--.*?-->|<!\[CDATA\[.*?\]\]>", re.S)  # text that holds no markup
_SUBSET = re.compile(r"<!DOCTYPE\b[^\[>]*\[(.*?)\]\s*>", re.S)
_REFERENCE = re.compile(r"&([A-Za-z_:][-\w.:]*);")


def _refuse_dtd(data: bytes, encoding: str | None, file: str) -> None:
    """A DOCTYPE that declares anything, or a reference to an entity XML does not predefine, is an
    error at its line: no DTD supplies, removes or changes a value."""
    try:
        text = codecs.decode(data, encoding or "utf-8")
    except (LookupError, ValueError):
        return  # the parser read it: it is the encoding lxml reports; nothing else to judge by
    text = _HIDDEN.sub(lambda m: "\n" * m.group(0).count("\n"), text)  # keep the line count
    subset = _SUBSET.search(text)
    if subset and re.search(r"<!|%", subset.group(1)):
        line = text.count("\n", 0, subset.start()) + 1
        raise RsxmlError(Diagnostic(file, line, "the DOCTYPE declares elements, attributes or entities: DTDs are "
                                                "refused, so that no DTD supplies or changes a value"))
    for m in _REFERENCE.finditer(text):
        if m.group(1) not in PREDEFINED:
            line = text.count("\n", 0, m.start()) + 1
            raise RsxmlError(Diagnostic(file, line, f"entity reference &{m.group(1)}; is not one of XML's own: "
                                                    "entities are refused"))


def _declaration_line(data: bytes, encoding: str | None, name: str) -> int:
    """The line of ``<!ENTITY name`` in the document's own encoding (1 when it cannot be told)."""
    try:
        text = codecs.decode(data, encoding or "utf-8")
    except (LookupError, ValueError):
        return 1
    m = re.search(r"<!ENTITY\s+(?:%\s+)?" + re.escape(name) + r"[\s\"']", text)
    return text.count("\n", 0, m.start()) + 1 if m else 1


def prolog_comments(root: etree._Element) -> tuple[str, ...]:
    """The comments before the root element (a licence or provenance note), in document order."""
    return tuple(c.text or "" for c in reversed(list(root.itersiblings(etree.Comment, preceding=True))))


def local(el: etree._Element) -> str:
    return etree.QName(el).localname


def namespace(el: etree._Element) -> str | None:
    return etree.QName(el).namespace


def children(el: etree._Element) -> list[etree._Element]:
    """Element children (comments and processing instructions dropped)."""
    return [c for c in el if isinstance(c.tag, str)]
