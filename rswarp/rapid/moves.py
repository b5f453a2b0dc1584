"""RAPID's motion instructions as ``Motion`` records: where each puts its target, speed, zone and
tool among its arguments (MoveJ, MoveL, MoveC, MoveAbsJ, their DO, AO, GO and Sync forms, TriggJ,
TriggL, TriggC, ArcL and ArcC with their Start and End forms, SearchL, SearchJ, SearchC, SpotL,
SpotJ, CapL, PaintL), with ``\\V``, ``\\T``, ``\\Z``, ``\\Inpos`` and ``\\WObj``, and the
settings in force (ConfJ, ConfL, AccSet, VelSet, GripLoad's payload). A process move runs its
motion; its process (the arc, the gun, the search's signal) is not modelled."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

from . import data as rd
from . import nodes as n
from .arguments import Arguments
from .errors import fail
from .motion import Motion

MAX_WAIT = 86_400.0  # s: a WaitTime longer than a day is no program's
NO_LOAD_KG = 0.001  # load0's (and tool0's tload's) mass: a load of at most this is none (GripLoad load0 disconnects)


@dataclass(frozen=True)
class HeldLoad(rd.Load):
    """A payload GripLoad connected: its loaddata (SI), and where (``GripLoad piece1 at
    file:line``), which a report names it by."""

    source: str = ""


@dataclass(frozen=True)
class MoveSpec:
    """Where a motion instruction has its arguments: indices among the required ones (negative:
    from the end); ``zone`` None for instructions that always stop (search, spot)."""

    kind: str
    targets: tuple[int, ...]
    speed: int
    zone: int | None
    tool: int
    least: int  # required arguments at least


_J, _L, _C = ("joint", (0,), 1, 2, 3, 4), ("linear", (0,), 1, 2, 3, 4), ("circular", (0, 1), 2, 3, 4, 5)
MOVES = {
    "movej": MoveSpec(*_J), "movel": MoveSpec(*_L), "movec": MoveSpec(*_C),
    "moveabsj": MoveSpec("absolute", (0,), 1, 2, 3, 4),
    "movejdo": MoveSpec(*_J), "moveldo": MoveSpec(*_L), "movecdo": MoveSpec(*_C),
    "movejao": MoveSpec(*_J), "movelao": MoveSpec(*_L), "movecao": MoveSpec(*_C),
    "movejgo": MoveSpec(*_J), "movelgo": MoveSpec(*_L), "movecgo": MoveSpec(*_C),
    "movejsync": MoveSpec(*_J), "movelsync": MoveSpec(*_L), "movecsync": MoveSpec(*_C),
    "triggj": MoveSpec("joint", (0,), 1, 3, 4, 5), "triggl": MoveSpec("linear", (0,), 1, 3, 4, 5),
    "triggc": MoveSpec("circular", (0, 1), 2, 4, 5, 6),
    "arcl": MoveSpec("linear", (0,), 1, -2, -1, 6), "arclstart": MoveSpec("linear", (0,), 1, -2, -1, 6),
    "arclend": MoveSpec("linear", (0,), 1, -2, -1, 6), "arcc": MoveSpec("circular", (0, 1), 2, -2, -1, 7),
    "arccstart": MoveSpec("circular", (0, 1), 2, -2, -1, 7), "arccend": MoveSpec("circular", (0, 1), 2, -2, -1, 7),
    "searchl": MoveSpec("linear", (2,), 3, None, 4, 5), "searchj": MoveSpec("joint", (2,), 3, None, 4, 5),
    "searchc": MoveSpec("circular", (2, 3), 4, None, 5, 6),
    "spotl": MoveSpec("linear", (0,), 1, None, -1, 4), "spotj": MoveSpec("joint", (0,), 1, None, -1, 4),
    "capl": MoveSpec("linear", (0,), 1, -2, -1, 4), "capc": MoveSpec("circular", (0, 1), 2, -2, -1, 5),
    "paintl": MoveSpec("linear", (0,), 1, 2, 3, 4), "paintc": MoveSpec("circular", (0, 1), 2, 3, 4, 5),
}


def run_move(interp, spec: MoveSpec, a: Arguments, s: n.ProcCall, frame) -> None:
    """One motion instruction: its ``Motion``, and its side effects (a DO set at the point, a
    Sync procedure called, a search point written)."""
    if len(a) < spec.least:
        fail(interp.path, s.line, f"{s.name} takes at least {spec.least} arguments, given {len(a)}")
    kind = "jointtarget" if spec.kind == "absolute" else "robtarget"
    convert = rd.jointtarget if spec.kind == "absolute" else rd.robtarget
    targets, names, declared = [], [], []
    for k in spec.targets:
        node = a.node(k)
        if interp.undeclared(node, frame):
            fail(interp.path, s.line, f"unknown name '{node.name}'")
        declared.append(_declared(node, frame))
        written = n.written(node)
        names.append(written if len(written) <= 60 else written[:57] + "...")
        targets.append(a.si(convert, a.value(k, kind, f"{s.name}'s target '{names[-1]}'"), f"'{names[-1]}'"))
    speed = a.si(rd.speed, a.value(spec.speed, "speeddata"), "the speeddata")
    speed, duration = _overrides(interp, a, speed, s)
    if speed.v_tcp * 1000.0 > rd.TOP_TCP_SPEED or speed.v_ori > _TOP_ORI:
        speed = _top_speed(interp, speed, s, n.written(a.node(spec.speed)))
    if s.key in WELDING and len(a) > spec.speed + 2:
        speed = _weld_speed(interp, a.value(spec.speed + 2), speed, s)
    zone = rd.FINE if spec.zone is None or a.has("Inpos") else a.si(rd.zone, a.value(spec.zone, "zonedata"),
                                                                      "the zonedata")
    if a.has("Z") and not zone.fine:
        z = a.option("Z", "num")
        if not 0 <= z < 1e30:
            fail(interp.path, s.line, f"{s.name}: \\Z must be 0 mm or more, not {z:g}")
        zone = rd.Zone(False, z / 1000.0, max(zone.pzone_ori, z / 1000.0), zone.zone_ori)
    tool_rec = a.value(spec.tool, "tooldata")
    wobj_rec = a.option("WObj", "wobjdata") or frame.module.get("wobj0").get()
    tool, wobj = a.si(rd.tool, tool_rec, "the tool"), a.si(rd.work_object, wobj_rec, "the wobj")
    interp.state["tool"], interp.state["wobj"] = tool_rec, wobj_rec
    state = interp.state
    conf = state["conf_j"] if spec.kind == "joint" else state["conf_l"] if spec.kind != "absolute" else True
    interp.emit(Motion(spec.kind, s.name, interp.path, s.line, frame.routine.name, frame.chain(), tuple(targets),
                       tuple(names), speed, zone, tool, wobj, conf, state["accel"], state["ramp"], state["override"],
                       state["vmax"], duration, 0.0, interp.pass_index, tuple(declared),
                       _held(state.get("grip_load"), tool, wobj), sync_id=_sync_id(a)))
    _after(interp, s, a, spec, frame)


def _held(load, tool, wobj):
    """``held_in_flange``, asked only where a GripLoad holds a payload (hashing a tool costs)."""
    return None if load is None else held_in_flange(load, tool, wobj)


@lru_cache(maxsize=1024)
def held_in_flange(load: HeldLoad | None, tool: rd.Tool, wobj: rd.WorkObject) -> HeldLoad | None:
    """GripLoad's payload moved from the frame RAPID gives it in into the flange's (tool0), where
    a tool's own load is: the tool's frame when the robot holds the tool, else the frame of the
    work object the robot holds (a stationary tool: the robot moves the part past it)."""
    if load is None:
        return None
    frame = tool.tframe if tool.robhold else rd.Pose(*_object_frame(wobj)) if wobj.robhold else rd.IDENTITY
    m = frame.matrix()
    cog = tuple(float(v) for v in m[:3, :3] @ load.cog + m[:3, 3])
    return HeldLoad(load.mass, cog, load.inertia, _quat_product(frame.quat, load.aom), load.source)


def _object_frame(wobj: rd.WorkObject) -> tuple:
    """The pose (translation, quaternion) of a work object's object frame in its user frame's parent."""
    u, o = wobj.uframe, wobj.oframe
    trans = u.matrix()[:3, :3] @ o.trans + u.trans
    return tuple(float(v) for v in trans), _quat_product(u.quat, o.quat)


def _quat_product(a, b) -> tuple[float, float, float, float]:
    """The rotation ``b`` then ``a`` (w, x, y, z): the axes ``b`` gives in the frame ``a`` turns to."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def _declared(node, frame) -> str:
    """``file:line`` of the data a target is or is built from (``Offs(p, ...)``: p's), "" where none."""
    while isinstance(node, n.Call):
        node = next((g.expr for g in node.args if not g.optional), None)
    cell = frame.cells.get(node.key) or frame.module.get(node.key) if isinstance(node, n.Name) else None
    cell = getattr(cell, "cell", cell)
    named = getattr(cell, "file", "") and cell.type in ("robtarget", "jointtarget")
    if named and getattr(cell, "set_at", None):  # a variable assigned at run time: where it was set
        return f"set {cell.set_at[0]}:{cell.set_at[1]}"
    return f"{cell.file}:{cell.line}" if named else ""  # an IN parameter's is its argument's declaration


WELDING = {"arcl", "arcc", "arclend", "arccend"}  # the arc burns: the TCP goes at the welddata's weld_speed


def _weld_speed(interp, weld, speed: rd.Speed, s) -> rd.Speed:
    """The welddata's weld_speed (mm/s) as the TCP's speed while welding: the first component in
    RobotWare 6's layout [weld_speed, org_weld_speed, main_arc, org_arc], the second in
    ArcWare's [weld_sched, weld_speed, ...]."""
    parts = weld if isinstance(weld, (list, tuple)) else getattr(weld, "value", None)
    if isinstance(parts, (list, tuple)) and len(parts) > 1:
        modern = len(parts) == 4 and isinstance(parts[2], (list, tuple))
        v = parts[0] if modern else parts[1]
        if isinstance(v, (int, float)) and not isinstance(v, bool) and 0 < v <= rd.MAX_SPEED:
            return replace(speed, v_tcp=float(v) / 1000.0)
    interp.warn(s.line, f"{s.name}: the welddata has no weld_speed rswarp can read: timed at the speeddata")
    return speed


_TOP_ORI = math.radians(rd.MAX_SPEED)  # rad/s: a turn faster than any axis, capped like the TCP's speed


def _top_speed(interp, speed: rd.Speed, s, name: str) -> rd.Speed:
    """A speed above the robot's top speed, run at the top speed as the controller runs it (one
    warning per speeddata and task)."""
    v = speed.v_tcp * 1000.0
    if v > rd.TOP_TCP_SPEED:
        interp.warn_once(("top speed", name.lower()), s.line,
                         f"{s.name}: '{name}' asks {v:g} mm/s of the TCP: the controller limits it to the robot's "
                         f"top speed, {rd.TOP_TCP_SPEED:g} mm/s, and so does rswarp (said once for '{name}')")
    return replace(speed, v_tcp=min(speed.v_tcp, rd.TOP_TCP_SPEED / 1000.0), v_ori=min(speed.v_ori, _TOP_ORI))


def _overrides(interp, a: Arguments, speed: rd.Speed, s) -> tuple[rd.Speed, float | None]:
    """``\\V`` (the TCP's speed, mm/s) and ``\\T`` (the move's time, s) of a move."""
    v = a.option("V", "num")
    if v is not None:
        if not 0 < v < 1e30:
            fail(interp.path, s.line, f"{s.name}: \\V must be above 0 mm/s, not {v:g}")
        speed = replace(speed, v_tcp=v / 1000.0)
    t = a.option("T", "num")
    if t is not None and not 0 < t <= MAX_WAIT:
        fail(interp.path, s.line, f"{s.name}: \\T must be above 0 and at most {MAX_WAIT:g} s, not {t:g}")
    return speed, t


def _after(interp, s: n.ProcCall, a: Arguments, spec: MoveSpec, frame) -> None:
    key = s.key
    if key.endswith(("do", "ao", "go")) and key.startswith("move") and len(a) >= spec.tool + 3:
        interp.signal_of(a.node(spec.tool + 1), frame).set(a.number(spec.tool + 2))
    elif key.endswith("sync") and len(a) > spec.tool + 1:
        interp.call_named(a.value(spec.tool + 1, "string"), (), frame, s.line)
    elif key.startswith("search"):
        point = a.reference(1)
        point.set(a.value(spec.targets[-1], "robtarget"))
        interp.warn(s.line, f"{s.name}: no signal is modelled; the search runs to its ToPoint and finds it there")


def _sync_id(a) -> float | None:
    """A move's ``\\ID`` (MultiMove's synchronized moves), or None."""
    return float(a.option("ID", "num")) if a.has("ID") else None


def wait(interp, seconds: float, s: n.ProcCall, frame) -> None:
    if not 0 <= seconds <= MAX_WAIT:
        fail(interp.path, s.line, f"WaitTime takes 0 to {MAX_WAIT:g} s (a day), not {seconds:g}")
    interp.waited += seconds
    interp.emit(Motion("wait", s.name, interp.path, s.line, frame.routine.name, frame.chain(), seconds=seconds,
                       cycle=interp.pass_index))
