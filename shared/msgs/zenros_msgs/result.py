"""`ResultCode`: why a zenros_msgs service call did not succeed, as a number, never as wording.

Services set it (nav on its refusals, tasks in every response); callers branch on it. A
caller that speaks HTTP (the gateway) maps it to a status in one table, so rewording a
message never changes what a client sees.
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["ResultCode"]


class ResultCode(IntEnum):
    """The outcome of a call. New codes are appended; a code never changes its number."""

    OK = 0
    INVALID = 1        # the request is malformed or a field is out of range
    NOT_FOUND = 2      # what the request names (map, path, nav point, task, ...) is not stored
    CONFLICT = 3       # not allowed in the current state (a task runs, no map is loaded, ...)
    UNAVAILABLE = 4    # a service the call needs is not there (yet)
    TIMEOUT = 5        # the work did not take effect within its time limit
    FAILED = 6         # the service failed (a bug or a broken store): not the caller's fault
