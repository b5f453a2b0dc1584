"""The Cosserat rod cable model as device code (the host side: ``rswarp.sim.cable``). Importing
the package imports nothing; each module is Warp code but ``slots``, plain Python the host reads.

- ``kernel``: the step kernel (``rod_kernel``), one frame of every environment in substeps.
- ``types``: the model struct (``RodParams``), the state, wear map and frame statistics the
  kernel updates (``RodBodies``, ``RodWear``, ``RodFrame``), the work records, the column layouts.
- ``slots``: the contact slot table (the meshes, the floor, the cables) and the statuses and
  sentinel the kernel writes for the host to read.
- ``algebra``: rotations and the 6x6 block algebra of the solve (LDL^T, triangular sweeps).
- ``joint``: an elastic joint's strain, forces and energy terms (stretch, shear, bend, twist).
- ``contact``: a capsule against a mesh, another capsule or the floor; a contact's terms.
- ``gather``: finding a substep's contacts and a frame's clearances.
- ``step``: prediction, one Gauss-Newton iteration (block-tridiagonal solve), commit.
- ``measure``: what a substep and a frame report (tension, bend, twist, loads, wear, pinch).
"""
