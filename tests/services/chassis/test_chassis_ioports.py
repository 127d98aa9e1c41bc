"""IoPorts: outputs start low, set and read back, changes are counted, bad requests name
what is wrong, and a robot without the extension board refuses it."""

from __future__ import annotations

import pytest
from zenros.services.chassis.ioports import IoError, IoPorts


def test_set_and_read_back() -> None:
    io = IoPorts()
    assert io.snapshot() == ([0, 0, 0], [0] * 8, [0] * 16)
    assert io.set("main", 2, 1) and io.version == 1
    assert not io.set("main", 2, 1) and io.version == 1  # no change
    assert io.set("ext", 7, 1)
    main, ext_out, ext_in = io.snapshot()
    assert main == [0, 1, 0] and ext_out[7] == 1 and ext_in == [0] * 16
    assert io.set("main", 2, 0) and io.snapshot()[0] == [0, 0, 0]


@pytest.mark.parametrize(("board", "port", "level", "words"), [
    ("main", 0, 1, "1..3"), ("main", 4, 1, "1..3"), ("ext", 8, 1, "0..7"),
    ("main", 1, 2, "level"), ("main", 1, True, "level"), ("side", 1, 1, "unknown IO board"),
])
def test_bad_requests(board: str, port: int, level: int, words: str) -> None:
    io = IoPorts()
    with pytest.raises(IoError, match=words):
        io.set(board, port, level)
    assert io.version == 0


def test_without_the_extension_board() -> None:
    io = IoPorts(extension_board=False)
    assert io.snapshot() == ([0, 0, 0], [], [])
    with pytest.raises(IoError, match="no extension IO board"):
        io.set("ext", 0, 1)
