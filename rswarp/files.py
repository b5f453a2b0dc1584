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
import tempfile
import threading
from pathlib import Path
from typing import Iterator

from .errors import InputError

DEFAULT_MAX_FILE_SIZE = 256 * 1024 * 1024  # bytes: the largest input file (model, library, mesh) read
_max_file_size = contextvars.ContextVar("rswarp_max_file_size", default=DEFAULT_MAX_FILE_SIZE)


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
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:64]}.", suffix=".tmp", dir=_folder(path))
        except OSError as exc:
            raise output_error(path, exc) from None
        try:
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
            usual_mode(tmp)
            commit(tmp, path)
        except OSError as exc:
            Path(tmp).unlink(missing_ok=True)
            raise output_error(path, exc) from None
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise


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


def _interrupt(signum, frame) -> None:
    _interrupted.set()
    raise KeyboardInterrupt


@contextlib.contextmanager
def note_interrupts() -> Iterator[None]:
    """For the block, Ctrl-C raises KeyboardInterrupt as usual and is also noted, so that one
    swallowed on its way (a library's catch-all around its optional imports: trimesh's around
    scipy) still stops the next ``commit``: no output is put in place after a Ctrl-C."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _interrupted.clear()
    previous = signal.signal(signal.SIGINT, _interrupt)
    try:
        yield
        stop_if_terminated()
    finally:
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
