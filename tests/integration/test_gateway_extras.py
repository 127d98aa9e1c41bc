"""REST extras through a real server: log, TTS as text, topic snapshots, self-test, ROS
parameters (with a real master), and the 504/404/503 answers when something is missing."""

from __future__ import annotations

from pathlib import Path

import httpx
from zenros.context import Context
from zenros.msgs.sensor_msgs import BatteryState, LaserScan
from zenros.msgs.std_msgs import String
from zenros.qos import QOS_LATCHED
from zenros.services.gateway.node import GatewayNode
from zenros.services.master.node import MasterNode
from zenros.testing import Collector, wait_for


def test_tts_log_topic_self_test(gw: GatewayNode, http: httpx.Client,
                                 make_node: object) -> None:
    other = make_node("speaker", 1)  # type: ignore[operator]
    said: Collector[String] = Collector()
    other.create_subscription(String, "tts", said, QOS_LATCHED)
    assert http.get("/system/tts", params={"text": "hello"}).json() == {"status": "ok"}
    assert said.wait(1, 5) and said.items[-1].data == "hello"
    assert http.get("/system/tts", params={"text": ""}).status_code == 400
    other.get_logger().warning("a line for the log")
    assert wait_for(lambda: "a line for the log" in http.get("/system/log").json()["log"], 5)
    # a topic snapshot: latched value at once; an unknown topic 404; a silent one 504
    batt = other.create_publisher(BatteryState, "battery_state", QOS_LATCHED)
    batt.publish(BatteryState(voltage=24.5, percentage=0.5))
    assert gw.graph.wait_for(lambda: bool(gw.graph.publishers("/battery_state")), 5)
    snap = http.get("/system/topic", params={"topic_name": "/battery_state"}).json()
    assert snap["voltage"] == 24.5
    assert http.get("/system/topic", params={"topic_name": "/nothing"}).status_code == 404
    other.create_publisher(String, "quiet", 10)
    assert gw.graph.wait_for(lambda: bool(gw.graph.publishers("/quiet")), 5)
    r = http.get("/system/topic", params={"topic_name": "quiet"})
    assert r.status_code == 504 and "no message" in r.json()["description"]
    assert http.get("/system/topic", params={"topic_name": "a b"}).status_code == 400
    assert wait_for(lambda: batt.publish(BatteryState(voltage=24.5)) or gw.topics.fresh(
        "battery_state"), 5)
    assert http.get("/system/schedule_manager").json() == {}
    test = http.get("/system/self_test").json()
    assert test["battery"] is True and test["lidar"] is False and test["camera"] is False


def test_self_test_listens_for_a_scan_when_no_diagnostics_say(
        gw: GatewayNode, http: httpx.Client, make_node: object) -> None:
    # the gateway does not follow the scan: asked, it waits up to 1 s for one
    laser = make_node("laser", 1)  # type: ignore[operator]
    pub = laser.create_publisher(LaserScan, "scan", 10)
    assert gw.graph.wait_for(lambda: bool(gw.graph.publishers("/scan")), 5)
    assert http.get("/system/self_test").json()["lidar"] is False  # in the graph, silent
    laser.create_timer(0.1, lambda: pub.publish(LaserScan(ranges=[1.0, 2.0])))
    assert http.get("/system/self_test").json()["lidar"] is True


def test_ros_params(ctx_pair: list[Context], gw: GatewayNode, http: httpx.Client,
                    tmp_path: Path) -> None:
    r = http.get("/system/ros_params", params={"param": "/demo/speed"})
    assert r.status_code == 503 and "master" in r.json()["description"]
    master = MasterNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path)})
    try:
        assert wait_for(lambda: http.put("/system/ros_params", json={
            "param": "/demo/speed", "value": 0.7}).status_code == 200, 10)
        assert http.get("/system/ros_params", params={"param": "/demo/speed"}).json() == {
            "value": 0.7}
        assert http.get("/system/ros_params", params={"param": "/demo"}).json() == {
            "value": {"speed": 0.7}}
        assert http.get("/system/ros_params", params={"param": "/nope"}).status_code == 404
        assert http.put("/system/ros_params", json={"param": "bad name!", "value": 1}
                        ).status_code == 400
    finally:
        master.close()
