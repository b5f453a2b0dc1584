"""The two kinds of failure a user can cause, kept apart from bugs: ``InputError`` (a bad argument,
path or setting) and its file-bound kind ``RsxmlError`` (``file:line: message``). The command line
turns these into exit 1; any other exception is an internal error (exit 2)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable

Warn = Callable[[str], None]  # one line for people, on stderr at the command line


def ignore(text: str) -> None:
    """A ``warn`` that drops the line (library callers read the results instead)."""


@dataclass(frozen=True)
class Diagnostic:
    """One problem in an input file; ``line`` is 0 when it concerns the whole file."""

    file: str
    line: int
    message: str
    severity: str = "error"  # "error", "warning" or "note" (what an input set, said)
    repeats: int = 1  # the problems this line stands for (a summary of many alike)

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line else self.file
        prefix = f"{self.severity}: " if self.severity in ("warning", "note") else ""
        return one_line(f"{where}: {prefix}{self.message}")


MAX_ALIKE = 20  # problems of one kind a file reports one by one; the rest are counted in one line
_NAMES = re.compile(r"<[^<>]*>|'[^']*'|\"[^\"]*\"|-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


class Diagnostics(list):
    """A file's problems as they are found, at most MAX_ALIKE of a kind (a message with its names
    and numbers left out): a file of millions of unknown elements costs a few lines and a count,
    not millions of objects. ``finish`` adds the line that counts the rest of each kind."""

    def __init__(self):
        super().__init__()
        self._alike: dict[tuple[str, str, str], list] = {}

    def append(self, d: Diagnostic) -> None:
        kind = (d.file, d.severity, _NAMES.sub("~", d.message))
        seen = self._alike.setdefault(kind, [0, d])
        seen[0] += 1
        if seen[0] <= MAX_ALIKE:
            super().append(d)

    def finish(self) -> "Diagnostics":
        for (file, severity, _), (n, first) in self._alike.items():
            if n > MAX_ALIKE:
                super().append(Diagnostic(file, 0, f"{n - MAX_ALIKE} more like: {first.message}", severity,
                                          n - MAX_ALIKE))
        self._alike = {}
        return self


_CONTROL = {c: f"\\x{c:02x}" for c in (*range(32), 127)} | {10: "\\n", 13: "\\r", 9: "\\t"}


def one_line(text: str) -> str:
    """``text`` with control characters escaped, so a newline in a file or link name cannot split
    a diagnostic line (or forge another)."""
    return text.translate(_CONTROL)


class InputError(ValueError):
    """Input rswarp cannot use (an argument, a path, a model unfit for the job); ``str()`` is one line
    saying what and where. A ValueError, so Python callers may catch either."""


class RsxmlError(InputError):
    """Raised for a file rswarp cannot use; ``str()`` is the first problem as ``file:line: message``."""

    def __init__(self, diagnostics: list[Diagnostic] | Diagnostic):
        if isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics = [d for d in diagnostics if d.severity == "error"] or list(diagnostics)
        first = self.diagnostics[0]
        self.file, self.line, self.message = first.file, first.line, first.message
        super().__init__(str(first))


class MeshNotFoundError(RsxmlError):
    """A Part's geometry was needed but no mesh file of its name exists; names every file tried.
    Exports go on without that Part (a warning): the kinematics are still worth having."""


class MeshError(RsxmlError):
    """A Part's mesh file exists but cannot be used (unreadable, corrupt, flat): an error in every
    export, since going on would silently drop geometry the author meant to be there."""


def model_error(model, message: str, line: int | None = None) -> RsxmlError:
    """An RsxmlError about a whole model (a Mechanism or SmartComponent), at its file and line."""
    file = getattr(model, "path", None) or getattr(model, "name", "<model>")
    return RsxmlError(Diagnostic(file, getattr(model, "line", 0) if line is None else line, message))


def nearest(key: str, names) -> str | None:
    """The name ``key`` most likely misspells: one or two letters off, a swapped pair counting as one
    (``pWrok`` for ``pWork``), case ignored; None where none is that near."""
    best, found = (3 if len(key) >= 5 else 2 if len(key) >= 3 else 0), None
    for name in names:
        d = _distance(key.lower(), name.lower(), best)
        if d < best:
            best, found = d, name
    return found if found is not None and found.lower() != key.lower() else None


def _distance(a: str, b: str, cap: int) -> int:
    """Edits (insert, delete, change, swap two neighbours) from ``a`` to ``b``, or ``cap`` if more."""
    if abs(len(a) - len(b)) >= cap:
        return cap
    before, row = None, list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        now = [i] + [0] * len(b)
        for j, cb in enumerate(b, 1):
            now[j] = min(row[j] + 1, now[j - 1] + 1, row[j - 1] + (ca != cb))
            if before is not None and i > 1 and j > 1 and ca == b[j - 2] and a[i - 2] == cb:
                now[j] = min(now[j], before[j - 2] + 1)
        if min(now) >= cap:
            return cap
        before, row = row, now
    return min(row[-1], cap)
