"""ControlLoop: ticks at its period while something drives; idle, it does not tick until a
wake (a goal started or halted) or its slow idle step."""

from __future__ import annotations

import logging
import threading

from zenros.clock import SteadyClock
from zenros.services.nav.motion.active import Motion
from zenros.services.nav.motion.loop import ControlLoop
from zenros.testing import wait_for


class Steps:
    def __init__(self) -> None:
        self.calls = 0
        self.stepped = threading.Event()

    def __call__(self) -> None:
        self.calls += 1
        self.stepped.set()


def test_an_idle_loop_steps_only_when_woken() -> None:
    idle = [True]
    steps = Steps()
    loop = ControlLoop(SteadyClock(), 0.01, steps, logging.getLogger("test"),
                       idle=lambda: idle[0], idle_period=60.0)
    loop.start()
    try:
        assert not steps.stepped.wait(0.3)  # 30 periods at rest: not one tick
        loop.wake()  # e.g. a goal was accepted: one step at once
        assert wait_for(lambda: steps.calls == 1, 5)
        idle[0] = False
        loop.wake()
        assert wait_for(lambda: steps.calls >= 10, 5)  # driving: ticks at the period
        idle[0] = True
        before = steps.calls
        threading.Event().wait(0.3)  # 30 periods
        assert steps.calls <= before + 1  # idle again: at most the tick under way
    finally:
        loop.stop()


def test_motion_is_idle_after_its_final_stop_command() -> None:
    """A halted behaviour leaves one zero command to send: not idle until it was ticked."""

    class Forever:
        done = threading.Event()

        def step(self, sense: object) -> tuple[float, float]:
            return 0.3, 0.0

        def halt(self, reason: str) -> None:
            pass

    changes: list[object] = []
    m = Motion(on_change=changes.append)
    assert m.idle
    b = Forever()
    m.start(b)  # type: ignore[arg-type]
    assert not m.idle and changes == [b]
    m.halt()
    assert not m.idle and changes == [b, None]
    assert m.tick(None) == (0.0, 0.0)  # type: ignore[arg-type]
    assert m.idle and m.tick(None) is None  # type: ignore[arg-type]
