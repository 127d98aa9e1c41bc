"""A lifecycle manager: Nav2's ``lifecycle_manager`` for zenros's (and ROS 2's) managed nodes.

It brings the nodes of ``node_names`` up in order (configure all, then activate all), takes
them down in reverse (pause, reset, shutdown), and while they are active watches each one's
bond heartbeat (``bond``, bond/Status, id = the node's name). When one stops (the process
died, hung, or left active), it takes the others down (deactivate, cleanup), logs it and
reports it on ``~/status``; with ``attempt_respawn_reconnection`` it then asks every node's
``get_state`` each second and starts them all up again once all answer (a launch
``respawn: true`` brings the dead one back), for at most ``bond_respawn_max_duration``.

Services: ``~/manage_nodes`` (nav2_msgs/ManageLifecycleNodes: STARTUP, PAUSE, RESUME,
RESET, SHUTDOWN, CONFIGURE, CLEANUP), ``~/is_active`` (std_srvs/Trigger). Run it with
``python -m zenros.lifecycle.manager -p node_names:="[a, b]" -p autostart:=true``.
docs/lifecycle.md has the rest.
"""

from __future__ import annotations

import asyncio
import threading
import time
import uuid
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

from ..clock import SteadyClock
from ..errors import ConfigError, ZenrosError
from ..msgs.bond import Status
from ..msgs.lifecycle_msgs import (
    ChangeState,
    ChangeStateRequest,
    GetState,
    GetStateRequest,
    Transition,
)
from ..msgs.nav2_msgs import (
    ManageLifecycleNodes,
    ManageLifecycleNodesRequest,
    ManageLifecycleNodesResponse,
)
from ..msgs.std_srvs import Trigger, TriggerRequest, TriggerResponse
from ..msgs.zenros_msgs.lifecycle import LifecycleManagerStatus
from ..names import Token
from ..node import Node
from ..qos import QOS_LATCHED
from ..runtime import run

__all__ = ["LifecycleManager"]

Cmd = ManageLifecycleNodesRequest
# the primary state each requested transition ends in (Nav2 checks it with get_state)
_GOAL = {Transition.TRANSITION_CONFIGURE: 2, Transition.TRANSITION_ACTIVATE: 3,
         Transition.TRANSITION_DEACTIVATE: 2, Transition.TRANSITION_CLEANUP: 1,
         Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: 4}
_LABEL = {Transition.TRANSITION_CONFIGURE: "configure", Transition.TRANSITION_ACTIVATE:
          "activate", Transition.TRANSITION_DEACTIVATE: "deactivate",
          Transition.TRANSITION_CLEANUP: "cleanup",
          Transition.TRANSITION_UNCONFIGURED_SHUTDOWN: "shutdown"}
_IN_ORDER = (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE)
BOND_CHECK_MIN = 0.2  # s: the shortest period of the bond check


class _Managed:
    """One managed node: its clients and its side of the bond."""

    def __init__(self, node: Node, name: str) -> None:
        self.name = name
        self.fqn = node.resolve_name(name, "node")
        self.bond_id = name.rstrip("/").rsplit("/", 1)[-1]
        self.change = node.create_client(ChangeState, f"{name}/change_state")
        self.get = node.create_client(GetState, f"{name}/get_state")
        self.bonded = False       # watched: a heartbeat is expected
        self.formed = threading.Event()
        self.last_beat = 0.0      # monotonic time of its last heartbeat
        self.left = False         # it sent active=False


class LifecycleManager(Node):
    """Nav2's lifecycle manager as a zenros node (parameters as Nav2's)."""

    node_name = "lifecycle_manager"

    def setup(self) -> None:
        p = self.parameters
        names = p.declare("node_names", [], read_only=True,
                          description="the managed nodes, in start-up order")
        if not isinstance(names, list) or not all(isinstance(n, str) and n for n in names):
            raise ConfigError(f"node_names: expected a list of node names, got {names!r}")
        if len(set(names)) != len(names):
            raise ConfigError(f"node_names: a node is named twice in {names!r}")
        autostart = bool(p.declare("autostart", False))
        self.bond_timeout = float(p.declare("bond_timeout", 4.0))
        self.service_timeout = float(p.declare("service_timeout", 5.0))
        self.respawn_max = float(p.declare("bond_respawn_max_duration", 10.0))
        self.respawn = bool(p.declare("attempt_respawn_reconnection", True))
        self.heartbeat_period = float(p.declare("bond_heartbeat_period", 0.25))
        self._nodes = [_Managed(self, n) for n in names]
        self._by_bond = {m.bond_id: m for m in self._nodes}
        self._instance = uuid.uuid4().hex
        self.active = False
        self._stop = threading.Event()
        self._work = ThreadPoolExecutor(1, thread_name_prefix=f"{self.name}-work")
        self.on_close(self._shutdown_worker)
        self._status = self.create_publisher(LifecycleManagerStatus, "~/status", QOS_LATCHED)
        self._bond_pub = self.create_publisher(Status, "bond", 10)
        self.create_subscription(Status, "bond", self._on_beat, 100)
        self.create_service(ManageLifecycleNodes, "~/manage_nodes", self._on_manage)
        self.create_service(Trigger, "~/is_active", self._on_is_active)
        # A silent bond is found within a tenth of bond_timeout (0.2 s at least: 0.4 s for
        # Nav2's 4 s, 1 s for robot.yaml's 10 s, where 5 checks a second were 4 of a robot's
        # 27 timer ticks at rest); a node that left the graph is checked at once (below).
        check = max(BOND_CHECK_MIN, self.bond_timeout / 10)
        self.create_timer(check, self._check_bonds, clock=SteadyClock())
        by_fqn = {m.fqn: m for m in self._nodes}
        executor = self.context.executor

        def on_graph(event: str, token: Token) -> None:
            # a process that died leaves the graph at once (its session is gone): its bond is
            # lost now, not a bond_timeout later (zenros's; Nav2 waits for the heartbeats)
            m = by_fqn.get(token.node)
            if event == "delete" and token.kind == "node" and m is not None and m.bonded:
                m.left = True
                executor.call_soon(self._check_bonds)

        self.on_close(self.graph.add_listener(on_graph))
        if self.heartbeat_period > 0:
            self.create_timer(self.heartbeat_period, self._beat, clock=SteadyClock())
        self._report("idle", "")
        if autostart:
            self._work.submit(self._guard(self._autostart))

    # ------------------------------------------------------------------ commands

    async def _on_manage(self, req: ManageLifecycleNodesRequest) -> ManageLifecycleNodesResponse:
        ops: dict[int, Callable[[], bool]] = {
            Cmd.STARTUP: self.startup, Cmd.PAUSE: self.pause, Cmd.RESUME: self.resume,
            Cmd.RESET: self.reset, Cmd.SHUTDOWN: self.shutdown,
            Cmd.CONFIGURE: self.configure, Cmd.CLEANUP: self.cleanup}
        op = ops.get(req.command)
        if op is None:
            self.logger.warning("manage_nodes: unknown command %d (0-6)", req.command)
            return ManageLifecycleNodesResponse(success=False)
        ok = await asyncio.wrap_future(self._work.submit(self._guard(op)))
        return ManageLifecycleNodesResponse(success=bool(ok))

    def _on_is_active(self, _req: TriggerRequest) -> TriggerResponse:
        return TriggerResponse(success=self.active)

    def startup(self) -> bool:
        """Configure every node in order, then activate every one; bond with each."""
        self._report("starting", "Starting managed nodes bringup...")
        if not self._all(Transition.TRANSITION_CONFIGURE) or \
                not self._all(Transition.TRANSITION_ACTIVATE):
            self._report("failed", "Failed to bring up all requested nodes. Aborting bringup.",
                         error=True)
            return False
        self.active = True
        self._report("active", "Managed nodes are active")
        return True

    def pause(self) -> bool:
        self._deactivated()
        if not self._all(Transition.TRANSITION_DEACTIVATE):
            self._report("failed", "Failed to pause nodes: aborting pause", error=True)
            return False
        self._report("paused", "Managed nodes have been paused")
        return True

    def resume(self) -> bool:
        if not self._all(Transition.TRANSITION_ACTIVATE):
            self._report("failed", "Failed to resume nodes: aborting resume", error=True)
            return False
        self.active = True
        self._report("active", "Managed nodes are active")
        return True

    def reset(self, hard: bool = False, skip: _Managed | None = None) -> bool:
        """Deactivate, then clean up, in reverse order; ``hard`` goes on past failures."""
        self._deactivated()
        ok = self._all(Transition.TRANSITION_DEACTIVATE, hard, skip) and \
            self._all(Transition.TRANSITION_CLEANUP, hard, skip)
        if not ok and not hard:
            self._report("failed", "Failed to reset nodes: aborting reset", error=True)
            return False
        self._report("reset", "Managed nodes have been reset")
        return True

    def shutdown(self) -> bool:
        self._deactivated()
        for t in (Transition.TRANSITION_DEACTIVATE, Transition.TRANSITION_CLEANUP,
                  Transition.TRANSITION_UNCONFIGURED_SHUTDOWN):
            self._all(t, hard=True)
        self._report("shutdown", "Managed nodes have been shut down")
        return True

    def configure(self) -> bool:
        return self._all(Transition.TRANSITION_CONFIGURE)

    def cleanup(self) -> bool:
        return self._all(Transition.TRANSITION_CLEANUP)

    # ------------------------------------------------------------------ transitions

    def _all(self, transition: int, hard: bool = False, skip: _Managed | None = None) -> bool:
        """One transition on every node: configure and activate in order, the others in
        reverse; stops at the first failure unless ``hard``."""
        nodes = self._nodes if transition in _IN_ORDER else self._nodes[::-1]
        ok = True
        for m in nodes:
            if m is skip or self._stop.is_set():
                continue
            if not self._change(m, transition):
                ok = False
                if not hard:
                    return False
        return ok

    def _change(self, m: _Managed, transition: int) -> bool:
        label = _LABEL[transition]
        self.logger.info("%s %s", label.capitalize(), m.name)
        if transition == Transition.TRANSITION_ACTIVATE:
            m.formed.clear()
            m.left = False
        try:
            if not m.change.wait_for_service(self.service_timeout):
                raise ZenrosError(f"{m.name}/change_state is not available")
            res = m.change.call(ChangeStateRequest(transition=Transition(id=transition)),
                                timeout=self.service_timeout)
            state = m.get.call(GetStateRequest(), timeout=self.service_timeout).current_state
        except ZenrosError as e:
            self.logger.error("Failed to change state for node: %s (%s)", m.name, e)
            return False
        if not res.success or state.id != _GOAL[transition]:
            self.logger.error("Failed to change state for node: %s (%s: now %s)", m.name,
                              label, state.label)
            return False
        if transition == Transition.TRANSITION_ACTIVATE:
            return self._bond(m)
        if transition == Transition.TRANSITION_DEACTIVATE:
            m.bonded = False
        return True

    def _bond(self, m: _Managed) -> bool:
        if self.bond_timeout <= 0:
            return True
        if not m.formed.wait(self.bond_timeout / 2):
            self.logger.error("Server %s was unable to be reached after %.2fs by bond. This "
                              "server may be misconfigured.", m.name, self.bond_timeout / 2)
            return False
        m.bonded = True
        self.logger.info("Server %s connected with bond.", m.name)
        return True

    def _deactivated(self) -> None:
        self.active = False
        for m in self._nodes:
            m.bonded = False

    # ------------------------------------------------------------------ bonds

    def _on_beat(self, s: Status) -> None:
        m = self._by_bond.get(s.id)
        if m is None or s.instance_id == self._instance:
            return
        m.last_beat = time.monotonic()
        if s.active:
            m.formed.set()
        else:
            m.left = True

    def _beat(self) -> None:
        for m in self._nodes:
            if m.bonded and not self._bond_pub.closed:
                self._bond_pub.publish(Status(
                    id=m.bond_id, instance_id=self._instance, active=True,
                    heartbeat_timeout=self.bond_timeout,
                    heartbeat_period=self.heartbeat_period))

    def _check_bonds(self) -> None:
        if not self.active or self.bond_timeout <= 0:
            return
        now = time.monotonic()
        for m in self._nodes:
            if m.bonded and (m.left or now - m.last_beat > self.bond_timeout):
                self._deactivated()  # once: the timer sees an inactive system from now on
                self._work.submit(self._guard(lambda m=m: self._lost(m)))
                return

    def _lost(self, m: _Managed) -> bool:
        self.logger.error("Have not received a heartbeat from %s.", m.name)
        self._report("down", f"CRITICAL FAILURE: SERVER {m.name} IS DOWN after not receiving "
                     f"a heartbeat for {int(self.bond_timeout * 1000)} ms. Shutting down "
                     "related nodes.", lost=m.name, error=True)
        self.reset(hard=True, skip=m)
        self._report("down", f"{m.name} lost its bond: the other nodes were reset",
                     lost=m.name, error=True)
        if self.respawn:
            return self._await_respawn(m)
        return False

    def _await_respawn(self, lost: _Managed) -> bool:
        """Ask each node's state every second; start up again once all answer."""
        self._report("respawning", "Waiting for every managed node to answer again",
                     lost=lost.name)
        deadline = time.monotonic() + self.respawn_max
        while not self._stop.is_set():
            if all(self._answers(m) for m in self._nodes):
                self.logger.info("Successfully re-established connections from server "
                                 "respawns, starting back up.")
                return self.startup()
            if time.monotonic() >= deadline:
                self._report("gave_up", f"Failed to bring up all requested nodes after "
                             f"{self.respawn_max:.2f} seconds, respawn timer exiting. Nodes "
                             "must be manually restarted.", lost=lost.name, error=True)
                return False
            self._stop.wait(1.0)
        return False

    def _answers(self, m: _Managed) -> bool:
        """Whether the node's get_state answers (whatever the state: Nav2's check)."""
        try:
            m.get.call(GetStateRequest(), timeout=1.0)
        except ZenrosError:
            return False
        return True

    def _autostart(self) -> bool:
        for m in self._nodes:
            while not m.get.wait_for_service(self.service_timeout):
                if self._stop.is_set():
                    return False
                self.logger.info("Waiting for %s/get_state", m.name)
        return self.startup()

    # ------------------------------------------------------------------ plumbing

    def _guard(self, op: Callable[[], bool]) -> Callable[[], bool]:
        def guarded() -> bool:
            try:
                return op()
            except Exception:
                if not self._stop.is_set():
                    self.logger.exception("lifecycle manager step failed")
                return False
        return guarded

    def _report(self, state: str, message: str, lost: str = "", error: bool = False) -> None:
        if message:
            (self.logger.error if error else self.logger.info)("%s", message)
        if self._status.closed:
            return
        self._status.publish(LifecycleManagerStatus(
            stamp=self.now(), state=state, active=self.active,
            nodes=[m.name for m in self._nodes], lost=lost, message=message))

    def _shutdown_worker(self) -> None:
        self._stop.set()
        for m in self._nodes:
            m.formed.set()  # a bond wait ends now
        self._work.shutdown(wait=False, cancel_futures=True)


if __name__ == "__main__":
    run(LifecycleManager)
