"""Exports: OpenUSD (flat or component layout), URDF and Newton models, with one frame convention
(``frames``) and one entry point that picks the format from the output's suffix (``export``)."""

from __future__ import annotations

import math
from pathlib import Path

from ..errors import InputError
from ..files import new_folders, output_error

USD_SUFFIXES = (".usda", ".usdc", ".usd", ".usdz")


def export(model, path: str | Path, *, layout: str = "flat", collision: str = "convexHull",
           density: float | None = None) -> list[str]:
    """Write ``model`` (a Mechanism, or a SmartComponent holding one) to ``path``: URDF for
    ``.urdf``, USD for ``.usda/.usdc/.usd/.usdz``. Returns warnings; bad settings raise InputError."""
    from ..geometry import DEFAULT_DENSITY
    from ..rsxml.model import Mechanism, SmartComponent

    if not isinstance(model, (Mechanism, SmartComponent)):
        raise InputError(f"a {type(model).__name__} does not export: only a mechanism (or a SmartComponent "
                         "holding one) does")
    path = Path(path)
    density = DEFAULT_DENSITY if density is None else density
    if not (math.isfinite(density) and density > 0):
        raise InputError(f"density must be a finite number > 0, not {density:g}")
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
    try:
        with new_folders(path):  # missing folders are made, and removed again if the export fails
            return _write(model, path, suffix, density, collision, layout)
    except OSError as exc:
        raise output_error(path, exc) from None


def _write(model, path: Path, suffix: str, density: float, collision: str, layout: str) -> list[str]:
    if suffix == ".urdf":
        from .urdf import to_urdf

        return to_urdf(model, path, density=density)
    from .usd_layout import to_usd

    return to_usd(model, path, density=density, collision=collision, layout=layout)
