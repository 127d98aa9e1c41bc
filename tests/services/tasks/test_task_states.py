"""Every allowed and refused task request, by state."""

from __future__ import annotations

import pytest
from zenros.services.tasks.states import (
    CANCELLED,
    COMPLETE,
    ERROR,
    FAILED,
    PAUSED,
    STATES,
    WAITTING,
    WORKING,
    TaskStateError,
    check_request,
)

ALLOWED = {
    ("start", WAITTING): WORKING, ("start", COMPLETE): WORKING,
    ("start", CANCELLED): WORKING, ("start", ERROR): WORKING, ("start", FAILED): WORKING,
    ("pause", WORKING): PAUSED,
    ("resume", PAUSED): WORKING,
    ("stop", WAITTING): CANCELLED, ("stop", WORKING): CANCELLED, ("stop", PAUSED): CANCELLED,
}


@pytest.mark.parametrize("request_", ["start", "pause", "resume", "stop"])
@pytest.mark.parametrize("state", STATES)
def test_every_request_in_every_state(request_: str, state: str) -> None:
    if (request_, state) in ALLOWED:
        assert check_request("t1", request_, state) == ALLOWED[(request_, state)]
    else:
        with pytest.raises(TaskStateError) as err:
            check_request("t1", request_, state)
        assert state in str(err.value) and "t1" in str(err.value)
        assert "allowed in" in str(err.value)


def test_spelling_of_waitting_is_the_wire_value() -> None:
    assert WAITTING == "WAITTING"


def test_start_on_running_task_says_what_to_do() -> None:
    with pytest.raises(TaskStateError, match="already running; pause or stop it first"):
        check_request("t1", "start", WORKING)
