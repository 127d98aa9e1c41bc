"""The ASR (voice) board's IO, PWM and servo outputs (docs/robot-api.md §3.8). No Zenoh here.

Eight IO ports: 0-3 are outputs (what ``PUT /system/asr/io`` sets, as the spec's example does)
and 4-7 inputs (what its ``GET`` example shows; not wired to anything in the simulation, so
they read false). Four PWM channels (ports 0-3: a frequency and a duty cycle) and four hobby
servos (ports 0-3: 0-180 degrees, turning at ``servo_speed`` degrees a second, starting at
90). The board takes at most ``max_rate`` updates a second, as the spec says of its IO.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass, field
from typing import Final

__all__ = ["INPUTS", "OUTPUTS", "AsrBoard", "AsrError"]

OUTPUTS: Final = (0, 1, 2, 3)
INPUTS: Final = (4, 5, 6, 7)
CHANNELS: Final = 4
MAX_FREQ: Final = 100_000  # Hz
SERVO_RANGE: Final = (0.0, 180.0)


class AsrError(ValueError):
    """A request the board refuses; the text says why."""


@dataclass
class AsrBoard:
    servo_speed: float = 300.0
    max_rate: float = 100.0
    io: list[bool] = field(default_factory=lambda: [False] * 8)
    pwm_freq: list[int] = field(default_factory=lambda: [0] * CHANNELS)
    pwm_percent: list[int] = field(default_factory=lambda: [0] * CHANNELS)
    servo_angle: list[float] = field(default_factory=lambda: [90.0] * CHANNELS)
    servo_target: list[float] = field(default_factory=lambda: [90.0] * CHANNELS)
    _last: float = -math.inf
    _lock: threading.Lock = field(default_factory=threading.Lock)

    def _update(self, now: float) -> None:
        if now - self._last < 1.0 / self.max_rate:
            raise AsrError(f"the ASR board takes at most {self.max_rate:g} updates a second")
        self._last = now

    def set_io(self, levels: dict[int, bool], now: float) -> bool:
        """Set outputs (port -> level), all or none; True when one changed.

        Raises:
            AsrError: no port, an input or unknown port, a level not a bool, or too fast.
        """
        if not levels:
            raise AsrError("give at least one output port: 0-3")
        for port, level in levels.items():
            if port in INPUTS:
                raise AsrError(f"port {port} is an input (inputs 4-7, outputs 0-3)")
            if port not in OUTPUTS:
                raise AsrError(f"no port {port}: outputs 0-3, inputs 4-7")
            if not isinstance(level, bool):
                raise AsrError(f"port {port}: the level must be true or false, got {level!r}")
        with self._lock:
            self._update(now)
            before = list(self.io)
            for port, level in levels.items():
                self.io[port] = level
            return before != self.io

    def set_pwm(self, port: int, freq: int, percent: int, now: float) -> None:
        """PWM on channel ``port``: ``freq`` Hz (0 off), ``percent`` duty cycle."""
        _channel(port)
        if not 0 <= freq <= MAX_FREQ:
            raise AsrError(f"freq must be 0-{MAX_FREQ} Hz, got {freq}")
        if not 0 <= percent <= 100:
            raise AsrError(f"percent must be 0-100, got {percent}")
        with self._lock:
            self._update(now)
            self.pwm_freq[port], self.pwm_percent[port] = freq, percent

    def set_servo(self, port: int, angle: float, now: float) -> None:
        """Turn servo ``port`` to ``angle`` degrees (0-180), at the servo's speed."""
        _channel(port)
        low, high = SERVO_RANGE
        if not (math.isfinite(angle) and low <= angle <= high):
            raise AsrError(f"angle must be {low:g}-{high:g} degrees, got {angle:g}")
        with self._lock:
            self._update(now)
            self.servo_target[port] = float(angle)

    @property
    def moving(self) -> bool:
        return self.servo_angle != self.servo_target

    def step(self, dt: float) -> bool:
        """Turn the servos ``dt`` seconds towards their targets; True when one arrived."""
        arrived = False
        with self._lock:
            reach = self.servo_speed * dt
            for i, (at, to) in enumerate(zip(self.servo_angle, self.servo_target, strict=True)):
                if at == to:
                    continue
                if abs(to - at) <= reach:
                    self.servo_angle[i] = to
                    arrived = True
                else:
                    self.servo_angle[i] = at + math.copysign(reach, to - at)
        return arrived


def _channel(port: int) -> None:
    if not 0 <= port < CHANNELS:
        raise AsrError(f"no channel {port}: channels 0-{CHANNELS - 1}")
