"""`CalibrationLink`: the chassis's calibrations (``calibration/command``,
zenros_msgs/Calibrate): start, cancel, complete and the state of the IMU's and the laser's,
and an IMU calibration waited for to its end."""

from __future__ import annotations

import asyncio
import time

from zenros.msgs.zenros_msgs import Calibrate, CalibrateRequest, CalibrateResponse, CalibrationState
from zenros.node import Node

from ..errors import Conflict, NoAnswer, Unavailable
from .calls import Lazy, call_port

__all__ = ["CalibrationLink"]

POLL = 0.1  # s between looks at a calibration being waited for


class CalibrationLink:
    """Calls ``calibration/command`` for the doors."""

    def __init__(self, node: Node, timeout: float = 5.0, imu_wait: float = 60.0) -> None:
        self.node = node
        self.timeout = timeout
        self.imu_wait = imu_wait
        self._client = Lazy(lambda: node.create_client(Calibrate, "calibration/command"))

    async def command(self, device: str, command: str) -> CalibrationState:
        """Send ``command`` to ``device``'s calibration; its state after it. A refusal (the
        robot moves, a state that does not allow it) is a `Conflict` naming the reason."""
        res: CalibrateResponse = await call_port(
            self._client.get(), CalibrateRequest(device=device, command=command),
            self.timeout, lambda: Unavailable(
                "no calibration service: calibration/command is not in the graph (the chassis "
                "is not running, or its calibration parameter is false)"))
        if not res.success:
            raise Conflict(res.message)
        return res.state

    async def calibrate_imu(self) -> CalibrationState:
        """Start the IMU's calibration and wait for its end (CALIBRATED or FAILED)."""
        state = await self.command("imu", "start")
        deadline = time.monotonic() + self.imu_wait
        while state.state == "CALIBRATING":
            if time.monotonic() > deadline:
                raise NoAnswer(f"the IMU calibration did not end within {self.imu_wait:g} s")
            await asyncio.sleep(POLL)
            state = await self.command("imu", "status")
        return state
