"""Messages in cause order (issue "Hardening the cell surfaces"): a misspelt key of an
``[[external]]`` is the one error, not what follows from that unit being left out; a folder or a
FIFO given where a file goes is named as what it is."""

from __future__ import annotations

import os

import pytest

from rswarp import examples
from rswarp.errors import RsxmlError
from rswarp.rsxml.cell import read_cell

ROBOT = examples.IRB2600.resolve().as_posix()
TRACK = examples.TRACK.resolve().as_posix()


def test_a_misspelt_key_of_a_unit_is_said_and_not_what_follows_from_it(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text(f'[robot]\nrsxml = "{ROBOT}"\non = "track"\n\n[[external]]\nname = "track"\n'
                    f'rsxml = "{TRACK}"\nfram = [0, 0, 0, 0, 0, 0]\naxes = ["eax_a"]\n')
    with pytest.raises(RsxmlError) as err:
        read_cell(str(cell))
    lines = [str(d) for d in err.value.diagnostics]
    assert len(lines) == 1 and f"{cell}:8: unknown key 'fram' in [[external]] 1; did you mean 'frame'?" in lines[0]


def test_a_folder_given_as_an_rsxml_file_is_called_a_folder(tmp_path):
    (tmp_path / "robot.rsxml").mkdir()
    cell = tmp_path / "cell.toml"
    cell.write_text('[robot]\nrsxml = "robot.rsxml"\n')
    with pytest.raises(RsxmlError, match=r"cell.toml:2: \[robot\] rsxml: 'robot.rsxml' is a folder, not a file"):
        read_cell(str(cell))


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_given_as_a_moc_cfg_is_called_a_fifo_and_never_opened(tmp_path):
    os.mkfifo(tmp_path / "MOC.cfg")
    cell = tmp_path / "cell.toml"
    cell.write_text(f'backup = "MOC.cfg"\n[robot]\nrsxml = "{ROBOT}"\n')
    with pytest.raises(RsxmlError, match=r"cell.toml:1: backup: 'MOC.cfg' is a FIFO, not a backup folder"):
        read_cell(str(cell))


def test_an_empty_moc_cfg_is_an_error_at_its_first_line(tmp_path):
    (tmp_path / "backup" / "SYSPAR").mkdir(parents=True)
    (tmp_path / "backup" / "SYSPAR" / "MOC.cfg").write_text("\n\n")
    cell = tmp_path / "cell.toml"
    cell.write_text(f'backup = "backup"\n[robot]\nrsxml = "{ROBOT}"\n')
    with pytest.raises(RsxmlError, match=r"MOC.cfg:1: not a MOC.cfg: the file is empty, without the header"):
        read_cell(str(cell))
