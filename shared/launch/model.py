"""What a launch file describes: the processes to run, and how to supervise each of them."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import yaml

from ..names import join

__all__ = [
    "ARG_TYPES",
    "ArgDecl",
    "ArgType",
    "ComponentSpec",
    "LaunchDescription",
    "Output",
    "ProcessSpec",
    "params_yaml",
    "ros_arguments",
    "write_params_files",
]

Output = Literal["screen", "log"]


ArgType = Literal["str", "bool", "int", "float", "file"]
ARG_TYPES: tuple[ArgType, ...] = ("str", "bool", "int", "float", "file")


@dataclass(frozen=True)
class ArgDecl:
    """A declared launch argument; one without a default must be given (``name:=value``).

    Attributes:
        type: what the value must be (`zenros.launch.args.check_value`): ``str`` (anything),
            ``bool`` (true/false/yes/no/on/off/1/0, normalized to true or false), ``int``,
            ``float`` (finite), ``file`` (an existing file or device, relative to the
            launcher's directory, made absolute).
        choices: the only values allowed (none: any).
        min: lowest allowed number (int and float).
        above: the number must be greater than this.
        max: highest allowed number.
    """

    name: str
    default: str | None = None
    description: str = ""
    type: ArgType = "str"
    choices: tuple[str, ...] = ()
    min: float | None = None
    above: float | None = None
    max: float | None = None


@dataclass(frozen=True)
class ComponentSpec:
    """A node that runs inside a container process (`zenros.container`), as a ROS 2
    composable node: built on the container's Zenoh session, so the nodes of one process
    hand messages to each other without serializing them.

    Attributes:
        plugin: the node class, ``package.module:Class``.
        name: the node's base name.
        namespace: the node's absolute namespace.
        remaps: ``(from, to)`` name remappings.
        params: parameters in order of precedence (later wins): inline dicts, or paths of
            ROS 2 params files.
    """

    plugin: str
    name: str
    namespace: str = "/"
    remaps: tuple[tuple[str, str], ...] = ()
    params: tuple[Mapping[str, Any] | str, ...] = ()

    @property
    def fqn(self) -> str:
        """The node's fully qualified name, e.g. ``/robot1/nav``."""
        return join(self.namespace, self.name)

    def as_json(self) -> str:
        """The ``--component`` argument the container reads (`zenros.container`)."""
        return json.dumps({"plugin": self.plugin, "name": self.name,
                           "namespace": self.namespace, "remaps": [list(r) for r in self.remaps],
                           "params": [p if isinstance(p, str) else dict(p)
                                      for p in self.params]}, separators=(",", ":"))


@dataclass(frozen=True)
class ProcessSpec:
    """One process of a launch: its command line and its supervision policy.

    Attributes:
        name: the node's base name (also the process label).
        cmd: the program and its own arguments, before any ROS arguments.
        namespace: the node's absolute namespace.
        ros_args: append the node flags (`ros_arguments`) to the command line.
        remaps: ``(from, to)`` name remappings, passed as ``-r from:=to``.
        params: parameters in order of precedence (later wins): inline dicts, or paths of
            ROS 2 params files.
        arguments: extra arguments, after the ROS arguments.
        env: variables added to the launcher's environment.
        cwd: working directory (None: the launcher's).
        respawn: restart the process whenever it exits (unless the launch is stopping).
        respawn_delay: seconds to wait before a restart.
        required: the launch cannot run without it. Without ``respawn``, the launch stops
            when it exits; with ``respawn``, it is restarted after a crash and the launch
            stops only when it cannot be run: a startup failure (exit code 3) or a crash
            loop given up.
        output: ``screen`` prints its lines prefixed with ``[label]``; ``log`` only writes the
            log file (always written).
        origin: where it was declared (``file.yaml: nodes[0]``), for messages.
        components: the nodes a container process runs (`ComponentSpec`); it is ready when
            all of them are.
    """

    name: str
    cmd: tuple[str, ...]
    namespace: str = "/"
    ros_args: bool = False
    remaps: tuple[tuple[str, str], ...] = ()
    params: tuple[Mapping[str, Any] | str, ...] = ()
    arguments: tuple[str, ...] = ()
    env: Mapping[str, str] = field(default_factory=dict)
    cwd: str | None = None
    respawn: bool = False
    respawn_delay: float = 0.0
    required: bool = False
    output: Output = "screen"
    origin: str = ""
    components: tuple[ComponentSpec, ...] = ()

    @property
    def fqn(self) -> str:
        """The node's fully qualified name, e.g. ``/robot1/chassis``."""
        return join(self.namespace, self.name)

    @property
    def label(self) -> str:
        """The output prefix: the FQN without its leading slash (``robot1/chassis``)."""
        return self.fqn.lstrip("/")

    @property
    def log_name(self) -> str:
        """The log file's base name: ``robot1.chassis``."""
        return self.label.replace("/", ".")

    def argv(self, params_files: Sequence[str] = ()) -> list[str]:
        """The full command line.

        Args:
            params_files: one file per entry of ``params``, in the same order (see
                `write_params_files`); ignored without ``ros_args``.
        """
        ros = (
            ros_arguments(self.name, self.namespace, self.remaps, params_files)
            if self.ros_args
            else []
        )
        parts = [a for c in self.components for a in ("--component", c.as_json())]
        return [*self.cmd, *ros, *parts, *self.arguments]


def ros_arguments(
    name: str, namespace: str, remaps: Sequence[tuple[str, str]], params_files: Sequence[str]
) -> list[str]:
    """The node flags of ``zenros.run()``: ``--name --ns -r from:=to --params-file F``."""
    out = ["--name", name, "--ns", namespace]
    for src, dst in remaps:
        out += ["-r", f"{src}:={dst}"]
    for path in params_files:
        out += ["--params-file", path]
    return out


def params_yaml(fqn: str, params: Mapping[str, Any]) -> str:
    """Inline parameters as a ROS 2 params file for one node (``fqn: {ros__parameters}``)."""
    text: str = yaml.safe_dump(
        {fqn: {"ros__parameters": dict(params)}}, sort_keys=False, allow_unicode=True
    )
    return text


def write_params_files(spec: ProcessSpec, directory: Path) -> list[str]:
    """Write each inline params dict of ``spec`` to ``directory``; return all params paths."""
    paths: list[str] = []
    for i, item in enumerate(spec.params):
        if isinstance(item, str):
            paths.append(item)
            continue
        directory.mkdir(parents=True, exist_ok=True)
        path = directory / f"{spec.log_name}.{i}.yaml"
        path.write_text(params_yaml(spec.fqn, item), encoding="utf-8")
        paths.append(str(path))
    return paths


@dataclass
class LaunchDescription:
    """A loaded launch: every process (includes and groups flattened) and the arguments."""

    processes: list[ProcessSpec] = field(default_factory=list)
    args: dict[str, str] = field(default_factory=dict)
    declared: list[ArgDecl] = field(default_factory=list)
    files: list[str] = field(default_factory=list)

    def process(self, label: str) -> ProcessSpec:
        """The process with this label (``robot1/chassis``) or base name.

        Raises:
            KeyError: no such process (the message lists the labels).
        """
        for spec in self.processes:
            if label in (spec.label, spec.fqn):
                return spec
        matches = [s for s in self.processes if s.name == label]
        if len(matches) == 1:
            return matches[0]
        raise KeyError(f"no process {label!r}; processes: {', '.join(self.labels())}")

    def labels(self) -> list[str]:
        return [s.label for s in self.processes]
