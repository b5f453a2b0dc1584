"""rswarp: ABB RobotStudio RSXML robot descriptions for OpenUSD, Newton and batched Warp kernels."""

from .documents import Report, RsxmlWarning, check, load, load_library
from .errors import Diagnostic, MeshNotFoundError, RsxmlError
from .model import (
    Attribute, Cable, ControlPoint, DynamicProperty, Flange, Group, IOSignal, Joint, Limit, Mechanism, Part,
    Pose, SmartComponent,
)
from .write import save, to_rsxml


def __getattr__(name):
    """Kinematics, sweeps and exports import Warp, USD or Newton: loaded on first use, so reading
    RSXML stays light."""
    if name == "Kinematics":
        from .kinematics import Kinematics

        return Kinematics
    if name == "workspace":
        from .sweeps import workspace

        return workspace
    if name == "to_usd":
        from .export_usd import to_usd

        return to_usd
    if name == "to_newton":
        from .newton_export import to_newton

        return to_newton
    if name == "to_urdf":
        from .export_urdf import to_urdf

        return to_urdf
    raise AttributeError(f"module 'rswarp' has no attribute '{name}'")


__version__ = "0.1.0"

__all__ = [
    "Attribute", "Cable", "ControlPoint", "Diagnostic", "DynamicProperty", "Flange", "Group", "IOSignal", "Joint",
    "Limit", "Mechanism", "MeshNotFoundError", "Part", "Pose", "Report", "RsxmlError", "RsxmlWarning",
    "SmartComponent", "check", "load", "load_library", "save", "to_rsxml", "Kinematics", "workspace",
    "to_usd", "to_newton", "to_urdf",
]
