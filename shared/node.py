"""`Node`: a named participant that creates publishers, subscriptions, services, clients,
timers and parameters on a shared `Context`."""

from __future__ import annotations

import logging
import os
import re
import socket
import threading
import time
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Self, TypeVar

import msgspec

from .clock import Clock, ManualClock, Rate, SystemClock, Time
from .context import Context
from .errors import NodeClosedError
from .executor import CallbackGroup
from .gate import DeliveryGate
from .graph import Graph
from .log import RosoutHandler, node_logger
from .message import ActionType, F, G, Message, Q, R, S, ServiceType
from .msgs.rcl_interfaces import Log, ParameterDescriptor, ParameterEvent
from .msgs.rosgraph_msgs import Clock as ClockMsg
from .names import Remapper, join, resolve, validate_namespace, validate_node_name
from .owner import Closable
from .param_backend import attach_parameter_backend
from .param_config import declare_parameters
from .param_describe import ParameterDescriptions
from .param_descriptors import descriptor_spec
from .param_events import PARAMETER_EVENTS, QOS_PARAMETER_EVENTS, parameter_event
from .param_services import serve_parameter_services
from .params import Parameter, Parameters, SetParametersResult, load_params_file
from .polled import PolledSubscription
from .pubsub import Publisher, Subscription, SubscriptionCallback
from .qos import QOS_SENSOR, QoSProfile, as_profile
from .qos_events import PublisherEventCallbacks, SubscriptionEventCallbacks
from .rpc import Client, Service
from .timer import Timer
from .type_descriptions import serve_type_descriptions

if TYPE_CHECKING:
    import zenoh

    from .action import ActionClient, ActionServer, ServerGoalHandle

__all__ = ["Closable", "Node"]


class _Callback:
    """``fn()`` as an owned resource (`Node.on_close`)."""

    __slots__ = ("_fn",)

    def __init__(self, fn: Callable[[], object]) -> None:
        self._fn = fn

    def close(self) -> None:
        self._fn()

    def __repr__(self) -> str:
        return f"<on_close {self._fn!r}>"


M = TypeVar("M", bound=Message)
W = TypeVar("W", bound=Closable)
C = TypeVar("C", bound=msgspec.Struct)


def _snake(name: str) -> str:
    name = name.removesuffix("Node") or name
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


class Node:
    """A ROS-style node. Subclasses override `setup()`, which runs at the end of __init__.

    Whatever ``setup()`` opens (endpoints, and through `own` and `on_close` the threads,
    sockets, servers, stores a service starts) belongs to the node: `close` releases it in
    the reverse order of opening, also when ``setup()`` raised half-way, so a subclass never
    needs a ``close()`` of its own, nor a guard for what ``setup()`` did not reach.

    No callback of an endpoint created during ``setup()`` (subscriptions, services, timers,
    action servers, also those helper objects create) runs before ``setup()`` has returned:
    what arrives meanwhile is held (a subscription keeps its QoS depth) and delivered after,
    so a callback never meets an attribute that setup() has not set yet.

    Args:
        name: the node's base name (default: ``node_name`` class attribute, or the class name
            in snake_case).
        namespace: the node's namespace (default ``/``).
        context: the `Context` (session) to run on; a new one is opened (and owned) if None.
        remappings: ``from:=to`` rules (and ``__ns:=``, ``__node:=``) or a `Remapper`.
        parameter_overrides: values that replace declared defaults (``-p name:=value``).
        params_files: ROS 2 params files whose sections for this node apply.
    """

    node_name: str | None = None
    uses_parameter_server: bool = True  # False for the master itself
    parameter_events: bool = True  # publish /parameter_events (zenros.param_events)
    parameter_services: bool = True  # ~/list_parameters... (zenros.param_services)
    type_description_service: bool = True  # ~/get_type_description (zenros.type_descriptions)

    def __init__(
        self,
        name: str | None = None,
        *,
        namespace: str | None = None,
        context: Context | None = None,
        remappings: list[str] | Remapper | None = None,
        parameter_overrides: dict[str, Any] | None = None,
        params_files: list[str] | None = None,
    ) -> None:
        remap = remappings if isinstance(remappings, Remapper) else Remapper.parse(remappings or [])
        self._remap = remap
        base = remap.node_name or (name if name is not None else
                                          self.node_name or _snake(type(self).__name__))
        self.name = validate_node_name(base)
        self.namespace = validate_namespace(remap.namespace or namespace or "/")
        self.fqn = join(self.namespace, self.name)
        self._own_context = context is None
        self.context = context or Context()
        self._endpoints: list[Any] = []
        self._timers: list[Timer] = []
        self._closed = False
        self._lock = threading.Lock()
        self.logger = node_logger(self.fqn)
        overrides: dict[str, Any] = {}
        for f in params_files or []:
            overrides.update(load_params_file(Path(f), self.fqn))
        overrides.update(parameter_overrides or {})
        self.parameters = Parameters(self.fqn, overrides)
        self._setup_gate: DeliveryGate | None = None  # closed while setup() runs
        self._token: zenoh.LivelinessToken | None = None  # declared once set up
        try:
            # a deterministic run's parameters are its overrides alone: no master's answer
            if self.uses_parameter_server and not self.context.deterministic:
                attach_parameter_backend(self)
            self._start()
            gate = self._setup_gate = DeliveryGate()
            self.setup()
            self._setup_gate = None
            gate.open()
            self._announce()
        except BaseException:
            self.close()
            raise

    def _start(self) -> None:
        ctx = self.context
        self.start_ns = time.time_ns()
        self.add_waitable(ParameterDescriptions(ctx, self.fqn, self.parameters))
        self._clock: Clock = SystemClock()
        if self.parameter_services:
            serve_parameter_services(self.parameters, self.create_service)
        if self.type_description_service:
            serve_type_descriptions(self.fqn, ctx.graph, self.create_service)
        if self.parameter_events:
            events = self.create_publisher(ParameterEvent, PARAMETER_EVENTS, QOS_PARAMETER_EVENTS)
            self.parameters.on_event(lambda kind, p: events.publish(
                parameter_event(kind, p, self.fqn, self.now())))
        if ctx.sim_clock is not None:  # a deterministic run's clock (zenros.replay)
            self._clock = ctx.sim_clock
            self.parameters.declare("use_sim_time", True)
        elif self.parameters.declare("use_sim_time", False):
            self._clock = ManualClock()
            sim = self._clock
            self.create_subscription(ClockMsg, "/clock", lambda m: sim.set(m.clock), QOS_SENSOR)
        self._rosout = self.create_publisher(Log, "/rosout", 100)
        handler = RosoutHandler(self.fqn, self._rosout.publish, self._clock.now)
        self.logger.addHandler(handler)
        self.on_close(lambda: self.logger.removeHandler(handler))

    def _announce(self) -> None:
        """Declare the node's liveliness token once `setup` has completed: a node is in the
        graph (and ``zenros launch`` reports it ready) only when it is set up, so one that
        refuses its configuration never shows as up."""
        ctx = self.context
        self._token = ctx.session.liveliness().declare_token(
            ctx.keys.node_token(self.fqn, ctx.zid, socket.gethostname(), os.getpid(),
                                self.start_ns)
        )

    def setup(self) -> None:
        """Declare parameters and create endpoints. Override in subclasses."""

    # ------------------------------------------------------------------ names

    def resolve_name(self, name: str, kind: str = "topic") -> str:
        """Resolve a topic/service name against this node, then apply remappings."""
        fqn = resolve(name, self.namespace, self.fqn, kind)
        return self._remap.apply(fqn, self.namespace, self.fqn, kind)

    # ------------------------------------------------------------------ endpoints

    def own(self, resource: W) -> W:
        """Make this node own ``resource`` (anything with ``close()``: a store, a server, a
        bridge): `close` closes it before whatever the node owned earlier and after whatever
        it came to own later, endpoints included (`contextlib.ExitStack` order). Returns
        ``resource``, so ``self.store = self.own(Store(path))``.

        Raises:
            NodeClosedError: the node is closed (``resource`` is closed right away).
        """
        return self.add_waitable(resource)

    def on_close(self, fn: Callable[[], object]) -> None:
        """Call ``fn()`` when the node closes, in the same reverse order as `own` (a thread
        to stop and join, a listener to remove, a last command to send).

        Raises:
            NodeClosedError: the node is closed (``fn`` is called right away).
        """
        self.add_waitable(_Callback(fn))

    def add_waitable(self, endpoint: W) -> W:
        """Make this node own ``endpoint`` (rclpy's name for `own`): closing the node closes
        it, before the endpoints created before it.

        Action servers and clients, parameter backends, state machine servers and other
        endpoints built from a node's parts register here. Returns ``endpoint``.

        Raises:
            NodeClosedError: the node is closed (``endpoint`` is closed right away).
        """
        with self._lock:
            if self._closed:
                endpoint.close()
                raise NodeClosedError(f"node {self.fqn} is closed")
            self._endpoints.append(endpoint)
        return endpoint

    def remove_waitable(self, endpoint: Any) -> None:
        """Stop owning ``endpoint`` without closing it (rclpy's ``remove_waitable``)."""
        with self._lock:
            if endpoint in self._endpoints:
                self._endpoints.remove(endpoint)

    def create_publisher(self, msg_type: type[M], topic: str,
                         qos: QoSProfile | int = 10, *,
                         event_callbacks: PublisherEventCallbacks | None = None
                         ) -> Publisher[M]:
        """A publisher of ``msg_type`` on ``topic`` (resolved and remapped);
        ``event_callbacks``: its QoS events (`zenros.qos_events`)."""
        pub = Publisher(self.context, self.fqn, msg_type, self.resolve_name(topic),
                        as_profile(qos), event_callbacks, self.logger)
        self._warn_type_conflict(pub.topic, pub.type_name)
        p: Publisher[M] = self.add_waitable(pub)
        return p

    def create_subscription(
        self,
        msg_type: type[M],
        topic: str,
        callback: SubscriptionCallback[M],
        qos: QoSProfile | int = 10,
        *,
        callback_group: CallbackGroup | None = None,
        event_callbacks: SubscriptionEventCallbacks | None = None,
    ) -> Subscription[M]:
        """Call ``callback(msg)`` for each message; sync callbacks run on Zenoh's thread.
        ``event_callbacks``: its QoS events (`zenros.qos_events`)."""
        sub = Subscription(self.context, self.fqn, msg_type, self.resolve_name(topic), callback,
                           as_profile(qos), self.logger, callback_group, self._setup_gate,
                           event_callbacks)
        self._warn_type_conflict(sub.topic, sub._codec.type_name)
        s: Subscription[M] = self.add_waitable(sub)
        return s

    def create_polled_subscription(self, msg_type: type[M], topic: str,
                                   qos: QoSProfile | int = 10) -> PolledSubscription[M]:
        """A subscription read with `PolledSubscription.take` (no callback, no thread): the
        last ``qos.depth`` samples wait in Zenoh until taken, only the newest is decoded."""
        sub = PolledSubscription(self.context, self.fqn, msg_type, self.resolve_name(topic),
                                 as_profile(qos), self.logger)
        self._warn_type_conflict(sub.topic, sub._codec.type_name)
        s: PolledSubscription[M] = self.add_waitable(sub)
        return s

    def create_service(self, srv_type: ServiceType, name: str, handler: Callable[..., Any], *,
                       callback_group: CallbackGroup | None = None) -> Service:
        srv = Service(self.context, self.fqn, srv_type, self.resolve_name(name, "service"),
                      handler, self.logger, callback_group, self._setup_gate)
        s: Service = self.add_waitable(srv)
        return s

    def create_client(self, srv_type: ServiceType[Q, S], name: str) -> Client[Q, S]:
        c: Client[Q, S] = self.add_waitable(
            Client(self.context, srv_type, self.resolve_name(name, "service"), node=self.fqn)
        )
        return c

    def create_action_server(
        self, action_type: ActionType[G, R, F], name: str,
        execute_callback: Callable[[ServerGoalHandle[G, F]], R | None | Awaitable[R | None]],
        **kwargs: Any,
    ) -> ActionServer[G, R, F]:
        """An `ActionServer` (zenros.action) owned by this node; see docs/actions.md. Typed by
        ``action_type``: its goal handles hold its Goal and take its Feedback."""
        from .action import ActionServer

        return ActionServer(self, action_type, name, execute_callback, **kwargs)

    def create_action_client(self, action_type: ActionType[G, R, F], name: str,
                             **kwargs: Any) -> ActionClient[G, R, F]:
        """An `ActionClient` (zenros.action) owned by this node, typed by ``action_type``."""
        from .action import ActionClient

        return ActionClient(self, action_type, name, **kwargs)

    def create_timer(self, period: float, callback: Callable[[], Any], *,
                     callback_group: CallbackGroup | None = None,
                     clock: Clock | None = None, autostart: bool = True) -> Timer:
        """Call ``callback()`` every ``period`` seconds of this node's clock, or of ``clock``
        (rclpy's ``clock=``): ``SteadyClock()`` ticks in wall time whatever ``use_sim_time``
        says, for what outside clients see (rates of status streams, serial frames). In a
        deterministic run (`zenros.replay`) every timer follows the run's clock. With
        ``autostart`` false (rclpy's) the timer waits, canceled, for its ``reset()``."""
        if self.context.sim_clock is not None:
            clock = self.context.sim_clock
        timer = Timer(period, callback, clock or self._clock, self.context.executor,
                      self.logger, callback_group, autostart=autostart,
                      gate=self._setup_gate)
        with self._lock:
            self._timers.append(timer)
        return timer

    def create_rate(self, hz: float, clock: Clock | None = None) -> Rate:
        return Rate(hz, clock or self._clock)

    def destroy(self, endpoint: Any) -> None:
        """Close one endpoint created by this node."""
        with self._lock:
            if endpoint in self._endpoints:
                self._endpoints.remove(endpoint)
        endpoint.close()

    def _warn_type_conflict(self, topic: str, type_name: str) -> None:
        graph = self.context._graph  # only if someone already built it: no cost otherwise
        if graph is None:
            return
        others = {t.type for t in graph.publishers(topic) + graph.subscribers(topic)}
        others.discard(type_name)
        if others:
            self.logger.warning("type conflict on %s: this node uses %s, others use %s",
                                topic, type_name, ", ".join(sorted(others)))

    # ------------------------------------------------------------------ parameters

    def declare_parameter(self, name: str, default: Any = None,
                          descriptor: ParameterDescriptor | None = None, *,
                          description: str = "", read_only: bool = False,
                          dynamic_typing: bool = False) -> Any:
        """Declare a parameter and return its current value. The default fixes its type
        unless ``dynamic_typing``. ``descriptor`` (rclpy's ``ParameterDescriptor``) may give
        the description, read-only, dynamic typing and a range with its step, which sets
        are then checked against (`zenros.param_limits`); the keywords add to it."""
        spec = descriptor_spec(descriptor) if descriptor is not None else None
        return self.parameters.declare(
            name, default, description=description or (spec.description if spec else ""),
            read_only=read_only or bool(spec and spec.read_only),
            constraints=spec.constraints if spec else None,
            dynamic_typing=dynamic_typing or bool(spec and spec.dynamic_typing))

    def undeclare_parameter(self, name: str) -> None:
        """Forget a declared parameter (rclpy's; no parameter event). Raises
        `ParameterImmutableError` for a read-only one, `ParameterNotDeclaredError` for a name
        not declared."""
        self.parameters.undeclare(name)

    def declare_parameters(self, config: type[C], *, read_only: bool = False) -> C:
        """Declare one parameter per field of the msgspec Struct ``config`` (its defaults,
        limits and descriptions) and return the current values as a ``config``; unless the
        Struct is frozen, the instance follows later changes (`zenros.param_config`)."""
        return declare_parameters(self.parameters, config, read_only=read_only)

    def get_parameter(self, name: str) -> Any:
        return self.parameters.get(name)

    def set_parameter(self, name: str, value: Any) -> None:
        self.parameters.set(name, value)

    def has_parameter(self, name: str) -> bool:
        return self.parameters.has(name)

    def add_on_set_parameters_callback(
        self, fn: Callable[[list[Parameter]], SetParametersResult]
    ) -> None:
        self.parameters.add_validator(fn)

    def on_parameter_change(self, fn: Callable[[Parameter], None], name: str | None = None) -> None:
        def guarded(p: Parameter) -> None:
            try:
                fn(p)
            except Exception:
                self.logger.exception("parameter callback for %s raised", p.name)

        self.parameters.on_change(guarded, name)

    # ------------------------------------------------------------------ time, logs, graph

    def get_clock(self) -> Clock:
        return self._clock

    def now(self) -> Time:
        return self._clock.now()

    def get_logger(self) -> logging.Logger:
        return self.logger

    @property
    def graph(self) -> Graph:
        return self.context.graph

    def get_node_names(self) -> list[str]:
        return self.graph.node_names()

    def get_topic_names_and_types(self) -> list[tuple[str, list[str]]]:
        return list(self.graph.topics().items())

    def get_service_names_and_types(self) -> list[tuple[str, list[str]]]:
        return list(self.graph.services().items())

    # ------------------------------------------------------------------ spinning, lifecycle

    def spin(self, timeout: float | None = None) -> None:
        """Block until the node is closed (or ``timeout``). Callbacks do not need spin to
        run; it exists for rclpy habits and for `run()`."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while not self._closed:
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                return
            self.context.executor.wait_for_work(min(left, 0.5) if left is not None else 0.5)

    def spin_once(self, timeout: float | None = None) -> bool:
        """Wait until the executor has run one timer or async callback; False on timeout."""
        return self.context.executor.wait_for_work(timeout)

    @property
    def closed(self) -> bool:
        return self._closed

    def close(self) -> None:
        """Stop timers; close what the node owns (endpoints, `own`, `on_close`) in reverse
        order, each whatever the others do; undeclare its token; close the context if owned.
        Safe on a node whose ``setup()`` raised half-way, and idempotent."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            gate, self._setup_gate = self._setup_gate, None
            endpoints, self._endpoints = self._endpoints, []
            timers, self._timers = self._timers, []
        if gate is not None:  # closed from (or after a failure in) setup(): drop what is held
            gate.abandon()
        for t in timers:
            t.cancel()
        for ep in reversed(endpoints):
            try:
                ep.close()
            except Exception:  # closing must go on whatever one endpoint does
                self.logger.debug("closing %r failed", ep, exc_info=True)
        token, self._token = self._token, None
        if token is not None:
            token.undeclare()  # type: ignore[no-untyped-call]  # zenoh stub: unannotated
        if self._own_context:
            self.context.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
