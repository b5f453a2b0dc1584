"""RAPID's built-in functions a program computes with: arithmetic, strings, bits, poses (Offs,
RelTool, OrientZYX, EulerZYX, PoseMult, PoseInv, PoseVect, NOrient, DefFrame, ...), I/O reads,
clocks, and the robot's state (CRobT, CJointT, CPos, CalcJointT, CalcRobT), which the task's
``Robot`` answers. A function rswarp does not evaluate is a ``file:line`` error: its value would
be a guess: one RAPID defines and rswarp does not compute, or one only the cell answers (a
socket, a file, the operator), gives a ``Live`` value, unknown until ``--input`` gives it."""

from __future__ import annotations

import math
import time

from . import byname, calibration, poses, strings, words
from . import data as rd
from .arguments import Arguments
from .errors import fail, rapid_error
from .live import Live, LiveValue, function_input
from .values import Arr, Rec, describe, whole


def call_function(interp, node, frame):
    entry = FUNCTIONS.get(node.key)
    if entry is None:
        entry = _unevaluated(node.key)
    args = Arguments(interp, node.name, node.args, frame, node.line)
    try:
        value = entry(interp, args)
    except LiveValue as lv:  # a function of what a live read gave is as unknown, and so is what it writes
        _unknown_outputs(interp, node, args, lv.live)
        return lv.live
    if isinstance(value, float) and not math.isfinite(value):
        fail(interp.path, node.line, f"{node.name} has no finite value here")
    return value


def _unknown_outputs(interp, node, args: Arguments, live: Live) -> None:
    """The data a function writes (StrToVal's value, ...) made unknown like its inputs."""
    from . import nodes as n

    places = words.positions(node.key)
    for p in words.outputs(node.key):
        k = next((i for i, group in enumerate(places) if p in group), None)
        expr = args.optional.get(p.name.lower()) if p.optional else args.node(k) if k is not None and k < len(args) \
            else None
        if expr.__class__ is n.Name and not expr.selectors:
            cell = args.frame.cells.get(expr.key) or args.frame.module.get(expr.key)
            if cell is not None and cell.kind not in ("const", "loop"):
                cell.set(live)


def _math(fn, count: int = 1, degrees_in: bool = False, degrees_out: bool = False):
    def run(interp, a: Arguments):
        a.need(count)
        xs = [a.number(k) for k in range(count)]
        if degrees_in:
            xs = [math.radians(x) for x in xs]
        try:
            v = fn(*xs)
        except (ValueError, ZeroDivisionError, OverflowError):
            fail(interp.path, a.line, f"{a.name}({', '.join(f'{x:g}' for x in xs)}) is outside its domain")
        return math.degrees(v) if degrees_out else float(v)
    return run


def _round(interp, a: Arguments, trunc: bool = False) -> float:
    a.need(1)
    x, dec = a.number(0), a.option("Dec", "num", 0.0)
    f = 10.0 ** int(dec)
    return (math.trunc(x * f) if trunc else math.floor(x * f + 0.5) if x >= 0 else -math.floor(-x * f + 0.5)) / f


def _numtostr(interp, a: Arguments) -> str:
    """NumToStr: ``dec`` decimals, the last rounded half away from zero as the controller rounds."""
    a.need(2)
    x, dec = a.number(0), max(int(a.number(1)), 0)
    if a.has("Exp"):
        return f"{x:.{dec}E}"
    f = 10.0 ** dec
    rounded = math.floor(abs(x) * f + 0.5 + 1e-9) / f
    return f"{math.copysign(rounded, x) if rounded else 0.0:.{dec}f}"


def _strpart(interp, a: Arguments) -> str:
    a.need(3)
    s, start, length = a.value(0, "string"), int(a.number(1)), int(a.number(2))
    if start < 1 or length < 0 or start - 1 + length > len(s):
        fail(interp.path, a.line, f"StrPart: characters {start} to {start + length - 1} of a string of {len(s)}")
    return s[start - 1:start - 1 + length]


def _strfind(interp, a: Arguments) -> float:
    a.need(3)
    s, start, chars = a.value(0, "string"), int(a.number(1)), a.value(2, "string")
    outside = a.has("NotInSet")
    for k in range(max(start, 1) - 1, len(s)):
        if (s[k] in chars) != outside:
            return float(k + 1)
    return float(len(s) + 1)


def _valtostr(interp, a: Arguments) -> str:
    """ValToStr: a value written as RAPID writes it (a num to 6 significant digits, a record as its
    aggregate ``[100,250,0]``), at most RAPID's 80 characters."""
    a.need(1)
    v = a.value(0)
    return v if isinstance(v, str) else rapid_text(v)[:80]


def rapid_text(v) -> str:
    if isinstance(v, bool):
        return "TRUE" if v else "FALSE"
    if isinstance(v, float):
        return f"{v:.6g}".upper()
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, Rec):
        return "[" + ",".join(rapid_text(x) for x in v.vals) + "]"
    if isinstance(v, Arr):
        return "[" + ",".join(rapid_text(x) for x in v.items) + "]"
    return describe(v)


def _bits(fn, count: int):
    def run(interp, a: Arguments):
        a.need(count)
        xs = [a.number(k) for k in range(count)]
        if not all(whole(x) for x in xs):
            fail(interp.path, a.line, f"{a.name} takes whole numbers")
        return float(fn(*(int(x) for x in xs)))
    return run


def _dim(interp, a: Arguments) -> float:
    a.need(2)
    arr, d = a.value(0), int(a.number(1))
    if not isinstance(arr, Arr) or not 1 <= d <= len(arr.dims):
        fail(interp.path, a.line, f"Dim: {describe(arr)} has no dimension {d}")
    return float(arr.dims[d - 1])


def _present(interp, a: Arguments) -> bool:
    a.need(1)
    node = a.node(0)
    cell = a.frame.cells.get(getattr(node, "key", ""))
    return cell is not None and cell.kind != "absent"


def _offs(interp, a: Arguments) -> Rec:
    a.need(4)
    return poses.offs(a.value(0, "robtarget"), a.number(1), a.number(2), a.number(3))


def _reltool(interp, a: Arguments) -> Rec:
    a.need(4)
    turns = [a.option(k, "num", 0.0) for k in ("Rx", "Ry", "Rz")]
    return poses.reltool(a.value(0, "robtarget"), a.number(1), a.number(2), a.number(3), *turns)


def _euler(interp, a: Arguments) -> float:
    a.need(1)
    which = next((k for k in "xyz" if a.has(k)), None)
    if which is None:
        fail(interp.path, a.line, "EulerZYX needs \\X, \\Y or \\Z")
    return poses.euler_zyx(a.value(0, "orient").vals, which)


def _deframe(interp, a: Arguments) -> Rec:
    a.need(3)
    p = [a.value(k, "robtarget").vals[0].vals for k in range(3)]
    f = poses.def_frame(*p, origin=int(a.option("Origin", "num", 1.0)))
    if f is None:
        fail(interp.path, a.line, "DefFrame: the three points are on one line")
    return f


def _robot(interp, a: Arguments, ask):
    interp.volatile()
    try:
        return ask()
    except LookupError as exc:
        fail(interp.path, a.line, f"{a.name}: {exc}")


def _extax(values) -> list[float]:
    """Six external-axis values as RAPID holds them (9E9 for an axis not there)."""
    values = list(values or ())
    return [9e9 if v is None else float(v) for v in values + [None] * (6 - len(values))]


def _robtarget(interp, pose: rd.Pose, conf, extax=()) -> Rec:
    return interp.types.coerce([[c * 1000.0 for c in pose.trans], list(pose.quat), [float(c) for c in conf],
                                _extax(extax)], "robtarget")


def _jointtarget(interp, joints, extax=()) -> Rec:
    revolute = interp.robot.revolute()
    values = [math.degrees(q) if r else q * 1000.0 for q, r in zip(joints, revolute)]
    return interp.types.coerce([values + [9e9] * (6 - len(values)), _extax(extax)], "jointtarget")


def _si_joints(interp, jt: Rec, a: Arguments) -> tuple[float, ...]:
    revolute = interp.robot.revolute()
    out = []
    for v, r in zip(jt.vals[0].vals, revolute):
        if rd.UNUSED[0] <= abs(v) <= rd.UNUSED[1]:
            fail(interp.path, a.line, f"{a.name}: the jointtarget leaves an axis of the robot unset (9E9)")
        if not (math.isfinite(v) and abs(v) <= rd.MAX_AXIS):
            fail(interp.path, a.line, f"{a.name}: the jointtarget holds {v:g}, beyond {rd.MAX_AXIS:g}")
        out.append(math.radians(v) if r else v / 1000.0)
    return tuple(out)


def _crobt(interp, a: Arguments) -> Rec:
    _, _, tool, wobj = a.tool_wobj()
    joints = _robot(interp, a, lambda: interp.robot.joints_after(interp.motions))
    extax = interp.robot.extax_after(interp.motions)
    pose, conf = _robot(interp, a, lambda: interp.robot.pose(joints, tool, wobj, extax))
    return _robtarget(interp, pose, conf, extax)


def _cpos(interp, a: Arguments) -> Rec:
    return _crobt(interp, a).vals[0]


def _cjointt(interp, a: Arguments) -> Rec:
    joints = _robot(interp, a, lambda: interp.robot.joints_after(interp.motions))
    return _jointtarget(interp, joints, interp.robot.extax_after(interp.motions))


def _calcjointt(interp, a: Arguments) -> Rec:
    a.need(2)
    target = a.si(rd.robtarget, a.value(0, "robtarget"), "CalcJointT's target")
    _, _, tool, wobj = a.tool_wobj(a.value(1, "tooldata"), active=False)
    joints, why = _robot(interp, a, lambda: interp.robot.solve(target, tool, wobj))
    if joints is None:
        rapid_error(interp.path, a.line, f"CalcJointT: {why}", "ERR_ROBLIMIT")
    return _jointtarget(interp, joints, target.extax)


def _calcrobt(interp, a: Arguments) -> Rec:
    a.need(2)
    jt = a.value(0, "jointtarget")
    joints = _si_joints(interp, jt, a)
    extax = [None if rd.UNUSED[0] <= abs(v) <= rd.UNUSED[1] else float(v) for v in jt.vals[1].vals]
    _, _, tool, wobj = a.tool_wobj(a.value(1, "tooldata"), active=False)
    pose, conf = _robot(interp, a, lambda: interp.robot.pose(joints, tool, wobj, extax))
    return _robtarget(interp, pose, conf, extax)


def _signal_value(interp, a: Arguments) -> float:
    a.need(1)
    return interp.signal_of(a.node(0), a.frame).get()


def _clkread(interp, a: Arguments) -> float:
    a.need(1)
    interp.volatile()
    return interp.clock_read(a.reference(0))


def _unknown(why: str | None = None):
    """A function whose value rswarp does not have (a live read's, ``why`` None; or as ``why``
    says): what ``--input NAME=VALUE`` gives under its own name, else an unknown value."""
    def run(interp, a: Arguments):
        text = interp.inputs.take(a.name)
        return Live(a.name, None, interp.path, a.line, why) if text is None else function_input(text)
    return run


def _unevaluated(key: str):
    """A function RAPID defines and rswarp does not compute, or one no one defines (an option's,
    a module's not in the task): a value rswarp does not have, so unknown, never a guess."""
    w = words.word(key)
    if w is not None and w.kind == "function" and key in words.STATE_VALUES:
        value = words.STATE_VALUES[key]
        return lambda interp, a: value
    if w is not None and w.handling == "live":
        return _unknown()
    return _unknown("a function of RAPID's that rswarp does not compute offline:" if w is not None else
                    "a function neither the task nor RAPID defines (an option's, or a module's not in the task):")


def _crossprod(interp, a: Arguments) -> Rec:
    """CrossProd, and ``pos * pos``: the vector product."""
    a.need(2)
    return poses.pos(poses.cross(a.value(0, "pos").vals, a.value(1, "pos").vals))


def _type(interp, a: Arguments) -> str:
    """Type(Data): the name of the data type of the data given (its alias's, unless \\BaseName)."""
    a.need(1)
    node = a.node(0)
    cell = a.frame.cells.get(getattr(node, "key", "")) or a.frame.module.get(getattr(node, "key", ""))
    type_ = cell.type if cell is not None and not getattr(node, "selectors", ()) else getattr(a.value(0), "type", "")
    if not type_:
        v = a.value(0)
        type_ = "bool" if isinstance(v, bool) else "num" if isinstance(v, float) else "string"
    return interp.types.base(type_) if a.has("BaseName") else type_


_N = lambda v: (lambda interp, a: v)  # noqa: E731  a constant answer

FUNCTIONS = {
    "abs": _math(abs), "absdnum": _math(abs), "sqrt": _math(math.sqrt), "sqrtdnum": _math(math.sqrt),
    "pow": _math(math.pow, 2), "powdnum": _math(math.pow, 2), "exp": _math(math.exp),
    "sin": _math(math.sin, degrees_in=True), "cos": _math(math.cos, degrees_in=True),
    "tan": _math(math.tan, degrees_in=True), "asin": _math(math.asin, degrees_out=True),
    "acos": _math(math.acos, degrees_out=True), "atan": _math(math.atan, degrees_out=True),
    "atan2": _math(math.atan2, 2, degrees_out=True), "round": _round, "rounddnum": _round,
    "trunc": lambda i, a: _round(i, a, True), "truncdnum": lambda i, a: _round(i, a, True),
    "numtodnum": _math(float), "dnumtonum": _math(float), "dim": _dim, "present": _present,
    "numtostr": _numtostr, "dnumtostr": _numtostr, "strlen": lambda i, a: float(len(a.value(0, "string"))),
    "strpart": _strpart, "strfind": _strfind, "valtostr": _valtostr,
    "strmemb": lambda i, a: a.value(0, "string")[int(a.number(1)) - 1:int(a.number(1))] in a.value(2, "string"),
    "strorder": lambda i, a: a.value(0, "string") <= a.value(1, "string"),
    "bitand": _bits(lambda x, y: x & y, 2), "bitor": _bits(lambda x, y: x | y, 2),
    "bitxor": _bits(lambda x, y: x ^ y, 2), "bitneg": _bits(lambda x: ~x & 0xFF, 1),
    "bitlsh": _bits(lambda x, k: (x << k) & 0xFF, 2), "bitrsh": _bits(lambda x, k: x >> k, 2),
    "bitcheck": lambda i, a: _bits(lambda x, k: (x >> (k - 1)) & 1 if 1 <= k <= 64 else 0, 2)(i, a) == 1.0,
    "offs": _offs, "reltool": _reltool,
    "orientzyx": lambda i, a: poses.orient_zyx(a.number(0), a.number(1), a.number(2)),
    "eulerzyx": _euler, "posemult": lambda i, a: poses.pose_mult(a.value(0, "pose"), a.value(1, "pose")),
    "poseinv": lambda i, a: poses.pose_inv(a.value(0, "pose")),
    "posevect": lambda i, a: poses.pose_vect(a.value(0, "pose"), a.value(1, "pos")),
    "norient": lambda i, a: poses.orient(poses.qnorm(a.value(0, "orient").vals)),
    "deframe": _deframe, "defframe": _deframe,
    "distance": lambda i, a: poses.distance(a.value(0, "pos").vals, a.value(1, "pos").vals),
    "dotprod": lambda i, a: float(sum(x * y for x, y in zip(a.value(0, "pos").vals, a.value(1, "pos").vals))),
    "vectmagn": lambda i, a: math.sqrt(sum(x * x for x in a.value(0, "pos").vals)),
    "crobt": _crobt, "cpos": _cpos, "cjointt": _cjointt, "calcjointt": _calcjointt, "calcrobt": _calcrobt,
    "ctool": lambda i, a: i.state["tool"] or a.frame.module.get("tool0").get(),
    "cwobj": lambda i, a: i.state["wobj"] or a.frame.module.get("wobj0").get(),
    "cspeedoverride": _N(100.0), "dinput": _signal_value, "doutput": _signal_value, "ainput": _signal_value,
    "aoutput": _signal_value, "ginput": _signal_value, "goutput": _signal_value,
    "testdi": lambda i, a: _signal_value(i, a) == 1.0, "validio": _N(True),
    "clkread": _clkread, "ctime": lambda i, a: time.strftime("%H:%M:%S"),
    "cdate": lambda i, a: time.strftime("%Y-%m-%d"),
    "gettime": lambda i, a: 0.0, "robos": _N(True), "opmode": _N(1.0), "runmode": _N(1.0),  # OP_AUTO, RUN_CONT_CYCLE
    "ismechunitactive": _N(True), "issyncmoveon": lambda i, a: bool(i.state.get("sync")),
    "isstopmoveact": _N(False), "taskrunrob": _N(True),
    "taskrunmec": _N(True), "gettaskname": _N("T_ROB1"), "robname": _N("ROB_1"), "getmecunitname": _N("ROB_1"),
    "modexist": _N(True), "ispers": _N(False), "isvar": _N(True),
    "argname": lambda i, a: getattr(a.node(0), "name", ""),
    "testandset": lambda i, a: _test_and_set(i, a),
    "crossprod": _crossprod, "type": _type, "maxrobspeed": lambda i, a: rd.TOP_TCP_SPEED,
    "orobt": lambda i, a: a.value(0, "robtarget"), "mirpos": lambda i, a: poses.mir_pos(
        a.value(0, "robtarget"), a.value(1, "wobjdata"), a.has("MirY")),
    "defdframe": lambda i, a: _defdframe(i, a),
    **strings.FUNCTIONS, **byname.FUNCTIONS, **calibration.FUNCTIONS,
}
FUNCTIONS.update({f"{k}dnum": FUNCTIONS[k] for k in ("asin", "acos", "atan", "atan2", "sin", "cos", "tan", "bitand",
                                                      "bitcheck", "bitlsh", "bitneg", "bitor", "bitrsh", "bitxor",
                                                      "ginput", "goutput")})


def _defdframe(interp, a: Arguments) -> Rec:
    """DefDFrame: the displacement frame that takes three old points to three new ones."""
    a.need(6)
    p = [a.value(k, "robtarget").vals[0].vals for k in range(6)]
    old, new = poses.def_frame(*p[:3]), poses.def_frame(*p[3:])
    if old is None or new is None:
        fail(interp.path, a.line, "DefDFrame: three of the points are on one line")
    return poses.pose_mult(new, poses.pose_inv(old))


def _test_and_set(interp, a: Arguments) -> bool:
    a.need(1)
    target = a.reference(0)
    before = target.get()
    target.set(True)
    return not before
