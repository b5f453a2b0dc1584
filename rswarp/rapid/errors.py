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
