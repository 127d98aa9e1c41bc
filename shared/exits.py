"""The exit codes of every zenros program (nodes, ``zenros`` verbs, the router, launch)."""

from __future__ import annotations

__all__ = ["EXIT_ERROR", "EXIT_OK", "EXIT_SESSION_FAILED", "EXIT_STARTUP", "EXIT_USAGE"]

EXIT_OK = 0
"""Success; Ctrl-C on a node, a streaming verb or a launch included."""

EXIT_ERROR = 1
"""A clear one-line error (a verb), or a launched process that did not end cleanly."""

EXIT_USAGE = 2
"""Bad flags (argparse's code)."""

EXIT_STARTUP = 3
"""Could not start: no Zenoh session (or nothing answered), bad flags or parameters, a bad
launch file, a router that cannot listen."""

EXIT_SESSION_FAILED = 4
"""The Zenoh session broke for good while running (`Context.fail`): the process ends so that
its supervisor (``zenros launch`` with ``respawn``, systemd) starts a fresh one."""
