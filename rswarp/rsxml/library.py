"""LibraryCompiler XML (how .rsxml files become .rslib libraries) and LibraryResource XML
(localized descriptions): their model and their reader."""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from pathlib import Path

from lxml import etree

from ..errors import Diagnostic
from .parse import children, local, namespace
from .read import NS_COMPONENT, Reader, read_component_root

PROPERTY_TAGS = ("Title", "Author", "Revision", "Image")


@dataclass(frozen=True)
class Image:
    """A library preview: generated (with zoom/pan/flip) or taken from ``source``."""

    generate: bool | None = None
    source: str | None = None
    zoom: float | None = None
    panx: float | None = None
    pany: float | None = None
    flip: str | None = None


@dataclass(frozen=True)
class DocumentProperties:
    """Library metadata; ``extra`` holds other property elements as (tag, text)."""

    title: str | None = None
    author: str | None = None
    revision: str | None = None
    image: Image | None = None
    extra: tuple[tuple[str, str], ...] = ()

    def over(self, base: "DocumentProperties") -> "DocumentProperties":
        """These properties where given, ``base``'s elsewhere (DocumentProperties over DefaultProperties)."""
        merged = {f.name: getattr(self, f.name) if getattr(self, f.name) is not None else getattr(base, f.name)
                  for f in fields(self) if f.name != "extra"}
        mine = dict(self.extra)
        extra = tuple((k, v) for k, v in base.extra if k not in mine) + self.extra
        return DocumentProperties(**merged, extra=extra)


@dataclass(frozen=True)
class Variant:
    """A ``Variant`` of a library: its XML attributes and the properties it overrides."""

    name: str | None
    options: tuple[tuple[str, str], ...] = ()
    properties: DocumentProperties = DocumentProperties()
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class LibraryEntry:
    """One ``Library``: the component it compiles and its effective properties."""

    file_name: str
    source: str | None = None  # as written, may use backslashes
    source_path: str | None = None  # resolved on disk, None if not found
    properties: DocumentProperties = DocumentProperties()  # defaults merged with own
    own: DocumentProperties = DocumentProperties()
    variants: tuple[Variant, ...] = ()
    component: object | None = None  # an inline SmartComponent/Mechanism
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class LibraryCompiler:
    path: str
    defaults: DocumentProperties = DocumentProperties()
    libraries: tuple[LibraryEntry, ...] = ()


@dataclass(frozen=True)
class ResourceEntry:
    """A localized description of a component, property or signal."""

    kind: str
    name: str
    description: str | None = None
    children: tuple["ResourceEntry", ...] = ()
    line: int = field(default=0, compare=False)


@dataclass(frozen=True)
class LibraryResource:
    path: str
    language: str | None
    entries: tuple[ResourceEntry, ...] = ()

    def descriptions(self, component: str) -> dict[str, str]:
        """Descriptions by name for one component: '' is the component itself."""
        out = {}
        for e in self.entries:
            if e.name == component:
                if e.description:
                    out[""] = e.description
                out.update({c.name: c.description for c in e.children if c.description})
        return out


def resolve_relative(base_dir: Path, source: str) -> Path | None:
    """A path written in a file (``dir\\file.rsxml`` allowed, absolute or relative to ``base_dir``),
    found case-insensitively; None when there is no such file (or the name cannot be one)."""
    posix = source.replace("\\", "/")
    rel = Path(posix) if posix.startswith("/") else Path(*posix.split("/"))
    try:
        direct = base_dir / rel  # an absolute rel replaces base_dir
        if direct.exists():
            return direct
        folder = Path(rel.anchor) if rel.is_absolute() else base_dir
        for part in rel.parts[1:] if rel.is_absolute() else rel.parts:
            if not folder.is_dir():
                return None
            match = [p for p in folder.iterdir() if p.name.lower() == part.lower()]
            if not match:
                return None
            folder = match[0]
        return folder
    except OSError:  # a name too long, a folder that cannot be listed: not a file we can read
        return None


def _properties(r: Reader, el: etree._Element) -> DocumentProperties:
    values: dict[str, object] = {}
    extra = []
    for c in r.children(el):
        tag = local(c)
        if tag == "Image":
            r.known(c, ("generate", "source", "zoom", "panx", "pany", "flip"))
            values["image"] = Image(generate=r.boolean(c, "generate", None), source=r.text(c, "source"),
                                    zoom=r.number(c, "zoom"), panx=r.number(c, "panx"), pany=r.number(c, "pany"),
                                    flip=r.text(c, "flip"))
        elif tag in PROPERTY_TAGS:
            values[tag.lower()] = (c.text or "").strip()
        else:
            extra.append((tag, (c.text or "").strip()))
    return DocumentProperties(**values, extra=tuple(extra))


def read_library(root: etree._Element, file: str, diagnostics: list[Diagnostic]) -> LibraryCompiler:
    """Read a LibraryCompiler root (any namespace prefix); sources are resolved, not yet read."""
    r = Reader(file, diagnostics)
    base_dir = Path(file).parent
    defaults, entries = DocumentProperties(), []
    for el in r.children(root):
        tag = local(el)
        if tag == "DefaultProperties":
            defaults = _properties(r, el)
        elif tag == "Library":
            entries.append(el)
        else:
            r.warn(el, f"unknown element <{tag}> in <LibraryCompiler> ignored")
    libraries = [_library_entry(r, el, defaults, base_dir, diagnostics) for el in entries]
    _check_entries(r, libraries)
    return LibraryCompiler(path=file, defaults=defaults, libraries=tuple(libraries))


def _library_entry(r: Reader, el: etree._Element, defaults: DocumentProperties, base_dir: Path,
                   diagnostics: list[Diagnostic]) -> LibraryEntry:
    """One ``Library``: its source or inline component, its properties and variants, its fileName."""
    r.known(el, ("source", "fileName"))
    source = r.text(el, "source")
    own, variants, component = DocumentProperties(), [], None
    for c in children(el):  # an inline component is in the component namespace
        tag = local(c)
        if namespace(c) not in (namespace(el), NS_COMPONENT):
            r.foreign(c)
        elif tag == "DocumentProperties":
            own = _properties(r, c)
        elif tag == "Variant":
            props = next((_properties(r, p) for p in r.children(c) if local(p) == "DocumentProperties"),
                         DocumentProperties())
            variants.append(Variant(name=c.get("name"), options=r.options(c, ("name",)),
                                    properties=props.over(own.over(defaults)), line=c.sourceline or 0))
        elif namespace(c) == NS_COMPONENT:
            component = read_component_root(c, r.file, diagnostics)
        else:
            r.warn(c, f"unknown element <{tag}> in <Library> ignored")
    file_name = r.text(el, "fileName")
    if not file_name:
        if source:
            file_name = Path(source.replace("\\", "/")).stem + ".rslib"
        elif component is not None:
            file_name = f"{getattr(component, 'name', 'component')}.rslib"
        else:
            file_name = ""
    if source is None and component is None:
        r.error(el, "Library has neither a source nor a component inside")
    elif source == "":
        r.error(el, "Library has an empty source")
    path = resolve_relative(base_dir, source) if source else None
    if source and path is None:
        r.error(el, f"Library source '{source}' not found (looked for {base_dir / source.replace(chr(92), '/')})")
    return LibraryEntry(file_name=file_name, source=source, source_path=str(path) if path else None,
                        properties=own.over(defaults), own=own, variants=tuple(variants), component=component,
                        line=el.sourceline or 0)


def _check_entries(r: Reader, libraries: list[LibraryEntry]) -> None:
    """Libraries built twice under one fileName, and libraries without a Title."""
    seen: dict[str, int] = {}
    for lib in libraries:
        if lib.file_name and lib.file_name.lower() in seen:
            first = seen[lib.file_name.lower()]
            r.error(lib.line, f"fileName '{lib.file_name}' is built twice (first at line {first})")
        seen.setdefault(lib.file_name.lower(), lib.line)
        if not lib.properties.title:
            r.warn(lib.line, f"Library '{lib.file_name}' has no Title")


def read_resource(root: etree._Element, file: str, diagnostics: list[Diagnostic]) -> LibraryResource:
    """Read a LibraryResource file ``Name.<language>.xml``."""
    r = Reader(file, diagnostics)

    def entry(el: etree._Element) -> ResourceEntry:
        return ResourceEntry(kind=local(el), name=r.text(el, "name", True) or "", description=el.get("description"),
                             children=tuple(entry(c) for c in r.children(el)), line=el.sourceline or 0)

    suffixes = Path(file).suffixes
    language = suffixes[-2].lstrip(".") if len(suffixes) >= 2 and suffixes[-1].lower() == ".xml" else None
    if language is None:
        r.warn(root, "a LibraryResource file should be named <Name>.<language>.xml")
    return LibraryResource(path=file, language=language, entries=tuple(entry(c) for c in r.children(root)))


def with_descriptions(component, resource: LibraryResource):
    """The component with its descriptions from a resource file attached (for info and exports)."""
    return replace(component, descriptions=tuple(sorted(resource.descriptions(component.name).items())))

