"""rswarp: ABB RobotStudio RSXML robot descriptions for OpenUSD, Newton and batched Warp kernels."""

from .documents import Report, RsxmlWarning, check, load, load_library
from .errors import Diagnostic, MeshNotFoundError, RsxmlError
from .model import (
    Attribute, Cable, ControlPoint, DynamicProperty, Flange, Group, IOSignal, Joint, Limit, Mechanism, Part,
    Pose, SmartComponent,
)
from .write import save, to_rsxml


def __getattr__(name):
    """Kinematics and workspace import Warp; load them on first use so reading RSXML stays light."""
    if name == "Kinematics":
        from .kinematics import Kinematics

        return Kinematics
    if name == "workspace":
        from .sweeps import workspace

        return workspace
    raise AttributeError(f"module 'rswarp' has no attribute '{name}'")


__version__ = "0.1.0"

__all__ = [
    "Attribute", "Cable", "ControlPoint", "Diagnostic", "DynamicProperty", "Flange", "Group", "IOSignal", "Joint",
    "Limit", "Mechanism", "MeshNotFoundError", "Part", "Pose", "Report", "RsxmlError", "RsxmlWarning",
    "SmartComponent", "check", "load", "load_library", "save", "to_rsxml", "Kinematics", "workspace",
]
