"""A managed talker (ROS 2's lifecycle_talker demo): publishes "Lifecycle HelloWorld #N" on
/lifecycle_chatter once a second, but only while active; `zenros lifecycle set
/lc_talker configure` then `activate` starts it, `deactivate` silences it."""

from __future__ import annotations

from zenros import run
from zenros.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from zenros.msgs.std_msgs import String
from zenros.timer import Timer


class LifecycleTalker(LifecycleNode):
    node_name = "lc_talker"

    def setup(self) -> None:
        self.count = 0
        self.rate = float(self.declare_parameter("rate", 1.0, description="messages per second"))
        self.timer: Timer | None = None

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.pub = self.create_lifecycle_publisher(String, "lifecycle_chatter")
        self.timer = self.create_timer(1.0 / self.rate, self.on_tick)
        self.logger.info("on_configure() is called.")
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.logger.info("on_activate() is called.")
        return super().on_activate(state)  # activates the lifecycle publisher

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.logger.info("on_deactivate() is called.")
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.timer is not None:
            self.timer.cancel()
            self.timer = None
        self.destroy_lifecycle_publisher(self.pub)
        self.logger.info("on_cleanup() is called.")
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.timer is not None:
            self.timer.cancel()
        self.logger.info("on_shutdown() is called.")
        return TransitionCallbackReturn.SUCCESS

    def on_tick(self) -> None:
        self.count += 1
        if self.pub.is_activated:
            self.pub.publish(String(data=f"Lifecycle HelloWorld #{self.count}"))


if __name__ == "__main__":
    run(LifecycleTalker)
