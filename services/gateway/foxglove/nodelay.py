"""`set_listener_nodelay`: TCP_NODELAY on a listening socket this process holds but did not
open itself (foxglove-sdk's server, made in Rust, with no setting for it).

The SDK writes each message to a socket with Nagle's algorithm on: a small frame sent while
the previous one is unacknowledged waits for the client's delayed ACK, so about one `/odom`
in five arrived 20-25 ms late (bench/rosbridge.py --only fairness, without any map). Linux
copies TCP_NODELAY from a listening socket to the connections it accepts, so setting it on
the listener once, right after the server starts, covers every client.
"""

from __future__ import annotations

import contextlib
import os
import socket

__all__ = ["set_listener_nodelay"]


def set_listener_nodelay(host: str, port: int) -> bool:
    """Set TCP_NODELAY on this process's listening TCP socket bound to (``host``, ``port``).

    Returns whether one was found (False off Linux, where ``/proc/self/fd`` does not exist;
    the server then works as the SDK made it).
    """
    try:
        fds = [int(name) for name in os.listdir("/proc/self/fd")]
    except OSError:
        return False
    found = False
    for fd in fds:
        try:
            if not os.readlink(f"/proc/self/fd/{fd}").startswith("socket:"):
                continue
            sock = socket.socket(fileno=os.dup(fd))  # a second handle: the SDK keeps its own
        except OSError:
            continue
        with sock, contextlib.suppress(OSError):
            if (sock.type == socket.SOCK_STREAM
                    and sock.family in (socket.AF_INET, socket.AF_INET6)
                    and sock.getsockopt(socket.SOL_SOCKET, socket.SO_ACCEPTCONN)
                    and sock.getsockname()[1] == port
                    and _same_host(sock.getsockname()[0], host)):
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                found = True
    return found


def _same_host(bound: str, host: str) -> bool:
    return bound == host or bound in ("0.0.0.0", "::") or host in ("localhost", "")
