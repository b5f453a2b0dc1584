"""Designs of a dress pack, for a design sweep: the variables a user varies (``--vary``) over a box,
the designs drawn in it by a scrambled Sobol sequence (scipy.stats.qmc), and each design as the
mechanism with its cable changed: its length (``desiredLength``), a control point's place shifted
in its link's frame, its direction tilted. A design whose attached control points lie inside a
link's mesh at rest is refused before any work."""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..rsxml.model import Cable, Mechanism
from ..rsxml.units import MAX_LENGTH
from ..transforms import euler_zyx_matrix

TILTS = ("pitch", "yaw")
PROPERTIES = ("x", "y", "z", *TILTS)  # a shift (m) along, or a tilt (deg) about y or z of, the link's axes
MAX_DESIGNS = 1 << 16
MAX_SHIFT = 1.0  # m: farther is another cell, not a clamp position
MAX_TILT = 90.0  # deg
_SPEC = re.compile(r"^\s*([^=]+?)\s*=\s*([^:]+):([^:]+)\s*$")


@dataclass(frozen=True)
class Variable:
    """One varied number: ``length`` (m), or a control point's (0-based ``point``) shift along
    ``x``/``y``/``z`` of its link's frame (m) or tilt ``pitch``/``yaw`` (rad), from ``low`` to
    ``high``; ``name`` as the user wrote it."""

    name: str
    what: str
    low: float
    high: float
    point: int | None = None

    @property
    def unit(self) -> str:
        """The unit --vary takes it in: degrees for a tilt, else metres."""
        return "deg" if self.what in TILTS else "m"

    def given(self, x: float) -> float:
        """``x`` (SI) in the unit --vary takes."""
        return math.degrees(x) if self.what in TILTS else x


def parse_vary(specs: list[str], cable: Cable) -> tuple[Variable, ...]:
    """``length=MIN:MAX`` (m), ``LINK.PROPERTY=MIN:MAX`` or ``N.PROPERTY=MIN:MAX`` (control point N,
    counted from 1; a shift in m, a tilt in degrees) as variables; an InputError, one line, for
    anything else."""
    out, seen = [], {}
    for spec in specs:
        m = _SPEC.match(spec)
        usage = f"--vary '{spec}': give length=MIN:MAX (m) or POINT.{{{','.join(PROPERTIES)}}}=MIN:MAX, POINT a " \
                "control point's link or its number"
        if m is None:
            raise InputError(usage)
        name, low, high = m.group(1), _number(m.group(2), spec), _number(m.group(3), spec)
        if not low < high:
            raise InputError(f"--vary '{spec}': an empty range ({low:g} to {high:g}); give MIN below MAX")
        if name == "length":
            if low <= 0:
                raise InputError(f"--vary '{spec}': a length above 0, please")
            if high > MAX_LENGTH:
                raise InputError(f"--vary '{spec}': a hose of at most {MAX_LENGTH:g} m, please (1 km, the bound of "
                                 "every length rswarp reads)")
            out.append(_once(Variable(name, "length", low, high), spec, seen))
            continue
        point_name, _, what = name.rpartition(".")
        if what not in PROPERTIES or not point_name:
            raise InputError(usage)
        point = _point(point_name, cable, spec)
        bound = MAX_TILT if what in TILTS else MAX_SHIFT
        if max(abs(low), abs(high)) > bound:
            raise InputError(f"--vary '{spec}': within ±{bound:g} {'deg' if bound == MAX_TILT else 'm'}, please")
        scale = math.pi / 180.0 if what in TILTS else 1.0
        out.append(_once(Variable(name, what, low * scale, high * scale, point), spec, seen))
    return tuple(out)


def _once(v: Variable, spec: str, seen: dict) -> Variable:
    """``v``, unless an earlier spec (in ``seen``: what it varies -> its spec) varies the same
    number, under this name or another (``Link6.z`` and ``3.z`` are one control point's z)."""
    key = (v.what, v.point)
    if key in seen:
        what = "the hose's length" if v.what == "length" else f"control point {v.point + 1}'s {v.what}"
        raise InputError(f"--vary '{spec}': '{seen[key]}' already varies {what}; give each variable once")
    seen[key] = spec
    return v


def _number(text: str, spec: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise InputError(f"--vary '{spec}': '{text.strip()}' is not a number")
    return value


def _point(name: str, cable: Cable, spec: str) -> int:
    """The control point ``name`` means: its number (from 1), or the one control point its link holds."""
    points = cable.control_points
    held = [f"{k + 1} on {p.attached_to}" for k, p in enumerate(points) if p.attached_to]
    if name.isdigit():
        k = int(name) - 1
        if not 0 <= k < len(points):
            raise InputError(f"--vary '{spec}': cable '{cable.name}' has control points 1 to {len(points)}")
    else:
        on = [k for k, p in enumerate(points) if p.attached_to == name]
        if len(on) != 1:
            why = "no control point" if not on else f"{len(on)} control points; name one by its number"
            raise InputError(f"--vary '{spec}': link '{name}' holds {why} of cable '{cable.name}' (held: "
                             f"{', '.join(held) or 'none'})")
        k = on[0]
    if points[k].attached_to is None:
        raise InputError(f"--vary '{spec}': control point {k + 1} of cable '{cable.name}' is held by no link; "
                         f"vary those held ({', '.join(held) or 'none'})")
    return k


def sample(variables: tuple[Variable, ...], designs: int, seed: int = 0) -> np.ndarray:
    """(designs, variables) values drawn by a scrambled Sobol sequence over the box, reproducible
    by ``seed``."""
    from scipy.stats import qmc

    if not 1 <= designs <= MAX_DESIGNS:
        raise InputError(f"--designs must be 1 to {MAX_DESIGNS}, not {designs}")
    if not variables:
        raise InputError("give at least one --vary")
    unit = qmc.Sobol(len(variables), scramble=True, seed=seed).random_base2(max(0, math.ceil(math.log2(designs))))
    low = np.array([v.low for v in variables])
    high = np.array([v.high for v in variables])
    return low + unit[:designs] * (high - low)


def design(mech: Mechanism, cable: int, variables: tuple[Variable, ...], values,
           axes: dict[int, np.ndarray] | None = None) -> Mechanism:
    """The mechanism with cable ``cable`` changed by one design's ``values`` (SI): its length, a
    point shifted along and its direction tilted about its link's axes at the zero position
    (``axes``: each held point's, from ``link_axes``), SI as the model keeps them."""
    c = mech.cables[cable]
    axes = link_axes(mech, cable) if axes is None else axes
    points = list(c.control_points)
    length = c.desired_length
    for v, value in zip(variables, values):
        if v.what == "length":
            length = float(value)
            continue
        p = points[v.point]
        turn = axes.get(v.point, np.eye(3))
        if v.what in ("x", "y", "z"):
            shift = turn[:, "xyz".index(v.what)] * float(value)
            points[v.point] = dataclasses.replace(p, position=tuple(float(a) for a in np.add(p.position, shift)))
        elif p.direction is not None:
            tilt = euler_zyx_matrix(0.0, float(value), 0.0) if v.what == "pitch" else \
                euler_zyx_matrix(0.0, 0.0, float(value))
            turned = turn @ tilt @ turn.T @ p.unit_direction
            points[v.point] = dataclasses.replace(p, direction=tuple(float(a) for a in turned))
    changed = dataclasses.replace(c, control_points=tuple(points), desired_length=length)
    cables = list(mech.cables)
    cables[cable] = changed
    return dataclasses.replace(mech, cables=tuple(cables))


def link_axes(mech: Mechanism, cable: int) -> dict[int, np.ndarray]:
    """Each held control point's link's axes (3 x 3, world) at the zero position."""
    from ..kinematics.kinematics import Kinematics
    from ..rsxml.model import iter_parts

    owner = {p.name: link.name for link in mech.links for p, _ in iter_parts(link)}
    poses = Kinematics(mech).fk64(np.zeros((1, mech.dof)))[0] if mech.dof else None
    out = {}
    for k, cp in enumerate(mech.cables[cable].control_points):
        if cp.attached_to is not None and poses is not None:
            out[k] = poses[mech.graph.link_index(owner.get(cp.attached_to, cp.attached_to)), :3, :3].copy()
    return out


def inside_links(mech: Mechanism, cable: int, designs: tuple[Mechanism, ...] = ()) -> list[str]:
    """The attached control points of cable ``cable`` that lie inside a link's (closed) mesh at the
    zero position, as "point N in LINK" (of ``mech``, or of each of ``designs``: "design D: point N
    in LINK"), each link's mesh built once."""
    from ..geometry.meshes import closed_link_meshes

    held = [(d, k, p.position) for d, m in enumerate(designs or (mech,))
            for k, p in enumerate(m.cables[cable].control_points) if p.attached_to]
    out = []
    for _, name, mesh in closed_link_meshes(mech) if held else ():
        inside = mesh.contains(np.array([p for *_, p in held]))
        out += [f"{f'design {d + 1}: ' if designs else ''}point {k + 1} in {name}"
                for (d, k, _), yes in zip(held, inside) if yes]
    return out


@dataclass(frozen=True)
class DesignSet:
    """The designs of a sweep: cable ``cable`` of the mechanism changed by each row of ``values``
    (designs, variables); environment e runs design e."""

    cable: int
    variables: tuple[Variable, ...]
    values: np.ndarray

    def __len__(self) -> int:
        return len(self.values)

    def mechanisms(self, mech: Mechanism) -> tuple[Mechanism, ...]:
        axes = link_axes(mech, self.cable)
        return tuple(design(mech, self.cable, self.variables, row, axes) for row in self.values)

    def take(self, span: range) -> "DesignSet":
        """The designs of environments ``span`` (a task's)."""
        return dataclasses.replace(self, values=self.values[span.start:span.stop])

    def key(self) -> tuple:
        return (self.cable, self.variables, self.values.tobytes())
