"""`LifecycleNode`: a `Node` with ROS 2's managed-node state machine, its services and events.

rclpy's API: ``on_configure``/``on_cleanup``/``on_activate``/``on_deactivate``/
``on_shutdown``/``on_error`` take the starting `LifecycleState` and return a
`TransitionCallbackReturn`; ``trigger_configure()``... run a transition from code; managed
entities (`ManagedEntity`, lifecycle publishers) follow the node's transitions through the
default callbacks, so an override calls ``super().on_activate(state)`` to activate them.
"""

from __future__ import annotations

import logging
import threading
import time
import uuid
from typing import Any, ClassVar, TypeVar

from ..clock import SteadyClock
from ..context import Context
from ..message import Message
from ..msgs.bond import Status
from ..msgs.lifecycle_msgs import (
    ChangeState,
    ChangeStateRequest,
    ChangeStateResponse,
    GetAvailableStates,
    GetAvailableStatesResponse,
    GetAvailableTransitions,
    GetAvailableTransitionsResponse,
    GetState,
    GetStateResponse,
    State,
    Transition,
    TransitionDescription,
    TransitionEvent,
)
from ..node import Node
from ..pubsub import Publisher
from ..qos import QoSProfile, as_profile
from ..timer import Timer
from .machine import (
    ACTIVE,
    ACTIVATING,
    CLEANINGUP,
    CONFIGURING,
    DEACTIVATING,
    ERRORPROCESSING,
    SHUTTINGDOWN,
    TRANSITIONS,
    InvalidTransitionError,
    LifecycleState,
    StateMachine,
    TransitionCallbackReturn,
    TransitionDef,
)

__all__ = ["LifecycleNode", "LifecyclePublisher", "ManagedEntity", "SimpleManagedEntity"]

M = TypeVar("M", bound=Message)
_OK = TransitionCallbackReturn.SUCCESS


class ManagedEntity:
    """Something that follows its node's transitions (rclpy's ``ManagedEntity``): each
    callback returns SUCCESS unless overridden."""

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        return _OK

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        return _OK

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        return _OK

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return _OK

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return _OK

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        return _OK


class SimpleManagedEntity(ManagedEntity):
    """A managed entity that is enabled while its node is active."""

    def __init__(self) -> None:
        self._enabled = False

    @property
    def is_activated(self) -> bool:
        return self._enabled

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._enabled = True
        return _OK

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._enabled = False
        return _OK


class LifecyclePublisher(SimpleManagedEntity, Publisher[M]):
    """A publisher that sends only while its node is active; what is published while it is
    inactive is dropped, with one warning per inactive spell (rclcpp's behaviour)."""

    def __init__(self, logger: logging.Logger, ctx: Context, node: str, msg_type: type[M],
                 topic: str, qos: QoSProfile) -> None:
        SimpleManagedEntity.__init__(self)
        Publisher.__init__(self, ctx, node, msg_type, topic, qos)
        self._logger = logger
        self._warned = False

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._warned = False
        return super().on_activate(state)

    def publish(self, msg: M) -> None:
        if not self._enabled:
            if not self._warned:
                self._warned = True
                self._logger.warning(
                    "publisher on %s is not activated: message dropped (and the next ones, "
                    "until the node is active)", self.topic)
            return
        Publisher.publish(self, msg)


def _state_msg(s: int) -> State:
    st = LifecycleState.of(s)
    return State(id=st.state_id, label=st.label)


def _description(t: TransitionDef) -> TransitionDescription:
    return TransitionDescription(transition=Transition(id=t.id, label=t.label),
                                 start_state=_state_msg(t.start), goal_state=_state_msg(t.goal))


_CALLBACK_NAMES = {CONFIGURING: "on_configure", CLEANINGUP: "on_cleanup",
                   SHUTTINGDOWN: "on_shutdown", ACTIVATING: "on_activate",
                   DEACTIVATING: "on_deactivate", ERRORPROCESSING: "on_error"}


class LifecycleNode(Node):
    """A managed node: it starts unconfigured and moves through ROS 2's state machine on
    requests to ``~/change_state`` or calls of ``trigger_*``; ``~/transition_event`` reports
    each step. While active (and ``bond_heartbeat_period`` > 0) it sends a heartbeat on
    ``bond`` (bond/Status, id = its name) for a lifecycle manager.

    A subclass that sets ``autostart_default = True`` (the robot's services: slam) also
    works without a manager: its ``autostart`` parameter (that default unless given)
    configures and activates it once set up; a launch that manages it passes
    ``autostart: false`` and lets a lifecycle manager bring it up (zenros's, not rclpy's).

    Args:
        enable_communication_interface: offer the ``~/change_state``... services and the
            ``~/transition_event`` topic (rclpy's flag).
        **kwargs: as `Node`.
    """

    autostart_default: ClassVar[bool] = False

    def __init__(self, name: str | None = None, *, enable_communication_interface: bool = True,
                 **kwargs: Any) -> None:
        self._machine = StateMachine()
        self._managed: list[ManagedEntity] = []
        self._interface = enable_communication_interface
        self._events: Publisher[TransitionEvent] | None = None
        self._heartbeat: Timer | None = None
        self._bond_pub: Publisher[Status] | None = None
        self._instance = uuid.uuid4().hex
        self._active = threading.Event()  # set while the node is active
        super().__init__(name, **kwargs)

    def _start(self) -> None:
        super()._start()
        self._bond_period = float(self.parameters.declare(
            "bond_heartbeat_period", 0.25,
            description="seconds between bond heartbeats while active (0: no bond)"))
        if self._bond_period > 0:
            self._bond_pub = self.create_publisher(Status, "bond", 10)
        self._autostart = bool(self.parameters.declare(
            "autostart", self.autostart_default,
            description="configure and activate by itself once set up (false: a lifecycle "
                        "manager brings it up)"))

    def _announce(self) -> None:
        """Offer the services once `setup` has returned: a transition never meets a node
        whose setup() is still running."""
        if self._interface:
            self._open_interface()
        super()._announce()
        if self._autostart:
            for label in ("configure", "activate"):
                if self.trigger_transition(label=label) is not TransitionCallbackReturn.SUCCESS:
                    self.logger.error("autostart: %s failed; the node stays %s", label,
                                      self.current_state.label)
                    break

    def _open_interface(self) -> None:
        self._events = self.create_publisher(TransitionEvent, "~/transition_event", 10)
        self.create_service(ChangeState, "~/change_state", self._on_change_state)
        self.create_service(GetState, "~/get_state", lambda _req: GetStateResponse(
            current_state=_state_msg(self._machine.state_id)))
        self.create_service(GetAvailableStates, "~/get_available_states",
                            lambda _req: GetAvailableStatesResponse(available_states=[
                                _state_msg(s.state_id) for s in StateMachine.states()]))
        self.create_service(GetAvailableTransitions, "~/get_available_transitions",
                            lambda _req: GetAvailableTransitionsResponse(available_transitions=[
                                _description(t) for t in self._machine.available()]))
        self.create_service(GetAvailableTransitions, "~/get_transition_graph",
                            lambda _req: GetAvailableTransitionsResponse(available_transitions=[
                                _description(t) for t in TRANSITIONS]))

    # ------------------------------------------------------------------ state machine

    @property
    def current_state(self) -> LifecycleState:
        return self._machine.state

    def available_transitions(self) -> list[TransitionDef]:
        return self._machine.available()

    def trigger_transition(self, transition_id: int = 0,
                           label: str = "") -> TransitionCallbackReturn:
        """Run the transition named by ``label`` (if given) or ``transition_id`` from the
        current state; raises `InvalidTransitionError` if there is none."""
        t = self._machine.find(transition_id, label)
        ret = self._machine.trigger(t, self._run_callback, self._emit)
        if self._machine.state_id == ACTIVE:
            self._active.set()
        else:
            self._active.clear()
        self._follow_bond()
        return ret

    def wait_for_active(self, timeout: float | None = None) -> bool:
        """Block until the node is active (True), or ``timeout`` s pass first (False): for a
        request that arrives while a manager is bringing the node up."""
        return self._active.wait(timeout)

    def trigger_configure(self) -> TransitionCallbackReturn:
        return self.trigger_transition(label="configure")

    def trigger_cleanup(self) -> TransitionCallbackReturn:
        return self.trigger_transition(label="cleanup")

    def trigger_activate(self) -> TransitionCallbackReturn:
        return self.trigger_transition(label="activate")

    def trigger_deactivate(self) -> TransitionCallbackReturn:
        return self.trigger_transition(label="deactivate")

    def trigger_shutdown(self) -> TransitionCallbackReturn:
        return self.trigger_transition(label="shutdown")

    def add_managed_entity(self, entity: ManagedEntity) -> None:
        self._managed.append(entity)

    def create_lifecycle_publisher(self, msg_type: type[M], topic: str,
                                   qos: QoSProfile | int = 10) -> LifecyclePublisher[M]:
        """A `LifecyclePublisher`: silent until the node is activated."""
        pub = LifecyclePublisher(self.logger, self.context, self.fqn, msg_type,
                                 self.resolve_name(topic), as_profile(qos))
        self._warn_type_conflict(pub.topic, pub.type_name)
        p: LifecyclePublisher[M] = self.add_waitable(pub)
        self.add_managed_entity(p)
        return p

    def destroy_lifecycle_publisher(self, pub: LifecyclePublisher[Any]) -> None:
        """Close ``pub`` and stop managing it (rclpy's name)."""
        if pub in self._managed:
            self._managed.remove(pub)
        self.destroy(pub)

    def _run_callback(self, state_id: int, starting: LifecycleState) -> TransitionCallbackReturn:
        name = _CALLBACK_NAMES[state_id]
        try:
            ret = getattr(self, name)(starting)
        except Exception:
            self.logger.exception("%s raised: counted as ERROR", name)
            return TransitionCallbackReturn.ERROR
        if not isinstance(ret, TransitionCallbackReturn):
            self.logger.error("%s returned %r, not a TransitionCallbackReturn: counted as "
                              "ERROR", name, ret)
            return TransitionCallbackReturn.ERROR
        return ret

    def _emit(self, t: TransitionDef) -> None:
        if self._events is None or self._events.closed:
            return
        self._events.publish(TransitionEvent(
            timestamp=time.time_ns(), transition=Transition(id=t.id, label=t.label),
            start_state=_state_msg(t.start), goal_state=_state_msg(t.goal)))

    def _on_change_state(self, req: ChangeStateRequest) -> ChangeStateResponse:
        tr = req.transition
        try:
            ret = self.trigger_transition(tr.id, tr.label)
        except InvalidTransitionError as e:
            self.logger.warning("change_state refused: %s", e)
            return ChangeStateResponse(success=False)
        return ChangeStateResponse(success=ret is TransitionCallbackReturn.SUCCESS)

    # ------------------------------------------------------------------ bond

    def _follow_bond(self) -> None:
        """Heartbeat while active; a last ``active=False`` when leaving active."""
        active = self._machine.state_id == ACTIVE
        if active and self._heartbeat is None and self._bond_pub is not None and not self.closed:
            self._beat()
            self._heartbeat = self.create_timer(self._bond_period, self._beat,
                                                clock=SteadyClock())
        elif not active and self._heartbeat is not None:
            self._heartbeat.cancel()
            self._heartbeat = None
            self._beat(active=False)

    def close(self) -> None:
        """Close the node; an active one first leaves its bond (``active=False``), so a
        manager learns at once that it is gone rather than after its bond timeout."""
        heartbeat, self._heartbeat = self._heartbeat, None
        if heartbeat is not None and not self.closed:
            heartbeat.cancel()
            self._beat(active=False)
        super().close()

    def _beat(self, active: bool = True) -> None:
        pub = self._bond_pub
        if pub is None or pub.closed:
            return
        pub.publish(Status(id=self.name, instance_id=self._instance, active=active,
                           heartbeat_period=self._bond_period))

    # ------------------------------------------------------------------ default callbacks

    def _entities(self, hook: str, state: LifecycleState) -> TransitionCallbackReturn:
        for entity in self._managed:
            ret: TransitionCallbackReturn = getattr(entity, hook)(state)
            if ret is not TransitionCallbackReturn.SUCCESS:
                return ret
        return _OK

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._entities("on_configure", state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._entities("on_cleanup", state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._entities("on_shutdown", state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._entities("on_activate", state)

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._entities("on_deactivate", state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        return self._entities("on_error", state)
