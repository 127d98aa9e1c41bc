"""What every `zenros` verb shares: the session from flags, output formatting, exit codes."""

from __future__ import annotations

import argparse
import json
import os
import sys
import threading
from typing import Any

import msgspec
import yaml

from ..codec import JSON, MSGPACK, decode_any, split_encoding, to_builtins
from ..context import Context
from ..errors import ZenrosError
from ..node import Node
from ..session import add_session_arguments, options_from_args

__all__ = [
    "STDOUT_CLOSED",
    "CliError",
    "ToolNode",
    "add_common",
    "open_context",
    "parse_yaml_arg",
    "payload_to_data",
    "print_data",
    "stdout_closed",
]

STDOUT_CLOSED = threading.Event()
"""Set once stdout's reader has gone (``zenros topic echo /chatter | head -4``)."""


def stdout_closed() -> None:
    """Note that stdout's reader went away: later writes (and the flush at exit) go to
    /dev/null, and streaming verbs stop quietly as they do on Ctrl-C."""
    if not STDOUT_CLOSED.is_set():
        devnull = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        finally:
            os.close(devnull)
        STDOUT_CLOSED.set()


class ToolNode(Node):
    """The short-lived node a verb joins the graph with; it declares no stored parameters,
    so it never asks master for any (nor warns when master is down)."""

    uses_parameter_server = False


class CliError(ZenrosError):
    """A CLI failure reported as one line, exit code 1."""


def add_common(parser: argparse.ArgumentParser) -> None:
    add_session_arguments(parser)


def open_context(args: argparse.Namespace, settle: bool = True) -> Context:
    """The tool's session; with ``settle``, its graph view has caught up with the network."""
    ctx = Context(options_from_args(args), prefix=args.prefix)
    if settle:
        ctx.graph.settle()
    return ctx


def parse_yaml_arg(text: str) -> Any:
    """A message body given on the command line in YAML flow style (``'{linear: {x: 0.5}}'``)."""
    try:
        value = yaml.safe_load(text) if text.strip() else {}
    except yaml.YAMLError as exc:
        raise CliError(f"invalid YAML {text!r}: {exc}") from exc
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise CliError(f"expected a mapping like '{{a: 1}}', got {text!r}")
    return value


def payload_to_data(data: bytes, encoding: str) -> Any:
    """Plain data from a payload: typed when the schema is known, generic otherwise."""
    mime, schema = split_encoding(encoding)
    if schema:
        try:
            return to_builtins(decode_any(data, encoding))
        except ZenrosError:
            pass
    if mime == MSGPACK:
        return msgspec.msgpack.decode(data)
    if mime == JSON or data[:1] in (b"{", b"["):
        try:
            return msgspec.json.decode(data)
        except msgspec.DecodeError:
            pass
    return data.decode("utf-8", "replace")


class _Dumper(yaml.SafeDumper):  # type: ignore[misc]
    pass


def _bytes_repr(d: yaml.SafeDumper, b: bytes) -> yaml.Node:
    return d.represent_scalar("tag:yaml.org,2002:str", f"<{len(b)} bytes>")


_Dumper.add_representer(bytes, _bytes_repr)


def print_data(data: Any, as_json: bool, *, separator: bool = True) -> None:
    """One message: YAML followed by ``---`` (as ros2 topic echo), or one JSON line."""
    if as_json:
        sys.stdout.write(json.dumps(data, default=str) + "\n")
    else:
        sys.stdout.write(yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=False))
        if separator:
            sys.stdout.write("---\n")
    sys.stdout.flush()
