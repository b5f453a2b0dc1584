"""Writing RSXML: load -> save -> load gives an equal model, and saving changes no value."""

import os

import pytest
from lxml import etree

import rswarp
from rswarp import examples
from rswarp.rsxml.parse import children, local

from conftest import DATA

GOOD = [examples.IRB1300, examples.IRB2600ID, examples.IRB2600, DATA / "smart" / "Counter.rsxml",
        *sorted(DATA.glob("*.rsxml")), DATA / "meshes" / "Cell.rsxml", DATA / "library" / "sub" / "IRB1_1_1__02.rsxml"]


def values(text: str):
    """Numbers of an attribute as floats (exact), or the text itself when it is not numeric."""
    try:
        return [float(v) for v in text.replace(",", " ").split()] or text
    except ValueError:
        return text.strip()


def assert_same_values(original: etree._Element, saved: etree._Element, where: str = "") -> None:
    """Every attribute of ``original`` is in ``saved`` with the same value; children matched by tag
    and position among siblings of that tag (sections may be written in another order)."""
    where = f"{where}/{local(original)}"
    assert local(original) == local(saved), where
    for key, text in original.attrib.items():
        assert key in saved.attrib, f"{where}@{key} lost"
        assert values(saved.get(key)) == values(text), f"{where}@{key}: {text!r} -> {saved.get(key)!r}"
    by_tag: dict[str, list] = {}
    for c in children(saved):
        by_tag.setdefault(local(c), []).append(c)
    seen: dict[str, int] = {}
    for c in children(original):
        i = seen.get(local(c), 0)
        seen[local(c)] = i + 1
        assert i < len(by_tag.get(local(c), [])), f"{where}/{local(c)}[{i}] lost"
        assert_same_values(c, by_tag[local(c)][i], where)


@pytest.mark.parametrize("path", GOOD, ids=[p.name for p in GOOD])
def test_round_trip(path, tmp_path):
    report = rswarp.check(path)
    assert report.ok
    out = tmp_path / path.name
    rswarp.save(report.model, out)
    again = rswarp.check(out)
    assert again.ok, [str(d) for d in again.errors]
    assert again.model == report.model
    if path.name == "warnings.rsxml":
        return  # its unknown attribute and element are dropped, its quaternion normalized: all warned
    parser = etree.XMLParser(remove_comments=True, resolve_entities=False)
    assert_same_values(etree.parse(str(path), parser).getroot(), etree.parse(str(out), parser).getroot())


def test_saving_twice_gives_the_same_bytes(tmp_path):
    m = rswarp.load(examples.IRB2600ID)
    rswarp.save(m, tmp_path / "a.rsxml")
    rswarp.save(rswarp.load(tmp_path / "a.rsxml"), tmp_path / "b.rsxml")
    assert (tmp_path / "a.rsxml").read_bytes() == (tmp_path / "b.rsxml").read_bytes()


def test_units_are_kept(tmp_path):
    m = rswarp.load(examples.IRB1300)
    rswarp.save(m, tmp_path / "r.rsxml")
    text = (tmp_path / "r.rsxml").read_text()
    assert 'lengthUnit="mm"' in text and 'point1="50, -100.5, 544"' in text and 'value="0, 0, 0, 0, 30, 0"' in text


def test_save_is_atomic(tmp_path, monkeypatch):
    target = tmp_path / "robot.rsxml"
    target.write_text("previous content")

    def broken_replace(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", broken_replace)
    with pytest.raises(rswarp.InputError, match=f"{target}: cannot write: disk full"):
        rswarp.save(rswarp.load(examples.IRB1300), target)
    assert target.read_text() == "previous content"
    assert [p.name for p in tmp_path.iterdir()] == ["robot.rsxml"]  # no temporary file left behind


def test_save_into_missing_folder_leaves_nothing(tmp_path):
    with pytest.raises(rswarp.InputError, match="cannot write: No such file or directory"):
        rswarp.save(rswarp.load(examples.IRB1300), tmp_path / "nope" / "r.rsxml")
    assert list(tmp_path.iterdir()) == []
