"""Every option of every ``rswarp`` command reaches its library function (``cli.library_arguments``):
each parameter named ``task``, ``hose``, ``design``, ``batch`` or ``video`` gets its ``rswarp.config``
object built from the parsed options, any other the option of its name, and none is left over (an
option that reaches nothing is an internal error, never dropped silently)."""

from __future__ import annotations

import functools
import inspect

import pytest

from rswarp import cli
from rswarp.cli import COMMANDS, OPTION_PARAMETERS, build_parser, entry_of, library_arguments
from rswarp.config import BatchOptions, DesignOptions, HoseOptions, TaskOptions, VideoOptions

MOST_PARAMETERS = 16
GIVEN_BY_CLI = {"json", "warn", "say", "progress"}  # what ``cli._call`` passes itself


def _defaults(name: str) -> dict:
    """The parsed arguments of ``rswarp NAME`` with every option at its default, as argparse sets
    them (the first action of a destination gives its default; then ``set_defaults``)."""
    parser = build_parser()
    sub = parser.commands[name]
    values = {"command": name, "debug": False, "max_file_size": 1.0}
    for action in sub._actions:
        if action.dest != "help":
            values.setdefault(action.dest, action.default)
    for dest, value in sub._defaults.items():
        values.setdefault(dest, value)
    return values


def _dests(name: str) -> set[str]:
    return {a.dest for a in build_parser().commands[name]._actions if a.dest != "help"}


def _entry(name: str):
    return entry_of(type("Args", (), {"entry": COMMANDS[name][0]})())


def _kwargs(argv: list[str]) -> dict:
    args = build_parser().parse_args(argv)
    kwargs, unused = library_arguments(entry_of(args), vars(args))
    assert not unused
    return kwargs


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_option_of_a_command_reaches_its_library_function(name):
    values = _defaults(name)
    fn = _entry(name)
    kwargs, unused = library_arguments(fn, values)
    assert unused == set(), f"rswarp {name}: {sorted(unused)} reach no parameter of {fn.__name__}"
    assert _dests(name) <= set(values)
    params = inspect.signature(fn).parameters
    for key, kind in OPTION_PARAMETERS.items():
        if key in params:
            assert type(kwargs[key]) is kind
    required = {p for p, v in params.items() if v.default is inspect.Parameter.empty
                and v.kind not in (v.VAR_KEYWORD, v.VAR_POSITIONAL)}
    assert required <= set(kwargs) | GIVEN_BY_CLI, f"rswarp {name}: {sorted(required - set(kwargs))} never given"


@pytest.mark.parametrize("name", list(COMMANDS))
def test_no_library_entry_takes_more_than_sixteen_parameters(name):
    assert len(inspect.signature(_entry(name)).parameters) <= MOST_PARAMETERS


def test_program_options_arrive_in_their_objects():
    kwargs = _kwargs(["program", "robot.rsxml", "x.mod", "--cycles", "3", "--io", "di1=1", "--floor", "5",
                      "--video", "v.gif", "--routine", "other", "--input", "n=2", "--input", "n=3",
                      "--device", "cuda:1"])
    task, video, batch = kwargs["task"], kwargs["video"], kwargs["batch"]
    assert isinstance(task, TaskOptions) and isinstance(video, VideoOptions) and isinstance(batch, BatchOptions)
    assert task.cycles == 3 and task.io == {"di1": 1.0} and task.floor == 5.0 and task.routine == "other"
    assert task.inputs == {"n": ("2", "3")}
    assert video.video == "v.gif" and video.video_size == 512
    assert batch.device == "cuda:1"
    assert kwargs["path"] == "robot.rsxml" and kwargs["programs"] == ["x.mod"]


def test_cable_options_arrive_in_their_objects():
    kwargs = _kwargs(["cable", "robot.rsxml", "--program", "x.mod", "--out", "o", "--friction", "0.7", "--seed",
                      "4", "--no-floor", "--max-torsion", "90", "--cable-model", "rod", "--envs", "2",
                      "--video", "v.gif", "--video-color", "wear", "--env", "box.stl@0,0,0", "--usd"])
    hose, batch, task, video = kwargs["hose"], kwargs["batch"], kwargs["task"], kwargs["video"]
    assert isinstance(hose, HoseOptions) and hose.friction == 0.7 and hose.max_torsion == 90.0
    assert batch.seed == 4
    assert task.floor is None and task.environment == ("box.stl@0,0,0",)
    assert video.video == "v.gif" and video.video_color == "wear"
    assert kwargs["envs"] == 2 and kwargs["program"] == ["x.mod"] and kwargs["usd"] is True
    assert kwargs["out"] == "o"


def test_dresspack_options_arrive_in_their_objects():
    kwargs = _kwargs(["dresspack", "robot.rsxml", "--program", "x.mod", "--out", "o", "--vary", "length=1:2",
                      "--vary", "Slide.pitch=-5:5", "--designs", "8", "--min-margin", "10", "--cable", "Hose",
                      "--min-bend-radius", "150", "--cycles", "2"])
    design = kwargs["design"]
    assert isinstance(design, DesignOptions)
    assert design.vary == ("length=1:2", "Slide.pitch=-5:5") and design.designs == 8
    assert design.min_margin == 10.0 and design.cable == "Hose"
    assert kwargs["hose"].min_bend_radius == 150.0 and kwargs["task"].cycles == 2
    assert kwargs["programs"] == ["x.mod"] and kwargs["out"] == "o"


def test_the_command_line_calls_the_entry_with_its_objects(monkeypatch, capsys):
    """Through ``main``: the entry gets the objects, ``json`` where it takes it."""
    from rswarp.report.output import Output

    real = _entry("cable")
    seen = {}

    @functools.wraps(real)
    def fake(**kwargs):
        seen.update(kwargs)
        return Output({}, "done")

    monkeypatch.setattr(cli, "entry_of", lambda args: fake)
    code = cli.main(["cable", "robot.rsxml", "--random", "--out", "o", "--seed", "4", "--friction", "0.7",
                     "--floor", "2"])
    assert code == 0 and capsys.readouterr().out.strip() == "done"
    assert seen["batch"].seed == 4 and seen["hose"].friction == 0.7 and seen["task"].floor == 2.0
    assert seen["random"] is True and "json" not in seen


def test_an_option_that_reaches_no_parameter_is_an_internal_error(monkeypatch, capsys):
    from rswarp.report.output import Output

    def narrow(path, out, batch=None, video=None, envs=None, trajectory=None, random=False, seconds=None,
               usd=False, program=None, progress=None, warn=None):  # no task, no hose
        return Output({}, "")

    monkeypatch.setattr(cli, "entry_of", lambda args: narrow)
    assert cli.main(["cable", "robot.rsxml", "--random", "--out", "o"]) == 2
    said = capsys.readouterr().err
    assert "reach no library parameter" in said and "friction" in said


def test_a_keyword_no_options_object_has_is_a_type_error(tmp_path):
    from rswarp.motion.plan import program_plan
    from rswarp.report.cables import run_cables
    from rswarp.report.dresspack import run_dresspack
    from rswarp.report.program import run_program

    missing = str(tmp_path / "missing.rsxml")
    with pytest.raises(TypeError, match="bogus"):
        run_program(missing, ["x.mod"], bogus=1)
    with pytest.raises(TypeError, match="bogus"):
        program_plan(missing, ["x.mod"], bogus=1)
    with pytest.raises(TypeError, match="bogus"):
        run_cables(missing, str(tmp_path / "o"), random=True, bogus=1)
    with pytest.raises(TypeError, match="bogus"):
        run_dresspack(missing, ["x.mod"], str(tmp_path / "o"), vary=["length=1:2"], bogus=1)


def test_the_repeated_command_names_only_the_options_that_differ():
    from rswarp.report.dresspack_options import repeat_command

    assert repeat_command("out", ["a.mod"], TaskOptions(), HoseOptions(), True) == \
        "rswarp cable out/best.rsxml --program a.mod --out out-best"
    task = TaskOptions(cycles=2, floor=None, io={"di1": 1.0, "do2": 0.25}, inputs={"n": ("2", "3")},
                       environment=("box.stl@0,0,0",), tool="gripper.stl", payload="6@0,0,0.1")
    hose = HoseOptions(friction=0.7, max_torsion=90.0, min_bend_radius=150.0, rated_cycles="1e7@300")
    assert repeat_command("sweep/", ["a.mod", "b.mod"], task, hose, False) == (
        "rswarp cable sweep/closest.rsxml --program a.mod b.mod --out sweep-closest --cycles 2 --tool gripper.stl "
        "--min-bend-radius 150 --max-torsion 90 --friction 0.7 --rated-cycles 1e7@300 --payload 6@0,0,0.1 "
        "--no-floor --io di1=1 --io do2=0.25 --input n=2 --input n=3 --env box.stl@0,0,0")
    assert "--floor 2.5" in repeat_command("o", ["a.mod"], TaskOptions(floor=2.5), HoseOptions(), True)


def test_the_hose_defaults_are_defined_once():
    import math

    from rswarp import config
    from rswarp.report import verdicts

    assert verdicts.MAX_STRAIN == config.MAX_STRAIN and verdicts.MAX_TORSION == math.radians(config.MAX_TORSION_DEG)
    values = _defaults("cable")
    hose = HoseOptions()
    for name in ("max_strain", "max_torsion", "density", "poisson", "friction", "frame_rate", "substeps"):
        assert values[name] == getattr(hose, name), name


def test_task_options_a_cable_run_without_a_program_ignores_are_said():
    """``rswarp cable --random --cycles 3``: the cycles reach nothing a run reads, and one warning says so."""
    from rswarp.config import TaskOptions
    from rswarp.report.cables import _say_unused

    said = []
    _say_unused(TaskOptions(cycles=3, io={"x": 1}), said.append)
    assert said and "--io, --cycles ignored" in said[0]
    said.clear()
    _say_unused(TaskOptions(floor=-5, tool="gripper.stl"), said.append)  # the hose meets those: no warning
    assert said == []


def test_options_objects_take_what_python_callers_give_and_refuse_the_rest():
    from rswarp.config import DesignOptions, TaskOptions
    from rswarp.errors import InputError

    assert TaskOptions(environment="m.stl@0,0,0").environment == ("m.stl@0,0,0",)
    assert DesignOptions(vary="length=1:2").vary == ("length=1:2",)
    assert TaskOptions(io=["x=1"]).io == {"x": 1.0} and TaskOptions(inputs={"a": 1}).inputs == {"a": ("1",)}
    for bad in (dict(io=["ab"]), dict(io={"x": "abc"}), dict(cycles=2.5), dict(inputs=["noeq"])):
        with pytest.raises(InputError):
            TaskOptions(**bad)
    from rswarp.examples import IRB2600, IRB2600_PROGRAM
    from rswarp.motion.plan import program_plan

    with pytest.raises(TypeError, match="task must be a TaskOptions"):  # a routine given where the options go
        program_plan(str(IRB2600), [str(IRB2600_PROGRAM)], "main")
