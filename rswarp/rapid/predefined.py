"""The data every controller predefines, as RAPID's reference manual lists it: the speeds v5 to
v7000 and vmax, the zones z0 to z200 and fine (zonedata table), tool0, wobj0 and load0, reg1 to
reg5, pi, and the constants programs compare with (EOF_NUM, stEmpty, diskhome, ...). A task's own
declaration of one of these names (base.sys declares tool0, user.sys reg1) takes its place."""

from __future__ import annotations

import math

from .values import Rec, Types

SPEEDS = (5, 10, 20, 30, 40, 50, 60, 80, 100, 150, 200, 300, 400, 500, 600, 800, 1000, 1500, 2000, 2500, 3000,
          4000, 5000, 6000, 7000)
# name: (pzone_tcp mm, pzone_ori mm, pzone_eax mm, zone_ori deg, zone_leax mm, zone_reax deg)
ZONES = {0: (0.3, 0.3, 0.3, 0.03, 0.3, 0.03), 1: (1, 1, 1, 0.1, 1, 0.1), 5: (5, 8, 8, 0.8, 8, 0.8),
         10: (10, 15, 15, 1.5, 15, 1.5), 15: (15, 23, 23, 2.3, 23, 2.3), 20: (20, 30, 30, 3.0, 30, 3.0),
         30: (30, 45, 45, 4.5, 45, 4.5), 40: (40, 60, 60, 6.0, 60, 6.0), 50: (50, 75, 75, 7.5, 75, 7.5),
         60: (60, 90, 90, 9.0, 90, 9.0), 80: (80, 120, 120, 12.0, 120, 12.0), 100: (100, 150, 150, 15, 150, 15),
         150: (150, 225, 225, 23, 225, 23), 200: (200, 300, 300, 30, 300, 30)}
_ORIGIN = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]
_LOAD0 = [0.001, [0.0, 0.0, 0.001], [1.0, 0.0, 0.0, 0.0], 0.0, 0.0, 0.0]
NO_AXES = [9e9] * 6


def predefined(types: Types) -> dict[str, tuple[str, str, object]]:
    """Name (lower case) -> (type, storage, value) of the predefined data."""
    out: dict[str, tuple[str, str, object]] = {}
    for v in SPEEDS:
        out[f"v{v}"] = ("speeddata", "const", [float(v), 500.0, 5000.0, 1000.0])
    out["vmax"] = ("speeddata", "const", [5000.0, 500.0, 5000.0, 1000.0])
    out["fine"] = ("zonedata", "const", [True, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    for z, (tcp, ori, eax, zori, leax, reax) in ZONES.items():
        out[f"z{z}"] = ("zonedata", "const", [False, float(tcp), float(ori), float(eax), float(zori), float(leax),
                                              float(reax)])
    out["load0"] = ("loaddata", "pers", _LOAD0)
    out["tool0"] = ("tooldata", "pers", [True, _ORIGIN, _LOAD0])
    out["wobj0"] = ("wobjdata", "pers", [False, True, "", _ORIGIN, _ORIGIN])
    out["pose0"] = ("pose", "const", _ORIGIN)
    for k in range(1, 6):
        out[f"reg{k}"] = ("num", "var", 0.0)
    out["clock1"] = ("clock", "var", None)
    out["pi"] = ("num", "const", math.pi)
    out["true"] = ("bool", "const", True)
    out["false"] = ("bool", "const", False)
    out["errno"] = ("errnum", "var", 0.0)
    out["intno"] = ("intnum", "var", 0.0)
    out["eof_num"] = ("num", "const", 9.998e36)
    out["eof_bin"] = ("num", "const", -1.0)
    out["stempty"] = ("string", "const", "")
    out["diskhome"] = ("string", "const", "HOME:")
    out["disktemp"] = ("string", "const", "TEMP:")
    out["diskram"] = ("string", "const", "RAMDISK:")
    out["high"] = ("dionum", "const", 1.0)
    out["low"] = ("dionum", "const", 0.0)
    for type_, names in CONSTANTS:
        for k, name in enumerate(names.split()):
            if name != "-":
                out[name.lower()] = (type_, "const", float(k + _FIRST.get(type_, 0)))
    out["max_rawbytes"] = ("num", "const", 1024.0)
    for name in STOP_POINTS:
        out[name] = ("stoppointdata", "const", None)
    return {k: (t, s, types.default(t) if v is None else types.coerce(v, t, k)) for k, (t, s, v) in out.items()}


# The reference manual's predefined constants, by type, in the order of their values (from 0, or
# from _FIRST's; '-' skips a value): what a program compares an answer with.
CONSTANTS = (
    ("btnres", "resUnkwn resOK resAbort resRetry resIgnore resCancel resYes resNo"),
    ("buttondata", "btnNone btnOK btnAbrtRtryIgn btnOKCancel btnRetryCancel btnYesNo btnYesNoCancel"),
    ("icondata", "iconNone iconInfo iconWarning iconError iconQuestion"),
    ("socketstatus", "- SOCKET_CREATED SOCKET_CONNECTED SOCKET_BOUND SOCKET_LISTENING SOCKET_CLOSED"),
    ("symnum", "OP_UNDEF OP_AUTO OP_MAN_PROG OP_MAN_TEST"),
    ("symnum", "RUN_UNDEF RUN_CONT_CYCLE RUN_INSTR_FWD RUN_INSTR_BWD RUN_SIM RUN_STEP_MOVE"),
    ("opnum", "- LT LTEQ EQ NOTEQ GTEQ GT"),
    ("opcalc", "- OpAdd OpSub OpMult OpDiv OpMod"),
    ("errtype", "TYPE_ALL TYPE_STATE TYPE_WARN TYPE_ERR"),
    ("event_type", "EVENT_NONE EVENT_POWERON EVENT_START EVENT_STOP EVENT_QSTOP EVENT_RESTART EVENT_RESET EVENT_STEP"),
    ("exec_level", "LEVEL_NORMAL LEVEL_TRAP LEVEL_SERVICE"),
    ("handler_type", "HANDLER_NONE HANDLER_BWD HANDLER_ERR HANDLER_UNDO"),
    ("iounit_state", "- IOUNIT_RUNNING IOUNIT_RUNERROR IOUNIT_DISABLE IOUNIT_OTHERERR"),
    ("signalorigin", "SIGORIG_NONE SIGORIG_CFG SIGORIG_ALIAS"),
    ("aiotrigg", "- AIO_ABOVE_HIGH AIO_BELOW_HIGH AIO_ABOVE_LOW AIO_BELOW_LOW AIO_BETWEEN AIO_OUTSIDE AIO_ALWAYS"),
    ("errdomain", "COMMON_ERR OP_STATE SYSTEM_ERR HARDWARE_ERR PROGRAM_ERR MOTION_ERR OPERATOR_ERR IO_COM_ERR "
                  "USER_DEF_ERR OPTION_PROD_ERR - PROCESS_ERR CFG_ERR"),
    ("busstate", "BUSSTATE_HALTED BUSSTATE_RUN BUSSTATE_ERROR BUSSTATE_STARTUP BUSSTATE_INIT"),
    ("triggmode", "- TRIGG_MODE1 TRIGG_MODE2 TRIGG_MODE3"),
    ("tunetype", "TUNE_DF TUNE_KP TUNE_KV TUNE_TI TUNE_FRIC_LEV TUNE_FRIC_RAMP TUNE_DG TUNE_DH TUNE_DI TUNE_DK "
                 "TUNE_DL"),
)
_FIRST = {"buttondata": -1}
STOP_POINTS = ("inpos20", "inpos50", "inpos100", "stoptime0_5", "stoptime1_0", "stoptime1_5", "fllwtime0_5",
               "fllwtime1_0", "fllwtime1_5")


def error_number(name: str) -> float | None:
    """A stand-in value for the controller's error constants (ERR_WAIT_MAXTIME, ...): distinct,
    stable numbers, so programs can compare ERRNO with them."""
    if not name.lower().startswith("err_"):
        return None
    return float(41000 + sum(ord(c) for c in name.lower()) % 1000)


def rec(type_: str, *vals) -> Rec:
    return Rec(type_, tuple(vals))
