"""`AggregatorNode`: diagnostic_aggregator's node on zenros (docs/diagnostics.md)."""

from __future__ import annotations

import threading

from zenros import Node
from zenros.diagnostics import Aggregator, analyzers_from_params
from zenros.diagnostics.status import ERROR
from zenros.errors import ConfigError
from zenros.msgs.diagnostic_msgs import DiagnosticArray, DiagnosticStatus
from zenros.qos import QoSProfile

from .robot import ROBOT_ANALYZERS

__all__ = ["AggregatorNode"]


class AggregatorNode(Node):
    """Parameters (diagnostic_aggregator's): ``pub_rate`` (Hz, 1.0), ``path`` (the tree's
    base), ``other_as_errors``, ``critical`` (publish at once when an item turns ERROR or
    worse), ``history_depth`` (1000), and the analyzers as ``analyzers.<name>.type``
    (``diagnostic_aggregator/GenericAnalyzer``), ``analyzers.<name>.path`` and their keys;
    with none given, the robot's own (`ROBOT_ANALYZERS`)."""

    node_name = "diagnostic_aggregator"

    def setup(self) -> None:
        rate = float(self.declare_parameter("pub_rate", 1.0, read_only=True))
        if not rate > 0:
            raise ConfigError(f"pub_rate must be > 0 Hz, got {rate}")
        path = str(self.declare_parameter("path", "", read_only=True))
        base = f"/{path.strip('/')}" if path.strip("/") else ""
        other = bool(self.declare_parameter("other_as_errors", False, read_only=True))
        self.critical = bool(self.declare_parameter("critical", False, read_only=True))
        depth = int(self.declare_parameter("history_depth", 1000, read_only=True))
        flat = {k: v for k, v in self.parameters.overrides.items()
                if k.startswith("analyzers.")} or ROBOT_ANALYZERS
        for k, v in flat.items():
            self.declare_parameter(k, v, read_only=True)
        self.aggregator = Aggregator(analyzers_from_params(flat, base, self.now().nanoseconds),
                                     base_path=base, other_as_errors=other)
        self._lock = threading.Lock()
        self.agg_pub = self.create_publisher(DiagnosticArray, "/diagnostics_agg", 1)
        self.top_pub = self.create_publisher(DiagnosticStatus, "/diagnostics_toplevel_state", 1)
        self.create_subscription(DiagnosticArray, "/diagnostics", self.on_diagnostics,
                                 QoSProfile(depth=max(1, depth)))
        self.create_timer(1.0 / rate, self.publish_tree)

    def on_diagnostics(self, msg: DiagnosticArray) -> None:
        with self._lock:
            raised = self.aggregator.add(msg.status, self.now().nanoseconds)
        if self.critical and raised >= ERROR:
            self.publish_tree()

    def publish_tree(self) -> None:
        with self._lock:
            tree, top = self.aggregator.report(self.now().nanoseconds)
        out = DiagnosticArray(status=tree)
        out.header.stamp = self.now()
        self.agg_pub.publish(out)
        self.top_pub.publish(top)
