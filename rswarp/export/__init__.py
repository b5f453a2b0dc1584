"""Exports: OpenUSD (flat or component layout), URDF and Newton models, with one frame convention
(``frames``) and one entry point that picks the format from the output's suffix (``export``)."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

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
    if not density > 0:
        raise InputError(f"density must be positive, not {density:g}")
    if not (path.parent if str(path.parent) else Path(".")).is_dir():
        raise InputError(f"{path.parent}: no such folder")
    suffix = path.suffix.lower()
    if suffix == ".urdf":
        if not isinstance(model, Mechanism):
            raise InputError("URDF export takes a mechanism file")
        from .urdf import to_urdf

        return to_urdf(model, path, density=density)
    if suffix in USD_SUFFIXES:
        from .usd_layout import to_usd

        return to_usd(model, path, density=density, collision=collision, layout=layout)
    raise InputError(f"{path}: the output must end in .usda, .usdc, .usdz or .urdf")
