"""What every `zenros` verb shares: the session from flags, output formatting, exit codes."""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import os
import pkgutil
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any, TypeVar

import msgspec
import yaml

from ..codec import JSON, MSGPACK, decode_any, split_encoding, to_builtins
from ..context import Context
from ..errors import StartupError, UnknownTypeError, ZenrosError
from ..message import ActionType, Message, ServiceType, normalize_type_name
from ..node import Node
from ..registry import lookup_action, lookup_service, lookup_type
from ..session import (
    DEFAULT_LEASE_MS,
    DEFAULT_ROUTER,
    SessionOptions,
    add_session_arguments,
    options_from_args,
)

__all__ = [
    "STDOUT_CLOSED",
    "CliError",
    "ToolNode",
    "add_common",
    "check_graph_type",
    "find_action_type",
    "find_message_type",
    "find_service_type",
    "open_context",
    "parse_yaml_arg",
    "payload_to_data",
    "print_data",
    "stdout_closed",
]

T = TypeVar("T")

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


def open_context(args: argparse.Namespace, settle: bool = True, *,
                 required: bool | None = None, waiting_for: str = "") -> Context:
    """The tool's session; with ``settle``, its graph view has caught up with the network.

    When no router or peer answered, a verb that needs one now (``required``, default
    ``settle``: the snapshot verbs) fails with `StartupError` (exit code 3) saying so and how
    to start a router; a waiting verb says on stderr what it is waiting for and waits (the
    session keeps trying to connect).
    """
    opts = options_from_args(args)
    endpoints = ", ".join(opts.connect or [DEFAULT_ROUTER])
    hint = (f"nothing answered at {endpoints} (no Zenoh router or peer there): start one with "
            "`zenros router` or `zenros launch deploy/launch/sim.yaml`, or pass -e ENDPOINT")
    waits = not (settle if required is None else required)
    try:
        ctx = _open(opts, args.prefix, waits)
    except StartupError as exc:
        if "Unable to connect" in str(exc):
            raise StartupError(hint) from None
        raise
    if not opts.listen and not opts.multicast_scouting and not _reached_anyone(ctx):
        if settle if required is None else required:
            ctx.close()
            raise StartupError(hint)
        what = f"waiting for {waiting_for}: " if waiting_for else "waiting: "
        sys.stderr.write(f"{what}{hint}\n")
        sys.stderr.flush()
    if settle:
        ctx.graph.settle()
    return ctx


VERB_LEASE_MS = 10_000
"""The lease a verb's session announces. A router runs out the link of a process it heard
nothing from within that process's lease, and a starved router (a loaded box: ten fresh CLIs,
a fleet and two CPU hogs on 2 cores) ran out fresh CLIs' links within 2.5 s; Zenoh does not
always make a client's link again after that (issue 37.4). A verb lives for one command and a
killed one closes its link at once, so only a frozen verb stays in the graph longer."""


def _open(opts: SessionOptions, prefix: str | None, waits: bool) -> Context:
    """The verb's context: a client of the first endpoint that answers, unless told otherwise.

    A verb lives for one command, and a client's every query and subscription goes through
    the link it made to a configured endpoint (Zenoh connects it again if it drops; a router,
    or a peer, routes for its clients). As a peer it would reach each of the graph's
    processes over a direct link found by gossip: tens of links to make before its first
    query, on a loaded box some late, and one whose lease runs out is never made again
    (docs/zenoh-config.md, "Known limit"; issue 37.4: one of ten fresh CLIs' goals answered
    by no robot). ``--mode``, ``$ZENROS_MODE``, a config file, a listen endpoint or multicast
    scouting keep the session as asked. A verb that waits for the network to appear (a
    client cannot open with nothing to connect to) falls back to a peer, which keeps trying.
    Its session announces a `VERB_LEASE_MS` lease (the router runs its link out after that
    much silence from it, not after the services' 2.5 s).
    """
    if opts.mode or opts.config_file or opts.listen or opts.multicast_scouting:
        return Context(opts, prefix=prefix)
    if opts.lease_ms == DEFAULT_LEASE_MS:
        opts = replace(opts, lease_ms=VERB_LEASE_MS)
    try:
        return Context(replace(opts, mode="client"), prefix=prefix)
    except StartupError as exc:
        if not (waits and "Unable to connect" in str(exc)):
            raise
    return Context(opts, prefix=prefix)


def _reached_anyone(ctx: Context, wait: float = 0.3) -> bool:
    """Whether the session is connected to a router or a peer (a short grace for late links)."""
    info = ctx.session.info
    deadline = time.monotonic() + wait
    while True:
        if any(True for _ in info.routers_zid()) or any(True for _ in info.peers_zid()):
            return True
        if time.monotonic() >= deadline:
            return False
        time.sleep(0.02)


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


class Echo:
    """What an echo verb prints: each message as `print_data` does, from any thread, until
    ``limit`` of them (0: no limit)."""

    def __init__(self, limit: int, as_json: bool) -> None:
        self.limit, self.as_json = limit, as_json
        self.count = 0
        self.done = threading.Event()
        self._lock = threading.Lock()

    def print(self, data: Any) -> None:
        with self._lock:
            if self.done.is_set():
                return
            self.count += 1
            print_data(data, self.as_json)
            if self.limit and self.count >= self.limit:
                self.done.set()

    def wait(self, timeout: float) -> bool:
        """Until the limit, ``timeout`` s (0: for ever) or Ctrl-C; False if the time ran out
        first."""
        try:
            return self.done.wait(timeout or None)
        except KeyboardInterrupt:
            return True


# ---------------------------------------------------------------------- types


def _served_types_loaded() -> bool:
    """Import the wire types that installed services declare in their own ``messages``
    module (``zenros.services.master.messages``: GetSystemState, LookupNode, ...) and the
    library's own (smach's SetInitialState, ...), so every type a service serves can be
    called from the command line. False if already done."""
    global _SERVED_LOADED
    if _SERVED_LOADED:
        return False
    _SERVED_LOADED = True
    for name in _LIBRARY_TYPES:
        importlib.import_module(name)
    try:
        import zenros.services as services
    except ImportError:
        return True
    for info in pkgutil.iter_modules(services.__path__):
        name = f"{services.__name__}.{info.name}.messages"
        try:
            if info.ispkg and importlib.util.find_spec(name) is not None:
                importlib.import_module(name)
        except Exception:  # noqa: BLE001 -- a broken service package must not break the CLI
            continue
    return True


_SERVED_LOADED = False
_LIBRARY_TYPES = ("zenros.action.types", "zenros.param_protocol", "zenros.smach.introspection")
"""Library modules that declare wire types outside zenros.msgs (actions, parameters, smach)."""


def _find(lookup: Callable[[str], T], name: str) -> T:
    try:
        return lookup(name)
    except UnknownTypeError:
        if not _served_types_loaded():
            raise
        return lookup(name)


def find_message_type(name: str) -> type[Message]:
    """A message type by name (short names and suggestions as `lookup_type`)."""
    return _find(lookup_type, name)


def find_service_type(name: str) -> ServiceType:
    """A service type by name, the types declared by installed services included."""
    return _find(lookup_service, name)


def find_action_type(name: str) -> ActionType:
    """An action type by name, the types declared by installed services included."""
    return _find(lookup_action, name)


def check_graph_type(kind: str, name: str, wanted: str, known: list[str] | None) -> None:
    """Refuse to talk ``wanted`` on a ``kind`` whose endpoints in the graph use another type
    (the other side would only log a mismatch)."""
    if known and normalize_type_name(wanted) not in {normalize_type_name(k) for k in known}:
        raise CliError(f"{kind} {name} has type {' and '.join(known)}, not {wanted}")
