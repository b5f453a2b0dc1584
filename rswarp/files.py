"""Files in and out, safely. Inputs: only regular files, never more than a size limit (a FIFO or
``/dev/zero`` named as a model must not hang or eat memory). Outputs: written atomically (a temporary
file or folder beside the target, then a rename), so a reader never sees half a file or a mixed
set, an interrupted write leaves nothing behind, and a failure the user can fix (a read-only
folder, a name too long, a folder where a file should go) is an ``InputError`` naming the path."""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import shutil
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
        data = fh.read(max_file_size() + 1)  # the file may grow between fstat and read
    if len(data) > max_file_size():
        raise OSError(f"the file grew past the {_size_text(max_file_size())} limit while being read")
    return data


def output_error(path: str | Path, exc: OSError) -> InputError:
    """An OSError met while writing ``path`` as the user's problem, in one line."""
    return InputError(f"{path}: cannot write: {exc.strerror or exc}")


def _folder(path: Path) -> Path:
    return path.parent if str(path.parent) else Path(".")


def atomic_write(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder, then rename."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{path}: is a folder, not a file name")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name[:64]}.", suffix=".tmp", dir=_folder(path))
    except OSError as exc:
        raise output_error(path, exc) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        _usual_mode(tmp)
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise output_error(path, exc) from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _usual_mode(path: str | Path) -> None:
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


@contextlib.contextmanager
def cleanup_on_terminate() -> Iterator[None]:
    """For the block, SIGTERM raises ``Terminated`` (SIGINT already raises KeyboardInterrupt), so
    temporary files are removed before the process ends. Only the main thread can set handlers;
    elsewhere the block runs unchanged."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise Terminated()

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _remove_empty(folders: list[Path]) -> None:
    for f in folders:  # deepest first
        with contextlib.suppress(OSError):
            f.rmdir()


@contextlib.contextmanager
def atomic_folder(out: str | Path, owned: tuple[str, ...]) -> Iterator[Path]:
    """A temporary folder to write a set of files into; on success it replaces ``out`` as a whole.

    ``out`` may be missing, empty, or a folder that holds only files named in ``owned`` (an earlier
    run's set): it is swapped out and then removed. A folder holding anything else is refused, so
    no file the user owns is ever deleted."""
    out = Path(out)
    check_replaceable(out, owned)
    with cleanup_on_terminate(), new_folders(out):
        try:
            tmp = Path(tempfile.mkdtemp(prefix=f".{out.name[:64]}.", suffix=".tmp", dir=_folder(out)))
        except OSError as exc:
            raise output_error(out, exc) from None
        try:
            yield tmp
            _usual_mode(tmp)
            _swap_in(tmp, out)
        except OSError as exc:
            raise output_error(out, exc) from None
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


def check_replaceable(out: Path, owned: tuple[str, ...]) -> None:
    """``InputError`` unless ``out`` is missing, or a folder holding only files named in ``owned``."""
    try:
        if not out.exists():
            return
        if not out.is_dir():
            raise InputError(f"{out}: is a file, not a folder")
        foreign = sorted(p.name for p in out.iterdir() if p.name not in owned)
    except OSError as exc:
        raise InputError(f"{out}: cannot use this folder: {exc.strerror or exc}") from None
    if foreign:
        raise InputError(f"{out}: holds files rswarp did not write ({', '.join(foreign[:3])}"
                         f"{', ...' if len(foreign) > 3 else ''}); name a new or empty folder")


def _swap_in(tmp: Path, out: Path) -> None:
    """Rename ``tmp`` to ``out``; an existing ``out`` (checked to be ours) is renamed aside first."""
    if not out.exists():
        os.replace(tmp, out)
        return
    old = Path(tempfile.mkdtemp(prefix=f".{out.name[:64]}.", suffix=".old", dir=_folder(out)))
    os.replace(out, old / out.name)
    try:
        os.replace(tmp, out)
    except BaseException:
        os.replace(old / out.name, out)
        raise
    finally:
        shutil.rmtree(old, ignore_errors=True)


def merge_folder(src: Path, out: Path) -> None:
    """Move the files of ``src`` into ``out``: the whole folder in one rename when ``out`` is
    missing, else file by file (each an atomic replace), so files in ``out`` that ``src`` does not
    name are kept and two writers racing for the same ``out`` both succeed."""
    try:
        os.rename(src, out)
        return
    except OSError as exc:
        if exc.errno not in (errno.EEXIST, errno.ENOTEMPTY):
            raise
    for f in sorted(src.iterdir()):
        os.replace(f, out / f.name)
