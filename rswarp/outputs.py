"""The files rswarp writes on its own, and never a file it did not write. A folder rswarp fills (a
sweep's, a collision sweep's, a cable run's, a library build's) holds a manifest, ``.rswarp.json``:
each file it wrote there, with the SHA-256 of what it wrote. A file is rswarp's only when the
manifest names it with its present content, so a user's file, even one named like an output and
even one rswarp wrote and the user then changed, is never replaced or deleted; a folder holding
anything else is refused before any work starts.

A set of outputs is written into a temporary folder beside the target, which then replaces the
target whole (``atomic_folder``): a reader never sees a mixed set, and a failure, a Ctrl-C or a
SIGTERM leaves the target as it was and nothing beside it."""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Iterable, Iterator

from .errors import InputError
from .files import (
    atomic_write,
    cleanup_on_terminate,
    commit,
    new_folders,
    output_error,
    read_regular,
    signals_held,
    stop_if_terminated,
    usual_mode,
)

MANIFEST = ".rswarp.json"
MAX_MANIFEST = 1 << 20  # bytes: a manifest larger than this is not rswarp's


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def manifest(folder: Path) -> dict[str, str]:
    """The files rswarp wrote into ``folder`` (and the folders it wrote there), by path relative to
    it, with their SHA-256 then; {} where none. A ``.rswarp.json`` that is not rswarp's manifest
    (the user's own file of that name) is an ``InputError``: rswarp then touches nothing there."""
    path = folder / MANIFEST
    try:
        if not (path.exists() or path.is_symlink()):
            return {}
        doc = None
        if not path.is_symlink() and path.is_file() and path.stat().st_size <= MAX_MANIFEST:
            doc = json.loads(read_regular(path))
    except (OSError, ValueError, RecursionError):
        doc = None
    files = doc.get("files") if isinstance(doc, dict) and doc.get("written_by") == "rswarp" else None
    if not isinstance(files, dict):
        raise InputError(f"{path}: is not rswarp's manifest (a file of yours?): rswarp writes nothing into "
                         f"{folder}; write elsewhere")
    return {k: v for k, v in files.items() if isinstance(k, str) and isinstance(v, str)}


def owned(path: Path, listed: dict[str, str] | None = None) -> bool:
    """Whether ``path`` is a file rswarp wrote and nobody changed since (its folder's manifest), or
    a folder holding only such files."""
    listed = manifest(path.parent) if listed is None else listed
    try:
        return all(not f.is_symlink() and f.is_file() and listed.get(rel) == _digest(f)
                   for rel, f in _files(path, path.name))
    except OSError:
        return False


def _files(path: Path, rel: str) -> Iterator[tuple[str, Path]]:
    """(relative path, path) of ``path`` if a file or a link, else of every file below it."""
    if path.is_symlink() or not path.is_dir():
        yield rel, path
        return
    for child in sorted(path.iterdir()):
        yield from _files(child, f"{rel}/{child.name}")


def record(folder: Path, names: Iterable[str]) -> None:
    """Note in ``folder``'s manifest the files (or folders of files) ``names`` as rswarp wrote them
    just now."""
    listed = manifest(folder)
    for name in names:
        for rel, f in _files(folder / name, name):
            listed[rel] = _digest(f)
    atomic_write(folder / MANIFEST, (json.dumps({"written_by": "rswarp", "files": listed}, indent=1,
                                                sort_keys=True) + "\n").encode())


def claim(path: Path, made: Path | None = None) -> None:
    """``InputError`` unless ``path`` is free for rswarp to write: missing, or a file it wrote,
    in a folder that exists (or is ``made``, the run's own, written later) and whose manifest (if
    any) is rswarp's; never the manifest itself."""
    if path.name == MANIFEST:
        raise InputError(f"{path}: {MANIFEST} is the name of rswarp's manifest of a folder; name the output otherwise")
    if not str(path) or not path.name or path.is_dir():
        raise InputError(f"{path}: is a folder, not a file name" if str(path) else "an output's file name is empty")
    folder = _folder(path)
    if (made is None or folder.resolve() != Path(made).resolve()) and not folder.is_dir():
        raise InputError(f"{path}: {folder} {'is a file, not a folder' if folder.exists() else 'does not exist'}")
    if folder.is_dir() and not os.access(folder, os.W_OK | os.X_OK):
        raise InputError(f"{path}: cannot write in {folder} (permission denied)")
    manifest(_folder(path))
    try:
        taken = path.exists() or path.is_symlink()
    except OSError as exc:  # a name too long for the file system, say
        raise output_error(path, exc) from None
    if taken and not owned(path):
        raise InputError(f"{path}: exists and rswarp did not write it; move it, or write elsewhere")


@contextlib.contextmanager
def atomic_folder(out: str | Path) -> Iterator[Path]:
    """A temporary folder to write a set of files into; on success it replaces ``out`` as a whole,
    with a manifest of what it holds. ``out`` must be replaceable (``check_replaceable``)."""
    out = Path(out)
    check_replaceable(out)
    with cleanup_on_terminate(), new_folders(out):
        tmp = None
        try:
            with signals_held():  # the name is kept before a Ctrl-C can land
                tmp = Path(tempfile.mkdtemp(prefix=f".{out.name[:64]}.", suffix=".tmp", dir=_folder(out)))
            yield tmp
            record(tmp, sorted(p.name for p in tmp.iterdir() if p.name != MANIFEST))
            usual_mode(tmp)
            _swap_in(tmp, out)
        except OSError as exc:
            raise output_error(out, exc) from None
        finally:
            if tmp is not None:
                shutil.rmtree(tmp, ignore_errors=True)


def check_replaceable(out: Path) -> None:
    """``InputError`` unless ``out`` can be replaced by a new set of files: it is missing, empty, or
    holds only files rswarp wrote there and nobody changed since (its manifest: an earlier set, a
    video written into it), and its place can take a folder (not the current folder, a mount point,
    or a folder that cannot be renamed)."""
    out = Path(out)
    try:
        if out.is_symlink() or (out.exists() and not out.is_dir()):
            raise InputError(f"{out}: is a file, not a folder")
        _check_where(out)
        if out.exists():
            listed = manifest(out)
            foreign = sorted(p.name for p in out.iterdir() if p.name != MANIFEST and not owned(p, listed))
            if foreign:
                raise InputError(f"{out}: holds files rswarp did not write ({', '.join(foreign[:3])}"
                                 f"{', ...' if len(foreign) > 3 else ''}); name a new or empty folder")
        _check_rename(out)
    except OSError as exc:
        raise InputError(f"{out}: cannot use this folder: {exc.strerror or exc}") from None


def _check_where(out: Path) -> None:
    """``out`` is not a folder that can never be replaced: the current one, one holding it, a mount
    point."""
    here, target = Path.cwd().resolve(), out.resolve()
    if here == target or target in here.parents:
        raise InputError(f"{out}: is the current folder or holds it, which cannot be replaced; name a folder "
                         "inside it")
    if out.exists() and os.path.ismount(out):
        raise InputError(f"{out}: is a mount point, which cannot be replaced; name a folder inside it")


def _check_rename(out: Path) -> None:
    """The folder ``out`` can be put in place at the end: refused now, before any work, if not."""
    parent = _folder(out)
    if not parent.exists():
        return  # made when the work is done (new_folders), and removed again if it fails
    with signals_held():  # made, tried and removed in one piece: a Ctrl-C never leaves it, nor ``out`` in it
        probe = Path(tempfile.mkdtemp(prefix=f".{out.name[:64]}.", suffix=".probe", dir=parent))
        try:
            if out.exists():  # a folder that cannot be renamed (immutable, busy) says so now
                os.rename(out, probe / "x")
                os.rename(probe / "x", out)
        finally:
            shutil.rmtree(probe, ignore_errors=True)


def _folder(path: Path) -> Path:
    return path.parent if str(path.parent) else Path(".")


def _swap_in(tmp: Path, out: Path) -> None:
    """Rename ``tmp`` to ``out``; an existing ``out`` (checked to be ours) is renamed aside first and
    removed once the new one is in place. Whatever fails, the earlier set is put back (or, if even
    that fails, kept aside and named), and nothing else is left beside ``out``."""
    if not out.exists():
        commit(tmp, out)
        return
    stop_if_terminated()
    with signals_held():  # the swap is one piece: a Ctrl-C lands after it, never between its renames
        old = Path(tempfile.mkdtemp(prefix=f".{out.name[:64]}.", suffix=".old", dir=_folder(out)))
        aside = old / out.name
        try:
            os.replace(out, aside)
        except BaseException:
            shutil.rmtree(old, ignore_errors=True)  # still empty
            raise
        try:
            os.replace(tmp, out)
        except BaseException:
            try:
                os.replace(aside, out)
            except OSError:
                raise InputError(f"{out}: the new set could not be put in place, nor the earlier one back; "
                                 f"the earlier one is kept in {aside}") from None
            shutil.rmtree(old, ignore_errors=True)
            raise
    shutil.rmtree(old, ignore_errors=True)


def merge_folder(src: Path, out: Path) -> None:
    """Move the files of ``src`` into ``out``: the whole folder in one rename when ``out`` is
    missing, else file by file (each an atomic replace), so files in ``out`` that ``src`` does not
    name are kept and two writers racing for the same ``out`` both succeed."""
    stop_if_terminated()
    try:
        os.rename(src, out)
        return
    except OSError as exc:
        if exc.errno not in (errno.EEXIST, errno.ENOTEMPTY):
            raise
    for f in sorted(src.iterdir()):
        os.replace(f, out / f.name)
