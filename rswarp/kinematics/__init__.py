"""Host side of kinematics: ``Kinematics`` (batched forward kinematics on Warp), the link tree as
the kernels' flat arrays, the loops of a mechanism and the host twins of the device functions that
solve them, and joint trajectories. ``Kinematics`` imports Warp, so it loads on first use."""


def __getattr__(name):
    if name == "Kinematics":
        from .kinematics import Kinematics

        return Kinematics
    raise AttributeError(f"module 'rswarp.kinematics' has no attribute '{name}'")
