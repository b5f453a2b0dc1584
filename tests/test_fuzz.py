"""No input yields a traceback: mutated XML goes through check and the CLI as diagnostics."""

import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

import rswarp
from rswarp import examples
from rswarp.cli import main

from conftest import DATA

SEEDS = [examples.IRB2600ID, DATA / "transforms.rsxml", DATA / "cable.rsxml", DATA / "parallel_rod.rsxml",
         DATA / "smart" / "Counter.rsxml", DATA / "library" / "Robots.xml", DATA / "units_inch.rsxml"]
NASTY = ["", " ", "nan", "inf", "-1e999", "1,2", "1,2,3,4,5", "abc", "0,0,0", "Link9", "Base", "true", "-0",
         "1e-320", "\u00e9\u4e2d", "&amp;", "J1", "0, 0, 0, 0"]
LINE = re.compile(r"^.+?(:\d+)?: ")


def assert_clean(path, capsys):
    report = rswarp.check(path)  # must not raise
    assert all(d.line >= 0 and d.message for d in report.all_diagnostics)
    code = main(["check", str(path)])
    out = capsys.readouterr()
    assert code in (0, 1) and code == (0 if report.ok else 1)
    assert "Traceback" not in out.out + out.err
    for line in out.out.splitlines() + out.err.splitlines():  # problems on stderr, verdict on stdout
        assert LINE.match(line), line
    if report.ok and report.kind == "Mechanism":
        assert main(["info", str(path), "--json"]) == 0
        capsys.readouterr()


@pytest.mark.parametrize("seed", SEEDS, ids=[p.name for p in SEEDS])
def test_every_attribute_with_every_nasty_value(seed, tmp_path, capsys):
    """Systematic: each attribute of a good file, replaced in turn by each nasty value."""
    tree = etree.parse(str(seed))
    elements = [e for e in tree.iter() if isinstance(e.tag, str)]
    for i, el in enumerate(elements):
        for key in list(el.attrib):
            original = el.get(key)
            for bad in NASTY[:: 1 + (i + len(key)) % 3]:  # a third to all of them, varying by position
                el.set(key, bad)
                path = tmp_path / seed.name
                tree.write(str(path))
                assert_clean(path, capsys)
            el.set(key, original)


mutation = st.tuples(st.sampled_from(["delete", "insert", "duplicate"]), st.floats(0, 1), st.integers(1, 40),
                     st.text(alphabet='<>&"\'=/ abcJLink0123456789.,-e\n', max_size=12))


@settings(max_examples=250, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(seed=st.sampled_from(SEEDS), mutations=st.lists(mutation, min_size=1, max_size=4))
def test_random_mutations(seed, mutations, tmp_path, capsys):
    """Random: slices deleted, junk inserted, lines duplicated."""
    text = seed.read_text()
    for op, where, size, junk in mutations:
        at = int(where * len(text))
        if op == "delete":
            text = text[:at] + text[at + size:]
        elif op == "insert":
            text = text[:at] + junk + text[at:]
        else:
            start = text.rfind("\n", 0, at) + 1
            end = text.find("\n", at) + 1 or len(text)
            text = text[:end] + text[start:end] + text[end:]
    path = tmp_path / seed.name
    path.write_text(text)
    # a library file's sources are looked up beside it
    if seed.parent.name == "library":
        (tmp_path / "sub").mkdir(exist_ok=True)
        (tmp_path / "sub" / "IRB1_1_1__02.rsxml").write_bytes((seed.parent / "sub" / "IRB1_1_1__02.rsxml").read_bytes())
    assert_clean(path, capsys)
