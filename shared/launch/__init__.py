"""``zenros launch``: launch files, their loader, and the process supervisor."""

from .cli import LaunchHooks, LaunchOptions, main
from .loader import declared_args, load_launch
from .model import ArgDecl, LaunchDescription, ProcessSpec
from .supervisor import Event, ProcessState, Supervisor, SupervisorConfig

__all__ = [
    "ArgDecl",
    "Event",
    "LaunchDescription",
    "LaunchHooks",
    "LaunchOptions",
    "ProcessSpec",
    "ProcessState",
    "Supervisor",
    "SupervisorConfig",
    "declared_args",
    "load_launch",
    "main",
]
