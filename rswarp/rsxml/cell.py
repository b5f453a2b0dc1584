"""A cell file (``cell.toml``): what stands where. The robot (its RSXML, on the floor or on an
external unit's carriage, at a frame), the external units (``ExternalAxis`` RSXML: tracks,
positioners) with their frames and the logical axes (``eax_a`` .. ``eax_f``) that drive their
joints, the tool on the flange and the environment meshes. Frames are six numbers as RAPID and
RobotStudio write them: x, y, z in mm, then rx, ry, rz in degrees, R = Rz(rz) Ry(ry) Rx(rx) (ABB's
Euler ZYX). Paths are relative to the cell file. docs/cell-file.md gives every key.

Read once, checked whole: every problem is an ``RsxmlError`` at the line of the key that holds it
(``file:line: message``), an unknown key names the nearest known one; a robot whose
AllowedTrackModels does not name the model it stands on is a warning, as are the RSXML files'
own warnings."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import Diagnostic, RsxmlError, nearest
from ..transforms import euler_zyx_matrix
from .cell_types import LOGICAL_AXES, Cell, CellMesh, CellTool, External, PlacedRobot
from .documents import load_mechanism
from .model import Mechanism
from .robot_data import read_toml
from .units import MAX_ANGLE, MAX_LENGTH

MECHANISM_SUFFIXES = (".rsxml", ".xml")  # a tool given by one of these is a Tool mechanism, else a mesh
KEYS = {  # table -> its keys; "" is the file's top level
    "": ("robot", "external", "tool", "environment", "backup"),
    "robot": ("rsxml", "on", "frame", "unit", "name", "task", "drives"),
    "external": ("name", "rsxml", "frame", "axes", "flange"),
    "tool": ("path", "frame"),
    "environment": ("mesh", "frame", "on"),
}
FRAME_WORDS = "x, y, z in mm, then rx, ry, rz in degrees (ABB's Euler ZYX)"


def read_cell(path) -> Cell:
    """A cell file, read and checked: its RSXML files loaded, its frames as 4x4 (m), its axes
    mapped; an ``RsxmlError`` with every problem found, each at its line (a table with one is
    left out, and what names it is not faulted for that)."""
    path = str(path)
    text, doc = read_toml(path)
    r = _Reader(path, text)
    r.attempt(lambda: r.known(doc, "", None))
    if isinstance(doc.get("robot"), list):  # MultiMove: [[robot]], once for each
        from .cell_team import read_team

        return read_team(r, doc)
    if "robot" not in doc:
        r.errors.append(Diagnostic(path, 0, "no [robot] table: a cell places one robot (rsxml = its RSXML file)"))
    externals = r.externals(r.attempt(r.tables, doc, "external", False, default=[]))
    robot = r.attempt(lambda: r.robot(r.table(doc, "robot"), externals)) if "robot" in doc else None
    tool = r.attempt(lambda: r.tool(r.table(doc, "tool"))) if "tool" in doc else None
    meshes = r.attempt(r.tables, doc, "environment", default=[])
    environment = tuple(m for k, t in enumerate(meshes) if (m := r.attempt(r.mesh, t, k, externals)))
    unit = r.attempt(r.unit, doc["robot"], doc) if isinstance(doc.get("robot"), dict) else None
    if isinstance(doc.get("robot"), dict) and "drives" in doc["robot"]:
        r.attempt(r.fail, ("robot", None), "drives", "[robot] drives: a cell of one robot drives every unit; "
                                                     "drives names a MultiMove robot's units, in [[robot]]")
    if r.errors:
        raise RsxmlError(sorted(r.errors, key=lambda d: d.line))
    cell = Cell(path, robot, externals, tool, environment)
    if "backup" in doc:
        cell = r.backup(cell, doc, doc["robot"], unit)
    return replace(cell, warnings=tuple(str(w) for w in r.warnings), diagnostics=tuple(r.warnings))


def frame_matrix(values) -> np.ndarray:
    """Six numbers (x, y, z in mm; rx, ry, rz in degrees, R = Rz Ry Rx) as a 4x4 transform in m."""
    m = np.eye(4)
    m[:3, :3] = euler_zyx_matrix(*np.radians(values[3:6]))
    m[:3, 3] = np.asarray(values[:3], float) / 1000.0
    return m


class _Reader:
    """One cell file's text, the line of each key (``_Lines``), its folder, the warnings so far."""

    def __init__(self, path: str, text: str):
        self.path, self.folder, self.lines = path, Path(path).parent, _Lines(text)
        self.warnings: list[Diagnostic] = []
        self.errors: list[Diagnostic] = []  # every problem found; a table with one is left out
        self.failed: set[str] = set()  # the names of [[external]] tables left out for a problem
        self.names: dict[tuple[str, int | None], str] = {}  # an [[external]]'s name, once known
        self.owner: dict[str, int] = {}  # MultiMove: unit -> the robot whose task drives it (axes are per task)

    def attempt(self, read, *args, default=None):
        """``read(*args)``, or ``default`` with its problem kept in ``errors`` (the rest read on)."""
        try:
            return read(*args)
        except RsxmlError as exc:
            self.errors.extend(exc.diagnostics)
            return default

    def title(self, where: tuple[str, int | None]) -> str:
        """``[robot]``, ``[[external]] 'track'`` (its name where known, else its number)."""
        name = self.names.get(where)
        return f"[[{where[0]}]] '{name}'" if name else _title(*where)

    def fail(self, where: tuple[str, int | None], key: str | None, message: str):
        raise RsxmlError(Diagnostic(self.path, self.lines.of(*where, key), message))

    def table(self, doc: dict, name: str) -> dict:
        value = doc[name]
        if not isinstance(value, dict):
            self.fail(("", None), name, f"{name} must be a table: [{name}]")
        self.known(value, name, None)
        return value

    def tables(self, doc: dict, name: str, keys: bool = True) -> list[dict]:
        """The array of tables ``name``; ``keys``: each table's keys checked here (else by its reader,
        so that a table with an unknown key is left out alone, said before what follows from it)."""
        value = doc.get(name, [])
        if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
            self.fail(("", None), name, f"{name} must be an array of tables: [[{name}]], once for each")
        for k, t in enumerate(value if keys else ()):
            self.known(t, name, k)
        return value

    def known(self, table: dict, name: str, index: int | None) -> None:
        """An error at the first key ``name`` does not know, naming the nearest known one."""
        keys = KEYS[name]
        for key in table:
            if key not in keys:
                near = nearest(key, keys)
                hint = f"; did you mean '{near}'?" if near else f" (known: {', '.join(keys)})"
                self.fail((name, index), key, f"unknown key '{key}' in {_title(name, index)}{hint}")

    def backup(self, cell: Cell, doc: dict, t: dict, unit, index: int | None = None) -> Cell:
        """``cell`` with the controller's own setup (SYSPAR/MOC.cfg, EIO.cfg) applied: bounds,
        carrier, frames, signals; ``t`` the robot's table, ``unit`` its ``unit`` (and line), ``index``
        its place among a MultiMove cell's robots."""
        from .cell_moc import apply_backup

        given = {("robot", "frame"): "frame" in t, ("robot", "unit"): unit, ("robot", "index"): index}
        given |= {("external", e.get("name")): "frame" in e for e in self.tables(doc, "external")}
        cell, said = apply_backup(cell, self.folder, doc["backup"], self.lines.of("", None, "backup"), given,
                                  lambda message: self.fail(("", None), "backup", message))
        self.warnings.extend(w for w in said if w not in self.warnings)
        return cell

    def robot(self, t: dict, externals: tuple[External, ...], where=("robot", None)) -> PlacedRobot:
        path, mech = self.mechanism(t, where, "Robot")
        on = t.get("on")
        if on is not None and on not in self.failed:  # a unit left out for its own problem: said there
            names = [e.name for e in externals]
            if not isinstance(on, str) or on not in names:
                near = nearest(str(on), names)
                hint = f"; did you mean '{near}'?" if near else \
                    f" (the cell's external units: {', '.join(names)})" if names else " (the cell has no [[external]])"
                self.fail(where, "on", f"{self.title(where)} on = {_shown(on)} names no [[external]]{hint}")
            self.allowed_track(mech, externals[names.index(on)], where)
        name, task = (self.text(t, where, key) for key in ("name", "task"))
        return PlacedRobot(path, mech, self.frame(t, where), on, self.lines.of(*where, None), name, task)

    def text(self, t: dict, where, key: str) -> str:
        """The table's ``key`` as text, stripped; "" where not given."""
        value = t.get(key, "")
        if not isinstance(value, str) or (key in t and not value.strip()):
            self.fail(where, key, f"{self.title(where)} {key}: give it as text, not {_shown(value)}")
        return value.strip()

    def unit(self, t: dict, doc: dict, where=("robot", None)) -> tuple[str, int] | None:
        """``[robot] unit`` (the backup's robot the cell's is, MultiMove) and its line; None where
        not given. It names a robot of the backup's MOC.cfg: without ``backup`` it is an error."""
        if "unit" not in t:
            return None
        value = t["unit"]
        if not isinstance(value, str) or not value.strip():
            self.fail(where, "unit", f"{self.title(where)} unit: give the backup's robot the cell's robot is, as "
                                     "text: its "
                                     "mechanical unit in MOC.cfg (\"ROB_2\") or its motion task (\"T_ROB2\")")
        if "backup" not in doc:
            self.fail(where, "unit", f"{self.title(where)} unit = {_shown(value)} names a robot of the cell's backup, "
                                     "and the cell file gives no backup = \"...\"")
        return value.strip(), self.lines.of(*where, "unit")

    def allowed_track(self, robot: Mechanism, carrier: External, where=("robot", None)) -> None:
        """A warning where the robot's AllowedTrackModels does not name the model it stands on."""
        allowed = robot.allowed_track_models
        model = carrier.mechanism.model_name or carrier.mechanism.name
        if allowed and not any(re.fullmatch(rf"{re.escape(a)}(_.*)?", model, re.I) for a in allowed):
            self.warnings.append(Diagnostic(
                self.path, self.lines.of(*where, "on"), f"robot '{robot.name}' allows the track models "
                f"{', '.join(allowed)} (AllowedTrackModels), not '{model}' of '{carrier.name}'", "warning"))

    def externals(self, tables: list[dict]) -> tuple[External, ...]:
        out: list[External] = []
        taken: dict[str, tuple[str, str, int]] = {}  # logical axis -> (unit, joint, line)
        for k, t in enumerate(tables):
            found = self.attempt(self.external, t, k, out, taken)
            if found is None:
                self.failed.add(str(t.get("name")))
            else:
                out.append(found)
        return tuple(out)

    def external(self, t: dict, k: int, out: list, taken: dict) -> External:
        """One [[external]] table read (``out``: those before it; ``taken``: their axes)."""
        where = ("external", k)
        name = t.get("name")
        if isinstance(name, str) and name.strip():
            self.names[where] = name
        self.known(t, "external", k)
        if not isinstance(name, str) or not name.strip():
            self.fail(where, "name" if "name" in t else None, f"{_title(*where)}: give it a name (text)")
        if name in (e.name for e in out):
            self.fail(where, "name", f"two external units are named '{name}'")
        self.names[where] = name
        path, mech = self.mechanism(t, where, "ExternalAxis")
        joints = tuple(j.name for j in mech.active_joints)
        axes = self.axes(t, where, name, joints, taken)
        return External(name, path, mech, self.frame(t, where), axes, joints, self.lines.of(*where, None),
                        self.flange(t, where, name, mech))

    def flange(self, t: dict, where, unit: str, mech: Mechanism) -> str | None:
        """The unit's mounting flange: the one ``flange`` names, else its only one (None: it has
        none); a unit of several flanges must name one."""
        names = [f.name for f in mech.flanges]
        if "flange" not in t:
            if len(names) > 1:
                self.fail(where, None, f"[[external]] '{unit}' has {len(names)} flanges ({', '.join(names)}): give "
                                       "flange = \"...\", the one what rides it is mounted on")
            return names[0] if names else None
        value = t["flange"]
        if not isinstance(value, str) or value not in names:
            near = nearest(str(value), names)
            hint = f"; did you mean '{near}'?" if near else f" (its flanges: {', '.join(names) or 'none'})"
            self.fail(where, "flange", f"[[external]] '{unit}' flange = {_shown(value)} names no Flange of "
                                       f"'{Path(mech.path or unit).name}'{hint}")
        return value

    def axes(self, t: dict, where, unit: str, joints: tuple[str, ...], taken: dict) -> tuple[str, ...]:
        """The logical axes of ``unit``'s joints: distinct, eax_a..eax_f, one per active joint, none
        already driving another unit's joint (``taken``, which this adds to)."""
        line = self.lines.of(*where, "axes")
        values = t.get("axes")
        count = f"{len(joints)} active joint{'s' * (len(joints) != 1)} ({', '.join(joints)})"
        if not isinstance(values, list) or not all(isinstance(a, str) for a in values):
            self.fail(where, "axes", f"[[external]] '{unit}' axes: give the logical axes (eax_a .. eax_f) of its "
                                     f"{count}, in joint order, as a list of text")
        axes = tuple(a.strip().lower() for a in values)
        for a in axes:
            if a not in LOGICAL_AXES:
                self.fail(where, "axes", f"[[external]] '{unit}' axes: '{a}' is not a logical axis: eax_a .. eax_f")
        if len(axes) != len(joints):
            self.fail(where, "axes", f"[[external]] '{unit}' axes: {len(axes)} logical "
                                     f"ax{'es' if len(axes) != 1 else 'is'} for its {count}: give one per joint, "
                                     "in joint order")
        for a, j in zip(axes, joints):
            a = (self.owner.get(unit), a)  # two tasks each have their own eax_a
            if a in taken:
                other, joint, first = taken[a]
                self.fail(where, "axes", f"[[external]] '{unit}' axes: {a[1]} already drives joint {joint} of "
                                         f"'{other}' (line {first})")
            taken[a] = (unit, j, line)
        return axes

    def tool(self, t: dict) -> CellTool:
        where = ("tool", None)
        path = self.file(t, where, "path", "the tool: a mesh file or an RSXML Mechanism of type Tool")
        mech = None
        if Path(path).suffix.lower() in MECHANISM_SUFFIXES:
            mech = self.load(path, where, "path", "Tool")
        return CellTool(path, self.frame(t, where), mech, self.lines.of(*where, None))

    def mesh(self, t: dict, k: int, externals: tuple[External, ...]) -> CellMesh:
        where = ("environment", k)
        path = self.file(t, where, "mesh", "an environment mesh file")
        on = t.get("on")
        names = [e.name for e in externals]
        if on is not None and on not in self.failed and (not isinstance(on, str) or on not in names):
            near = nearest(str(on), names)
            hint = f"; did you mean '{near}'?" if near else \
                f" (the cell's external units: {', '.join(names)})" if names else " (the cell has no [[external]])"
            self.fail(where, "on", f"{_title(*where)} on = {_shown(on)} names no [[external]]{hint}")
        return CellMesh(Path(path).stem, path, self.frame(t, where), self.lines.of(*where, None), on)

    def mechanism(self, t: dict, where, kind: str) -> tuple[str, Mechanism]:
        path = self.file(t, where, "rsxml", f"an RSXML Mechanism of type {kind}")
        return path, self.load(path, where, "rsxml", kind)

    def file(self, t: dict, where, key: str, what: str) -> str:
        """The path ``key`` gives, relative to the cell file (``\\`` taken as ``/``); it must exist."""
        value = t.get(key)
        if not isinstance(value, str) or not value.strip():
            self.fail(where, key if key in t else None, f"{self.title(where)} {key}: give {what}, as a path relative "
                                                        "to the cell file")
        path = self.folder / value.strip().replace("\\", "/")
        if path.exists() and not path.is_file():
            from .cell_moc import kind_of

            self.fail(where, key, f"{self.title(where)} {key}: '{value}' is {kind_of(path)}, not a file")
        if not path.is_file():
            self.fail(where, key, f"{self.title(where)} {key}: no such file '{value}' (looked for {path})")
        return str(path)

    def load(self, path: str, where, key: str, kind: str) -> Mechanism:
        """The mechanism in ``path``, which must be of type ``kind``; its warnings are the cell's."""
        mech, report = load_mechanism(path)
        if mech.type != kind:
            self.fail(where, key, f"{self.title(where)} {key}: '{Path(path).name}' is a mechanism of type "
                                  f"{mech.type or '(none)'}, not {kind}")
        self.warnings.extend(w for w in report.warnings)
        return mech

    def frame(self, t: dict, where) -> np.ndarray:
        """The table's ``frame`` as a 4x4 (m); the identity where it gives none."""
        values = t.get("frame")
        if values is None:
            return np.eye(4)
        prefix = f"{self.title(where)} frame"
        if not isinstance(values, list) or len(values) != 6:
            given = f"{len(values)} values" if isinstance(values, list) else _shown(values)
            extra = " (a quaternion is not taken: give rx, ry, rz)" if isinstance(values, list) and \
                len(values) == 7 else ""
            self.fail(where, "frame", f"{prefix}: give 6 numbers, {FRAME_WORDS}, not {given}{extra}")
        for k, v in enumerate(values):
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                self.fail(where, "frame", f"{prefix}: value {k + 1} ({_shown(v)}) is not a finite number")
        if max(abs(v) for v in values[:3]) > MAX_LENGTH * 1000 or max(abs(v) for v in values[3:]) > \
                math.degrees(MAX_ANGLE):
            self.fail(where, "frame", f"{prefix}: a position within {MAX_LENGTH * 1000:g} mm and angles within "
                                      f"{math.degrees(MAX_ANGLE):.6g} degrees, please")
        return frame_matrix([float(v) for v in values])


class _Lines:
    """The line of each key of a cell file by table (``[robot]``; the k-th ``[[external]]``), and
    of each table's header, found by scanning the text: tomllib keeps no positions."""

    _HEADER = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.-]+)\s*\]\]?\s*(#.*)?$")
    _KEY = re.compile(r"""^\s*([A-Za-z0-9_-]+|"[^"]*"|'[^']*')\s*[=.]""")

    def __init__(self, text: str):
        self.keys: dict[tuple[str, int | None, str], int] = {}
        self.headers: dict[tuple[str, int | None], int] = {}
        counts: dict[str, int] = {}
        table: tuple[str, int | None] = ("", None)
        for n, raw in enumerate(text.splitlines(), 1):
            head = self._HEADER.match(raw)
            if head:
                name = head.group(2)
                parent, dot, child = name.partition(".")
                if dot:  # [robot.extra]: the key 'extra' of [robot]
                    self.keys.setdefault((parent, None, child.split(".")[0]), n)
                if head.group(1) == "[[":
                    counts[name] = counts.get(name, -1) + 1
                table = (name, counts[name] if head.group(1) == "[[" else None)
                self.headers.setdefault(table, n)
                continue
            key = self._KEY.match(raw)
            if key:
                self.keys.setdefault((*table, key.group(1).strip("\"'")), n)

    def of(self, table: str, index: int | None, key: str | None) -> int:
        """The line of ``key`` in the table, else of the table's header, else of the table's name
        as a top-level key (an inline table), else 0."""
        if key is not None and (table, index, key) in self.keys:
            return self.keys[(table, index, key)]
        if (table, index) in self.headers:
            return self.headers[(table, index)]
        if not table and key is not None:  # a top-level key that opens a table: [robto]
            return self.headers.get((key, None)) or self.headers.get((key, 0)) or self.keys.get(("", None, key), 0)
        return self.keys.get(("", None, table), 0)


def _title(name: str, index: int | None) -> str:
    if not name:
        return "the cell file"
    return f"[{name}]" if index is None else f"[[{name}]] {index + 1}"


def _shown(value) -> str:
    return f"'{value}'" if isinstance(value, str) else repr(value)
