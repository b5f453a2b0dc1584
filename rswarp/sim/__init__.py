"""Host side of the Warp work: the batch engine and its clients (workspace sweeps, collisions,
cables, program checks, render); ``cable/``, the dress-pack cable's model and what a cable run
reports. The launcher they all run kernels on is ``rswarp.launch``."""
