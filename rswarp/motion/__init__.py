"""The planner: a RAPID task's motion records (``rswarp.rapid``) to a timed, checked joint
trajectory, as the controller would move the robot.

- ``plan``: ``program_plan`` (the public ``rswarp.program``): a task read, run and planned on a
  robot or a cell.
- ``planner``: the ``Planner`` the interpreter drives (CRobT, CalcJointT, each motion as it comes)
  and the ``Plan`` it finishes into: moves, times, joint values, findings.
- ``plan_steps``: its three batched steps (targets, paths, timing) so the kinematics run in a few
  large launches.
- ``tcp`` (where a target puts the flange: tool and work object), ``targets`` (the joints a move
  goes to: a jointtarget's axes, or the robtarget's inverse kinematics with its confdata),
  ``paths`` (a linear or circular move's poses), ``follow`` (joint values along a path of
  flange poses, continuous from where the robot is).
- ``timing`` (joint and path moves timed under the axes' limits), ``scurve`` (Ruckig's jerk-limited
  profile in closed form), ``topp`` (TOPP-RA's path timing on the host side of
  ``kernels.topp``), ``timing_batch`` (a batch's moves timed together), ``zones`` and
  ``zone_batch`` (zoned corners blended).
- ``misses`` and ``shortfall``: a target the robot cannot take, and by how much.
- ``payload``: ``--payload``, the loads a task carries and how they lower the accelerations.
- ``cell_plan`` (a task over a cell: the external axes with the robot's) and ``cells`` (a cell file
  wherever a command takes a robot).
"""
