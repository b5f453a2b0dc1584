"""Host side of the Warp work: the launcher (device, chunks, threads), the chain of flat arrays a
mechanism compiles to, forward kinematics and workspace sweeps."""
