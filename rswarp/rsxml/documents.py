"""Open any RSXML-family file: a component (.rsxml), a LibraryCompiler or a LibraryResource XML.

``check`` returns everything found (model and diagnostics); ``load`` raises on errors.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

from ..errors import Diagnostic, RsxmlError
from .library import (
    LibraryCompiler, LibraryResource, read_library, read_resource, resolve_relative, with_descriptions,
)
from .model import Mechanism, SmartComponent
from .read import NS_LIBRARY, NS_RESOURCE, local, namespace, parse_xml, read_component_root
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


def check(path: str | Path, _seen: frozenset[str] = frozenset()) -> Report:
    """Read and validate one file; never raises for bad input (problems are in the report)."""
    file = str(path)
    diags: list[Diagnostic] = []
    try:
        root = parse_xml(path)
    except RsxmlError as exc:
        return Report(file, "unknown", None, tuple(exc.diagnostics))
    ns, kind = namespace(root), local(root)
    if ns == NS_LIBRARY and kind == "LibraryCompiler":
        lib = read_library(root, file, diags)
        subs = _check_sources(lib, diags, _seen | {str(Path(file).resolve())})
        return Report(file, kind, lib, tuple(diags), subs)
    if ns == NS_RESOURCE and kind == "LibraryResource":
        return Report(file, kind, read_resource(root, file, diags), tuple(diags))
    model = read_component_root(root, file, diags)
    if isinstance(model, Mechanism):
        validate_mechanism(model, file, diags)
    elif isinstance(model, SmartComponent):
        validate_smart_component(model, file, diags)
        model = _describe(model, Path(file).parent, diags)
    return Report(file, kind, model, tuple(diags))


def _check_sources(lib: LibraryCompiler, diags: list[Diagnostic], seen: frozenset[str]) -> tuple[Report, ...]:
    """Check every source a library builds, and its Revision against the component's name."""
    reports = []
    for entry in lib.libraries:
        component = entry.component
        if entry.source_path:
            if str(Path(entry.source_path).resolve()) in seen:
                diags.append(Diagnostic(lib.path, entry.line, f"Library source '{entry.source}' refers back to itself"))
                continue
            sub = check(entry.source_path, seen)
            reports.append(sub)
            component = sub.model
        elif isinstance(component, SmartComponent):
            validate_smart_component(component, lib.path, diags)
            component = _describe(component, Path(lib.path).parent, diags)
        elif isinstance(component, Mechanism):
            validate_mechanism(component, lib.path, diags)
        name = getattr(component, "name", None)
        parts = robot_name_parts(name) if name else None
        rev = entry.properties.revision
        if parts and rev is not None and rev != parts["revision"]:
            diags.append(Diagnostic(lib.path, entry.line, f"Revision {rev} disagrees with the revision "
                                    f"{parts['revision']} in the name '{name}'", "warning"))
    return tuple(reports)


def _describe(sc: SmartComponent, folder: Path, diags: list[Diagnostic]) -> SmartComponent:
    """Attach descriptions from ``<name>.<language>.xml`` beside the component (English first)."""
    candidates = sorted(folder.glob(f"{sc.name}.*.xml"), key=lambda p: (p.suffixes[-2:-1] != [".en"], p.name))
    for path in candidates:
        report = check(path)
        if isinstance(report.model, LibraryResource):
            diags.extend(report.diagnostics)
            known = {p.name for p in sc.properties} | {s.name for s in sc.signals}
            for e in report.model.entries:
                for c in e.children if e.name == sc.name else ():
                    if c.name not in known:
                        diags.append(Diagnostic(str(path), c.line, f"{c.kind} '{c.name}' is not in SmartComponent "
                                                f"'{sc.name}'", "warning"))
            return with_descriptions(sc, report.model)
    return sc


def checked(path: str | Path) -> Report:
    """The report of a file without errors; raise ``RsxmlError`` (every error) otherwise."""
    report = check(path)
    if report.errors:
        raise RsxmlError(report.errors)
    return report


def load_mechanism(path: str | Path) -> tuple[Mechanism, Report]:
    """A mechanism file's model and report (its warnings); any other kind of file is refused."""
    report = checked(path)
    if not isinstance(report.model, Mechanism):
        raise RsxmlError(Diagnostic(report.path, 1, f"this is a {report.kind}, not a mechanism"))
    return report.model, report


def load(path: str | Path):
    """Read and validate a component file (.rsxml); raise ``RsxmlError`` on any error.

    Returns a ``Mechanism`` for a mechanism file (a ``SmartComponent``, ``Group`` or ``Part`` for
    those roots); warnings are issued as ``RsxmlWarning``.
    """
    report = check(path)
    if report.errors:
        raise RsxmlError(report.errors)
    if report.kind in ("LibraryCompiler", "LibraryResource"):
        raise RsxmlError(Diagnostic(report.path, 1, f"this is a {report.kind} file, not a component: "
                                                   "use rswarp.load_library"))
    for w in report.warnings:
        warnings.warn(str(w), RsxmlWarning, stacklevel=2)
    return report.model


def load_library(path: str | Path) -> LibraryCompiler:
    """Read a LibraryCompiler XML and check every source it builds; raise ``RsxmlError`` on errors."""
    report = check(path)
    if report.errors:
        raise RsxmlError(report.errors)
    if report.kind != "LibraryCompiler":
        raise RsxmlError(Diagnostic(report.path, 1, f"this is a {report.kind} file, not a LibraryCompiler file"))
    for w in report.warnings:
        warnings.warn(str(w), RsxmlWarning, stacklevel=2)
    return report.model


__all__ = ["Report", "RsxmlWarning", "check", "checked", "load", "load_library", "load_mechanism", "resolve_relative"]
