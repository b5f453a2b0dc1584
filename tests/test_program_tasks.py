"""Whole RAPID tasks as users have them (issue "RAPID tasks as the controller runs them"): a task of
three modules given as files and as a folder, every move held against where the task puts the TCP
(computed here from the RAPID data, apart from rswarp); the main loop's cycle; external axes;
and tasks shaped like real ones under tests/data/rapid/real (a RobotStudio backup, a palletizer,
generated code, a welding path, ERROR handlers), each run to its end with every move on its
target by the robot's own forward kinematics."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import rswarp
from rswarp.cli import main
from rswarp.errors import RsxmlError
from rswarp.examples import IRB2600, IRB2600_CELL
from rswarp.kinematics.kinematics import Kinematics
from rswarp.motion.plan import program_plan
from rswarp.motion.tcp import frames
from rswarp.report.program import run_program

from conftest import DATA

TASK3 = DATA / "rapid" / "task3"
REAL = DATA / "rapid" / "real"
TOOL_DOWN = Rotation.from_quat([0, 1, 0, 0])  # RAPID [0, 0, 1, 0]: the tool's z points down


@lru_cache(maxsize=None)
def kin() -> Kinematics:
    return Kinematics(rswarp.load(IRB2600))


def plan(*paths, **options):
    return program_plan(str(IRB2600), [str(p) for p in paths], **options)[1]


def tcp_at_end(p, k: int) -> np.ndarray:
    """The TCP pose in its work object where move ``k`` ends, by the robot's forward kinematics."""
    mv = p.moves[k]
    link, m = kin().flange_frame()
    flange = kin().fk64(p.q[mv.rows[1] - 1][None])[:, link] @ m
    return frames(kin().mech, mv.motion.tool, mv.motion.wobj).relative(flange)[0]


def every_move_on_its_target(p, tol: float = 5e-4) -> int:
    """Each completed move ends with the TCP on its robtarget (or the joints on its jointtarget),
    a move in a zone where the next one takes over, inside its zone; the number of moves checked."""
    checked = 0
    for k, mv in enumerate(p.moves):
        m = mv.motion
        if m.kind == "wait" or mv.rows[1] == mv.rows[0] or mv.findings:
            continue
        if m.zone is not None and not m.zone.fine:
            checked += inside_its_zone(p, k)
            continue
        if m.kind == "absolute":
            want = np.radians([v for v in m.targets[0].robax if v is not None])
            assert np.abs(p.q[mv.rows[1] - 1] - want).max() < 1e-9
        else:
            got, want = tcp_at_end(p, k), m.targets[-1].pose.matrix()
            assert np.linalg.norm(got[:3, 3] - want[:3, 3]) < tol, (m.file, m.line)
            assert np.abs(got[:3, :3] - want[:3, :3]).max() < 1e-6, (m.file, m.line)
        checked += 1
    return checked


def inside_its_zone(p, k: int) -> bool:
    """Move ``k``, in a zone, ends (where the next move takes over) within the zone of its point."""
    m = p.moves[k].motion
    got = tcp_at_end(p, k)
    if m.kind == "absolute":
        link, f = kin().flange_frame()
        q = np.radians([v for v in m.targets[0].robax if v is not None])
        want = frames(kin().mech, m.tool, m.wobj).relative(kin().fk64(q[None])[:, link] @ f)[0]
    else:
        want = m.targets[-1].pose.matrix()
    assert np.linalg.norm(got[:3, 3] - want[:3, 3]) <= m.zone.pzone_tcp + 2e-3, (m.file, m.line)
    turn = np.arccos(np.clip((np.trace(got[:3, :3].T @ want[:3, :3]) - 1) / 2, -1, 1))
    assert turn <= m.zone.zone_ori + 0.01, (m.file, m.line)
    return True


def expected_task3() -> list[tuple[np.ndarray, Rotation]]:
    """Where tests/data/rapid/task3 puts the TCP, move after move, in wTable (mm): its FOR, TEST,
    DIV, MOD, WHILE and IF worked out here by hand, RelTool by SciPy."""
    base = np.array([100.0, 100.0, 150.0])
    out = []

    def visit(offset, height):
        p = base + offset
        above = p + [0, 0, height]
        out.extend([(above, TOOL_DOWN), (p, TOOL_DOWN), (above, TOOL_DOWN)])

    for i in range(4):
        row = i // 2
        visit(np.array([0.0 if i % 2 == 0 else 100.0, row * 100.0, 0.0]), 100.0 if i % 2 == 0 else 150.0)
    visit(np.array([50.0, 50.0, 0.0]), 100.0)  # the WHILE's one visit; its second pass only counts
    now = out[-1][0]
    turn = TOOL_DOWN * Rotation.from_euler("z", 30, degrees=True)
    out.append((now + TOOL_DOWN.apply([0, 0, -50.0]), turn))  # RelTool(pNow, 0, 0, -50 \Rz:=30)
    return out


@pytest.mark.parametrize("given", ["files", "folder", "pgf"])
def test_a_task_of_three_modules_puts_every_move_where_the_task_says(given):
    paths = {"files": [TASK3 / "CalibData.mod", TASK3 / "Lib.mod", TASK3 / "Main.mod"], "folder": [TASK3],
             "pgf": [TASK3 / "task3.pgf"]}[given]
    p = plan(*paths)
    moves = [k for k, mv in enumerate(p.moves) if mv.motion.kind != "absolute"]
    want = expected_task3()
    assert len(moves) == len(want) == 16
    for k, (pos, rot) in zip(moves, want):
        got, zone = tcp_at_end(p, k), p.moves[k].motion.zone
        if zone.fine:  # a zone's move ends where the next takes over: inside the zone (inside_its_zone)
            assert np.linalg.norm(got[:3, 3] * 1000 - pos) < 0.5
            assert np.abs(got[:3, :3] - rot.as_matrix()).max() < 1e-6
        else:
            assert np.linalg.norm(got[:3, 3] * 1000 - pos) <= zone.pzone_tcp * 1000 + 2
    visit = p.moves[1].motion
    assert (visit.file.endswith("Lib.mod"), visit.line, visit.routine) == (True, 13, "Visit")
    assert visit.chain == (f"main ({TASK3 / 'Main.mod'}:14)",)
    assert p.moves[0].motion.kind == "absolute" and not p.moves[0].findings  # MoveAbsJ to q5 = 0: no finding


def test_the_table_names_files_and_routines_of_a_task(capsys):
    assert main(["program", str(IRB2600), str(TASK3)]) == 0
    out = capsys.readouterr().out
    assert "file:line" in out and "Lib.mod:14   Visit    MoveL" in out and "Main.mod:28  main" in out


def test_a_main_loop_runs_its_passes_and_gives_the_cycle_time():
    out = run_program(str(IRB2600), [str(IRB2600_CELL)])
    doc = out.doc
    assert out.code == 0 and doc["main_loop"].endswith("MainModule.mod:10") and len(doc["cycles_s"]) == 1
    first = next(m for m in doc["moves"] if m["line"] == 24)  # the loop's first move
    assert doc["cycle_s"] == pytest.approx(doc["duration_s"] - first["start_s"])
    two = run_program(str(IRB2600), [str(IRB2600_CELL)], cycles=2).doc
    assert len(two["cycles_s"]) == 2 and two["cycle_s"] == pytest.approx(doc["cycle_s"], rel=0.02)
    assert sum(m["kind"] != "wait" for m in two["moves"]) == 1 + 2 * (sum(m["kind"] != "wait" for m in doc["moves"]) - 1)
    assert "cycle: " in out.text and "one pass of the main loop at MainModule.mod:10" in out.text


def test_a_track_target_is_ignored_as_the_controller_ignores_it_or_refused_when_asked(tmp_path, capsys):
    path = tmp_path / "track.mod"
    path.write_text("MODULE Track\n  CONST robtarget pOnTrack:=[[900,0,900],[0,0,1,0],[0,0,0,0],"
                    "[1500,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveJ pOnTrack, v500, fine, tool0;\n"
                    "  ENDPROC\nENDMODULE\n")
    warned = []
    p = program_plan(str(IRB2600), [str(path)], warn=warned.append)[1]  # the controller ignores an axis it lacks
    assert every_move_on_its_target(p) == 1
    assert sum("1 target give eax_a (1500)" in w for w in warned) == 1 and "eax_a 1500: ignored" in p.targets[0].ignored
    with pytest.raises(RsxmlError) as exc:
        program_plan(str(IRB2600), [str(path)], external_axes="error")
    assert exc.value.line == 4 and "puts the external axis eax_a at 1500" in exc.value.message
    assert main(["program", str(IRB2600), str(path), "--external-axes", "error"]) == 1
    assert f"{path}:4: MoveJ: 'pOnTrack' puts the external axis eax_a at 1500" in capsys.readouterr().err


def test_a_robtarget_a_coordinated_work_object_moves_is_an_error(tmp_path):
    path = tmp_path / "coordinated.mod"
    path.write_text("MODULE Coord\n  PERS wobjdata wStation:=[FALSE,FALSE,\"STN1\",[[0,0,0],[1,0,0,0]],"
                    "[[0,0,0],[1,0,0,0]]];\n  CONST robtarget p:=[[900,0,900],[0,0,1,0],[0,0,0,0],"
                    "[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveJ p, v500, fine, tool0\\WObj:=wStation;\n"
                    "  ENDPROC\nENDMODULE\n")
    with pytest.raises(RsxmlError, match="moved by STN1 .ufprog FALSE.") as exc:
        plan(path)
    assert exc.value.line == 5


@pytest.mark.parametrize("path, moves", [
    ("backup", 20), ("palletizer.mod", 109), ("generated.mod", 104), ("welding.mod", 11), ("errors.mod", 22),
])
def test_tasks_shaped_like_users_own_run_to_their_end_with_every_move_on_its_target(path, moves):
    p = plan(REAL / path)
    assert not p.errors and sum(mv.motion.kind != "wait" for mv in p.moves) == moves
    assert every_move_on_its_target(p) >= moves - 2  # a search's or a Sync move's point may differ


def test_a_backup_runs_its_first_task_and_says_so():
    warned = []
    _, p = program_plan(str(IRB2600), [str(REAL / "backup")], warn=warned.append)
    assert "the folder holds the tasks TASK1, TASK2: running TASK1" in warned[0]
    assert {f.split("/")[-1] for f in p.run.files} == {"Module1.mod", "CalibData.mod", "user.sys", "base.sys"}


def test_the_palletizer_stacks_where_its_grid_says():
    """Offs(pBase, col * dx, row * dy, layer * dz), col = n MOD cols, row = n DIV cols, for the
    small pattern (2 rows, 3 columns, 3 layers, 150/120/100 mm)."""
    p = plan(REAL / "palletizer.mod")
    drops = [tcp_at_end(p, k)[:3, 3] * 1000 for k, mv in enumerate(p.moves)
             if mv.motion.instruction == "MoveL" and mv.motion.line == 70]
    want = [np.array([80 + (n % 3) * 150, 60 + (n // 3) * 120, layer * 100]) for layer in range(3) for n in range(6)]
    assert len(drops) == 18 and max(np.linalg.norm(d - w) for d, w in zip(drops, want)) < 0.5


def test_arc_welds_go_at_their_weld_speed():
    """welding.mod's ArcL over 250 mm at weld_speed 8 mm/s (its speeddata says v100), handing over
    to the next move as it enters its z1 zone, 1 mm before its point (1/8 s at 8 mm/s)."""
    p = plan(REAL / "welding.mod")
    arc = next(mv for mv in p.moves if mv.motion.instruction == "ArcL")
    assert arc.motion.speed.v_tcp == pytest.approx(0.008)
    assert 249 / 8 < arc.end - arc.start < 250 / 8 + 0.1


def test_error_handlers_let_a_task_with_errors_run_on():
    """errors.mod raises ERR_NOPART (main's handler takes it: TRYNEXT), divides by zero (RETRY
    after fixing the divisor, TRYNEXT in another routine), and still makes all its moves."""
    p = plan(REAL / "errors.mod")
    lines = [mv.motion.line for mv in p.moves if mv.motion.kind != "wait"]
    assert 53 not in lines  # CheckPart's MoveL: its RAISE went to main's handler
    assert lines.count(78) == 4 and lines.count(33) == 6  # the GOTO square, then the FOR
