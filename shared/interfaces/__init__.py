"""ROS interface packages (.msg, .srv, .action files) as zenros types: made at run time
(`load_interface_package`, or by name from the folders of ``ZENROS_INTERFACE_PATH``) or written
as a Python module (`generate_module`, ``zenros interface generate``). docs/interfaces.md."""

from .build import load_interface_package, loaded_packages, make_types
from .codegen import generate_module
from .package import InterfacePackage, find_packages, read_package
from .spec import InterfaceSpec, StructSpec, parse_interface

__all__ = ["InterfacePackage", "InterfaceSpec", "StructSpec", "find_packages",
           "generate_module", "load_interface_package", "loaded_packages", "make_types",
           "parse_interface", "read_package"]
