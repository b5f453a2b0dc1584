"""Nothing the user owns is lost (issue "Hardening the newer surfaces"): an output folder holds a
manifest of what rswarp wrote, so a user's file, a sub-folder named like an output or an output
the user changed is never replaced; a folder that cannot take the outputs is refused before any
work and nothing is left beside it; a library build detects outputs that land on one path and
never replaces a file it did not write; a playback stage keeps every cable; SIGTERM and internal
errors end with their own exit codes."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from PIL import Image

import rswarp
from rswarp import outputs
from rswarp.cli import main
from rswarp.report.library import build_library

from conftest import DATA

IRB = DATA.parent.parent / "examples" / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
FOLD = DATA / "collisions" / "fold.rsxml"
ARM = DATA / "library" / "cell" / "parts" / "IRB9_1_1__01.rsxml"
ENV = {**os.environ, "PYTHONPATH": str(DATA.parent.parent)}


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("command", ["collisions", "sweep"])
def test_a_sub_folder_named_like_an_output_is_left_alone(tmp_path, capsys, command):
    """``heatmap.png/`` or ``report.json/`` holding the user's files: the folder is refused, whole."""
    out = tmp_path / "out"
    (out / "report.json").mkdir(parents=True)
    (out / "report.json" / "mine.txt").write_text("keep me")
    code, _, err = run([command, FOLD, "--samples", 50, "--out", out], capsys)
    assert code == 1 and "holds files rswarp did not write (report.json)" in err
    assert (out / "report.json" / "mine.txt").read_text() == "keep me"


def test_a_file_of_the_users_named_like_an_output_is_never_replaced(tmp_path, capsys):
    """A report.json the user put there, or one rswarp wrote and the user then changed: refused.
    rswarp's own unchanged set is replaced as before."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text("my notes")
    assert run(["collisions", FOLD, "--samples", 50, "--out", out], capsys)[0] == 1
    assert (out / "report.json").read_text() == "my notes"
    (out / "report.json").unlink()
    assert run(["collisions", FOLD, "--samples", 50, "--out", out], capsys)[0] == 0  # empty: taken
    assert run(["collisions", FOLD, "--samples", 60, "--out", out], capsys)[0] == 0  # its own set: replaced
    with open(out / "report.json", "a") as f:
        f.write(" ")
    code, _, err = run(["collisions", FOLD, "--samples", 50, "--out", out], capsys)
    assert code == 1 and "(report.json)" in err and (out / "report.json").read_text().endswith(" ")


def test_a_folder_that_cannot_take_the_outputs_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    """``--out .`` (or a folder holding the current one) is refused at once: not after a
    million-sample sweep, and nothing is left beside it."""
    monkeypatch.chdir(tmp_path)
    started = time.perf_counter()
    code, _, err = run(["collisions", IRB, "--samples", 10_000_000, "--out", "."], capsys)
    assert code == 1 and "is the current folder" in err and time.perf_counter() - started < 20
    code, _, err = run(["collisions", IRB, "--samples", 10_000_000, "--out", tmp_path.parent], capsys)
    assert code == 1 and "is the current folder or holds it" in err
    assert list(tmp_path.iterdir()) == []


def test_a_swap_that_fails_leaves_the_old_set_and_nothing_beside(tmp_path, capsys, monkeypatch):
    """The final rename fails: the earlier set stays, no ``.old`` or ``.tmp`` folder is left."""
    out = tmp_path / "out"
    assert run(["collisions", FOLD, "--samples", 50, "--out", out], capsys)[0] == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    real = os.replace

    def refuse(src, dst):
        if str(dst) == str(out) and str(src).endswith(".tmp"):  # the new set into place; not the way back
            raise PermissionError(13, "Permission denied")
        return real(src, dst)

    monkeypatch.setattr(outputs.os, "replace", refuse)
    code, _, err = run(["collisions", FOLD, "--samples", 60, "--out", out], capsys)
    assert code == 1 and "cannot write" in err
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_library_build_finds_outputs_that_land_on_one_path(tmp_path):
    """A Library and its Variant with one fileName, names that differ as text but name one file,
    and a fileName that names no file: each later one fails at its line; the rest build."""
    lib = tmp_path / "L.xml"
    lib.write_text(f'''<LibraryCompiler xmlns="urn:abb-robotics-robotstudio-librarycompiler">
  <Library source="{ARM}" fileName="a.rslib"><DocumentProperties><Title>A</Title></DocumentProperties>
    <Variant name="v" fileName="a.rslib"/>
  </Library>
  <Library source="{ARM}" fileName="sub\\A.usdz"><DocumentProperties><Title>B</Title></DocumentProperties></Library>
  <Library source="{ARM}" fileName=".."><DocumentProperties><Title>C</Title></DocumentProperties></Library>
  <Library source="{ARM}" fileName="{'x' * 300}.rslib"><DocumentProperties><Title>D</Title></DocumentProperties></Library>
  <Library source="{ARM}"><DocumentProperties><Title>E</Title></DocumentProperties><Variant/></Library>
</LibraryCompiler>''')
    build = build_library(lib, tmp_path / "out")
    got = {r.library: (r.status, r.message) for r in build.results}
    assert got["a.rslib"][0] == "built"
    assert got["a.rslib:v"] == ("failed", f"{lib}:3: its asset 'a' is the asset of the Library at line 2 too")
    assert got["sub\\A.usdz"] == ("failed", f"{lib}:5: its asset 'A' is the asset of the Library at line 2 too")
    assert got[".."] == ("failed", f"{lib}:6: fileName '..' names no file")
    long = got["x" * 300 + ".rslib"]
    assert long[0] == "failed" and long[1].startswith(f"{lib}:7: ") and "name too long" in long[1].lower()
    assert sum(r.status == "built" for r in build.results) == 3  # a, E and E's nameless variant
    assert not any("None" in r.library for r in build.results)


def test_a_build_never_replaces_a_file_it_did_not_write(tmp_path):
    """A user's ``<name>.png`` beside the output: that asset fails and the picture is kept; the
    build's own files are replaced on a rebuild."""
    lib = tmp_path / "L.xml"
    lib.write_text(f'''<LibraryCompiler xmlns="urn:abb-robotics-robotstudio-librarycompiler">
  <Library source="{ARM}" fileName="pic.rslib"><DocumentProperties><Title>P</Title><Image generate="true"/>
  </DocumentProperties></Library></LibraryCompiler>''')
    (tmp_path / "pic.png").write_text("my picture")
    (r,) = build_library(lib, size=16).results
    assert r.status == "failed" and "pic.png: exists and rswarp did not write it" in r.message
    assert (tmp_path / "pic.png").read_text() == "my picture" and not (tmp_path / "pic.usdz").exists()
    (tmp_path / "pic.png").unlink()
    assert [r.status for r in build_library(lib, size=16).results] == ["built"]
    assert [r.status for r in build_library(lib, size=16).results] == ["built"]  # its own files: replaced


def test_a_huge_picture_fails_its_asset_only(tmp_path, recwarn):
    """A 13000 x 13000 Image source (a small PNG, a decompression bomb) fails its asset with one
    line and no warning from PIL; a picture within the cap is scaled to the preview size."""
    Image.new("1", (13000, 13000)).save(tmp_path / "bomb.png", optimize=True)
    Image.new("RGB", (2000, 1000), (0, 200, 0)).save(tmp_path / "wide.png")
    lib = tmp_path / "L.xml"
    lib.write_text(f'''<LibraryCompiler xmlns="urn:abb-robotics-robotstudio-librarycompiler">
  <Library source="{ARM}" fileName="b.rslib"><DocumentProperties><Title>B</Title><Image source="bomb.png"/>
  </DocumentProperties></Library>
  <Library source="{ARM}" fileName="w.rslib"><DocumentProperties><Title>W</Title><Image source="wide.png"/>
  </DocumentProperties></Library></LibraryCompiler>''')
    bomb, wide = build_library(lib, tmp_path / "out", size=64).results
    assert bomb.status == "failed" and "bomb.png" in bomb.message and "\n" not in bomb.message
    assert wide.status == "built"
    with Image.open(tmp_path / "out" / "w.png") as im:
        assert im.size == (64, 32)
    assert not [w for w in recwarn if "DecompressionBomb" in type(w.message).__name__]


def test_playback_keeps_cables_whose_names_collide(tmp_path):
    """Three cables named alike once made valid identifiers: three curves in the stage."""
    from pxr import Usd, UsdGeom

    from rswarp.export.playback import PlaybackCable, write_playback

    cables = [PlaybackCable(name, np.zeros((2, 3, 3)), 0.01, (0, 0, 0)) for name in ("a b", "a_b", "a-b")]
    write_playback(tmp_path / "p.usda", "r", [], cables, 60.0)
    stage = Usd.Stage.Open(str(tmp_path / "p.usda"))
    assert len([p for p in stage.Traverse() if p.IsA(UsdGeom.BasisCurves)]) == 3


def test_sigterm_while_usd_is_written_ends_with_143_and_leaves_nothing(tmp_path):
    """SIGTERM arrives while pxr is busy writing the stage (here: sent from inside the writer, the
    exact moment): it is noted, nothing is renamed into place, the run ends with 143 and without a
    traceback, whatever pxr does with the signal meanwhile."""
    script = textwrap.dedent(f"""
        import os, signal, sys
        import rswarp.export.usd_layout as layout
        real = layout.build_stage
        def inside(stage, *args, **kwargs):
            os.kill(os.getpid(), signal.SIGTERM)  # pending while pxr builds and writes the stage
            return real(stage, *args, **kwargs)
        layout.build_stage = inside
        from rswarp.cli import main
        sys.exit(main(["export", {str(IRB)!r}, "-o", {str(tmp_path / "out" / "r.usdc")!r}]))
    """)
    done = subprocess.run([sys.executable, "-c", script], env=ENV, capture_output=True, text=True, timeout=300)
    assert done.returncode == 143 and "Traceback" not in done.stderr, done.stderr
    assert list(tmp_path.iterdir()) == []


def test_an_internal_error_is_exit_2_with_or_without_debug(monkeypatch, capsys):
    """A bug is exit 2; ``--debug`` adds its traceback, never another exit code."""
    from rswarp.report import info

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(info, "run_info", broken)
    assert main(["info", str(IRB)]) == 2
    assert "internal error: ZeroDivisionError: a bug" in capsys.readouterr().err
    assert main(["--debug", "info", str(IRB)]) == 2
    err = capsys.readouterr().err
    assert "Traceback" in err and "internal error" in err


def test_the_manifest_names_what_was_written(tmp_path, capsys):
    """Each output folder's ``.rswarp.json`` lists its files with their SHA-256."""
    out = tmp_path / "out"
    assert run(["sweep", FOLD, "--samples", 100, "--out", out], capsys)[0] == 0
    listed = outputs.manifest(out)
    assert sorted(listed) == ["report.json", "side.png", "top.png", "workspace.npz"]
    assert all(outputs.owned(out / name, listed) for name in listed)
    assert isinstance(rswarp.__version__, str)
