"""rswarp: ABB RobotStudio RSXML robot descriptions for OpenUSD, Newton and batched Warp kernels.

Layers, imports pointing down only (docs/layout.md, kept true by tests/test_layout.py): ``rsxml`` (the
format) -> ``rapid`` (RAPID programs) -> ``geometry`` (meshes, the mass model) -> ``kinematics``
(forward and inverse, batched on Warp) -> ``sim`` (the batch engine and its sweeps and cable runs)
-> ``export`` (USD, URDF, Newton) -> ``motion`` (the planner: RAPID motions to timed, checked
trajectories) -> ``report`` (what people read) -> ``cli``. A run's options are the typed objects
of ``config``. Device code lives in ``rswarp.kernels``.
"""

from . import files as files  # first: in the rswarp command a Ctrl-C while it loads waits for main
from .config import BatchOptions, DesignOptions, HoseOptions, PlaceOptions, TaskOptions, VideoOptions
from .errors import Diagnostic, InputError, MeshError, MeshNotFoundError, RsxmlError
from .rsxml.documents import Report, RsxmlWarning, check, load, load_library
from .rsxml.graph import LinkGraph
from .rsxml.model import (
    Attribute,
    Cable,
    ControlPoint,
    DynamicProperty,
    Flange,
    Group,
    IOSignal,
    Joint,
    Limit,
    Mechanism,
    Part,
    Pose,
    SmartComponent,
)
from .rsxml.write import save, to_rsxml

# Kinematics, sweeps and exports import Warp, USD or Newton: loaded on first use, so reading RSXML
# stays light.
_LAZY = {
    "Kinematics": ("kinematics.kinematics", "Kinematics"),
    "workspace": ("sim.workspace", "workspace"),
    "collisions": ("sim.collisions", "collisions"),
    "simulate_cables": ("sim.cables", "simulate_cables"),
    "Cluster": ("sim.engine", "Cluster"),
    "build_library": ("report.library", "build_library"),
    "program": ("motion.plan", "program_plan"),
    "place": ("report.placement.run", "place"),
    "reach": ("report.placement.study", "reach"),
    "to_usd": ("export.usd_layout", "to_usd"),
    "to_newton": ("export.newton", "to_newton"),
    "to_urdf": ("export.urdf", "to_urdf"),
    "examples": ("examples", None),  # the bundled robots' paths, a module
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        found = importlib.import_module(f".{module}", __name__)
        return found if attr is None else getattr(found, attr)
    raise AttributeError(f"module 'rswarp' has no attribute '{name}'")


__version__ = "0.1.0"

__all__ = [
    "Attribute", "Cable", "ControlPoint", "Diagnostic", "DynamicProperty", "Flange", "Group", "IOSignal",
    "InputError", "Joint", "Limit", "LinkGraph", "Mechanism", "MeshError", "MeshNotFoundError", "Part", "Pose",
    "Report",
    "RsxmlError", "RsxmlWarning", "SmartComponent", "check", "load", "load_library", "save", "to_rsxml",
    "Kinematics", "workspace", "collisions", "simulate_cables", "Cluster", "build_library", "to_usd", "to_newton",
    "to_urdf", "program", "place", "reach", "PlaceOptions", "TaskOptions", "HoseOptions", "DesignOptions",
    "BatchOptions", "VideoOptions",
]
