"""Running a task through the gateway's REST API in a test: create it, start it, wait for its
end (`run_task`)."""

from __future__ import annotations

from typing import Any

import httpx
from zenros.testing import wait_for

ENDED = ("COMPLETE", "ERROR", "FAILED", "CANCELLED")


def run_task(http: httpx.Client, *actions: dict[str, Any], name: str = "test",
             timeout: float = 60) -> dict[str, Any]:
    """Create and start a task of ``actions``; the task once it has ended."""
    r = http.post("/task", json={"name": name, "sub_tasks": list(actions)})
    assert r.status_code == 200, r.text
    assert http.get("/task/start", params={"id": r.json()["id"]}).status_code == 200
    got: list[dict[str, Any]] = []

    def ended() -> bool:
        got.append(http.get("/task", params={"id": r.json()["id"]}).json())
        return got[-1]["state"] in ENDED

    assert wait_for(ended, timeout, interval=0.1), got[-1:]
    return got[-1]
