"""ERROR handlers, run as the controller runs them: an error a routine meets (RAISE, division by
zero, an index outside its array, a robtarget CalcJointT cannot reach) goes to the routine's
ERROR handler when it takes that error number, with ERRNO set. There RETRY runs the statement
again (at most ``MAX_RETRIES`` times), TRYNEXT goes on after it, RETURN returns, RAISE passes
the error to the caller, and a handler that ends returns from the routine. An error no handler
takes stops the task at its line. BACKWARD and UNDO handlers are parsed, never run."""

from __future__ import annotations

from . import nodes as n
from .errors import RapidError, fail
from .flow import Returned

MAX_RETRIES = 4  # the controller's "No Of Retry" default


class _Retry(Exception):
    pass


class _TryNext(Exception):
    pass


def takes(interp, frame, err: RapidError) -> bool:
    """Whether ``frame``'s routine has an ERROR handler for ``err`` (and is not already in it)."""
    routine = frame.routine
    if routine is None or routine.error is None or frame.handling is not None:
        return False
    if not routine.error_numbers:
        return True
    return any(interp.ev(e, frame) == err.errno for e in routine.error_numbers)


def recover(interp, run, s, frame, err: RapidError) -> None:
    """Run the handler for ``err`` met in statement ``s``, then what it says: ``run(s)`` again
    (RETRY), or go on (TRYNEXT); RETURN and RAISE leave as exceptions."""
    for _ in range(MAX_RETRIES):
        if _handle(interp, frame, err) == "trynext":
            return
        try:
            run(s)
            return
        except RapidError as again:
            if not takes(interp, frame, again):
                raise
            err = again
    raise err


def _handle(interp, frame, err: RapidError) -> str:
    interp.cell("errno", "ERRNO", frame, err.line).set(float(err.errno))
    frame.handling = err
    try:
        interp.body(frame.routine.error, frame)
    except _Retry:
        return "retry"
    except _TryNext:
        return "trynext"
    finally:
        frame.handling = None
    raise Returned(None)  # a handler that ends returns from its routine


def jump(interp, s: n.Jump, frame) -> None:
    """RETRY, TRYNEXT and RAISE."""
    err = frame.handling
    if s.kind in ("retry", "trynext"):
        if err is None:
            fail(interp.path, s.line, f"{s.kind.upper()} outside an ERROR handler")
        raise _Retry() if s.kind == "retry" else _TryNext()
    if s.expr is None:
        if err is None:
            fail(interp.path, s.line, "RAISE without an error number outside an ERROR handler")
        raise err  # to the caller's handler
    errno = interp.number(s.expr, frame, "RAISE's error number")
    raise RapidError(interp.path, s.line, f"RAISE {n.written(s.expr)} ({errno:g}): no ERROR handler takes this error, "
                                          "so the task stops here", errno, n.written(s.expr))
