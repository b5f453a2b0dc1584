"""A model as the files a worker rebuilds it from: the RSXML file's bytes plus every mesh file it
uses (and environment meshes), each under the SHA-256 of its content (``Package``). A worker writes
them into a folder of its own, reads the model there like any file, and keeps it, with whatever
tasks built from it (kernels, bodies), for every later task of the same model. Here, a model run
locally is the same interface over the files where they are (``LocalModel``)."""

from __future__ import annotations

import atexit
import hashlib
import json
import os
import re
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from ..errors import InputError
from ..files import read_regular
from ..geometry.meshes import part_mesh_path
from ..rsxml.documents import load_mechanism
from ..rsxml.model import Mechanism


@dataclass(frozen=True)
class Package:
    """A model's files as workers rebuild them: paths relative to a common folder, each with the
    SHA-256 of its bytes (``key`` hashes them all, naming the model on every worker)."""

    key: str
    model: str  # the RSXML file
    files: tuple[tuple[str, str], ...]  # (relative path, sha256), the RSXML file among them
    extra: dict[str, str] = field(default_factory=dict, compare=False)  # a driver path -> its relative path


def package(mech: Mechanism, extra: Sequence[str | Path] = ()) -> tuple[Package, dict[str, bytes]]:
    """The package of ``mech`` (its file and every mesh its parts use) plus ``extra`` files
    (environment meshes), and the bytes of each hash."""
    if not mech.path:
        raise InputError(f"mechanism '{mech.name}' was not read from a file: a Ray run ships the RSXML file "
                         "its workers read")
    paths = [_absolute(mech.path), *_mesh_files(mech), *(_absolute(p) for p in extra)]
    paths = list(dict.fromkeys(_with_sidecars(paths)))
    root = Path(os.path.commonpath([str(p.parent) for p in paths]))
    blobs: dict[str, bytes] = {}
    files = []
    for p in paths:
        data = read_regular(p)
        digest = hashlib.sha256(data).hexdigest()
        blobs[digest] = data
        files.append((p.relative_to(root).as_posix(), digest))
    key = hashlib.sha256(json.dumps(files).encode()).hexdigest()[:16]
    extra_rel = {str(e): _absolute(e).relative_to(root).as_posix() for e in extra}
    return Package(key, files[0][0], tuple(files), extra_rel), blobs


def _mesh_files(mech: Mechanism) -> list[Path]:
    out = []
    for link in mech.link_names:
        for part, _ in mech.parts(link):
            found = part_mesh_path(mech, part)
            if found is not None:
                out.append(_absolute(found))
    return out


def _absolute(path: str | Path) -> Path:
    """An absolute path, symbolic links kept: a mesh reached through a linked folder must lie at
    the same place relative to the model on a worker as here."""
    return Path(os.path.abspath(path))


def _with_sidecars(paths: list[Path]) -> list[Path]:
    """The files plus those a glTF or OBJ file names beside it (buffers, textures, materials)."""
    out = []
    for p in paths:
        out.append(p)
        try:
            if p.suffix.lower() == ".gltf":
                doc = json.loads(read_regular(p))
                names = [b.get("uri", "") for key in ("buffers", "images") for b in doc.get(key, [])]
            elif p.suffix.lower() == ".obj":
                names = re.findall(rb"^mtllib\s+(.+?)\s*$", read_regular(p), re.M)
                names = [n.decode(errors="replace") for n in names]
            else:
                continue
        except (OSError, ValueError, AttributeError):
            continue  # the mesh reader says what is wrong with the file itself
        for n in names:
            side = _absolute(p.parent / n)
            if n and not n.startswith("data:") and side.is_file():
                out.append(side)
    return out


class LocalModel:
    """A mechanism and its files where they are: what a local run's tasks build from."""

    def __init__(self, mech: Mechanism):
        self.mech = mech
        self._built: dict[Any, Any] = {}

    def local(self, driver_path: str) -> str:
        """Where a file given on the driver lies for this run: where it is."""
        return str(driver_path)

    def cached(self, key, build: Callable[[], Any]):
        """``build()`` once per model and ``key`` (kernels, bodies)."""
        if key not in self._built:
            self._built[key] = build()
        return self._built[key]


class ShippedModel(LocalModel):
    """A model rebuilt on a worker from its package, in a folder of the worker's own."""

    def __init__(self, pkg: Package, folder: Path):
        super().__init__(load_mechanism(folder / pkg.model)[0])
        self.key, self.folder = pkg.key, folder
        self.extra = {driver: str(folder / rel) for driver, rel in pkg.extra.items()}

    def local(self, driver_path: str) -> str:
        """Where an extra file given on the driver lies on this worker."""
        return self.extra[str(driver_path)]


_SHIPPED: dict[str, ShippedModel] = {}  # per worker process: models by key


_WORKER_FOLDER = re.compile(r"rswarp-[0-9a-f]{16}-(\d+)-")


def _sweep_dead_workers() -> None:
    """Remove the copies of workers that are gone: Ray ends its workers without running their
    ``atexit`` handlers. Only folders of this user's whose process no longer runs."""
    for folder in Path(tempfile.gettempdir()).glob("rswarp-*-*-*"):
        m = _WORKER_FOLDER.match(folder.name)
        try:
            if m is None or folder.is_symlink() or folder.stat().st_uid != os.getuid():
                continue
            os.kill(int(m.group(1)), 0)
        except ProcessLookupError:
            shutil.rmtree(folder, ignore_errors=True)
        except (OSError, ValueError, OverflowError):  # alive but another's, or unreadable: left alone
            continue


def unpack(pkg: Package, fetch: Callable[[str], bytes]) -> ShippedModel:
    """The model on this worker, written out and read on the first task that needs it; ``fetch``
    gives the bytes of a hash (from the object store), each checked against it."""
    if pkg.key not in _SHIPPED:
        if not _SHIPPED:
            _sweep_dead_workers()
        folder = Path(tempfile.mkdtemp(prefix=f"rswarp-{pkg.key}-{os.getpid()}-"))
        atexit.register(shutil.rmtree, folder, True)  # the worker's copy goes with the worker
        for rel, digest in pkg.files:
            data = fetch(digest)
            if hashlib.sha256(data).hexdigest() != digest:
                raise RuntimeError(f"the object store returned other bytes for {rel}")
            target = folder / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        _SHIPPED[pkg.key] = ShippedModel(pkg, folder)
    return _SHIPPED[pkg.key]
