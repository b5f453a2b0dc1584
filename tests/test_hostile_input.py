"""Hostile and careless input files: entities in every encoding, files that never end, libraries
that fan out or nest without end, numbers Python would take but RSXML does not, magnitudes that
overflow float32. Each case ends in a clear ``file:line: message``, never a hang or a traceback."""

import os
import subprocess
import sys
import time

import pytest
from generated import NS, library, mechanism

import rswarp
from rswarp.cli import main
from rswarp.rsxml import documents

from conftest import DATA

ENTITY_DOC = """<?xml version="1.0" encoding="{enc}"?>
<!DOCTYPE Mechanism [
  <!ENTITY n "EVIL_EXPANDED">
]>
<Mechanism xmlns="{ns}" type="Other" name="&n;"><Links baseLink="B"><Part name="B"/></Links></Mechanism>
"""


def errors(path, **kw) -> list[str]:
    return [str(d) for d in rswarp.check(path, **kw).errors]


# -- 1. entities are judged on the parsed document, in every encoding ----------------------------------


@pytest.mark.parametrize("enc", ["UTF-8", "UTF-16", "UTF-16LE", "ISO-8859-1", "UTF-32"])
def test_entity_declaration_refused_in_every_encoding(tmp_path, enc):
    path = tmp_path / "m.rsxml"
    text = ENTITY_DOC.format(enc=enc, ns=NS)
    path.write_bytes(text.encode(enc.lower().replace("utf-16", "utf-16").replace("utf-32", "utf-32")))
    if enc == "UTF-16LE":  # no BOM: the declaration names the byte order
        path.write_bytes(text.encode("utf-16-le"))
    assert errors(path) == [f"{path}:3: entity 'n' declared in the DOCTYPE: entities are refused"]
    assert main(["info", str(path), "--json"]) == 1


def test_external_entity_in_utf16_refused(tmp_path):
    path = tmp_path / "m.rsxml"
    path.write_bytes(f"""<?xml version="1.0" encoding="UTF-16"?>
<!DOCTYPE Mechanism [<!ENTITY x SYSTEM "file:///etc/hostname">]>
<Mechanism xmlns="{NS}" name="m"><Links baseLink="B"><Part name="B"/></Links>&x;</Mechanism>
""".encode("utf-16"))
    assert errors(path) == [f"{path}:2: external entity 'x' declared in the DOCTYPE: entities are refused"]


def test_parameter_entity_and_external_dtd_reference_refused(tmp_path):
    a, b = tmp_path / "a.rsxml", tmp_path / "b.rsxml"
    a.write_text(f'<!DOCTYPE M [<!ENTITY % p "x">]>\n<Mechanism xmlns="{NS}" name="m"/>\n')
    b.write_text(f'<!DOCTYPE M SYSTEM "evil.dtd">\n<Mechanism xmlns="{NS}" name="m">\n&e;</Mechanism>\n')
    assert errors(a) == [f"{a}:1: entity 'p' declared in the DOCTYPE: entities are refused"]
    assert errors(b) == [f"{b}:3: entity reference &e; to an external DTD: entities are refused"]


def test_entity_bomb_in_utf16_is_refused_at_once(tmp_path):
    decls = ['<!ENTITY l0 "lollollollollollollollollollol">'] + \
        [f'<!ENTITY l{i} "{f"&l{i - 1};" * 10}">' for i in range(1, 12)]
    path = tmp_path / "bomb.rsxml"
    path.write_bytes(("<?xml version='1.0' encoding='UTF-16'?>\n<!DOCTYPE M [\n" + "\n".join(decls) +
                      f']>\n<Mechanism xmlns="{NS}" name="&l11;"/>\n').encode("utf-16"))
    assert errors(path) == [f"{path}:15: entity expansion too large: entities are refused"]


@pytest.mark.parametrize("enc", ["utf-8", "utf-16", "iso-8859-1"])
def test_comment_mentioning_entity_is_harmless(tmp_path, enc):
    """The old byte search refused a valid file because of its comment."""
    text = (DATA / "branching.rsxml").read_text().replace('encoding="utf-8"', f'encoding="{enc}"')
    text = text.replace("<!-- A branching", "<!-- mentions <!ENTITY x 'y'> in passing. A branching")
    path = tmp_path / "m.rsxml"
    path.write_bytes(text.encode(enc))
    report = rswarp.check(path)
    assert report.ok and report.model.name == "TwinArm"


# -- 2. only regular files, within a size limit ----------------------------------------------------------


def test_dev_zero_and_folders_are_refused(tmp_path):
    assert errors("/dev/zero") == ["/dev/zero: cannot read file: not a regular file: only regular files are read"]
    assert errors(tmp_path) == [f"{tmp_path}: cannot read file: a folder: only regular files are read"]


def test_file_over_the_size_limit(tmp_path, capsys):
    path = DATA / "branching.rsxml"
    size = path.stat().st_size
    assert errors(path, max_file_size=1000) == [
        f"{path}: cannot read file: the file is {size} bytes, over the 1000 bytes limit (raise it with --max-file-size)"]
    assert rswarp.check(path).ok  # the limit was for that call only
    assert main(["--max-file-size", "0.001", "info", str(path)]) == 1
    assert "over the 1048 bytes limit" in capsys.readouterr().err


def test_fifo_as_file_and_as_library_source_does_not_hang(tmp_path):
    fifo = tmp_path / "pipe.rsxml"
    os.mkfifo(fifo)
    lib = tmp_path / "lib.xml"
    lib.write_text(library(["pipe.rsxml"]))
    start = time.monotonic()
    run = subprocess.run([sys.executable, "-m", "rswarp.cli", "check", str(fifo), str(lib)],
                         capture_output=True, text=True, timeout=120)
    assert time.monotonic() - start < 120
    assert run.returncode == 1
    assert run.stderr.count("not a regular file: only regular files are read") == 2


# -- 3. libraries: each file once, a depth limit, no recursion error -------------------------------------


def test_library_fan_out_checks_each_file_once(tmp_path, monkeypatch):
    """26 levels of two Library entries per level: 2**26 checks before, 27 files now."""
    (tmp_path / "m.rsxml").write_text(mechanism(2))
    for level in range(26):
        below = "m.rsxml" if level == 0 else f"lib{level - 1}.xml"
        (tmp_path / f"lib{level}.xml").write_text(library([below, below]))
    parsed = []
    real = documents.parse_xml
    monkeypatch.setattr(documents, "parse_xml", lambda p: parsed.append(p) or real(p))
    report = rswarp.check(tmp_path / "lib25.xml")
    assert report.ok and len(parsed) == 27
    assert len(report.all_diagnostics) == 0


def test_library_chain_deeper_than_the_limit(tmp_path, capsys):
    depth = 600
    (tmp_path / "m.rsxml").write_text(mechanism(1))
    for level in range(depth):
        below = "m.rsxml" if level == 0 else f"lib{level - 1}.xml"
        (tmp_path / f"lib{level}.xml").write_text(library([below]))
    top = tmp_path / f"lib{depth - 1}.xml"
    stopped = tmp_path / f"lib{depth - 1 - documents.MAX_LIBRARY_DEPTH}.xml"
    assert errors(top) == [f"{stopped}:1: Library sources nest deeper than {documents.MAX_LIBRARY_DEPTH} levels; "
                           f"'lib{depth - 2 - documents.MAX_LIBRARY_DEPTH}.xml' is not checked"]
    assert main(["check", str(top)]) == 1
    assert "RecursionError" not in capsys.readouterr().err


def test_library_cycle_still_reported(tmp_path):
    (tmp_path / "a.xml").write_text(library(["b.xml"]))
    (tmp_path / "b.xml").write_text(library(["a.xml"]))
    assert errors(tmp_path / "a.xml") == [f"{tmp_path / 'b.xml'}:1: Library source 'a.xml' refers back to itself"]


def test_library_absolute_empty_and_too_long_sources(tmp_path):
    (tmp_path / "m.rsxml").write_text(mechanism(1))
    lib = tmp_path / "lib.xml"
    lib.write_text(library([str(tmp_path / "m.rsxml")]))
    assert rswarp.check(lib).ok  # an absolute source is used as written
    lib.write_text(library([""]))
    assert errors(lib) == [f"{lib}:1: Library has an empty source"]
    long = "x" * 300 + ".rsxml"
    lib.write_text(library([long]))
    (err,) = errors(lib)
    assert err.startswith(f"{lib}:1: Library source '{long}' not found")


# -- 5. magnitudes: nothing past float32 or physical sense gets through ------------------------------------


@pytest.mark.parametrize("change, message", [
    ({"point": "0,0,1e308"}, "'point1' has a number out of range '1e308'"),
    ({"point": "0,0,2e6"}, "'point1' value 2e+06 is beyond 1 km, the most a model may span"),
    ({"t": "0,0,-1e300"}, "'t' has a number out of range '-1e300'"),
    ({"limits": ("-1e9", "1e9")}, "'min' value -1e+09 is beyond 100000 rad (about 15,915 turns), the most a joint may turn"),
])
def test_magnitudes_beyond_sense_are_errors(tmp_path, change, message):
    path = tmp_path / "m.rsxml"
    path.write_text(mechanism(2, **change))
    assert any(e.endswith(message) for e in errors(path)), errors(path)


def test_huge_quaternion_is_normalized_not_nan(tmp_path):
    path = tmp_path / "m.rsxml"
    path.write_text(mechanism(1).replace('t="0,0,10"', 't="0,0,10" quat="1e29,0,0,1e29"'))
    report = rswarp.check(path)
    assert report.ok and "quat has length" in str(report.warnings[0])
    assert main(["fk", str(path), "--q", "0", "--json"]) == 0


# -- 10. numbers are plain ASCII decimals ------------------------------------------------------------------


@pytest.mark.parametrize("number", ["1_80", "\uff11\uff18\uff10", "\u0661\u0668\u0660", "0x10", "1e5e5"])
def test_numbers_python_takes_but_rsxml_does_not(tmp_path, number, capsys):
    path = tmp_path / "m.rsxml"
    path.write_text(mechanism(1, limits=("-90", number)), encoding="utf-8")
    assert f"{path}:8: 'max' has a bad number '{number}'" in errors(path)
    assert main(["fk", str(DATA / "branching.rsxml"), "--q", f"0,0,0,{number}"]) == 1
    assert capsys.readouterr().err == f"rswarp: --q: '0,0,0,{number}' has a bad number '{number}'\n"


def test_q_beyond_what_a_joint_can_do(capsys):
    assert main(["fk", str(DATA / "branching.rsxml"), "--q", "0,1e308,0,0"]) == 1
    assert capsys.readouterr().err == "rswarp: --q: '0,1e308,0,0' has a number out of range '1e308'\n"
    assert main(["fk", str(DATA / "branching.rsxml"), "--q", "0,1e20,0,0"]) == 1
    assert capsys.readouterr().err == "rswarp: --q: Shoulder = 1e+20 is beyond what a joint can do (100000 rad)\n"


# -- 11. foreign namespaces, empty sources, odd file names -------------------------------------------------


def test_foreign_namespace_elements_are_not_rsxml(tmp_path):
    path = tmp_path / "m.rsxml"
    xhtml = "http://www.w3.org/1999/xhtml"
    text = mechanism(1).replace("<Joints>", f'<x:Joints xmlns:x="{xhtml}"><x:Joint name="J9"/></x:Joints><Joints>')
    path.write_text(text)
    report = rswarp.check(path)
    assert report.ok and [j.name for j in report.model.joints] == ["J0"]
    assert f"{path}:5: warning: element <x:Joints> of namespace '{xhtml}' is not RSXML; ignored" in map(str, report.warnings)


def test_newline_in_a_file_name_stays_on_one_line(tmp_path, capsys):
    path = tmp_path / "two\nlines.rsxml"
    path.write_text(mechanism(1, limits=("90", "-90")))
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "two\\nlines.rsxml:8: Limit of 'J0' has min 90 > max -90" in err
