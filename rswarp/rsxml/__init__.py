"""The RSXML file format (lxml and NumPy only): units, the model, reading, validation, the link
graph, LibraryCompiler/LibraryResource files, and writing RSXML back."""

from .documents import Report, RsxmlWarning, check, load, load_library, load_mechanism
from .graph import LinkGraph
from .model import Mechanism, SmartComponent

__all__ = ["LinkGraph", "Mechanism", "Report", "RsxmlWarning", "SmartComponent", "check", "load", "load_library",
           "load_mechanism"]
