"""A RAPID task as the controller loads it: its module files (named one by one, a folder and
everything under it, a RobotStudio backup's task, or a .pgf program file), parsed once, and its
names resolved as the controller resolves them. Global data and routines are seen by every module;
LOCAL ones stay in their module; a name declared twice is an error naming both places (a PERS
declared in several modules is one object, as on the controller)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import Diagnostic, InputError, RsxmlError
from ..files import no_cyclic_gc
from . import nodes
from .errors import fail, warning
from .parse import SUFFIXES, NotText, read_file
from .values import Types

MAX_FILES = 10_000  # module files of one task
# Bytes of RAPID text in one task: 350 000 declared robtargets, each some 5 KB of memory once read
# (nodes, values and their records); more is refused before it is read.
MAX_TASK_BYTES = 32 * 1024 * 1024
_TASK_FOLDER = re.compile(r"^(TASK\d+|T_ROB\w*)$", re.I)


@dataclass
class Symbol:
    """A module-level name: its declaration (``nodes.Data`` or ``nodes.Routine``) and module."""

    node: object
    module: nodes.Module


@dataclass
class Task:
    """The modules of a task and its names: ``globals`` (data and routines every module sees) and
    ``locals`` per module (its LOCAL ones)."""

    modules: list[nodes.Module]
    files: list[str]
    types: Types
    globals: dict[str, Symbol] = field(default_factory=dict)
    locals: dict[str, dict[str, Symbol]] = field(default_factory=dict)
    notes: list = field(default_factory=list)
    signals: dict = field(default_factory=dict)  # lower-case name -> eio.Signal, from a backup's EIO.cfg

    def routine(self, name: str) -> nodes.Routine:
        """The entry routine: a global (or the only) PROC without parameters; an error for one that
        is missing (naming the procedures there), and at its line for a FUNC, a TRAP, or one that
        takes arguments."""
        key = name.lower()
        found = self.globals.get(key)
        if found is None:
            local = [m[key] for m in self.locals.values() if key in m]
            found = local[0] if len(local) == 1 else None
        if found is None or not isinstance(found.node, nodes.Routine):
            procs = sorted({s.node.name for s in self._all() if isinstance(s.node, nodes.Routine)
                            and s.node.kind == "proc" and not s.node.params})
            files = ", ".join(Path(f).name for f in self.files[:3]) + (", ..." if len(self.files) > 3 else "")
            raise InputError(f"no routine '{name}' in the task of {files} (procedures without parameters: "
                             f"{', '.join(procs) or 'none'})")
        r = found.node
        if r.kind != "proc":
            fail(r.file, r.line, f"'{r.name}' is a {'FUNC' if r.kind == 'func' else 'TRAP'}: a task runs a PROC")
        if any(not p.optional for p in r.params):
            fail(r.file, r.line, f"PROC '{r.name}' takes arguments: a task starts from a PROC without them")
        return r

    def _all(self):
        yield from self.globals.values()
        for names in self.locals.values():
            yield from names.values()


def task_files(paths: list[str | Path], name: str | None = None) -> tuple[list[Path], list]:
    """The module files of ``paths`` (files, folders, .pgf program files) in load order, and notes
    on what a folder held that is not run; ``name``: the task a backup's folder runs (``T_ROB2``;
    None: its first)."""
    files: list[Path] = []
    notes: list = []
    for p in map(Path, paths):
        if p.is_dir():
            files += _folder_files(p, notes, name)
        elif p.suffix.lower() == ".pgf":
            files += _program_file(p)
        else:
            files.append(p)
    seen, out = set(), []
    for f in files:
        key = f.resolve() if f.exists() else f
        if key not in seen:
            seen.add(key)
            out.append(f)
    if len(out) > MAX_FILES:
        fail(str(paths[0]), 0, f"{len(out)} module files: a task takes at most {MAX_FILES}")
    return out, notes


def backup_tasks(paths: list[str | Path]) -> tuple[str, ...]:
    """The task folders (``T_ROB1``, ...) of the first folder given that is a backup's (or its
    RAPID folder); none where no folder given holds any."""
    for folder in (Path(p) for p in paths):
        root = folder / "RAPID" if (folder / "RAPID").is_dir() else folder
        if root.is_dir():
            tasks = sorted(d.name for d in root.iterdir() if d.is_dir() and _TASK_FOLDER.match(d.name))
            if tasks:
                return tuple(tasks)
    return ()


def _folder_files(folder: Path, notes: list, name: str | None = None) -> list[Path]:
    """Every module file under ``folder``; of a backup (RAPID/ and its task folders), the task
    ``name`` names (its first where None, with a note naming the others)."""
    root = folder / "RAPID" if (folder / "RAPID").is_dir() else folder
    tasks = sorted((d for d in root.iterdir() if d.is_dir() and _TASK_FOLDER.match(d.name)), key=lambda d: d.name)
    if name is not None and tasks:
        found = [t for t in tasks if t.name.lower() == name.lower()]
        if not found:
            have = ", ".join(t.name for t in tasks)
            fail(str(folder), 0, f"--task {name}: the backup has no such task (it has {have})")
        root = found[0]
    elif tasks:
        if len(tasks) > 1:
            notes.append(warning(str(folder), 0, f"the folder holds the tasks {', '.join(t.name for t in tasks)}: "
                                                 f"running {tasks[0].name} (--task names another)"))
        root = tasks[0]
    files = []
    for f in sorted(root.rglob("*")):
        if f.suffix.lower() in SUFFIXES and f.is_file():
            files.append(f)
            if len(files) > MAX_FILES:
                fail(str(folder), 0, f"more than {MAX_FILES} module files under the folder")
    if not files:
        fail(str(folder), 0, f"no RAPID module ({', '.join(SUFFIXES)}) under the folder")
    return files


def _program_file(path: Path) -> list[Path]:
    """The modules a RobotStudio program file (.pgf) names, beside it."""
    from ..rsxml.parse import local, parse_xml

    root = parse_xml(path)
    named = [((el.text or "").strip(), el.sourceline or 0) for el in root.iter()
             if isinstance(el.tag, str) and local(el) == "Module"]
    if not named:
        fail(str(path), 0, "the program file names no <Module>")
    folder = path.parent.resolve()
    out, problems = [], []
    for name, line in named:
        relative = Path(name.replace("\\", "/"))
        f = (path.parent / relative)
        inside = not relative.is_absolute() and not relative.drive and folder in (f.resolve(), *f.resolve().parents)
        if not inside:  # refused before it is read: a program file names its own modules
            problems.append(Diagnostic(str(path), line, f"the program file names '{name}', outside its folder: a .pgf "
                                                        "names modules in its folder and below it"))
        elif not f.is_file():
            problems.append(Diagnostic(str(path), line, f"the program file names '{name}', which is not beside it"))
        out.append(f)
    if problems:  # every one at once
        raise RsxmlError(problems)
    return out


def load_task(paths: list[str | Path], name: str | None = None) -> Task:
    """The task made of ``paths``: parsed, its types and names resolved; ``name``: which task of a
    backup's folder (``T_ROB2``; None: its first)."""
    with no_cyclic_gc():
        return _load_task(paths, name)


def _io_configuration(paths: list[str | Path], notes: list) -> dict:
    """The signals of the backup a folder given belongs to (its SYSPAR/EIO.cfg), said in a note."""
    from .eio import find_eio, read_eio

    for p in map(Path, paths):
        cfg = find_eio(p) if p.is_dir() else None
        if cfg is not None:
            signals = read_eio(cfg)
            notes.append(warning(str(cfg), 0, f"the I/O configuration: {len(signals)} signals read (their names are "
                                              "signals in the task, at their default values unless --io sets them)"))
            return signals
    return {}


def _named(paths: list[str | Path]) -> set[Path]:
    """The module files given by themselves (not a folder's, nor a .pgf program file's)."""
    return {p.resolve() for p in map(Path, paths) if not p.is_dir() and p.suffix.lower() != ".pgf"}


def _modules_of(f: Path, named: set[Path], notes: list) -> list[nodes.Module] | None:
    """The modules of file ``f``; None, with a warning, for an encrypted module (binary: ABB's own
    system modules, a module saved NOVIEW) that a folder or a .pgf brings: the controller loads it,
    rswarp cannot read it, so only what the task needs from it is missing (an error at that use).
    One named by itself is the error it is: that file is all the user asked for."""
    try:
        return read_file(f)[0]
    except NotText as exc:
        if f.resolve() in named:
            d = exc.diagnostics[0]
            fail(d.file, d.line, f"{d.message}; in a task's folder an encrypted module is skipped with a warning")
        notes.append(warning(str(f), 0, "an encrypted module: skipped; only what the task needs from it is missing"))
        return None


def _load_task(paths: list[str | Path], name: str | None = None) -> Task:
    files, notes = task_files(paths, name)
    signals = _io_configuration(paths, notes)
    named = _named(paths)
    modules: list[nodes.Module] = []
    names: dict[str, nodes.Module] = {}
    total, skipped = 0, 0
    for f in files:
        total += f.stat().st_size if f.is_file() else 0
        if total > MAX_TASK_BYTES:
            fail(str(f), 0, f"the task's modules pass {MAX_TASK_BYTES >> 20} MiB of text with this file: rswarp "
                            f"reads at most {MAX_TASK_BYTES >> 20} MiB of RAPID (some 350 000 robtargets)")
        found = _modules_of(f, named, notes)
        if found is None:
            skipped += 1
            continue
        for m in found:
            other = names.get(m.name.lower())
            if other is not None:
                fail(m.file, m.line, f"a second module '{m.name}': the first is at {other.file}:{other.line}")
            names[m.name.lower()] = m
            modules.append(m)
    if files and skipped == len(files):
        fail(str(paths[0]), 0, f"every module of the task is encrypted ({', '.join(f.name for f in files[:3])}"
                               f"{', ...' if len(files) > 3 else ''}): rswarp reads none, so there is nothing to run")
    task = Task(modules, [str(f) for f in files], Types(), notes=notes, signals=signals)
    for m in modules:
        for r in m.records:
            task.types.add_record(r.name, r.components)
        for a in m.aliases:
            task.types.add_alias(a.name, a.type)
    for m in modules:
        _declare(task, m)
    return task


def _declare(task: Task, module: nodes.Module) -> None:
    """The module's data and routines into the task's names, each once."""
    own: dict[str, Symbol] = {}
    task.locals[module.name.lower()] = own
    routines = [nodes.Routine(**{**{f: getattr(r, f) for f in r.__slots__}, "module": module.name})
                for r in module.routines]
    for r in routines:
        _check_routine_names(module, r)
    for node in (*module.data, *routines):
        key = node.name.lower()
        local = node.local if isinstance(node, nodes.Routine) else node.scope == "local"
        before = own.get(key) or (None if local else task.globals.get(key))
        if before is not None and not _same_pers(before.node, node):
            b = before.node
            where = b.file if isinstance(b, nodes.Routine) else before.module.file
            fail(module.file, node.line, f"'{node.name}' is declared twice: also at {where}:{b.line}")
        symbol = Symbol(node, module)
        own[key] = symbol
        if not local:
            task.globals.setdefault(key, symbol)
    object.__setattr__(module, "routines", tuple(routines))


def _check_routine_names(module: nodes.Module, r: nodes.Routine) -> None:
    """A ``file:line`` error where a routine's parameters and data name one thing twice (the
    controller refuses it; the last would win unnoticed)."""
    seen: dict[str, str] = {}
    for p in r.params:
        if p.key in seen:
            fail(module.file, r.line, f"{r.name} has two parameters named '{p.name}'")
        seen[p.key] = f"a parameter of {r.name}"
    for d in r.body.statements:
        if d.__class__ is nodes.Data:
            key = d.name.lower()
            if key in seen:
                fail(module.file, d.line, f"'{d.name}' is declared twice in {r.name}: it is also {seen[key]}")
            seen[key] = f"declared at line {d.line}"


def _same_pers(a, b) -> bool:
    return (isinstance(a, nodes.Data) and isinstance(b, nodes.Data) and a.storage == b.storage == "pers"
            and a.type.lower() == b.type.lower())
