"""Files in and out, safely. Inputs: only regular files, never more than a size limit (a FIFO or
``/dev/zero`` named as a model must not hang or eat memory), read without allocating the limit.
Outputs: written atomically (a temporary file beside the target, then a rename, ``commit``), so a
reader never sees half a file, an interrupted write leaves nothing behind (SIGTERM included), and a
failure the user can fix (a read-only folder, a name too long, a folder where a file should go) is
an ``InputError`` naming the path. Output folders and the files rswarp owns: ``outputs``."""

from __future__ import annotations

import contextlib
import contextvars
import gc
import os
import signal
import stat
import sys
import sysconfig
import tempfile
import threading
import time
from pathlib import Path
from typing import Iterator

from .errors import InputError

DEFAULT_MAX_FILE_SIZE = 256 * 1024 * 1024  # bytes: the largest input file (model, library, mesh) read
_max_file_size = contextvars.ContextVar("rswarp_max_file_size", default=DEFAULT_MAX_FILE_SIZE)


HELD_SIGNALS = {signal.SIGINT, signal.SIGTERM}


@contextlib.contextmanager
def signals_held():
    """Ctrl-C and SIGTERM held back while native code runs in the main thread (a kernel launch,
    Warp compiling a module with its in-process compiler, which installs handlers of its own), or
    while a temporary file is made and its name kept, and delivered, as KeyboardInterrupt or the
    SIGTERM handler, the moment the block ends."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "pthread_sigmask"):
        yield
        return
    before = signal.pthread_sigmask(signal.SIG_BLOCK, HELD_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, before)


def max_file_size() -> int:
    """The input size limit in force (``DEFAULT_MAX_FILE_SIZE`` unless set by ``file_size_limit``)."""
    return _max_file_size.get()


@contextlib.contextmanager
def file_size_limit(limit: int | None) -> Iterator[None]:
    """Read inputs of up to ``limit`` bytes within this block (None keeps the limit in force)."""
    if limit is None:
        yield
        return
    if not limit > 0:
        raise InputError(f"the file size limit must be positive, not {limit}")
    token = _max_file_size.set(int(limit))
    try:
        yield
    finally:
        _max_file_size.reset(token)


def _size_text(n: int) -> str:
    return f"{n / 2**20:.1f} MiB" if n >= 2**20 else f"{n} bytes"


def open_regular(path: str | Path) -> tuple[int, int]:
    """An open descriptor on a regular file and its size; ``OSError`` for anything else, without
    blocking on a FIFO (opened non-blocking, checked with fstat before any read)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            kind = "a folder" if stat.S_ISDIR(info.st_mode) else "not a regular file"
            raise OSError(f"{kind}: only regular files are read")
        limit = max_file_size()
        if info.st_size > limit:
            raise OSError(f"the file is {_size_text(info.st_size)}, over the {_size_text(limit)} limit "
                          "(raise it with --max-file-size)")
        return fd, info.st_size
    except BaseException:
        os.close(fd)
        raise


def read_regular(path: str | Path) -> bytes:
    """The bytes of a regular file of at most ``max_file_size()`` bytes; ``OSError`` otherwise."""
    fd, size = open_regular(path)
    with os.fdopen(fd, "rb") as fh:
        data = fh.read(size + 1)  # what fstat saw, and a byte more: the file may grow while being read
        if len(data) > size:
            data += fh.read(max_file_size() + 1 - len(data))
    if len(data) > max_file_size():
        raise OSError(f"the file grew past the {_size_text(max_file_size())} limit while being read")
    return data


def output_error(path: str | Path, exc: OSError) -> InputError:
    """An OSError met while writing ``path`` as the user's problem, in one line."""
    return InputError(f"{path}: cannot write: {exc.strerror or exc}")


def _folder(path: Path) -> Path:
    return path.parent if str(path.parent) else Path(".")


def atomic_write(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder, then rename; a
    SIGTERM meanwhile leaves neither (``cleanup_on_terminate``)."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder, not a file name")
    with cleanup_on_terminate():
        tmp = None
        try:
            with signals_held():  # the name is kept before a Ctrl-C can land
                fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:64]}.", suffix=".tmp", dir=_folder(path))
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
            usual_mode(tmp)
            commit(tmp, path)
        except OSError as exc:
            _unlink(tmp)
            raise output_error(path, exc) from None
        except BaseException:
            _unlink(tmp)
            raise


def _unlink(tmp: str | None) -> None:
    if tmp is not None:
        Path(tmp).unlink(missing_ok=True)


def usual_mode(path: str | Path) -> None:
    """mkstemp/mkdtemp make 0600/0700; a saved output gets the mode a plain create would give."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, (0o777 if Path(path).is_dir() else 0o666) & ~umask)


@contextlib.contextmanager
def new_folders(path: str | Path) -> Iterator[None]:
    """Create the missing folders above ``path`` for the block; remove those it created if the
    block fails, so a failed write leaves nothing behind (folders that existed are never touched)."""
    folder = _folder(Path(path))
    missing = []
    while not folder.exists() and folder != folder.parent:
        missing.append(folder)
        folder = folder.parent
    if not folder.is_dir():
        raise InputError(f"{folder}: not a folder")
    try:
        for f in reversed(missing):
            f.mkdir()
    except OSError as exc:
        _remove_empty(missing)
        raise output_error(missing[-1] if missing else folder, exc) from None
    try:
        yield
    except BaseException:
        _remove_empty(missing)
        raise


class Terminated(BaseException):
    """SIGTERM arrived while writing: raised so that every ``finally`` and ``with`` cleans up."""


_terminated = threading.Event()  # SIGTERM arrived during a write; set by the handler
_interrupted = threading.Event()  # Ctrl-C arrived: set by ``note_interrupts``' handler
_held = threading.Event()  # Ctrl-C arrived while the rswarp command started (``hold_start_interrupts``)
_retrying = threading.Event()  # a Ctrl-C waits for the main thread to be back in rswarp's own code
_retry: list = []  # the thread that delivers it again meanwhile, while one runs
_nudged = False  # the SIGINT now arriving is the retry thread's, not the user's
RETRY_S = 0.02  # s between deliveries of a Ctrl-C that waits
_OWN = os.path.dirname(os.path.abspath(__file__)) + os.sep
_STDLIB = tuple({os.path.join(sysconfig.get_paths()[k], "") for k in ("stdlib", "platstdlib")})
_SITE = tuple({os.path.join(sysconfig.get_paths()[k], "") for k in ("purelib", "platlib")})
_SAFE = (f"{os.sep}ray{os.sep}",)  # libraries built to be interrupted while the main thread waits in them


def _safe_to_raise(frame) -> bool:
    """Whether a KeyboardInterrupt may be raised in ``frame``: not inside an import (a native
    module's initialization aborts the process on it, or turns it into an ImportError; a library's
    catch-all around its optional imports swallows it), not in a finalizer (where it is printed as
    "Exception ignored"), and where the innermost code outside the standard library is rswarp's
    own, not a library's (Cython code that cannot pass it on prints and drops it, native code
    called back crashes): there a Ctrl-C waits until the library returns."""
    inner = None
    while frame is not None:
        code = frame.f_code
        if code.co_filename.startswith("<frozen importlib") or code.co_name == "__del__":
            return False
        name = code.co_filename
        if inner is None and not (name.startswith("<") or (name.startswith(_STDLIB) and not name.startswith(_SITE))):
            inner = name
        frame = frame.f_back
    return inner is None or inner.startswith(_OWN) or any(lib in inner for lib in _SAFE)


def _interrupt(signum, frame) -> None:
    """Ctrl-C within ``note_interrupts``: noted, and raised as KeyboardInterrupt where that is
    safe (``_safe_to_raise``); elsewhere delivered again every ``RETRY_S`` until it is."""
    global _nudged
    nudge, _nudged = _nudged, False
    _interrupted.set()
    if nudge and not _retrying.is_set():  # a retry's last delivery, after the interrupt was raised
        return
    if not _safe_to_raise(frame):
        _retry_later()
        return
    _retrying.clear()
    raise KeyboardInterrupt


def _retry_later() -> None:
    """Deliver SIGINT to the main thread again every ``RETRY_S`` until ``_retrying`` is cleared."""
    _retrying.set()
    if _retry and _retry[0].is_alive():
        return
    main = threading.main_thread().ident

    def deliver() -> None:
        global _nudged
        while True:
            time.sleep(RETRY_S)
            if not _retrying.is_set():
                return
            _nudged = True
            if hasattr(signal, "pthread_kill"):  # to the main thread: a wait it is in is cut short
                signal.pthread_kill(main, signal.SIGINT)
            else:
                import _thread

                _thread.interrupt_main()

    _retry[:] = [threading.Thread(target=deliver, name="rswarp-ctrl-c", daemon=True)]
    _retry[0].start()


def _stop_retrying() -> None:
    """No more deliveries; the last one, if any is on its way, lands in ``_interrupt`` and is dropped."""
    _retrying.clear()
    if _retry:
        _retry.pop().join()
        if _nudged:
            time.sleep(RETRY_S)  # a signal in flight is handled meanwhile


def _hold(signum, frame) -> None:
    _held.set()


def hold_start_interrupts() -> None:
    """In the ``rswarp`` command (its console script, or ``python -m rswarp.cli``), from the first
    import of the package until its ``main`` takes over (``note_interrupts``): Ctrl-C is noted,
    never raised, so that it cannot land in a native library's loading (an abort, exit 134) or
    among imports as a traceback; ``main`` then ends with 130 before any work. Imported as a
    library, nothing changes."""
    argv = getattr(sys, "argv", None) or [""]
    orig = list(getattr(sys, "orig_argv", ()))
    command = os.path.splitext(os.path.basename(argv[0]))[0] in ("rswarp", "rswarp-script") or \
        any(a == "-m" and b == "rswarp.cli" for a, b in zip(orig, orig[1:]))
    if command and threading.current_thread() is threading.main_thread() and \
            signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _hold)


hold_start_interrupts()  # imported first by the package: the command's start is held from here


def interrupted() -> bool:
    """Whether Ctrl-C arrived in the last ``note_interrupts`` block (a library may have swallowed it,
    or turned it into an error of its own)."""
    return _interrupted.is_set()


@contextlib.contextmanager
def note_interrupts() -> Iterator[None]:
    """For the block, Ctrl-C raises KeyboardInterrupt and is also noted, so that one swallowed on
    its way (a library's catch-all around its optional imports: trimesh's around scipy) still
    stops the next ``commit``: no output is put in place after a Ctrl-C. It is raised only where
    that is safe (``_safe_to_raise``), at once where rswarp's own code runs; one that came while
    the command started (``hold_start_interrupts``) is raised as the block begins. A SIGINT the
    process was started ignoring (``nohup``, a script's background job) stays ignored, as Python
    itself leaves it: else one sent in the first tenth of a second was lost and a later one not."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _interrupted.clear()
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        yield
        stop_if_terminated()
        return
    previous = signal.signal(signal.SIGINT, _interrupt)
    try:
        if _held.is_set():
            _held.clear()
            _interrupted.set()
            raise KeyboardInterrupt
        yield
        stop_if_terminated()
    finally:
        _stop_retrying()
        signal.signal(signal.SIGINT, previous)


@contextlib.contextmanager
def cleanup_on_terminate() -> Iterator[None]:
    """For the block, SIGTERM means stop: it is noted, and the next ``commit`` (or the block's end)
    raises ``Terminated`` instead of renaming anything into place, so every ``finally`` and
    ``with`` removes its temporary files and nothing half-done is kept. The handler itself raises
    nothing: an exception raised inside native code (pxr importing a module of its own, say) would
    be printed and swallowed there. Only the main thread can set handlers; elsewhere the block runs
    unchanged."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, lambda signum, frame: _terminated.set())
    outermost = previous in (signal.SIG_DFL, signal.SIG_IGN, None) or not callable(previous) or \
        getattr(previous, "__qualname__", "").split(".")[0] != "cleanup_on_terminate"
    try:
        yield
        stop_if_terminated()
    finally:
        signal.signal(signal.SIGTERM, previous)
        if outermost and _terminated.is_set():
            _terminated.clear()  # the run ends here, whatever else failed: as terminated
            raise Terminated()


def stop_if_terminated() -> None:
    """Raise ``Terminated`` if SIGTERM arrived during a write, and KeyboardInterrupt if Ctrl-C
    did, even one swallowed on its way."""
    if _terminated.is_set():
        raise Terminated()
    stop_if_interrupted()


def stop_if_interrupted() -> None:
    """Raise KeyboardInterrupt if Ctrl-C arrived and was swallowed on its way."""
    if _interrupted.is_set():
        raise KeyboardInterrupt


def commit(src: str | Path, dst: str | Path) -> None:
    """Rename a finished temporary file or folder into place, unless SIGTERM arrived meanwhile."""
    stop_if_terminated()
    os.replace(src, dst)


def _remove_empty(folders: list[Path]) -> None:
    for f in folders:  # deepest first
        with contextlib.suppress(OSError):
            f.rmdir()


@contextlib.contextmanager
def no_cyclic_gc():
    """Pause Python's cycle collector while an input is read: the millions of objects of a large
    model or module trigger it over and over, and reading makes no cycles to collect."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def cache_root() -> Path:
    """rswarp's cache folder: ``$RSWARP_CACHE_DIR``, else ``~/.cache/rswarp``."""
    return Path(os.environ.get("RSWARP_CACHE_DIR") or Path.home() / ".cache" / "rswarp")
