"""Test support: isolated sessions on loopback, `wait_for` (from `zenros.waiting`), `Collector`,
process helpers."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Generic, Self, TypeVar

from .clock import ManualClock, Time
from .context import Context
from .errors import StartupError
from .session import SessionOptions
from .waiting import Waited, WaitTimeout, wait_for, wait_for_async, wait_until

__all__ = [
    "Collector",
    "Proc",
    "RawWebSocket",
    "RecordingClock",
    "WaitTimeout",
    "Waited",
    "free_port",
    "linked_contexts",
    "loopback_options",
    "roslibpy_connect",
    "start_process",
    "store_on_master",
    "unique_prefix",
    "wait_for",
    "wait_for_async",
    "wait_until",
]

T = TypeVar("T")


_LOWEST_PORT = 10000
_port_lock = threading.Lock()
_next_port = (0, 0)  # (pid, port): a forked child starts its own walk


def _ephemeral_floor() -> int:
    """The lowest port the kernel gives an outgoing connection (Linux; 32768 elsewhere)."""
    try:
        return int(Path("/proc/sys/net/ipv4/ip_local_port_range").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return 32768


def _bindable(port: int) -> bool:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            return False
        return True


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nothing uses right now, below the kernel's ephemeral range.

    The port stays free until its user binds it: an outgoing connection, whose local port the
    kernel picks from the ephemeral range, cannot take it in between (a port from ``bind(0)``
    could be, and was: a Zenoh listener then failed with "Address already in use"). Each
    process walks the range from its own starting point, so parallel test processes seldom
    pick the same port."""
    global _next_port
    floor = _ephemeral_floor()
    span = floor - _LOWEST_PORT
    if span < 1000:  # a kernel that hands out (nearly) every port: let it choose
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
            s.bind(("127.0.0.1", 0))
            chosen: int = s.getsockname()[1]
            return chosen
    with _port_lock:
        pid, port = _next_port
        if pid != os.getpid():
            port = _LOWEST_PORT + (os.getpid() * 7919) % span
        for _ in range(span):
            _next_port = (os.getpid(), _LOWEST_PORT + (port + 1 - _LOWEST_PORT) % span)
            if _bindable(port):
                return port
            port = _next_port[1]
    raise RuntimeError(f"no free TCP port on 127.0.0.1 in {_LOWEST_PORT}..{floor - 1}")


def unique_prefix() -> str:
    """A fresh key prefix, so tests never see each other's traffic."""
    return "zt" + uuid.uuid4().hex[:10]


def loopback_options(port: int | None = None, connect: Sequence[int] = ()) -> SessionOptions:
    """A peer listening on 127.0.0.1:``port`` and connecting to the given local ports."""
    return SessionOptions(
        mode="peer",
        listen=[f"tcp/127.0.0.1:{port or free_port()}"],
        connect=[f"tcp/127.0.0.1:{p}" for p in connect],
    )


@contextmanager
def linked_contexts(n: int = 2, prefix: str | None = None) -> Iterator[list[Context]]:
    """``n`` contexts (separate Zenoh sessions) meshed on loopback, sharing one prefix.

    Each connects to every one before it by its configured endpoints, not by gossip: Zenoh
    1.10 connects again to a configured endpoint whose link was lost (a lease that ran out
    while a loaded box starved the process), but never to a peer it had found by gossip, and
    a router no longer forwards between two peers that lost their direct link (Zenoh 1.9
    removed the failover brokering), so those two stay apart for good."""
    prefix = prefix or unique_prefix()
    ports: list[int] = []
    ctxs: list[Context] = []
    try:
        for _ in range(n):
            ctx, port = _context_listening(prefix, connect=ports)
            ctxs.append(ctx)
            ports.append(port)
        yield ctxs
    finally:
        for c in reversed(ctxs):
            c.close()


def _context_listening(prefix: str, connect: Sequence[int],
                       attempts: int = 3) -> tuple[Context, int]:
    """A context listening on a free port; another port when something took it meanwhile."""
    for attempt in range(attempts):
        port = free_port()
        try:
            return Context(loopback_options(port, connect=connect), prefix=prefix), port
        except StartupError as e:
            if "Address already in use" not in str(e) or attempt == attempts - 1:
                raise
    raise AssertionError("unreachable")


class RecordingClock(ManualClock):  # type: ignore[misc, unused-ignore]
    """A `ManualClock` that records every deadline a sleeper asks for (sync or async), so a
    test can wait until a timer or a `Rate` has gone to sleep before advancing time."""

    def __init__(self, start: Time | None = None) -> None:
        super().__init__(start)
        self.requests: list[Time] = []
        self._req = threading.Condition()

    def _record(self, t: Time) -> None:
        with self._req:
            self.requests.append(t)
            self._req.notify_all()

    def sleep_until(self, t: Time, timeout: float | None = None) -> bool:
        self._record(t)
        woke: bool = super().sleep_until(t, timeout)
        return woke

    async def async_sleep_until(self, t: Time) -> None:
        self._record(t)
        await super().async_sleep_until(t)

    def wait_requests(self, n: int, timeout: float = 5.0) -> list[Time]:
        """The deadlines asked for so far, once there are at least ``n``.

        Raises:
            AssertionError: fewer than ``n`` within ``timeout`` seconds.
        """
        with self._req:
            assert self._req.wait_for(lambda: len(self.requests) >= n, timeout), self.requests
            return list(self.requests)


class Collector(Generic[T]):
    """A callback that records what it gets; `wait(n)` blocks until n items arrived."""

    def __init__(self) -> None:
        self.items: list[T] = []
        self._cond = threading.Condition()

    def __call__(self, item: T) -> None:
        with self._cond:
            self.items.append(item)
            self._cond.notify_all()

    def wait(self, n: int = 1, timeout: float = 5.0) -> bool:
        with self._cond:
            return self._cond.wait_for(lambda: len(self.items) >= n, timeout)

    def __len__(self) -> int:
        return len(self.items)


class Proc:
    """A child process whose output is collected line by line (for system tests)."""

    def __init__(self, argv: Sequence[str], env: dict[str, str] | None = None,
                 cwd: str | None = None) -> None:
        self.argv = list(argv)
        full_env = dict(os.environ)
        full_env.update(env or {})
        full_env.setdefault("PYTHONUNBUFFERED", "1")
        self.popen = subprocess.Popen(
            self.argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
            env=full_env, cwd=cwd, start_new_session=True,
        )
        self.lines: list[str] = []
        self._cond = threading.Condition()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.popen.stdout is not None
        for line in self.popen.stdout:
            with self._cond:
                self.lines.append(line.rstrip("\n"))
                self._cond.notify_all()
        with self._cond:
            self._cond.notify_all()

    @property
    def output(self) -> str:
        with self._cond:
            return "\n".join(self.lines)

    def wait_line(self, needle: str, timeout: float = 10.0) -> bool:
        """Block until a line containing ``needle`` was printed (False on timeout or exit)."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while True:
                if any(needle in ln for ln in self.lines):
                    return True
                left = deadline - time.monotonic()
                if left <= 0 or (self.popen.poll() is not None and not self._reader.is_alive()):
                    return False
                self._cond.wait(min(left, 0.1))

    def signal(self, sig: int) -> None:
        if self.popen.poll() is None:
            self.popen.send_signal(sig)

    def wait(self, timeout: float = 10.0) -> int:
        rc = self.popen.wait(timeout)
        self._reader.join(2)
        return rc

    def stop(self, timeout: float = 5.0) -> int:
        """SIGINT, then SIGKILL (of the whole process group) if it does not end in time."""
        if self.popen.poll() is None:
            self.popen.send_signal(signal.SIGINT)
            try:
                self.popen.wait(timeout)
            except subprocess.TimeoutExpired:
                try:
                    os.killpg(self.popen.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                self.popen.wait(5)
        self._reader.join(2)
        if self.popen.stdout is not None:
            self.popen.stdout.close()
        return self.popen.returncode


def roslibpy_connect(host: str, port: int, timeout: float = 10.0) -> Any:
    """A connected ``roslibpy.Ros`` (roslibpy is a test dependency, imported here).

    roslibpy 2.1's ``Ros.run`` can miss its own connection: ``on_ready`` checks for the
    protocol and then adds a "ready" listener, while the reactor thread may set the protocol
    and emit "ready" between the two (seen under a CPU hog). A client that is connected when
    ``run`` times out is therefore taken; one that is not still fails as roslibpy says.
    """
    import roslibpy

    ros = roslibpy.Ros(host, port)
    try:
        ros.run(timeout)
    except roslibpy.core.RosTimeoutError:
        if not wait_for(lambda: ros.is_connected, 1.0):
            # roslibpy would keep reconnecting in the background for the rest of the process.
            stop = getattr(ros.factory, "stopTrying", None)
            if stop is not None:
                from twisted.internet import reactor

                reactor.callFromThread(stop)
            raise
    return ros


def store_on_master(home: str | os.PathLike[str], prefix: str, values: dict[str, Any]) -> None:
    """Parameter values stored before a launch: a master started for this under ``home``
    (its ZENROS_HOME) keeps them, and nodes read stored values over their launch file's
    (system tests move the gateway's fixed ports to free ones this way)."""
    from .param_client import ParameterClient

    listen = f"tcp/127.0.0.1:{free_port()}"
    master = Proc([sys.executable, "-m", "zenros.services.master", "-l", listen,
                   "--prefix", prefix], env={"ZENROS_HOME": os.fspath(home)})
    try:
        if not master.wait_line("started", 30):
            raise RuntimeError(f"master did not start:\n{master.output}")
        with Context(SessionOptions(connect=[listen]), prefix=prefix) as ctx:
            client = ParameterClient(ctx, timeout=10.0)
            if not client.wait_for_master(20):
                raise RuntimeError("master does not answer")
            for name, value in values.items():
                client.set(name, value)
    finally:
        master.stop()


def start_process(*args: str, env: dict[str, str] | None = None) -> Proc:
    """Start ``python -m ...``-style children with the current interpreter."""
    return Proc([sys.executable, *args], env=env)


class RawWebSocket:
    """A WebSocket client on a bare socket, to see exactly which frames a server sends (and
    when: it reads only when asked, through a small receive buffer).

    Args:
        port: the server's port on 127.0.0.1.
        path: the request path (with its query).
    """

    def __init__(self, port: int, path: str = "/", timeout: float = 10.0) -> None:
        self.sock = socket.socket()
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        self.sock.connect(("127.0.0.1", port))
        self.sock.settimeout(timeout)
        self.sock.sendall(f"GET {path} HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\n"
                          "Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
                          "Sec-WebSocket-Version: 13\r\n\r\n".encode())
        head = b""
        while b"\r\n\r\n" not in head:
            head += self.sock.recv(1)
        self.status = int(head.split(b" ", 2)[1])
        self._buf = b""

    def send_text(self, text: str) -> None:
        """One masked text frame (a zero mask key, as RFC 6455 allows)."""
        data = text.encode()
        n = len(data)
        head = bytes([0x81, 0x80 | n]) if n < 126 else bytes([0x81, 0xFE]) + n.to_bytes(2, "big")
        self.sock.sendall(head + b"\0\0\0\0" + data)

    def _need(self, n: int) -> None:
        while len(self._buf) < n:
            chunk = self.sock.recv(1 << 20)
            if not chunk:
                raise ConnectionError("the server closed the connection")
            self._buf += chunk

    def read_message(self) -> list[tuple[int, bool, bytes]]:
        """The frames (opcode, FIN, payload) of the next data message, fragmented or not
        (control frames in between are skipped)."""
        frames: list[tuple[int, bool, bytes]] = []
        while not frames or not frames[-1][1]:
            self._need(2)
            fin, op, n, at = bool(self._buf[0] & 0x80), self._buf[0] & 0x0F, self._buf[1] & 0x7F, 2
            if n == 126:
                self._need(4)
                n, at = int.from_bytes(self._buf[2:4], "big"), 4
            elif n == 127:
                self._need(10)
                n, at = int.from_bytes(self._buf[2:10], "big"), 10
            self._need(at + n)
            if op < 8:
                frames.append((op, fin, self._buf[at:at + n]))
            self._buf = self._buf[at + n:]
        return frames

    def close(self) -> None:
        self.sock.close()

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
