"""Logs every std_msgs/String it hears on /chatter."""

from __future__ import annotations

from zenros import Node, run
from zenros.msgs.std_msgs import String


class Listener(Node):
    """Subscribes to chatter and logs what it hears."""

    node_name = "listener"

    def setup(self) -> None:
        self.create_subscription(String, "chatter", self.on_chatter)

    def on_chatter(self, msg: String) -> None:
        self.logger.info("I heard: %s", msg.data)


if __name__ == "__main__":
    run(Listener)
