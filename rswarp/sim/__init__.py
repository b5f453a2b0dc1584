"""Host side of the Warp work: the batch engine and its clients (workspace sweeps, collisions,
cables, program checks, render). The launcher they all run kernels on is ``rswarp.launch``."""
