"""The dress-pack cable on the host: the seam a cable model implements, the Cosserat rod model
(its device code: ``rswarp.kernels.rod``), and what a run reports. A run itself, a client of the
batch engine, is ``rswarp.sim.cables``; the designs a sweep varies, ``rswarp.sim.designs``.
Importing the package imports nothing.

- ``solver``: the seam, ``CableSolver`` (state, step, statistics, totals), its options
  (``CableOptions``) and the meshes a cable may touch (``contact_meshes``).
- ``models``: the cable models by the name that chooses them (``--cable-model``).
- ``rod``: ``CosseratRod``, the rod model's solver, its kernel's model made from a layout.
- ``layout``: a mechanism's cables as the rod's segments, joints and clamps (``RodLayout``).
- ``rest_checks``: a rest shape through the floor or a link refused before a run.
- ``results``: what a run reports per cable (``CableResult``, the spread over time ``Series``).
- ``extremes``: the running extremes a run gathers them by, frame by frame.
- ``tally``: a run cut into tasks put back together exactly as one run gathers it.
- ``rainflow``: bending cycles counted per segment (ASTM E1049), streamed, for the fatigue.
"""
