"""One finding record for everything a run finds (a program's moves, a collision sweep, a hose):
what it is (``kind``), how bad (``severity``), where (the program's ``file``/``line``/``routine``,
its call ``chain`` and where its target is ``declared``, the ``links`` involved, a cable's ``env``
and arc length ``at_m``), when (``t_s`` and the ``joints`` then), how much (``value`` against
``limit``, in ``unit``, SI) and what to change (``advice``), with ``text``, the same in words. It
sits beside ``errors`` at the bottom of the package because the planner makes findings as well as
the reports; ``report.findings`` prints them."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

FAIL = "fail"  # the program or design must change: the controller would stop, or something breaks
WARN = "warn"  # worth a look; nothing stops or breaks

# what each kind means, for the docs and for tests that every kind made is a known one
KINDS = {
    "collision": "two bodies touch (links, the environment, the tool)",
    "floor": "a link goes below the floor",
    "joint_limit": "a joint goes outside its limits",
    "singularity": "a linear or circular move passes near the wrist singularity (q5 = 0)",
    "path": "a linear or circular move cannot be followed to its end",
    "configuration": "a move ends in another configuration than its robtarget's confdata",
    "unreachable": "a target the robot cannot reach",
    "target": "a target the robot cannot take for another reason (confdata, external axes, unset axes)",
    "tool": "the tool's TCP is not on or near its body",
    "taut": "a hose pulled, not hanging: its axial strain past its rating",
    "kink": "a hose bent tighter than its static bend radius: permanent damage",
    "bend": "a hose bent tighter than its dynamic bend radius (a warning where the robot is at rest)",
    "torsion": "a hose twisted more per metre than its rating",
    "rub": "a hose touching a link, the floor or the cell: time in contact, force and wear",
    "pinch": "a hose pressed from opposite sides harder than its own weight could",
    "crush": "a hose the robot drove through something: its run stopped",
    "clamp": "a clamp pulled harder than its rating",
    "slack": "a hose with no length to spare, or none given",
}


@dataclass(frozen=True)
class Finding:
    """One thing found, as data and as words; all numbers SI (m, rad, s, N, kg)."""

    kind: str
    text: str  # what a reader sees, without the place (the report puts ``file:line`` before it)
    severity: str = WARN
    file: str | None = None
    line: int | None = None
    routine: str | None = None
    t_s: float | None = None  # when, from the start of the run
    links: tuple[str, ...] = ()  # the bodies involved, each named once
    joint: str | None = None  # the axis concerned, where one is
    joints: tuple[float, ...] | None = None  # the joint values (rad, m) at t_s
    value: float | None = None
    limit: float | None = None
    unit: str | None = None
    advice: str | None = None
    cable: str | None = None
    env: int | None = None
    at_m: float | None = None  # arc length along a cable from its first clamp
    chain: tuple[str, ...] = ()  # the calls that led to the move, outermost first: ``main (file:line)``
    declared: str | None = None  # ``file:line`` of the data its target is or is built from

    def __post_init__(self):
        if self.kind not in KINDS or self.severity not in (FAIL, WARN):
            raise ValueError(f"finding of unknown kind or severity: {self.kind}, {self.severity}")

    def record(self) -> dict:
        """The finding as JSON-ready data: every field, numbers as plain floats."""
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if isinstance(v, tuple):
                v = [_plain(x) for x in v]
            out[f.name] = _plain(v)
        if out.get("declared"):  # ``file:line`` of the target's declaration, or of its last assignment ("set ...")
            out["declared_by"] = "assignment" if out["declared"].startswith("set ") else "declaration"
            out["declared"] = out["declared"].removeprefix("set ")
        return out


def _plain(v):
    if isinstance(v, (np.floating, float)):
        return float(v) if np.isfinite(v) else None
    if isinstance(v, np.integer):
        return int(v)
    return v


def at_time(kind: str, text: str, motion, t_s: float | None, joints=None, **more) -> Finding:
    """A finding of a program's move ``motion`` (its file, line, routine, call chain and where its
    target's data is declared), at ``t_s``."""
    q = None if joints is None else tuple(float(v) for v in np.asarray(joints, float))
    where = getattr(motion, "declared", ())
    return Finding(kind, text, file=motion.file, line=motion.line, routine=motion.routine,
                   chain=tuple(getattr(motion, "chain", ())), declared=where[-1] or None if where else None,
                   t_s=None if t_s is None else float(t_s), joints=q, **more)
