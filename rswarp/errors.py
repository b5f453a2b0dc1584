"""Diagnostics (``file:line: message``) and the one exception type rswarp raises for bad input."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Diagnostic:
    """One problem in an input file; ``line`` is 0 when it concerns the whole file."""

    file: str
    line: int
    message: str
    severity: str = "error"  # "error" or "warning"

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        prefix = "warning: " if self.severity == "warning" else ""
        return f"{where}: {prefix}{self.message}"


class RsxmlError(Exception):
    """Raised for an input rswarp cannot use; ``str()`` is the first problem as ``file:line: message``."""

    def __init__(self, diagnostics: list[Diagnostic] | Diagnostic):
        if isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics = [d for d in diagnostics if d.severity == "error"] or list(diagnostics)
        first = self.diagnostics[0]
        self.file, self.line, self.message = first.file, first.line, first.message
        super().__init__(str(first))


class MeshNotFoundError(RsxmlError):
    """A Part's geometry was needed but no mesh file of its name exists; names every file tried."""
