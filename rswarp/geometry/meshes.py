"""Link geometry: find the mesh that stands in for a Part's CAD source, load it (lazily, with
trimesh) and place it in the world at the zero position, in metres.

RobotStudio loads ``link1.rsgfx`` in place of ``link1.SAT`` when it exists; rswarp does the same
with a mesh of the same stem (case-insensitive).
"""

from __future__ import annotations

import hashlib
import io
import os
from collections import OrderedDict
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..errors import Diagnostic, MeshError, MeshNotFoundError, one_line
from ..files import read_regular
from ..rsxml.model import Mechanism, Part

MESH_EXTENSIONS = (".stl", ".obj", ".ply", ".glb", ".gltf", ".off")
METRIC_EXTENSIONS = (".glb", ".gltf")  # glTF is metres by its own spec; the others carry no unit


def mesh_candidates(source: str, folder: Path) -> list[Path]:
    """The files that may stand in for ``source``, in the order they are tried."""
    rel = Path(*source.replace("\\", "/").split("/"))
    base = folder / rel.parent
    names = [rel.name] if rel.suffix.lower() in MESH_EXTENSIONS else []
    names += [rel.stem + ext for ext in MESH_EXTENSIONS]
    return [base / n for n in names]


def find_mesh(source: str, folder: Path) -> Path | None:
    """The first candidate that exists, matching names case-insensitively (None if none does, or
    the name cannot be a file: too long, a folder that cannot be listed)."""
    try:
        return _first_existing(mesh_candidates(source, folder))
    except OSError:
        return None


def _first_existing(candidates: list[Path]) -> Path | None:
    for cand in candidates:
        if cand.exists():
            return cand
        if cand.parent.is_dir():
            for p in cand.parent.iterdir():
                if p.name.lower() == cand.name.lower() and p.is_file():
                    return p
    return None


def _folder(mech: Mechanism) -> Path:
    return Path(mech.path).parent if mech.path else Path.cwd()


def part_mesh_path(mech: Mechanism, part: Part) -> Path | None:
    return find_mesh(part.source, _folder(mech)) if part.source else None


SIDECAR_FORMATS = (".gltf", ".obj")  # may name other files (buffers, materials) beside them
_MESHES: OrderedDict = OrderedDict()  # (content hash, suffix, folder for sidecar formats) -> mesh
CACHED_MESHES = 64


def _load(path: str):
    """The mesh in a file, or ``ValueError`` saying in one line why it cannot be used. Meshes are
    kept by content hash: a file that several variants (or copies) share is parsed once."""
    try:
        stat = Path(path).stat()
        digest = _digest(str(Path(path).resolve()), stat.st_mtime_ns, stat.st_size)
    except OSError as exc:
        raise ValueError(f"cannot read it: {exc.strerror or exc}") from None
    suffix = Path(path).suffix.lower()
    key = (digest, suffix, str(Path(path).resolve().parent) if suffix in SIDECAR_FORMATS else "")
    if key in _MESHES:
        _MESHES.move_to_end(key)
        return _MESHES[key]
    mesh = _parse(path, suffix)
    _MESHES[key] = mesh
    if len(_MESHES) > CACHED_MESHES:
        _MESHES.popitem(last=False)
    return mesh


@lru_cache(maxsize=256)
def _digest(path: str, mtime_ns: int, size: int) -> str:
    """The content hash of a file, read once while it is unchanged (bounded read: a regular file
    within the size limit)."""
    return hashlib.sha256(read_regular(path)).hexdigest()


def _guarded_resolver(path: str):
    """A trimesh resolver that reads the files a mesh names (glTF buffers and images, an OBJ's
    materials) as rswarp reads any input: regular files only, within the size limit, so a name of
    a FIFO cannot hang a load and a name of a huge file cannot fill memory."""
    from trimesh.resolvers import FilePathResolver

    class GuardedResolver(FilePathResolver):
        def get(self, name: str) -> bytes:
            for candidate in (name.strip(), name.strip().lstrip("/"), os.path.split(name)[-1]):
                try:
                    found = self.absolute(candidate)
                except ValueError:
                    continue
                if found.exists():
                    try:
                        return read_regular(found)
                    except OSError as exc:
                        raise ValueError(f"'{name}', which it names: {exc}") from None
            self.absolute(name)  # a name that escapes the mesh's folder says so
            raise FileNotFoundError(name)

    return GuardedResolver(path)


def _parse(path: str, suffix: str):
    """The mesh in a file, read as every input is (``read_regular``), with the files it names."""
    import trimesh  # imported on first use: kinematics never needs it

    kind = suffix.lstrip(".")
    try:
        data = read_regular(path)
    except OSError as exc:
        raise ValueError(f"cannot read it: {exc.strerror or exc}") from None
    try:  # process=True merges STL vertices
        mesh = trimesh.load(io.BytesIO(data), file_type=kind, resolver=_guarded_resolver(path), force="mesh")
    except Exception as exc:  # trimesh raises many types (even ImportError) for broken files
        detail = "" if isinstance(exc, ImportError) else f" ({one_line(str(exc))[:120]})"
        raise ValueError(f"not a readable {kind} file{detail}") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ValueError(f"the {kind} file holds no triangles")
    if not np.all(np.isfinite(mesh.vertices)):
        raise ValueError("it has non-finite vertex coordinates")
    centred = mesh.vertices - mesh.vertices.mean(axis=0)
    s = np.linalg.svd(centred, compute_uv=False)
    if len(s) < 3 or s[2] <= 1e-9 * max(s[0], 1e-300):
        raise ValueError("it is flat (all its points lie in one plane or line): no volume for a mass "
                         "or a collision hull; give the part a solid mesh or remove it")
    return mesh


def part_mesh(mech: Mechanism, part: Part, transform: np.ndarray | None = None):
    """The Part's mesh in world coordinates at the zero position, metres; ``transform`` is the
    Part's placement (see ``Mechanism.parts``). Raises MeshNotFoundError naming the files tried
    when there is no mesh, MeshError when the mesh found cannot be used."""
    file = mech.path or "<memory>"
    if not part.source:
        raise MeshNotFoundError(Diagnostic(file, part.line, f"part '{part.name}' has no source"))
    path = part_mesh_path(mech, part)
    if path is None:
        tried = ", ".join(str(p) for p in mesh_candidates(part.source, _folder(mech)))
        raise MeshNotFoundError(Diagnostic(file, part.line, f"no mesh for part '{part.name}' "
                                           f"(source '{part.source}'); looked for {tried}"))
    try:
        return file_mesh(mech, path, transform)
    except (ValueError, OSError) as exc:
        raise MeshError(Diagnostic(file, part.line, f"mesh {path} of part '{part.name}': {exc}")) from None


def file_mesh(mech: Mechanism, path: Path, transform: np.ndarray | None = None):
    """The mesh in a file, in metres (read in the document's length unit unless glTF), moved by
    ``transform``; ValueError or OSError saying in one line why it cannot be used."""
    import trimesh

    loaded = _load(str(path))
    scale = 1.0 if path.suffix.lower() in METRIC_EXTENSIONS else mech.length_factor
    m = (np.eye(4) if transform is None else transform) @ np.diag([scale, scale, scale, 1.0])
    # a new mesh on the moved vertices, sharing the faces: no copy of the loaded mesh's caches
    vertices = loaded.vertices @ m[:3, :3].T + m[:3, 3]
    faces = loaded.faces if np.linalg.det(m[:3, :3]) > 0 else loaded.faces[:, ::-1]
    return trimesh.Trimesh(vertices, faces, visual=loaded.visual, process=False, validate=False)


def closed_link_meshes(mech: Mechanism):
    """(index, name, trimesh.Trimesh) of each link whose parts make one closed mesh (world, zero
    position): the links an inside test can trust; the others are left to the run's winding
    numbers."""
    import trimesh

    for j, name in enumerate(mech.graph.links):
        try:
            mesh = link_mesh(mech, name)
        except MeshNotFoundError:
            continue
        if mesh is not None and mesh.is_watertight:
            yield j, name, trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)


def link_mesh(mech: Mechanism, link: str):
    """All Parts of a link as one mesh (world, zero position, metres); None if it has no geometry."""
    import trimesh

    meshes = [part_mesh(mech, p, m) for p, m in mech.parts(link) if p.source]
    return trimesh.util.concatenate(meshes) if meshes else None


GRAPHITE_WHITE = (215 / 255, 215 / 255, 215 / 255)  # the authoring guide's colour for ABB robots


def mesh_color(mesh) -> tuple[float, float, float]:
    """The mesh's own uniform colour if it defines one, else Graphite White (RGB, 0 to 1)."""
    visual = getattr(mesh, "visual", None)
    try:
        if visual is not None and visual.kind in ("face", "vertex") and visual.defined:
            rgba = np.asarray(visual.main_color, float) / 255.0
            return tuple(float(c) for c in rgba[:3])
    except Exception:  # trimesh visuals of odd files raise many types; the default colour is fine
        pass
    return GRAPHITE_WHITE
