"""IoPorts: the simulated robot's IO ports (main-board outputs, extension IO board).

The main board has three outputs, ``out1``..``out3`` (ports 1..3). The optional extension
board has eight outputs (ports 0..7) and sixteen inputs (0..15); its inputs are not wired
to anything in the simulation, so they read 0. Outputs start low. Plain logic, no zenoh.
"""

from __future__ import annotations

import threading
from typing import Final

__all__ = ["BOARDS", "IoError", "IoPorts"]

MAIN_OUTPUTS: Final = 3
EXT_OUTPUTS: Final = 8
EXT_INPUTS: Final = 16
BOARDS: Final = ("main", "ext")


class IoError(ValueError):
    """A request naming an unknown board, port or level; the text says which."""


class IoPorts:
    """Output and input levels (0/1), thread-safe; ``version`` counts changes."""

    def __init__(self, extension_board: bool = True) -> None:
        self._lock = threading.Lock()
        self.extension_board = extension_board
        self._main = [0] * MAIN_OUTPUTS
        self._ext_out = [0] * EXT_OUTPUTS if extension_board else []
        self._ext_in = [0] * EXT_INPUTS if extension_board else []
        self.version = 0

    def set(self, board: str, port: int, level: int) -> bool:
        """Set one output; True when its level changed. Raises IoError on a bad request."""
        if level not in (0, 1) or isinstance(level, bool):
            raise IoError(f"level must be 0 or 1, got {level!r}")
        if board == "main":
            if not 1 <= port <= MAIN_OUTPUTS:
                raise IoError(f"main-board output port must be 1..{MAIN_OUTPUTS}, got {port}")
            outputs, index = self._main, port - 1
        elif board == "ext":
            if not self.extension_board:
                raise IoError("this robot has no extension IO board")
            if not 0 <= port < EXT_OUTPUTS:
                raise IoError(f"extension-board output port must be 0..{EXT_OUTPUTS - 1},"
                              f" got {port}")
            outputs, index = self._ext_out, port
        else:
            raise IoError(f"unknown IO board {board!r}; boards: {', '.join(BOARDS)}")
        with self._lock:
            if outputs[index] == level:
                return False
            outputs[index] = level
            self.version += 1
            return True

    def snapshot(self) -> tuple[list[int], list[int], list[int]]:
        """(main outputs out1..out3, extension outputs, extension inputs)."""
        with self._lock:
            return list(self._main), list(self._ext_out), list(self._ext_in)
