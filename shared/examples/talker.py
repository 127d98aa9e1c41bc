"""Publishes "hello world N" on /chatter (std_msgs/String) at `rate` Hz; `rate` follows live
changes (`zenros param set /talker/rate 5.0`)."""

from __future__ import annotations

from zenros import Node, run
from zenros.msgs.std_msgs import String
from zenros.params import Parameter, SetParametersResult


class Talker(Node):
    """Publishes std_msgs/String on chatter."""

    node_name = "talker"

    def setup(self) -> None:
        self.count = 0
        self.pub = self.create_publisher(String, "chatter")
        rate = self.declare_parameter("rate", 2.0, description="messages per second (> 0)")
        self.timer = self.create_timer(1.0 / rate, self.on_tick)
        self.add_on_set_parameters_callback(self.check_rate)
        self.on_parameter_change(self.on_rate, "rate")

    def check_rate(self, params: list[Parameter]) -> SetParametersResult:
        """Refuse a rate that is not a positive number of Hz."""
        for p in params:
            if p.name == "rate" and not p.value > 0:
                return SetParametersResult(False, f"rate must be > 0 Hz, got {p.value}")
        return SetParametersResult(True)

    def on_rate(self, p: Parameter) -> None:
        """A new rate: the next message one new period from now."""
        self.timer.cancel()
        self.timer = self.create_timer(1.0 / p.value, self.on_tick)
        self.logger.info("rate is now %g Hz", p.value)

    def on_tick(self) -> None:
        self.count += 1
        self.pub.publish(String(data=f"hello world {self.count}"))


if __name__ == "__main__":
    run(Talker)
