"""The corpus of bad files: each one names, in its first line, the exact error it must produce."""

import re
from pathlib import Path

import pytest

import rswarp
from rswarp.cli import main

from conftest import DATA

BAD = sorted((DATA / "bad").iterdir())
EXPECT = re.compile(r"<!-- expect: (\d+): (.*) -->")


def expectation(path: Path) -> str:
    if path.stat().st_size == 0:
        return f"{path}:1: XML syntax error: Document is empty"
    m = EXPECT.match(path.read_text())
    assert m, f"{path.name} has no expect comment"
    return f"{path}:{m.group(1)}: {m.group(2).replace('{dir}', str(path.parent))}"


def test_corpus_is_large_enough():
    assert len(BAD) >= 30


@pytest.mark.parametrize("path", BAD, ids=[p.name for p in BAD])
def test_bad_file_reports_its_error(path):
    report = rswarp.check(path)
    assert not report.ok
    assert expectation(path) in [str(d) for d in report.errors]


@pytest.mark.parametrize("path", BAD, ids=[p.name for p in BAD])
def test_bad_file_on_the_command_line(path, capsys):
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr()
    assert expectation(path) in out.err.splitlines()  # problems on stderr
    assert out.out.splitlines() == [f"{path}: FAILED" + out.out.split("FAILED", 1)[1].rstrip()]
    assert "Traceback" not in out.out + out.err
    for command in (["info"], ["export", "-o", "never.usda"], ["fk", "--q", "0"]):
        assert main([command[0], str(path), *command[1:]]) == 1
        captured = capsys.readouterr()
        assert expectation(path) in captured.err.splitlines() and captured.out == ""
    assert not (path.parent / "never.usda").exists()


def test_load_raises_with_file_and_line():
    path = DATA / "bad" / "min_greater_than_max.rsxml"
    with pytest.raises(rswarp.RsxmlError) as info:
        rswarp.load(path)
    assert (info.value.file, info.value.line) == (str(path), 14)
    assert str(info.value) == f"{path}:14: Limit of 'J2' has min 90 > max -90"


def test_missing_file():
    report = rswarp.check("no/such/file.rsxml")
    assert [str(d) for d in report.errors] == ["no/such/file.rsxml: cannot read file: No such file or directory"]


def test_entities_are_never_expanded(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOPSECRET")
    doc = tmp_path / "x.rsxml"
    doc.write_text(f'<!DOCTYPE M [<!ENTITY x SYSTEM "file://{secret}">]>\n'
                   '<Mechanism xmlns="urn:abb-robotics-robotstudio-graphiccomponent" name="&x;"/>')
    report = rswarp.check(doc)
    assert "TOPSECRET" not in repr(report)
    assert [str(d) for d in report.errors] == [f"{doc}:1: external entity 'x' declared in the DOCTYPE: entities are refused"]
