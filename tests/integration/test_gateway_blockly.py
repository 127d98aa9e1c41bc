"""docs/robot-api.md §10 through a real server, the real tasks service and the simulated
chassis: a Blockly program saved over REST (checked: a block the robot does not run is a 400
naming it), changed field by field, run by a task's blockly_action (IO set on the chassis in a
loop, a condition on the IO read back, speech on ``tts``), listed and deleted."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for

PROGRAM = """<xml xmlns="https://developers.google.com/blockly/xml">
  <block type="controls_repeat_ext" id="loop">
    <value name="TIMES"><shadow type="math_number"><field name="NUM">3</field></shadow></value>
    <statement name="DO">
      <block type="robot_set_io"><field name="PORT">2</field><field name="LEVEL">1</field>
        <next><block type="robot_wait"><field name="SECONDS">0.05</field>
          <next><block type="robot_set_io"><field name="PORT">2</field><field name="LEVEL">0</field>
          </block></next></block></next></block>
    </statement>
    <next><block type="robot_set_io"><field name="PORT">3</field><field name="LEVEL">1</field>
      <next><block type="controls_if">
        <value name="IF0"><block type="logic_compare"><field name="OP">EQ</field>
          <value name="A"><block type="robot_io"><field name="BOARD">main</field>
            <field name="PORT">3</field></block></value>
          <value name="B"><block type="math_number"><field name="NUM">1</field></block></value>
        </block></value>
        <statement name="DO0"><block type="robot_speak"><value name="TEXT">
          <block type="text"><field name="TEXT">blockly done</field></block></value></block>
        </statement></block></next></block></next>
  </block>
</xml>"""


@pytest.fixture
def robot(ctx_pair: list[Context], tmp_path: Path,
          gw: GatewayNode) -> Iterator[tuple[ChassisNode, TasksNode]]:
    chassis = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 0.0, "actuators": False, "speed": 5.0})
    tasks = TasksNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path / "t")})
    assert gw.graph.wait_for_service("/tasks/blockly/save", 10)
    yield chassis, tasks
    tasks.close()
    chassis.close()


def test_a_program_saved_over_rest_runs_as_a_task(robot: Any, http: httpx.Client,
                                                   ctx_pair: list[Context]) -> None:
    r = http.post("/blockly_task", json={"title": "blink", "description": "three blinks",
                                         "blocklyxml": PROGRAM, "py": "import os  # never run"})
    assert r.status_code == 200, r.text
    program = r.json()
    assert program["title"] == "blink" and program["is_enabled"] is True and program["id"]
    said: list[str] = []
    user = Node("blockly_listener", context=ctx_pair[0])
    try:
        user.create_subscription(String, "tts", lambda m: said.append(m.data), QOS_LATCHED)
        r = http.post("/task", json={"name": "blockly", "sub_tasks": [
            {"type": "blockly_action", "api_key": program["id"]}]})
        assert r.status_code == 200, r.text
        task = r.json()
        assert http.get("/task/start", params={"id": task["id"]}).status_code == 200
        assert wait_for(lambda: http.get("/task", params={"id": task["id"]}).json()["state"]
                        in ("COMPLETE", "ERROR"), 30)
        done = http.get("/task", params={"id": task["id"]}).json()
        assert done["state"] == "COMPLETE", done["sub_tasks"][0]["result"]
        assert wait_for(lambda: "blockly done" in said, 10), said
    finally:
        user.close()
    assert http.get("/system/io").json() == {"status": "ok", "out1": "0", "out2": "0",
                                             "out3": "1"}
    # changed field by field: the others stay
    r = http.put("/blockly_task", json={"id": program["id"], "is_enabled": False})
    assert r.status_code == 200 and r.json()["title"] == "blink", r.text
    assert r.json()["is_enabled"] is False and r.json()["blocklyxml"] == PROGRAM
    r = http.post("/action", json={"type": "blockly_action", "api_key": program["id"]})
    auto = r.json()
    http.get("/task/start", params={"id": auto["id"]})
    assert wait_for(lambda: http.get("/task", params={"id": auto["id"]}).json()["state"]
                    == "ERROR", 20)
    result = http.get("/task", params={"id": auto["id"]}).json()["sub_tasks"][0]["result"]
    assert "is disabled" in result, result
    listed = http.get("/blockly_task").json()
    assert [p["id"] for p in listed] == [program["id"]]
    assert http.delete("/blockly_task", params={"id": program["id"]}).json() == {
        "status": "ok"}
    assert http.get("/blockly_task").json() == []


def test_refusals(robot: Any, http: httpx.Client) -> None:
    for body, words in (
            ({"blocklyxml": "<xml><block type='os_system'/></xml>"}, "'os_system': not a block"),
            ({"blocklyxml": "<xml><block"}, "not XML"),
            ({"title": "no xml"}, "blocklyxml"),
            ({"blocklyxml": "<xml/>", "run": True}, "run")):
        r = http.post("/blockly_task", json=body)
        assert r.status_code == 400 and words in r.json()["description"], (body, r.text)
    r = http.put("/blockly_task", json={"id": "nope", "title": "x"})
    assert r.status_code == 404 and "no Blockly program 'nope'" in r.json()["description"]
    r = http.put("/blockly_task", json={"id": "nope"})
    assert r.status_code == 400 and "at least one field" in r.json()["description"]
    assert http.delete("/blockly_task", params={"id": "nope"}).status_code == 404
    assert http.delete("/blockly_task").status_code == 400
    r = http.post("/task", json={"name": "b", "sub_tasks": [
        {"type": "blockly_action", "api_key": "missing"}]})
    task = r.json()
    http.get("/task/start", params={"id": task["id"]})
    assert wait_for(lambda: http.get("/task", params={"id": task["id"]}).json()["state"]
                    == "ERROR", 20)
    assert http.get("/blockly_task").json() == []
