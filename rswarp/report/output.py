"""What a command shows, in one shape: its JSON document (SI units, snake_case keys), its text in
the file's units and its exit code (warnings go to a ``warn`` callback as they happen); and JSON as
rswarp writes it."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import Warn, ignore  # noqa: F401  (the commands' warn callbacks, re-exported for report/)


@dataclass(frozen=True)
class Output:
    """A command's result as people and programs read it."""

    doc: Any
    text: str
    code: int = 0
    errors: tuple[str, ...] = ()  # file:line lines for stderr (a report that still has something to show)


def json_safe(value):
    """``value`` with every non-finite float as None (JSON has no NaN, and a reader must not choke),
    NumPy arrays as lists and NumPy numbers as Python's."""
    if isinstance(value, np.ndarray):
        return json_safe(value.tolist())
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    return value


def json_text(doc) -> str:
    """The JSON rswarp prints and writes: indented, never NaN."""
    return json.dumps(doc, indent=2, allow_nan=False)


def json_bytes(doc) -> bytes:
    """``json_text`` as a file's bytes, newline-terminated."""
    return (json_text(doc) + "\n").encode()
