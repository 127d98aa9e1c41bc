"""The standalone rosbridge node as a process: roslibpy reaches the graph through it, SIGINT
ends it cleanly, a taken port is a startup failure (exit code 3)."""

from __future__ import annotations

import signal
import socket
import sys

import pytest
import roslibpy
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.testing import Proc, free_port, roslibpy_connect, wait_for

pytestmark = pytest.mark.system


def start(router: str, prefix: str, port: int) -> Proc:
    return Proc([sys.executable, "-m", "zenros.services.gateway.rosbridge", "-e", router,
                 "--prefix", prefix, "-p", f"port:={port}"])


def test_rosbridge_process(router: str, prefix: str, observer: Context,
                           procs: list[Proc]) -> None:
    port = free_port()
    proc = start(router, prefix, port)
    procs.append(proc)
    assert proc.wait_line("rosbridge v2 listening on ws://127.0.0.1:", 20), proc.output
    talker = Node("talker", context=observer)
    try:
        pub = talker.create_publisher(String, "/chatter")
        ros = roslibpy_connect("127.0.0.1", port)
        try:
            assert wait_for(lambda: "/talker" in ros.get_nodes(), 10)
            got: list[dict[str, str]] = []
            roslibpy.Topic(ros, "/chatter", "std_msgs/String").subscribe(got.append)
            assert pub.wait_for_subscribers(1, 10)
            assert wait_for(lambda: (pub.publish(String(data="hi")), bool(got))[1], 10)
            # a type whose module zenros.msgs leaves out, by its ROS 2 name (issue 37.6)
            details = roslibpy.Service(ros, "/rosapi/action_goal_details",
                                       "rosapi_msgs/srv/ActionGoalDetails")
            typedefs = details.call(roslibpy.ServiceRequest(
                {"type": "test_msgs/action/Fibonacci"}), timeout=10)["typedefs"]
            assert [(t["type"], t["fieldnames"]) for t in typedefs] == [
                ("test_msgs/msg/FibonacciGoal", ["order"])], typedefs
        finally:
            ros.close()
    finally:
        talker.close()
    proc.signal(signal.SIGINT)
    assert proc.wait(10) == 0, proc.output


def test_taken_port_fails_at_startup(router: str, prefix: str, procs: list[Proc]) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        proc = start(router, prefix, taken.getsockname()[1])
        procs.append(proc)
        assert proc.wait(20) == 3, proc.output
        assert "startup failed" in proc.output
