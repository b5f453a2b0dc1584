"""Prim names for every stage rswarp writes: valid USD identifiers, unique among their siblings.
Every module that writes a stage imports this one, so Newton's schemas are registered with USD
before any stage exists (USD reads its schema plugins once, when the first stage is made)."""

from __future__ import annotations

import newton_usd_schemas  # noqa: F401 (registers Newton's schemas, NewtonJointAPI and others, with USD)
from pxr import Tf


class PrimNames:
    """Valid, unique prim names; the RSXML name is kept as displayName. A name that is one of the
    exporter's own scopes (``RESERVED``) is renamed, with a warning, so it never takes their place."""

    RESERVED = frozenset({"joints", "cables", "visuals", "collisions"})

    def __init__(self, warnings: list[str] | None = None):
        self.used: set[str] = set(self.RESERVED) if warnings is not None else set()
        self.warnings = warnings

    def __call__(self, name: str, what: str = "") -> str:
        base = Tf.MakeValidIdentifier(name or "unnamed")
        out, i = base, 1
        while out in self.used:
            out, i = f"{base}_{i}", i + 1
        self.used.add(out)
        if base in self.RESERVED and self.warnings is not None:
            self.warnings.append(f"{what or 'prim'} '{name}': named '{out}' in USD ('{base}' is the exporter's own "
                                 "scope); its display name stays")
        return out
