"""A RobotStudio backup's I/O configuration (``SYSPAR/EIO.cfg``): the signals the controller
defines, by name, with their type (DI, DO, AI, AO, GI, GO) and default value. A task's name that
the configuration declares is a signal, as on the controller."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..files import read_regular
from ..rsxml.cfg import parse_cfg
from .errors import fail, warning
from .parse import NotText, decode

_TYPES = {"DI": "signaldi", "DO": "signaldo", "AI": "signalai", "AO": "signalao", "GI": "signalgi", "GO": "signalgo"}


@dataclass(frozen=True)
class Signal:
    """A signal the I/O configuration defines: its name, RAPID type and default value."""

    name: str
    type: str
    default: float
    file: str
    line: int


def find_eio(folder: Path) -> Path | None:
    """The backup's ``SYSPAR/EIO.cfg`` for a folder given as a task: the backup itself, its RAPID
    folder, a task folder in it, or the folder that holds the one backup."""
    for root in (folder, folder.parent, folder.parent.parent):
        for name in ("SYSPAR", "syspar"):
            cfg = root / name / "EIO.cfg"
            if cfg.is_file():
                return cfg
    below = [c for c in folder.glob("*/SYSPAR/EIO.cfg") if c.is_file()]  # the folder that holds the backup
    return below[0] if len(below) == 1 else None


def read_eio(path: Path) -> dict[str, Signal]:
    """The signals of an EIO.cfg by lower-case name; ``file:line`` errors where it cannot be read."""
    try:
        text = decode(read_regular(path), str(path))
    except OSError as exc:
        fail(str(path), 0, f"cannot read: {exc.strerror or exc}")
    except NotText:
        fail(str(path), 0, "not a CFG text file (it holds NUL bytes or control characters: binary)")
    out: dict[str, Signal] = {}
    for entry in parse_cfg(text, str(path), strict=False):  # lenient: an optional file, read for names
        name, kind = entry.name, (entry.text("signaltype") or entry.text("type") or "").upper()
        if entry.section != "EIO_SIGNAL" or not name or kind not in _TYPES:
            continue
        try:
            default = float(entry.text("default") or "0")
        except ValueError:
            default = 0.0
        out.setdefault(name.lower(), Signal(name, _TYPES[kind], default, str(path), entry.line))
    return out


def add_configuration(task, path) -> None:
    """The I/O configuration of a cell's backup (``Cell.eio``, its SYSPAR/EIO.cfg) given to
    ``task`` as a task folder's backup gives its own, said in a note: its signals join those the
    task's folder brought (the cell's backup's default where both declare a name); nothing where
    the task's folder is that same backup."""
    cfg = Path(path)
    if any(Path(s.file).resolve() == cfg.resolve() for s in task.signals.values()):
        return
    signals = read_eio(cfg)
    task.signals = {**task.signals, **signals}
    task.notes.append(warning(str(cfg), 0, f"the I/O configuration of the cell's backup: {len(signals)} signals read "
                                           "(their names are signals in the task, at their default values unless "
                                           "--io sets them)"))
