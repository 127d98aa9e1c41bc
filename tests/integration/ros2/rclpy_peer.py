"""An unmodified rclpy node for the DDS bridge tests: ``pub KIND TOPIC`` publishes a sample of
KIND every 50 ms, ``sub KIND TOPIC`` prints one JSON line per message received; ``--tl`` makes
the endpoint transient local (depth 1); ``--drive`` makes each Twist the same sane velocity
command (0.3 m/s, 0.2 rad/s: a chassis refuses one far beyond its limits, as the counter in
angular.z soon is); ``srv SetBool NAME`` serves std_srvs/SetBool (replies
success=data, message "got <data>") and prints one JSON line per request. Runs until killed."""

from __future__ import annotations

import json
import sys

import rclpy
from geometry_msgs.msg import Twist
from nav_msgs.msg import OccupancyGrid
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from std_srvs.srv import SetBool


def sample(kind: str, i: int, drive: bool = False) -> object:
    if kind == "String":
        return String(data=f"hello {i}")
    if kind == "Twist":
        t = Twist()
        t.linear.x = 0.3 if drive else 0.5
        t.angular.z = 0.2 if drive else float(i)  # the counter shows samples keep coming
        return t
    if kind == "LaserScan":
        s = LaserScan(angle_min=-1.0, angle_max=1.0, range_max=10.0)
        s.header.frame_id = "laser"
        s.ranges = [float(k % 10) for k in range(720)]
        return s
    g = OccupancyGrid()
    g.header.frame_id = "map"
    g.info.width = g.info.height = 1000
    g.info.resolution = 0.05
    g.data = [k % 100 for k in range(1000 * 1000)]
    return g


def summary(msg: object) -> dict[str, object]:
    if isinstance(msg, String):
        return {"data": msg.data}
    if isinstance(msg, Twist):
        return {"x": msg.linear.x, "z": msg.angular.z}
    return {"type": type(msg).__name__}


def main() -> None:
    mode, kind, topic = sys.argv[1:4]
    tl = "--tl" in sys.argv
    drive = "--drive" in sys.argv
    qos = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL) if tl else 10
    types = {"String": String, "Twist": Twist, "LaserScan": LaserScan, "OccupancyGrid": OccupancyGrid}
    rclpy.init()
    node = Node(f"peer_{mode}")
    if mode == "srv":
        def serve(req: SetBool.Request, resp: SetBool.Response) -> SetBool.Response:
            resp.success = req.data
            resp.message = f"got {req.data}"
            print(json.dumps({"served": req.data}), flush=True)
            return resp
        node.create_service(SetBool, topic, serve)
    elif mode == "pub":
        pub = node.create_publisher(types[kind], topic, qos)
        msg = sample(kind, 0)
        counter = [0]

        def tick() -> None:
            counter[0] += 1
            if kind in ("String", "Twist"):
                pub.publish(sample(kind, counter[0], drive))
            else:
                pub.publish(msg)
        node.create_timer(0.05, tick)
    else:
        def got(m: object) -> None:  # with the topic's types as this node's graph has them
            types = dict(node.get_topic_names_and_types()).get(topic, [])
            print(json.dumps({**summary(m), "types": types}), flush=True)
        node.create_subscription(types[kind], topic, got, qos)
    print(json.dumps({"ready": node.get_name()}), flush=True)
    rclpy.spin(node)


if __name__ == "__main__":
    main()
