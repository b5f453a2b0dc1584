"""Errors of a RAPID task, always at a file and line: ``fail`` raises the ``RsxmlError`` the
command line prints as ``file:line: message`` (exit 1)."""

from __future__ import annotations

from ..errors import Diagnostic, RsxmlError


def fail(path: str, line: int, message: str):
    """Raise ``RsxmlError`` at ``path:line``."""
    raise RsxmlError(Diagnostic(path, line, message))


def warning(path: str, line: int, message: str) -> Diagnostic:
    return Diagnostic(path, line, message, "warning")


class RapidError(RsxmlError):
    """An error RAPID lets a routine's ERROR handler take (RAISE, division by zero, an index
    outside its array, a robtarget CalcJointT cannot reach): ``errno`` is ERRNO's value there."""

    def __init__(self, path: str, line: int, message: str, errno: float, name: str = ""):
        super().__init__(Diagnostic(path, line, message))
        self.errno, self.name = errno, name


def rapid_error(path: str, line: int, message: str, name: str):
    """Raise the controller's error ``name`` (ERR_DIVZERO, ...) at ``path:line``."""
    from .predefined import error_number

    raise RapidError(path, line, message, error_number(name), name)


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
