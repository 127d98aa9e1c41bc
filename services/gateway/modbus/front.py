"""`ModbusFront`: the docs/robot-api.md §14 Modbus TCP server (pymodbus 3.16), live from
GalileoStatus, and the ASR board's IO where the map has room (discrete inputs 31-38 read its
ports 0-7, coils 1-4 read and write its outputs 0-3).

Reads are served by the pull hook from registers precomputed at every status refresh (a
read never waits for Zenoh); writes go through `parse_holding_write` and are refused with
ILLEGAL_VALUE / DEVICE_FAILURE exception codes rather than ever reaching the robot half-done.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any, Protocol

from pymodbus.constants import ExcCodes
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import DataType, SimData, SimDevice
from zenros.errors import ConfigError
from zenros.msgs.galileo_msgs import GalileoStatus
from zenros.msgs.zenros_msgs import AsrBoardState, SetAsrBoardRequest

from ..errors import PortError, Refused
from ..state.core import Core, NavUnavailable
from .tables import (
    COIL_COUNT,
    DI_COUNT,
    HR_COUNT,
    IR_COUNT,
    HoldingWrite,
    discrete_inputs,
    input_registers,
    parse_holding_write,
)

__all__ = ["ModbusFront"]

FC_COILS, FC_DI, FC_IR = 1, 2, 4
FC_HR_WRITES = (6, 16)
FC_COIL_WRITES = (5, 15)


class AsrBoard(Protocol):
    """The ASR board as the Modbus door needs it (`ports.asr_link.AsrLink`)."""

    def io_bits(self) -> list[bool]: ...

    async def set(self, req: SetAsrBoardRequest) -> AsrBoardState: ...


def _pack_bits(bits: list[bool]) -> list[int]:
    words = [0] * ((len(bits) + 15) // 16)
    for i, b in enumerate(bits):
        if b:
            words[i // 16] |= 1 << (i % 16)
    return words


class ModbusFront:
    """Serves unit id 1 (and any other: one robot, one device) on ``host:port``."""

    def __init__(self, core: Core, logger: logging.Logger,
                 io_bits: Callable[[], tuple[list[int], list[int]]] | None = None,
                 asr: AsrBoard | None = None) -> None:
        self.core = core
        self.logger = logger
        self.io_bits = io_bits  # the extension IO board's (inputs, outputs), for DI 7-30
        self.asr = asr  # the ASR board: DI 31-38, coils 1-4
        self._ir = input_registers(core.status)
        self._di = _pack_bits(discrete_inputs(core.status, *self._io(), self._asr_io()))
        core.status_listeners.append(self._on_status)
        self.device = SimDevice(id=0, action=self._on_request, simdata=(
            [SimData(0, count=COIL_COUNT, values=False, datatype=DataType.BITS)],
            [SimData(0, count=DI_COUNT, values=False, datatype=DataType.BITS)],
            [SimData(0, count=HR_COUNT, values=0, datatype=DataType.REGISTERS)],
            [SimData(0, count=IR_COUNT, values=0, datatype=DataType.REGISTERS)]))
        self.server: ModbusTcpServer | None = None

    def _on_status(self, st: GalileoStatus) -> None:
        self._ir = input_registers(st)
        self._di = _pack_bits(discrete_inputs(st, *self._io(), self._asr_io()))

    def _io(self) -> tuple[list[int], list[int]]:
        return self.io_bits() if self.io_bits is not None else ([], [])

    def _asr_io(self) -> list[bool]:
        return self.asr.io_bits() if self.asr is not None else []

    async def start(self, host: str, port: int) -> int:
        """Listen; returns the bound port.

        Raises:
            ConfigError: the port cannot be bound.
        """
        self.server = ModbusTcpServer(self.device, address=(host, port))
        try:
            await self.server.serve_forever(background=True)
        except OSError as exc:
            raise ConfigError(f"cannot listen on {host}:{port}: {exc.strerror or exc}") from exc
        transport: Any = self.server.transport
        bound: int = transport.sockets[0].getsockname()[1] if transport is not None else port
        return bound

    async def stop(self) -> None:
        if self.server is not None:
            await self.server.shutdown()  # type: ignore[no-untyped-call]  # pymodbus leaves it untyped

    async def _on_request(self, fc: int, start: int, address: int, count: int,
                          registers: list[int], set_values: Any) -> ExcCodes | None:
        if fc == FC_IR:
            registers[address:address + count] = self._ir[address:address + count]
        elif fc == FC_DI:
            registers[:len(self._di)] = self._di
        elif fc == FC_COILS:
            if address >= COIL_COUNT:  # (pymodbus counts whole 16-bit words here: a read
                return ExcCodes.ILLEGAL_ADDRESS  # of coils 1-16 gets 0 past coil 4)
            registers[:1] = _pack_bits(self._asr_io()[:COIL_COUNT] or [False] * COIL_COUNT)
        elif fc in FC_COIL_WRITES and set_values is not None:
            bits = set_values if isinstance(set_values, list) else [set_values]
            if address + len(bits) > COIL_COUNT:
                return ExcCodes.ILLEGAL_ADDRESS
            return await self._set_outputs(address, [bool(b) for b in bits])
        elif fc in FC_HR_WRITES and set_values:
            values = [int(v) for v in (set_values if isinstance(set_values, list)
                                       else [set_values])]
            try:
                cmd = parse_holding_write(registers, address, values,
                                          self.core.settings.current.max_control_speed)
            except ValueError as exc:
                self.logger.warning("modbus write at %d refused: %s", address + 1, exc)
                return ExcCodes.ILLEGAL_VALUE
            return await self._apply(cmd)
        return None

    async def _set_outputs(self, address: int, bits: list[bool]) -> ExcCodes | None:
        """Coils ``address``... : the ASR board's outputs, all or none."""
        if self.asr is None:
            return ExcCodes.DEVICE_FAILURE
        ports = list(range(address, address + len(bits)))
        try:
            await self.asr.set(SetAsrBoardRequest(kind="io", ports=ports, levels=bits))
        except Refused as exc:  # an input port, too fast
            self.logger.warning("modbus coil write at %d refused: %s", address + 1, exc)
            return ExcCodes.ILLEGAL_VALUE
        except PortError as exc:  # no board, no answer
            self.logger.warning("modbus coil write at %d failed: %s", address + 1, exc)
            return ExcCodes.DEVICE_FAILURE
        self._di = _pack_bits(discrete_inputs(self.core.status, *self._io(), self._asr_io()))
        return None

    async def _apply(self, cmd: HoldingWrite) -> ExcCodes | None:
        if cmd.speed is not None:
            self.core.deadman.command(cmd.speed[0], 0.0, cmd.speed[1])
        try:
            if cmd.nav_index is not None:
                nav = self.core.navigation()
                if cmd.nav_index < 0:
                    await nav.cancel()
                else:
                    await nav.goto_index(cmd.nav_index)
            if cmd.control is not None:
                nav = self.core.navigation()
                await (nav.cancel, nav.pause, nav.resume)[cmd.control]()
            if cmd.charge is not None:
                nav = self.core.navigation()
                await (nav.go_charge() if cmd.charge else nav.stop_charge())
            if cmd.goal is not None:
                await self.core.navigation().goto_pose(*cmd.goal)
        except NavUnavailable as exc:
            self.logger.warning("modbus command refused: %s", exc)
            return ExcCodes.DEVICE_FAILURE
        except ValueError as exc:
            self.logger.warning("modbus command refused: %s", exc)
            return ExcCodes.ILLEGAL_VALUE
        return None
