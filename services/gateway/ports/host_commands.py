"""`HostCommands`: the commands the operator gave for what only the host can do (join a Wi-Fi
network, restart the router or the remote desktop, tell whether the robot is online;
docs/robot-api.md §3.3, §3.5).

Each is an argument list in the gateway's configuration file (``host_commands``, e.g.
``{"wifi": ["nmcli", "device", "wifi", "connect", "{ssid}", "password", "{password}"]}``).
A request's values are checked and put in place of their ``{name}`` in the arguments they
appear in, each value within one argument: no shell runs them, nothing received becomes a
command (an operator who writes ``sh -c`` with a placeholder in its script gives that away). An operation the operator gave no command for is refused (503) saying where to give
one; a command that fails is a 502 with its exit code and last line, never a success.
"""

from __future__ import annotations

import asyncio
import ipaddress
import re
from collections.abc import Mapping, Sequence
from typing import Final

from ..errors import Failed, NoAnswer, Unavailable

__all__ = ["OPERATIONS", "HostCommands", "check_value"]

OPERATIONS: Final[dict[str, tuple[str, ...]]] = {
    "wifi": ("ssid", "password"),
    "restart_router": ("type", "ip", "username", "password"),
    "restart_novnc": (),
    "is_online": (),
}
"""The operations and the values each one's command may use."""

_CHECKS: Final[dict[str, tuple[re.Pattern[str], str]]] = {
    "ssid": (re.compile(r"^[^\x00-\x1f\x7f]{1,32}$"), "1-32 characters, no control characters"),
    "password": (re.compile(r"^[\x20-\x7e]{0,63}$"), "at most 63 printable ASCII characters"),
    "type": (re.compile(r"^[a-z0-9_-]{1,32}$"), "a router brand: a-z, 0-9, '_', '-'"),
    "username": (re.compile(r"^[\x21-\x7e]{0,64}$"), "at most 64 printable ASCII, no spaces"),
}


def check_value(name: str, value: str) -> str:
    """``value`` if it is a valid ``name`` (an ``ip`` must be an IP address); else ValueError
    naming the field."""
    if name == "ip":
        try:
            return str(ipaddress.ip_address(value))
        except ValueError:
            raise ValueError(f"ip: {value!r} is not an IP address") from None
    pattern, rule = _CHECKS[name]
    if not pattern.match(value):
        raise ValueError(f"{name}: {rule}")
    return value


class HostCommands:
    """Runs the operator's commands (``table``: operation -> argument list), ``timeout`` s
    each; ``where`` says where the table is kept (for the refusal's text)."""

    def __init__(self, table: Mapping[str, Sequence[str]], where: str,
                 timeout: float = 60.0) -> None:
        unknown = sorted(set(table) - set(OPERATIONS))
        if unknown:
            raise ValueError(f"host_commands: unknown operation(s) {', '.join(unknown)}; "
                             f"known: {', '.join(OPERATIONS)}")
        for op, argv in table.items():
            if not argv or not all(isinstance(a, str) for a in argv):
                raise ValueError(f"host_commands.{op}: a non-empty list of strings")
        self.table = {op: list(argv) for op, argv in table.items()}
        self.where = where
        self.timeout = timeout

    def argv(self, op: str, values: Mapping[str, str]) -> list[str]:
        """The command of ``op`` with ``values`` (checked) in place of their placeholders.

        Raises:
            Unavailable: no command for ``op``.
            ValueError: a value that is not valid.
        """
        template = self.table.get(op)
        if template is None:
            raise Unavailable(f"no host command for {op}: the operator gives one as "
                              f"host_commands.{op} in {self.where} (docs/gateway.md, "
                              "\"Host commands\")")
        checked = {k: check_value(k, v) for k, v in values.items() if k in OPERATIONS[op]}
        out = []
        for arg in template:
            for key, value in checked.items():
                arg = arg.replace("{" + key + "}", value)
            out.append(arg)
        return out

    async def run(self, op: str, values: Mapping[str, str] | None = None) -> tuple[int, str]:
        """Run ``op``'s command; its exit code (0: it worked) and the last line it wrote on
        stderr.

        Raises:
            Unavailable: no command for ``op``, or it cannot be started.
            NoAnswer: it did not end within the timeout (it is killed).
            ValueError: a value that is not valid.
        """
        argv = self.argv(op, values or {})
        try:
            proc = await asyncio.create_subprocess_exec(
                *argv, stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE,
                stderr=asyncio.subprocess.PIPE, start_new_session=True)
        except OSError as exc:
            raise Unavailable(f"cannot run the {op} command {argv[0]!r}: "
                              f"{exc.strerror or exc}") from None
        try:
            _, err = await asyncio.wait_for(proc.communicate(), self.timeout)
        except TimeoutError:
            proc.kill()
            await proc.wait()
            raise NoAnswer(f"the {op} command did not end within {self.timeout:g} s") \
                from None
        last = (err.decode(errors="replace").strip().splitlines() or [""])[-1]
        return (proc.returncode if proc.returncode is not None else -1), last

    async def must_run(self, op: str, values: Mapping[str, str] | None = None) -> None:
        """Run ``op``'s command; `Failed` (502) with its exit code and last line unless it
        exits 0."""
        code, last = await self.run(op, values)
        if code != 0:
            raise Failed(f"the {op} command failed (exit code {code})"
                         + (f": {last}" if last else ""))
