"""The ``/rosapi/*`` services, answered inside the bridge from the graph and the parameters.

Pure: it talks to a `Graph`-like view and a `ParameterClient`-like object handed in, so it is
unit-tested without Zenoh. Parameter values cross the wire as JSON text, as ROS 2 rosapi
sends them; names may be ``/node:param`` (rosapi style) or plain ``/node/param``.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping
from typing import Any, Protocol

from zenros.errors import UnknownTypeError, ZenrosError
from zenros.msgs.builtin_interfaces import Time
from zenros.registry import lookup_action, lookup_service, lookup_type

from .convert import long_type
from .typedefs import typedefs

__all__ = ["ROSAPI", "Args", "Rosapi", "RosapiError", "Values", "param_name"]

Args = Mapping[str, object]
"""A rosapi request's arguments by name, as the client sent them (JSON values)."""
Values = dict[str, object]
"""A rosapi response's values by name (encoded as JSON)."""

PREFIX = "/rosapi/"


class RosapiError(ValueError):
    """A rosapi request that cannot be answered (unknown service, bad arguments)."""


class GraphView(Protocol):
    def topics(self) -> dict[str, list[str]]: ...
    def services(self) -> dict[str, list[str]]: ...
    def actions(self) -> dict[str, list[str]]: ...
    def node_names(self) -> list[str]: ...
    def endpoints_of(self, node: str) -> dict[str, list[Any]]: ...
    def publishers(self, topic: str) -> list[Any]: ...
    def subscribers(self, topic: str) -> list[Any]: ...
    def servers(self, service: str) -> list[Any]: ...


class ParamStore(Protocol):
    def lookup(self, name: str) -> tuple[bool, Any]: ...
    def set(self, name: str, value: Any) -> Any: ...
    def delete(self, name: str) -> Any: ...
    def has(self, name: str) -> bool: ...
    def list(self, prefix: str = "/") -> list[str]: ...


def param_name(name: str) -> str:
    """``/talker:use_sim_time`` → ``/talker/use_sim_time``; ``a.b`` after the colon nests."""
    name = name.strip()
    if not name:
        raise RosapiError("parameter name is empty")
    node, sep, param = name.partition(":")
    if sep:
        node = "/" + node.strip("/")
        return (node.rstrip("/") + "/" + param.replace(".", "/").strip("/")).replace("//", "/")
    return name if name.startswith("/") else "/" + name


def _str(args: Args, key: str, default: str | None = None) -> str:
    value = args.get(key, default)
    if not isinstance(value, str):
        if value is None:
            raise RosapiError(f"missing argument {key!r}")
        raise RosapiError(f"argument {key!r} must be a string, got {type(value).__name__}")
    return value


def _slash(name: str) -> str:
    return name if name.startswith("/") else "/" + name


class Rosapi:
    """Answers rosapi requests: ``call(service, args) -> values``."""

    def __init__(self, graph: GraphView, params: ParamStore, now: Callable[[], Time],
                 distro: str = "zenros",
                 local: Callable[[], tuple[dict[str, str], dict[str, str]]] | None = None
                 ) -> None:
        self._graph = graph
        self._local = local or (lambda: ({}, {}))
        self._params = params
        self._now = now
        self._distro = distro
        self._handlers: dict[str, Callable[[Args], Values]] = {
            name: getattr(self, "_" + name) for name in ROSAPI
        }

    @staticmethod
    def handles(service: str) -> bool:
        return service.startswith(PREFIX)

    def call(self, service: str, args: Args) -> Values:
        """The response values of rosapi ``service`` (``/rosapi/topics``).

        Raises:
            RosapiError: unknown service or bad arguments.
            ZenrosError: the parameter server failed (no master, timeout).
        """
        short = service[len(PREFIX):]
        handler = self._handlers.get(short)
        if handler is None:
            raise RosapiError(f"Service {service} does not exist; rosapi offers: "
                              + ", ".join(PREFIX + n for n in ROSAPI))
        return handler(args)

    # ------------------------------------------------------------------ graph

    def _all_topics(self) -> dict[str, str]:
        """The graph's topics and those only rosbridge clients see, with one type each."""
        out = {n: long_type(ts[0]) if ts else "" for n, ts in self._graph.topics().items()}
        for name, type_name in self._local()[0].items():
            out.setdefault(name, type_name)
        return out

    def _topics(self, args: Args) -> Values:
        topics = self._all_topics()
        return {"topics": list(topics), "types": list(topics.values())}

    def _topic_type(self, args: Args) -> Values:
        return {"type": self._all_topics().get(_slash(_str(args, "topic")), "")}

    def _topics_for_type(self, args: Args) -> Values:
        want = long_type(_str(args, "type"))
        return {"topics": [n for n, t in self._all_topics().items() if t == want]}

    def _all_services(self) -> dict[str, str]:
        out = {n: long_type(ts[0], "srv") for n, ts in self._graph.services().items() if ts}
        for name, type_name in self._local()[1].items():
            out.setdefault(name, type_name)
        out.update({PREFIX + n: f"rosapi/srv/{_camel(n)}" for n in ROSAPI})
        return dict(sorted(out.items()))

    def _services(self, args: Args) -> Values:
        return {"services": list(self._all_services())}

    def _service_type(self, args: Args) -> Values:
        return {"type": self._all_services().get(_slash(_str(args, "service")), "")}

    def _services_for_type(self, args: Args) -> Values:
        want = long_type(_str(args, "type"), "srv")
        return {"services": [n for n, t in self._all_services().items() if t == want]}

    def _providers(self, args: Args) -> list[str]:
        name = _slash(_str(args, "service"))
        return sorted({t.node for t in self._graph.servers(name)})

    def _service_providers(self, args: Args) -> Values:
        return {"providers": self._providers(args)}

    def _service_node(self, args: Args) -> Values:
        providers = self._providers(args)
        return {"node": providers[0] if providers else ""}

    def _nodes(self, args: Args) -> Values:
        return {"nodes": self._graph.node_names()}

    def _node_details(self, args: Args) -> Values:
        ends = self._graph.endpoints_of(_slash(_str(args, "node")))
        return {"subscribing": sorted({t.name for t in ends.get("sub", [])}),
                "publishing": sorted({t.name for t in ends.get("pub", [])}),
                "services": sorted({t.name for t in ends.get("srv", [])})}

    def _publishers(self, args: Args) -> Values:
        topic = _slash(_str(args, "topic"))
        return {"publishers": sorted({t.node for t in self._graph.publishers(topic)})}

    def _subscribers(self, args: Args) -> Values:
        topic = _slash(_str(args, "topic"))
        return {"subscribers": sorted({t.node for t in self._graph.subscribers(topic)})}

    def _action_servers(self, args: Args) -> Values:
        return {"action_servers": list(self._graph.actions())}

    def _action_type(self, args: Args) -> Values:
        types = self._graph.actions().get(_slash(_str(args, "action")))
        return {"type": long_type(types[0], "action") if types else ""}

    # ------------------------------------------------------------------ parameters

    def _get_param(self, args: Args) -> Values:
        name = param_name(_str(args, "name"))
        default = args.get("default_value", "")
        found, value = self._params.lookup(name)
        if found:
            return {"value": json.dumps(value), "successful": True, "reason": ""}
        if isinstance(default, str) and default:
            return {"value": default, "successful": True, "reason": ""}
        # as rosapi: the value is JSON text even then ("null"; roslibpy's Param.get() -> None)
        return {"value": "null", "successful": False, "reason": f"parameter {name} is not set"}

    def _set_param(self, args: Args) -> Values:
        name = param_name(_str(args, "name"))
        text = _str(args, "value")
        try:
            value = json.loads(text)
        except ValueError as exc:
            return {"successful": False, "reason": f"value of {name} is not JSON text: {exc}"}
        except RecursionError:
            return {"successful": False, "reason": f"value of {name} is nested too deep"}
        try:
            self._params.set(name, value)
        except ZenrosError as exc:
            return {"successful": False, "reason": str(exc)}
        return {"successful": True, "reason": ""}

    def _has_param(self, args: Args) -> Values:
        return {"exists": self._params.has(param_name(_str(args, "name")))}

    def _delete_param(self, args: Args) -> Values:
        name = param_name(_str(args, "name"))
        try:
            self._params.delete(name)
        except ZenrosError as exc:
            return {"successful": False, "reason": str(exc)}
        return {"successful": True, "reason": ""}

    def _get_param_names(self, args: Args) -> Values:
        return {"names": self._params.list("/")}

    # ------------------------------------------------------------------ type details

    def _message_details(self, args: Args) -> Values:
        return {"typedefs": typedefs(_lookup(lookup_type, _str(args, "type")))}

    def _service_request_details(self, args: Args) -> Values:
        return {"typedefs": typedefs(_lookup(lookup_service, _str(args, "type")).Request)}

    def _service_response_details(self, args: Args) -> Values:
        return {"typedefs": typedefs(_lookup(lookup_service, _str(args, "type")).Response)}

    def _action_goal_details(self, args: Args) -> Values:
        return {"typedefs": typedefs(_lookup(lookup_action, _str(args, "type")).Goal)}

    def _action_result_details(self, args: Args) -> Values:
        return {"typedefs": typedefs(_lookup(lookup_action, _str(args, "type")).Result)}

    def _action_feedback_details(self, args: Args) -> Values:
        return {"typedefs": typedefs(_lookup(lookup_action, _str(args, "type")).Feedback)}

    # ------------------------------------------------------------------ time, version

    def _get_time(self, args: Args) -> Values:
        t = self._now()
        return {"time": {"sec": t.sec, "nanosec": t.nanosec, "secs": t.sec, "nsecs": t.nanosec}}

    def _get_ros_version(self, args: Args) -> Values:
        return {"version": 2, "distro": self._distro}


def _lookup(find: Callable[[str], Any], name: str) -> Any:
    try:
        return find(name)
    except UnknownTypeError as exc:
        raise RosapiError(str(exc)) from None


def _camel(name: str) -> str:
    return "".join(p.capitalize() for p in name.split("_"))


ROSAPI = (
    "topics", "topic_type", "topics_for_type", "services", "service_type", "services_for_type",
    "service_providers", "service_node", "nodes", "node_details", "publishers", "subscribers",
    "action_servers", "action_type", "get_param", "set_param", "has_param", "delete_param",
    "get_param_names", "get_time", "get_ros_version", "message_details",
    "service_request_details", "service_response_details", "action_goal_details",
    "action_result_details", "action_feedback_details",
)
"""Every rosapi service the bridge answers (under ``/rosapi/``)."""
