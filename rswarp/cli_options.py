"""The options of each ``rswarp`` command, beside those every command of a kind shares (``cli``'s
parent parsers). Each option's destination is the keyword of the library function it goes to,
or a field of the ``rswarp.config`` options object it is gathered into; numbers are parsed and
bounded by ``rswarp.options``."""

from __future__ import annotations

import argparse

from .config import DENSITY, FRAME_RATE, FRICTION, MAX_STRAIN, MAX_TORSION_DEG, POISSON, SUBSTEPS
from .export.physics import DRIVE_HZ
from .geometry.mass import DEFAULT_DENSITY
from .options import argument

LENGTH = "in the file's length unit"


def check(p: argparse.ArgumentParser) -> None:
    p.add_argument("paths", nargs="+", metavar="FILE")


CELL_HELP = "a robot's RSXML file, or a cell file (cell.toml: the robot on its track or beside its positioner)"


def info(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="FILE")


def fk(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="FILE")
    p.add_argument("--q", required=True, help='active joint values in the file\'s units, e.g. "0,0,0,0,30,0"')


def sweep(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="FILE", help=CELL_HELP)
    p.add_argument("--samples", type=argument("samples"), default=1_000_000,
                   help="joint configurations (default 1000000)")
    p.add_argument("--method", choices=["random", "sobol", "grid"], default="random")
    p.add_argument("--resolution", type=argument("resolution"), help=f"voxel size {LENGTH} (default 25 mm)")


def collisions(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="FILE", help=CELL_HELP)
    p.add_argument("--samples", type=argument("samples"), default=1_000_000,
                   help="random configurations (default 1000000)")
    p.add_argument("--padding", type=argument("padding"), default=0.0,
                   help=f"pairs closer than this ({LENGTH}) count as colliding (default 0)")
    p.add_argument("--env", action="append", default=[], metavar="MESH@x,y,z",
                   help=f"an environment mesh placed in the world ({LENGTH}), tested against every link; repeat "
                        "for more")
    _tool(p)


def export(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="FILE")
    p.add_argument("-o", "--output", required=True, metavar="OUT")
    p.add_argument("--layout", choices=["flat", "component"],
                   help="USD only: one file (default), or an interface layer with payloaded geometry/materials/"
                        "physics layers")
    p.add_argument("--mesh-paths", choices=["absolute", "relative"],
                   help="URDF only: name the meshes/ files by absolute path (default: every loader finds them, "
                        "pinocchio included) or relative to the URDF (a folder that can be moved)")
    p.add_argument("--collision", choices=["convexHull", "convexDecomposition"], default="convexHull",
                   help="collision geometry rswarp computes once (cached): a convex hull per part (default), or "
                        "a convex decomposition with CoACD")
    p.add_argument("--density", type=argument("density"), default=DEFAULT_DENSITY,
                   help=f"kg/m^3 for link masses (default {DEFAULT_DENSITY:g}, cast aluminium)")
    p.add_argument("--mass", type=argument("mass"), metavar="KG",
                   help="the robot's total mass: scales the density so the links weigh this in all")
    p.add_argument("--payload", metavar="KG[@x,y,z] | MODULE:NAME",
                   help=f"a load on the flange, added to its link's mass and sizing the estimated efforts: a mass "
                        f"with its centre of gravity in the flange's frame ({LENGTH}), or a RAPID tooldata's or "
                        "loaddata's load (default: none authored; efforts sized for the robot data's rated payload)")
    p.add_argument("--drive-hz", type=argument("drive-hz"), default=DRIVE_HZ, metavar="HZ",
                   help=f"bandwidth of the position drives holding home (default {DRIVE_HZ:g}; 0: no drives)")
    p.add_argument("--armature", type=argument("armature"), metavar="KGM2",
                   help="motor reflected inertia for every joint, kg m^2 (kg for prismatic joints); default "
                        "1e-3 x total mass x reach^2")
    p.add_argument("--effort", type=argument("effort"), metavar="NM",
                   help="effort limit for every joint, N m (N); default twice the largest gravity load plus "
                        "10 rad/s^2 of acceleration")
    p.add_argument("--velocity", type=argument("velocity"), metavar="RAD_S",
                   help="velocity limit for every joint, rad/s (m/s); default --limits, else 90 deg/s (0.5 m/s)")
    _limits(p)
    matrix = p.add_mutually_exclusive_group()
    matrix.add_argument("--collision-matrix", dest="collision_matrix_srdf", metavar="SRDF",
                        help="filter every pair an SRDF disables (from 'rswarp collisions' or MoveIt) from contact")
    matrix.add_argument("--collision-samples", type=argument("collision-samples"), metavar="N",
                        help="run a collision sweep of N samples and filter every pair its matrix disables")


def build(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="LIBRARY.xml")
    p.add_argument("-o", "--out", metavar="DIR", help="where the assets go (default: beside the XML)")
    p.add_argument("--layout", choices=["usdz", "component"], default="usdz",
                   help="one .usdz per asset (default), or a folder per asset: an interface layer with payloaded "
                        "geometry/materials/physics layers and the preview PNG")
    p.add_argument("--size", type=argument("size"), default=512,
                   help="preview image width and height in pixels (default 512)")


def program(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="ROBOT", help=CELL_HELP + ": a robtarget's extax drives its external axes")
    p.add_argument("programs", nargs="+", metavar="PATH",
                   help="the RAPID task: module files (.mod, .modx, .prg, .sys), a folder of them (a backup's "
                        "RAPID/TASK1), or a .pgf program file")
    _task(p)
    p.add_argument("--csv", metavar="CSV", help="write the trajectory as the CSV rswarp cable --trajectory reads")
    p.add_argument("--speed-plot", metavar="FILE.png",
                   help="plot the TCP's speed over time against each move's programmed speed (PNG)")
    p.add_argument("--env", dest="environment", action="append", default=[], metavar="MESH@x,y,z",
                   help=f"a mesh placed in the world ({LENGTH}), checked against every link; repeat for more")
    p.add_argument("--collision-matrix", metavar="SRDF",
                   help="skip the link pairs this SRDF disables (rswarp collisions writes one)")
    floor = p.add_mutually_exclusive_group()
    floor.add_argument("--floor", type=argument("floor"), default=0.0,
                       help=f"height of the floor {LENGTH} (the robot file's, not RAPID's mm; default 0)")
    floor.add_argument("--no-floor", dest="floor", action="store_const", const=None,
                       help="no floor to check the links against")
    p.add_argument("--video", metavar="FILE", help="also render the motion as a .gif or .mp4, links in collision red")
    _tool(p)


def place(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="ROBOT", help="the robot's RSXML file, or a cell file (its [robot] frame moves, or "
                                                 "the frame of the unit the robot rides; its meshes are checked)")
    p.add_argument("programs", nargs="+", metavar="PATH",
                   help="the RAPID task (module files, a folder, a .pgf) whose every pose the robot must reach")
    _task(p)
    p.add_argument("--vary", action="append", required=True, metavar="NAME=MIN:MAX[:N]",
                   help="a variable of the base and its range: x, y, z (mm) or yaw (degrees), as a cell file writes "
                        "frames; with N, N values ends included (every such variable a grid, all combinations), "
                        "without, drawn --samples times; repeat for more")
    p.add_argument("--samples", type=argument("samples"), metavar="N",
                   help="quasi-random draws of the variables given without N (scrambled Halton, --seed)")
    p.add_argument("--top", type=argument("top"), default=8,
                   help="the best bases (by their margin to the singularities) run through the whole program and "
                        "ranked by cycle time (default 8)")
    p.add_argument("--env", dest="environment", action="append", default=[], metavar="MESH@x,y,z",
                   help=f"a mesh placed in the world ({LENGTH}), checked at every pose; repeat for more")
    _tool(p)


def reach(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="ROBOT", help="the robot's RSXML file, or a cell file whose robot stands on the "
                                                 "floor")
    p.add_argument("part", metavar="MESH@x,y,z", help=f"the part: a mesh file and where its origin goes in the "
                                                      f"world ({LENGTH}); every face centre is a target")
    p.add_argument("--spin", type=float, default=90.0, metavar="DEG",
                   help="the tool spun about each face's normal every DEG degrees (default 90: four approaches)")
    _tool(p)


def _task(p: argparse.ArgumentParser) -> None:
    """How a RAPID task runs: its entry routine, its inputs, its main loop's passes, external axes."""
    p.add_argument("--routine", default="main", help="the routine to run (default main)")
    p.add_argument("--io", action="append", metavar="NAME=VALUE",
                   help="an I/O signal's value (default 0 for every signal); repeat for more")
    p.add_argument("--input", dest="inputs", action="append", metavar="NAME=VALUE",
                   help="what a live read gives (SocketReceive, ReadNum, TPReadNum, UINumEntry, ...): NAME is the "
                        "data it stores into, or a function's own name; repeat a name for each read, in order")
    p.add_argument("--cycles", type=argument("cycles"), default=1,
                   help="passes of a main loop that never ends (WHILE TRUE), or runs of the routine (default 1)")
    p.add_argument("--external-axes", choices=["auto", "error", "ignore"], default="auto",
                   help="auto (default): as the controller, a target's value for an external axis the robot "
                        "does not have is ignored (one warning an axis), a work object a unit moves is an error; "
                        "error: both are errors; ignore: both are ignored with a warning")
    p.add_argument("--task", dest="motion_task", metavar="NAME",
                   help="the task of a backup's folder to run (T_ROB2, MultiMove; default its first)")
    p.add_argument("--assume-missing", action="store_true",
                   help="run a task whose repository lacks its configuration: a name declared nowhere becomes, by "
                        "its use, a stand-in (a signal or num at 0, a tooldata or wobjdata at the identity with no "
                        "load, a speeddata v1000, a zonedata fine), each listed once with the line that first uses it")
    _limits(p)


def _tool(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tool", metavar="MESH[@x,y,z,rx,ry,rz]",
                   help=f"a tool on the flange: a mesh placed in the flange's frame ({LENGTH}, degrees about x, "
                        "y, z: ABB's Euler ZYX), or an RSXML Mechanism of type Tool; checked against every link but "
                        "the one it is on, the meshes and the cables, and drawn in videos")


def _limits(p: argparse.ArgumentParser) -> None:
    p.add_argument("--limits", metavar="FILE",
                   help="axis speeds (and accelerations, efforts) from a URDF's <limit>, MoveIt's joint_limits.yaml "
                        "or a robot-data .robot.toml, matched by joint name or order (default: the .robot.toml "
                        "beside the RSXML, else 90 deg/s, said in the output)")


def cable(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="FILE", help=CELL_HELP + " (its robot's RSXML with the Cable; a track carries it)")
    p.add_argument("--envs", type=argument("envs"), default=None,
                   help="parallel environments (default 16; 1 with --program, whose environments would be alike)")
    how = p.add_mutually_exclusive_group(required=True)
    how.add_argument("--trajectory", action="append", metavar="CSV",
                     help="joint trajectory, time,<joint>,... in the file's units; repeat for more (assigned "
                          "round-robin)")
    how.add_argument("--random", action="store_true",
                     help="random programs, one per environment (seeded by --seed): smooth moves within the limits "
                          "that keep the robot clear of itself and of the floor")
    how.add_argument("--program", nargs="+", metavar="PATH",
                     help="a RAPID task (module files, a folder, a .pgf) whose routine (--routine) every environment "
                          "runs (rswarp program)")
    _task(p)
    p.add_argument("--video", metavar="FILE", help="also render the worst environment (or --video-env) as a .gif "
                                                   "or .mp4: the robot, and the hose coloured by --video-color")
    p.add_argument("--video-env", type=int, metavar="K", help="the environment --video renders")
    p.add_argument("--video-color", choices=["bend", "wear"], default="bend",
                   help="colour the hose by its bend radius against the allowed one (default) or by its wear")
    p.add_argument("--seconds", type=argument("seconds"),
                   help="simulated time (default: the longest trajectory; 10 with --random)")
    p.add_argument("--usd", action="store_true",
                   help="also write playback.usdc: environment 0's robot and cables over time, for usdview")
    _hose(p)
    p.add_argument("--cable-model", default="rod", metavar="MODEL",
                   help="how the cables are simulated: a model of rswarp.sim.cable.models (default rod: "
                        "discrete Cosserat rods)")


def dresspack(p: argparse.ArgumentParser) -> None:
    p.add_argument("path", metavar="ROBOT", help="the robot's RSXML file, with its dress-pack Cable, or a cell file "
                                                 "whose robot has it (a track carries it)")
    p.add_argument("--program", dest="programs", nargs="+", required=True, metavar="PATH",
                   help="the RAPID task (module files, a folder, a .pgf) whose routine (--routine) every design runs")
    _task(p)
    p.add_argument("--vary", action="append", required=True, metavar="SPEC",
                   help="a variable and its range: length=MIN:MAX (m), or POINT.x|y|z=MIN:MAX (m, along its link's "
                        "axes) or POINT.pitch|yaw=MIN:MAX (deg), POINT a control point's link or number; repeat "
                        "for more, or give one TOML file of them")
    p.add_argument("--designs", type=argument("designs"), default=64,
                   help="designs drawn by Sobol over the box, each run as its own environment (default 64)")
    p.add_argument("--cable", metavar="NAME", help="the cable to vary (default: the only one)")
    p.add_argument("--min-margin", type=argument("min-margin"), default=0.0, metavar="PCT",
                   help="the least margin to every rating the chosen design must keep, in %% (default 0: the "
                        "shortest hose that passes at all)")
    p.add_argument("--video", metavar="FILE", help="also render the chosen design's run (best.rsxml's, or "
                                                   "closest.rsxml's) as a .gif or .mp4: the robot, and the hose "
                                                   "coloured by --video-color")
    p.add_argument("--video-color", choices=["bend", "wear"], default="bend",
                   help="colour the hose by its bend radius against the allowed one (default) or by its wear")
    _hose(p)


def _hose(p: argparse.ArgumentParser) -> None:
    """The hose's ratings, the cell and the material: what a cable run holds the hose to."""
    p.add_argument("--min-bend-radius", type=argument("min-bend-radius"), metavar="R",
                   help=f"the hose's dynamic bend radius {LENGTH}: tighter while moving fails (default ten times "
                        "the diameter)")
    p.add_argument("--static-bend-radius", type=argument("static-bend-radius"), metavar="R",
                   help=f"the hose's static bend radius {LENGTH}: tighter is a kink (default five times the "
                        "diameter)")
    p.add_argument("--max-strain", type=argument("max-strain"), default=MAX_STRAIN, metavar="STRAIN",
                   help=f"axial strain past which the hose is pulled taut, not hanging (default {MAX_STRAIN:g}: "
                        f"{MAX_STRAIN * 100:g} %%)")
    p.add_argument("--max-torsion", type=argument("max-torsion"), default=MAX_TORSION_DEG, metavar="DEG_PER_M",
                   help=f"twist a metre the hose is rated for (default {MAX_TORSION_DEG:g}, a torsion-rated robot "
                        "hose)")
    p.add_argument("--max-contact-force", type=argument("max-contact-force"), metavar="N",
                   help="a contact harder than this fails (default: contact is a warning)")
    p.add_argument("--max-clamp-load", type=argument("max-clamp-load"), metavar="N",
                   help="a clamp pulled harder than this fails (default: clamp loads are reported only)")
    p.add_argument("--rated-cycles", metavar="N@R",
                   help=f"the hose's bending life: N cycles to failure bent to radius R {LENGTH}; gives the passes "
                        "of the program its worst location lasts (Miner's rule, exponent 4)")
    floor = p.add_mutually_exclusive_group()
    floor.add_argument("--floor", type=argument("floor"), default=0.0, help=f"height of the floor {LENGTH} (default 0)")
    floor.add_argument("--no-floor", dest="floor", action="store_const", const=None, help="no floor")
    p.add_argument("--env", dest="environment", action="append", default=[], metavar="MESH@x,y,z",
                   help=f"a mesh placed in the world ({LENGTH}) that the cables meet; repeat for more")
    _tool(p)
    p.add_argument("--density", type=argument("density"), default=DENSITY, help=f"kg/m^3 (default {DENSITY:g}, a hose)")
    p.add_argument("--poisson", type=argument("poisson"), default=POISSON,
                   help=f"Poisson's ratio of the cable's material, 0 to 0.5 (default {POISSON:g}, rubber: G = E/3)")
    p.add_argument("--friction", type=argument("friction"), default=FRICTION,
                   help=f"Coulomb friction coefficient of the cables on everything (default {FRICTION:g}: rubber on "
                        "painted metal)")
    p.add_argument("--frame-rate", type=argument("frame-rate"), default=FRAME_RATE,
                   help=f"results per simulated second (default {FRAME_RATE:g})")
    p.add_argument("--substeps", type=argument("substeps"), default=SUBSTEPS,
                   help=f"steps per frame (default {SUBSTEPS})")


def demo(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="rswarp-demo", metavar="DIR", help="where the outputs go (default ./rswarp-demo)")
