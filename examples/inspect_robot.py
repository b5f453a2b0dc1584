"""Load a real robot, print its joint axes in SI, and measure its link meshes.

Run: python examples/inspect_robot.py [FILE.rsxml]   (default: the bundled IRB 2600-12/1.65)
"""

import sys
from pathlib import Path

import rswarp
from rswarp.geometry import link_mesh


def main(path: str) -> None:
    mech = rswarp.load(path)
    lo, hi = mech.bounds()
    print(f"{mech.name}: {mech.dof} axes, base link {mech.base_link}")
    for joint, a, b in zip(mech.active_joints, lo, hi):
        through = tuple(round(v, 4) for v in joint.point1)
        print(f"  {joint.name}: {joint.type:10s} axis {joint.axis.round(3)} through {through} m,"
              f" range [{a:+.3f}, {b:+.3f}] {'rad' if joint.revolute else 'm'}")
    for name in mech.link_names:
        try:
            mesh = link_mesh(mech, name)
        except rswarp.MeshNotFoundError as exc:
            print(f"  {name}: no mesh ({exc.message})")
            continue
        if mesh is not None:
            print(f"  {name}: {len(mesh.faces)} triangles, {mesh.volume * 1e3:.2f} litres, "
                  f"watertight={mesh.is_watertight}")


if __name__ == "__main__":
    default = Path(__file__).parent / "irb2600_12_165" / "IRB2600_12_165__01.rsxml"
    main(sys.argv[1] if len(sys.argv) > 1 else str(default))
