"""Example robots shipped with rswarp (installed as ``rswarp.examples``); ``rswarp demo`` runs on them."""

from pathlib import Path

FOLDER = Path(__file__).parent
IRB1300 = FOLDER / "irb1300" / "IRB1300_11_90__01.rsxml"
IRB1300_LIBRARY = FOLDER / "irb1300" / "IRB1300.xml"
IRB2600ID = FOLDER / "irb2600id" / "IRB2600ID_8_200__03.rsxml"
IRB2600 = FOLDER / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
IRB2600_LIBRARY = FOLDER / "irb2600_12_165" / "IRB2600_12_165.xml"
IRB2600_DRESSPACK = FOLDER / "irb2600_12_165" / "IRB2600_12_165_DressPack_01.rsxml"  # with a process hose
IRB2600_PROGRAM = FOLDER / "irb2600_12_165" / "pick_place.mod"  # a RAPID pick-and-place routine (rswarp program)
IRB2600_GRIPPER = FOLDER / "irb2600_12_165" / "gripper" / "Gripper.rsxml"  # a Tool for --tool, TCP as tGripper's
IRB2600_CELL = FOLDER / "irb2600_12_165" / "cell"  # a palletizing task of three modules, a main loop (rswarp program)
PALLETIZER = FOLDER / "palletizer" / "IRB9460_110_240__01.rsxml"
CELLS = FOLDER / "cells"  # cell files: the IRB 2600 on the track, and beside the positioner
MULTIMOVE_CELL = CELLS / "multimove_cell.toml"  # two IRB 2600s of one MultiMove backup, each on its task
MULTIMOVE_BACKUP = CELLS / "multimove"  # that backup: SYSPAR/MOC.cfg, SYS.cfg, RAPID/T_ROB1, T_ROB2
STANDARD_CYCLE = FOLDER / "standard_cycle.mod"  # ABB's 25 x 300 x 25 mm pick cycle, for any 6-axis arm
TRACK = FOLDER / "track" / "IRBT2005_4m.rsxml"  # an ExternalAxis: a 4 m robot track (one prismatic axis)
POSITIONER = FOLDER / "positioner" / "IRBP_A250.rsxml"  # an ExternalAxis: a tilt-and-turn positioner
ALL = (IRB1300, IRB1300_LIBRARY, IRB2600ID, IRB2600, IRB2600_LIBRARY, PALLETIZER)
