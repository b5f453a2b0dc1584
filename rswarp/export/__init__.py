"""Exports: OpenUSD (flat or component layout), URDF and Newton models, with one frame convention
(``frames``) and one entry point that picks the format from the output's suffix (``export``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..files import new_folders, output_error

USD_SUFFIXES = (".usda", ".usdc", ".usd", ".usdz")


@dataclass(frozen=True)
class Exported:
    """What an export wrote: the file, the warnings, and the physics it authored."""

    output: Path
    warnings: tuple[str, ...]
    physics: object  # physics.RobotPhysics
    mechanism: object  # rsxml.model.Mechanism


def export(model, path: str | Path, *, layout: str | None = None, mesh_paths: str | None = None, physics=None,
           **options) -> Exported:
    """Write ``model`` (a Mechanism, or a SmartComponent holding one) to ``path``: URDF for
    ``.urdf``, USD for ``.usda/.usdc/.usd/.usdz``. ``physics`` (a ``PhysicsOptions``, or its fields
    as keywords) says how it simulates. Bad settings raise InputError."""
    from ..files import cleanup_on_terminate
    from ..rsxml.model import Mechanism, SmartComponent
    from .frames import mechanism_of
    from .physics import PhysicsOptions, robot_physics

    if not isinstance(model, (Mechanism, SmartComponent)):
        raise InputError(f"a {type(model).__name__} does not export: only a mechanism (or a SmartComponent "
                         "holding one) does")
    path = Path(path)
    physics = physics or PhysicsOptions(**options)
    try:
        if path.is_dir():
            raise InputError(f"{path}: is a folder; name the file to write")
    except OSError as exc:
        raise output_error(path, exc) from None
    suffix = path.suffix.lower()
    if suffix == ".urdf" and not isinstance(model, Mechanism):
        raise InputError("URDF export takes a mechanism file")
    if suffix != ".urdf" and suffix not in USD_SUFFIXES:
        raise InputError(f"{path}: the output must end in .usda, .usdc, .usd, .usdz or .urdf")
    if suffix == ".urdf" and layout is not None:
        raise InputError("--layout applies to USD outputs only: a URDF is one file with a meshes/ folder beside it")
    if suffix != ".urdf" and mesh_paths is not None:
        raise InputError("--mesh-paths applies to URDF outputs only: a USD file holds its meshes")
    mech = mechanism_of(model)[0]
    robot = robot_physics(mech, physics)
    try:
        with cleanup_on_terminate(), new_folders(path):  # missing folders are made, and removed if it fails
            warnings = _write(model, path, suffix, robot, layout or "flat", mesh_paths or "absolute")
    except OSError as exc:
        raise output_error(path, exc) from None
    return Exported(path, tuple(warnings), robot, mech)


def _write(model, path: Path, suffix: str, physics, layout: str, mesh_paths: str) -> list[str]:
    if suffix == ".urdf":
        from .urdf import to_urdf

        return to_urdf(model, path, physics=physics, mesh_paths=mesh_paths)
    from .usd_layout import to_usd

    return to_usd(model, path, physics=physics, layout=layout)
