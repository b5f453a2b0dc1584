"""Typed values read from RSXML attributes, each checked as it is read, every problem recorded as
``file:line: message``: numbers in the file's units to SI within physical bounds (lengths within
1 km, angles within ``MAX_ANGLE``), booleans, poses. ``ValueReader`` is the base of the document
reader (``read``), which holds the file's units in ``length`` and ``angle``."""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np
from lxml import etree

from ..errors import Diagnostic
from .model import Pose
from .parse import children, local, namespace, number
from .units import BOUNDS

ORTHO_TOL = 1e-5  # |R^T R - I| allowed for x/y/z written with six decimals
QUAT_TOL = 1e-6  # |q| - 1 above this is warned about and normalized


class ValueReader:
    """Values of one file's elements, in its units (``length``, ``angle``: SI per file unit)."""

    def __init__(self, file: str, diagnostics: list[Diagnostic] | None = None):
        self.file = file
        self.diagnostics: list[Diagnostic] = [] if diagnostics is None else diagnostics
        self.length = 1.0
        self.angle = 1.0

    # -- diagnostics -------------------------------------------------------------------------------
    def error(self, where: etree._Element | int, message: str) -> None:
        line = where if isinstance(where, int) else (where.sourceline or 0)
        self.diagnostics.append(Diagnostic(self.file, line, message))

    def warn(self, where: etree._Element | int, message: str) -> None:
        line = where if isinstance(where, int) else (where.sourceline or 0)
        self.diagnostics.append(Diagnostic(self.file, line, message, "warning"))

    def children(self, el: etree._Element) -> list[etree._Element]:
        """Element children in ``el``'s namespace; an element of another namespace is not RSXML
        (``<x:Joints xmlns:x="...xhtml">`` is no Joints section): reported and skipped."""
        ns, out = namespace(el), []
        for c in children(el):
            if namespace(c) == ns:
                out.append(c)
            else:
                self.foreign(c)
        return out

    def foreign(self, el: etree._Element) -> None:
        self.warn(el, f"element <{el.prefix + ':' if el.prefix else ''}{local(el)}> of namespace "
                      f"'{namespace(el)}' is not RSXML; ignored")

    # -- attributes --------------------------------------------------------------------------------
    def known(self, el: etree._Element, allowed: Iterable[str]) -> None:
        for key in el.attrib:
            name = etree.QName(key).localname if key.startswith("{") else key
            if key.startswith("{") or name in allowed:
                continue
            self.warn(el, f"unknown attribute '{name}' on <{local(el)}> ignored")

    def text(self, el: etree._Element, name: str, required: bool = False) -> str | None:
        value = el.get(name)
        if value is None:
            if required:
                self.error(el, f"<{local(el)}> is missing attribute '{name}'")
            return None
        value = value.strip()
        if required and not value:
            self.error(el, f"<{local(el)}> has an empty '{name}'")
        return value

    def floats(self, el: etree._Element, name: str, count: int | None = None, factor: float = 1.0,
               required: bool = False, bound: str | None = None) -> tuple[float, ...] | None:
        """Numbers of an attribute ("1, 2, 3" or "1 2 3") times ``factor`` (to SI); ``bound`` is
        "length" or "angle" when the values must be within its ``BOUNDS``."""
        raw = self.text(el, name, required)
        if raw is None:
            return None
        try:
            values = tuple(number(p) * factor for p in (raw.split(",") if "," in raw else raw.split()))
        except ValueError as exc:
            self.error(el, f"'{name}' has {exc}")
            return None
        if count is not None and len(values) != count:
            self.error(el, f"'{name}' needs {count} numbers, got {len(values)}")
            return None
        if bound:
            worst = max(values, key=abs, default=0.0)
            if not self.within(el, name, format(worst / factor, "g"), worst, bound):
                return None
        return values

    def within(self, where: etree._Element, name: str, text: str, si: float, bound: str) -> bool:
        """Whether an SI length or angle makes physical sense; reports it when not."""
        limit, what = BOUNDS[bound]
        if abs(si) <= limit:
            return True
        self.error(where, f"'{name}' value {text} is beyond {what}")
        return False

    def number(self, el: etree._Element, name: str, factor: float = 1.0, required: bool = False,
               bound: str | None = None) -> float | None:
        values = self.floats(el, name, 1, factor, required, bound)
        return None if values is None else values[0]

    def boolean(self, el: etree._Element, name: str, default: bool | None) -> bool | None:
        raw = self.text(el, name)
        if raw is None:
            return default
        if raw.lower() in ("true", "1"):
            return True
        if raw.lower() in ("false", "0"):
            return False
        self.error(el, f"'{name}' must be true or false, not '{raw}'")
        return default

    def options(self, el: etree._Element, skip: Iterable[str] = ()) -> tuple[tuple[str, str], ...]:
        skip = set(skip)
        return tuple((k, v) for k, v in el.attrib.items() if not k.startswith("{") and k not in skip)

    def pose(self, el: etree._Element) -> Pose:
        """The 3D transform attributes of ``el`` (t, x/y/z, euler, quat), validated."""
        t = self.floats(el, "t", 3, self.length, bound="length")
        x, y, z = (self.floats(el, k, 3) for k in "xyz")
        euler = self.floats(el, "euler", 3, self.angle, bound="angle")
        quat = self.floats(el, "quat", 4)
        given = [k for k in "xyz" if el.get(k) is not None]
        forms = (["x/y/z"] if given else []) + [k for k in ("euler", "quat") if el.get(k) is not None]
        if len(forms) > 1:
            self.error(el, f"<{local(el)}> gives its rotation twice ({' and '.join(forms)})")
            return Pose(t=t)
        if given and len(given) < 3:
            missing = ", ".join(k for k in "xyz" if k not in given)
            self.error(el, f"<{local(el)}> gives {', '.join(given)} without {missing}: x, y and z go together")
            return Pose(t=t)
        if given and None not in (x, y, z):
            r = np.array([x, y, z], dtype=float).T
            if np.abs(r.T @ r - np.eye(3)).max() > ORTHO_TOL:
                self.error(el, f"<{local(el)}> x, y, z are not orthonormal")
            elif np.linalg.det(r) < 0:
                self.error(el, f"<{local(el)}> x, y, z are left-handed (z must be x cross y)")
        if quat is not None:
            norm = math.sqrt(sum(q * q for q in quat))
            if norm < 1e-12:
                self.error(el, f"<{local(el)}> quat is zero")
                quat = None
            elif abs(norm - 1.0) > QUAT_TOL:
                self.warn(el, f"<{local(el)}> quat has length {norm:.6g}; normalized")
                quat = tuple(q / norm for q in quat)
        return Pose(t=t, x=x if given else None, y=y if given else None, z=z if given else None,
                    euler=euler, quat=quat)
