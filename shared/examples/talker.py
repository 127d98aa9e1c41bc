"""Publishes "hello world N" on /chatter (std_msgs/String) at `rate` Hz."""

from __future__ import annotations

from zenros import Node, run
from zenros.msgs.std_msgs import String


class Talker(Node):
    """Publishes std_msgs/String on chatter."""

    node_name = "talker"

    def setup(self) -> None:
        self.count = 0
        self.pub = self.create_publisher(String, "chatter")
        self.create_timer(1.0 / self.declare_parameter("rate", 2.0), self.on_tick)

    def on_tick(self) -> None:
        self.count += 1
        self.pub.publish(String(data=f"hello world {self.count}"))


if __name__ == "__main__":
    run(Talker)
