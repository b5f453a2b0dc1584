"""A MultiMove cell file: several robots, ``[[robot]]`` once for each, every one with its ``name``
and the motion ``task`` it runs (``T_ROB2``), and the external units its task drives (``drives``:
the unit it stands on by default, and, for the first robot, every unit no other robot claims). As
on the controller, each task has its own logical axes: two robots' units may both be ``eax_a``.

Read as one cell per robot (``Cell.team``), each with its own units, the environment meshes that
stand still or ride its units, and, with ``backup``, its robot of the backup's MOC.cfg: the one its
``unit`` names, else the robot in the same place among the controller's; its base frame and task
from there where the cell file gives none. The ``[tool]`` is the first robot's."""

from __future__ import annotations

from dataclasses import replace

from ..errors import Diagnostic, RsxmlError, nearest
from .cell_types import Cell


def read_team(r, doc: dict) -> Cell:
    """The cell of a file with ``[[robot]]`` tables (``r``: its ``cell._Reader``): the first robot's
    cell, with every robot's in ``team``; every problem found an ``RsxmlError`` at its line."""
    tables = r.attempt(r.tables, doc, "robot", default=[])
    if not tables:
        r.errors.append(Diagnostic(r.path, r.lines.of("", None, "robot"), "[[robot]]: give each robot a table"))
    given = doc.get("external", [])
    names = [t.get("name") for t in given if isinstance(t, dict)] if isinstance(given, list) else []
    drives = [r.attempt(_drives, r, t, k, names) or () for k, t in enumerate(tables)]
    r.owner = _owners(tables, drives, names)
    externals = r.externals(r.attempt(r.tables, doc, "external", False, default=[]))
    robots = [r.attempt(lambda t=t, k=k: r.robot(t, externals, ("robot", k))) for k, t in enumerate(tables)]
    units = [r.attempt(r.unit, t, doc, ("robot", k)) for k, t in enumerate(tables)]
    tool = r.attempt(lambda: r.tool(r.table(doc, "tool"))) if "tool" in doc else None
    meshes = r.attempt(r.tables, doc, "environment", default=[])
    environment = tuple(m for k, t in enumerate(meshes) if (m := r.attempt(r.mesh, t, k, externals)))
    if r.errors:
        raise RsxmlError(sorted(r.errors, key=lambda d: d.line))
    cells = []
    for k, (t, robot, unit) in enumerate(zip(tables, robots, units)):
        mine = tuple(e for e in externals if r.owner.get(e.name) == k)
        held = tuple(m for m in environment if m.on is None or r.owner.get(m.on) == k)
        cell = Cell(r.path, robot, mine, tool if k == 0 else None, held)
        if "backup" in doc:
            cell = r.attempt(r.backup, cell, doc, t, unit, k)
        if cell is not None:
            cells.append(_named(cell, k))
    if r.errors:
        raise RsxmlError(sorted(r.errors, key=lambda d: d.line))
    _distinct(r, cells)
    team = tuple(replace(c, warnings=tuple(str(w) for w in r.warnings), diagnostics=tuple(r.warnings)) for c in cells)
    return replace(team[0], team=team)


def _drives(r, t: dict, k: int, names: list) -> tuple[str, ...]:
    """The units a ``[[robot]]``'s ``drives`` names, each an ``[[external]]`` of the cell."""
    where = ("robot", k)
    value = t.get("drives", [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        r.fail(where, "drives", f"{r.title(where)} drives: give the names of the [[external]] units its task "
                                "drives, as a list of text")
    for v in value:
        if v not in names:
            near = nearest(v, [n for n in names if isinstance(n, str)])
            hint = f"; did you mean '{near}'?" if near else ""
            r.fail(where, "drives", f"{r.title(where)} drives '{v}': no [[external]] of that name{hint}")
    return tuple(value)


def _owners(tables: list[dict], drives: list[tuple[str, ...]], names: list) -> dict[str, int]:
    """Unit -> the robot whose task drives it: the one whose ``drives`` names it, else the one
    standing on it, else the first robot."""
    out: dict[str, int] = {}
    for k, given in enumerate(drives):
        for name in given:
            out.setdefault(name, k)
    for k, t in enumerate(tables):
        if isinstance(t.get("on"), str):
            out.setdefault(t["on"], k)
    for name in names:
        if isinstance(name, str):
            out.setdefault(name, 0)
    return out


def _named(cell: Cell, k: int) -> Cell:
    """The robot with a name and a task where neither the cell file nor the backup gave one:
    ABB's defaults for the k-th robot of a MultiMove system (``ROB_2``, ``T_ROB2``)."""
    robot = cell.robot
    return replace(cell, robot=replace(robot, name=robot.name or f"ROB_{k + 1}",
                                       task=robot.task or f"T_ROB{k + 1}"))


def _distinct(r, cells: list[Cell]) -> None:
    """Two robots of one name or one task are an error at the second's table."""
    for attr in ("name", "task"):
        seen: dict[str, int] = {}
        for k, c in enumerate(cells):
            value = getattr(c.robot, attr).lower()
            if value in seen:
                r.fail(("robot", k), attr, f"[[robot]] {k + 1} {attr}: '{getattr(c.robot, attr)}' is also "
                                           f"[[robot]] {seen[value] + 1}'s: give each robot its own {attr}")
            seen[value] = k
