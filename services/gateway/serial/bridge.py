"""`SerialBridge`: docs/robot-api.md §13 on a serial port: status frames out at 30 Hz, command
frames in.

Runs on a thread of its own. A missing or vanished port never blocks the gateway: the
bridge says so once per outage and retries every ``retry`` seconds.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

import serial

from ..state.core import Core
from .frame import CommandParser, status_frame

__all__ = ["SerialBridge"]


class SerialBridge:
    """Bridges ``port`` (a device path or pyserial URL) to the gateway's core."""

    def __init__(self, core: Core, port: str, logger: logging.Logger, *, baud: int = 115200,
                 rate: float = 30.0, retry: float = 1.0,
                 on_command: Callable[[bytes], None] | None = None) -> None:
        self.core = core
        self.port = port
        self.baud = baud
        self.period = 1.0 / rate
        self.retry = retry
        self.logger = logger
        self.on_command = on_command or core.send_native
        self.parser = CommandParser()
        self.sent = 0
        self.received = 0
        self.connected = threading.Event()
        self._said = False  # the port's trouble logged once (again after it came back)
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=f"serial:{port}", daemon=True)
        self._thread.start()

    def _open(self) -> serial.Serial | None:
        try:
            return serial.serial_for_url(self.port, baudrate=self.baud, bytesize=8,
                                         parity="N", stopbits=1, timeout=0,
                                         write_timeout=0.2)
        except (serial.SerialException, OSError, ValueError) as exc:
            self._down(f"cannot open serial port {self.port}: {exc}")
            return None

    def _down(self, why: str) -> None:
        if self.connected.is_set() or not self._said:
            self.logger.warning("%s; retrying every %g s", why, self.retry)
            self._said = True
        self.connected.clear()

    def _run(self) -> None:
        while not self._stop.is_set():
            port = self._open()
            if port is None:
                self._stop.wait(self.retry)
                continue
            self.logger.info("serial bridge on %s at %d baud", self.port, self.baud)
            self._said = False
            self.connected.set()
            try:
                self._serve(port)
            except (serial.SerialException, OSError) as exc:
                self._down(f"serial port {self.port} failed: {exc}")
            finally:
                port.close()
            self._stop.wait(self.retry)

    def _serve(self, port: serial.Serial) -> None:
        next_at = time.monotonic()
        while not self._stop.is_set():
            now = time.monotonic()
            if now >= next_at:
                try:
                    port.write(status_frame(self.core.status, self.sent))
                    self.sent += 1
                except serial.SerialTimeoutException:
                    pass  # nobody drains the line: drop this frame, keep going
                next_at = max(next_at + self.period, now)
            waiting = port.in_waiting
            if waiting:
                for cmd in self.parser.feed(port.read(waiting)):
                    self.received += 1
                    try:
                        self.on_command(cmd)
                    except Exception:  # a bad command never ends the bridge
                        self.logger.exception("serial command %s failed", cmd.hex(" "))
            self._stop.wait(min(0.005, max(0.0, next_at - time.monotonic())))

    def close(self) -> None:
        self._stop.set()
        self._thread.join(2.0)
