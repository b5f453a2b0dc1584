"""Open any RSXML-family file: a component (.rsxml), a LibraryCompiler or a LibraryResource XML.

``check`` returns everything found (model and diagnostics); ``load`` raises on errors.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

from ..errors import Diagnostic, Diagnostics, RsxmlError
from ..files import file_size_limit, no_cyclic_gc
from .library import (
    LibraryCompiler,
    LibraryResource,
    read_library,
    read_resource,
    resolve_relative,
    with_descriptions,
)
from .model import Mechanism, SmartComponent
from .parse import local, namespace, parse_xml
from .read import NS_LIBRARY, NS_RESOURCE, read_component_root
from .validate import robot_name_parts, validate_mechanism, validate_smart_component


class RsxmlWarning(UserWarning):
    """A problem worth knowing that does not stop a model from loading."""


@dataclass(frozen=True)
class Report:
    """What ``check`` found in one file: the kind of document, its model and every problem."""

    path: str
    kind: str  # Mechanism, SmartComponent, GraphicComponentGroup, Part, LibraryCompiler, LibraryResource
    model: object | None
    diagnostics: tuple[Diagnostic, ...]
    children: tuple["Report", ...] = ()  # the sources a LibraryCompiler file builds

    @property
    def all_diagnostics(self) -> list[Diagnostic]:
        return list(self.diagnostics) + [d for c in self.children for d in c.all_diagnostics]

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.all_diagnostics if d.severity == "error"]

    @property
    def warnings(self) -> list[Diagnostic]:
        return [d for d in self.all_diagnostics if d.severity == "warning"]

    @property
    def ok(self) -> bool:
        return not self.errors


MAX_LIBRARY_DEPTH = 32  # LibraryCompiler files building LibraryCompiler files, at most this deep


def check(path: str | Path, *, max_file_size: int | None = None) -> Report:
    """Read and validate one file; never raises for bad input (problems are in the report).

    Files are read within ``max_file_size`` bytes (default ``rswarp.files.DEFAULT_MAX_FILE_SIZE``)."""
    with file_size_limit(max_file_size), no_cyclic_gc():
        return _Checker().check(str(path), 0)


class _Checker:
    """One ``check`` run: each file is read and validated once, however many libraries build it
    (without that, two Library entries per level double the work at every level)."""

    def __init__(self):
        self.done: dict[str, Report] = {}
        self.open: set[str] = set()  # libraries being checked: a source among them is a cycle

    def check(self, file: str, depth: int) -> Report:
        diags = Diagnostics()
        try:
            root = parse_xml(file)
        except RsxmlError as exc:
            return Report(file, "unknown", None, tuple(exc.diagnostics))
        ns, kind = namespace(root), local(root)
        if ns == NS_LIBRARY and kind == "LibraryCompiler":
            lib = read_library(root, file, diags)
            key = _key(file)
            self.open.add(key)
            try:
                subs = self._sources(lib, diags, depth)
            finally:
                self.open.discard(key)
            return Report(file, kind, lib, tuple(diags.finish()), subs)
        if ns == NS_RESOURCE and kind == "LibraryResource":
            return Report(file, kind, read_resource(root, file, diags), tuple(diags.finish()))
        model = read_component_root(root, file, diags)
        if isinstance(model, Mechanism):
            validate_mechanism(model, file, diags)
        elif isinstance(model, SmartComponent):
            validate_smart_component(model, file, diags)
            model = self._describe(model, Path(file).parent, diags)
        return Report(file, kind, model, tuple(diags.finish()))

    def _source(self, lib: LibraryCompiler, entry, diags: list[Diagnostic], depth: int) -> tuple[Report | None, bool]:
        """The report of one Library source (None: not checkable), and whether this is its first check."""
        key = _key(entry.source_path)
        if key in self.open:
            diags.append(Diagnostic(lib.path, entry.line, f"Library source '{entry.source}' refers back to itself"))
            return None, False
        if key in self.done:
            return self.done[key], False
        if depth >= MAX_LIBRARY_DEPTH:
            diags.append(Diagnostic(lib.path, entry.line, f"Library sources nest deeper than {MAX_LIBRARY_DEPTH} "
                                    f"levels; '{entry.source}' is not checked"))
            return None, False
        self.done[key] = self.check(entry.source_path, depth + 1)
        return self.done[key], True

    def _sources(self, lib: LibraryCompiler, diags: list[Diagnostic], depth: int) -> tuple[Report, ...]:
        """Check every source a library builds, and its Revision against the component's name.
        A source built twice is reported once (under its first Library)."""
        reports = []
        for entry in lib.libraries:
            component = entry.component
            if entry.source_path:
                sub, first = self._source(lib, entry, diags, depth)
                if sub is None:
                    continue
                if first:
                    reports.append(sub)
                component = sub.model
            elif isinstance(component, SmartComponent):
                validate_smart_component(component, lib.path, diags)
                component = self._describe(component, Path(lib.path).parent, diags)
            elif isinstance(component, Mechanism):
                validate_mechanism(component, lib.path, diags)
            _revision(lib, entry, component, diags)
        return tuple(reports)

    def _describe(self, sc: SmartComponent, folder: Path, diags: list[Diagnostic]) -> SmartComponent:
        """Attach descriptions from ``<name>.<language>.xml`` beside the component (English first)."""
        try:
            names = [p for p in folder.iterdir() if p.name.startswith(f"{sc.name}.") and p.suffix == ".xml"
                     and len(p.suffixes) >= 2]
        except OSError:
            return sc
        for path in sorted(names, key=lambda p: (p.suffixes[-2:-1] != [".en"], p.name)):
            report = self.check(str(path), 0)
            if isinstance(report.model, LibraryResource):
                diags.extend(report.diagnostics)
                _unknown_descriptions(sc, report.model, path, diags)
                return with_descriptions(sc, report.model)
        return sc


def _key(file: str) -> str:
    return str(Path(file).resolve())


def _revision(lib: LibraryCompiler, entry, component, diags: list[Diagnostic]) -> None:
    """Warn when a Library's Revision disagrees with the revision in its robot's name."""
    name = getattr(component, "name", None)
    parts = robot_name_parts(name) if name else None
    rev = entry.properties.revision
    if parts and rev is not None and rev != parts["revision"]:
        diags.append(Diagnostic(lib.path, entry.line, f"Revision {rev} disagrees with the revision "
                                f"{parts['revision']} in the name '{name}'", "warning"))


def _unknown_descriptions(sc: SmartComponent, resource: LibraryResource, path: Path, diags: list[Diagnostic]) -> None:
    known = {p.name for p in sc.properties} | {s.name for s in sc.signals}
    for e in resource.entries:
        for c in e.children if e.name == sc.name else ():
            if c.name not in known:
                diags.append(Diagnostic(str(path), c.line, f"{c.kind} '{c.name}' is not in SmartComponent "
                                        f"'{sc.name}'", "warning"))


def checked(path: str | Path, *, max_file_size: int | None = None) -> Report:
    """The report of a file without errors; raise ``RsxmlError`` (every error) otherwise."""
    report = check(path, max_file_size=max_file_size)
    if report.errors:
        raise RsxmlError(report.errors)
    return report


def load_mechanism(path: str | Path, *, max_file_size: int | None = None) -> tuple[Mechanism, Report]:
    """A mechanism file's model and report (its warnings); any other kind of file is refused."""
    report = checked(path, max_file_size=max_file_size)
    if not isinstance(report.model, Mechanism):
        raise RsxmlError(Diagnostic(report.path, 1, f"this is a {report.kind}, not a mechanism"))
    return report.model, report


def load(path: str | Path, *, max_file_size: int | None = None):
    """Read and validate a component file (.rsxml); raise ``RsxmlError`` on any error.

    Returns a ``Mechanism`` for a mechanism file (a ``SmartComponent``, ``Group`` or ``Part`` for
    those roots); warnings are issued as ``RsxmlWarning``.
    """
    report = check(path, max_file_size=max_file_size)
    if report.errors:
        raise RsxmlError(report.errors)
    if report.kind in ("LibraryCompiler", "LibraryResource"):
        raise RsxmlError(Diagnostic(report.path, 1, f"this is a {report.kind} file, not a component: "
                                                   "use rswarp.load_library"))
    for w in report.warnings:
        warnings.warn(str(w), RsxmlWarning, stacklevel=2)
    return report.model


def load_library(path: str | Path, *, max_file_size: int | None = None) -> LibraryCompiler:
    """Read a LibraryCompiler XML and check every source it builds; raise ``RsxmlError`` on errors."""
    report = check(path, max_file_size=max_file_size)
    if report.errors:
        raise RsxmlError(report.errors)
    if report.kind != "LibraryCompiler":
        raise RsxmlError(Diagnostic(report.path, 1, f"this is a {report.kind} file, not a LibraryCompiler file"))
    for w in report.warnings:
        warnings.warn(str(w), RsxmlWarning, stacklevel=2)
    return report.model


__all__ = ["Report", "RsxmlWarning", "check", "checked", "load", "load_library", "load_mechanism", "resolve_relative"]
