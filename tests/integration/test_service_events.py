"""Service introspection over real Zenoh (ROS 2's ``configure_introspection``): a server
and a client publish each request and response on ``<service>/_service_event`` as
``<pkg>/srv/<Name>_Event``, with the contents (CONTENTS) or without (METADATA), and nothing
while OFF."""

from __future__ import annotations

from typing import Any

from zenros.msgs.service_msgs import ServiceEventInfo as Info
from zenros.msgs.std_srvs import SetBool, SetBoolRequest, SetBoolResponse
from zenros.ros2.registry import ros_name_of
from zenros.service_events import ServiceIntrospectionState as State
from zenros.service_events import event_type_of
from zenros.testing import Collector, wait_for


def _rig(make_node: Any) -> tuple[Any, Any, Any, Collector[Any]]:
    server_node = make_node("server", 0)
    srv = server_node.create_service(
        SetBool, "/flag", lambda req: SetBoolResponse(success=req.data, message="set"))
    client = make_node("caller", 1).create_client(SetBool, "/flag")
    events: Collector[Any] = Collector()
    make_node("watcher", 1).create_subscription(event_type_of(SetBool),
                                                "/flag/_service_event", events)
    assert client.wait_for_service(10)
    return server_node, srv, client, events


def test_contents_come_from_both_sides_in_order(make_node: Any) -> None:
    server_node, srv, client, events = _rig(make_node)
    srv.configure_introspection(server_node.get_clock(), None, State.CONTENTS)
    client.configure_introspection(server_node.get_clock(), None, State.CONTENTS)
    assert srv.events.wait_for_subscribers(1, 10) and client.events.wait_for_subscribers(1, 10)
    assert client.call(SetBoolRequest(data=True), timeout=10).success
    assert events.wait(4, 10), events.items
    kinds = sorted(e.info.event_type for e in events.items)
    assert kinds == [Info.REQUEST_SENT, Info.REQUEST_RECEIVED, Info.RESPONSE_SENT,
                     Info.RESPONSE_RECEIVED]
    by_kind = {e.info.event_type: e for e in events.items}
    assert by_kind[Info.REQUEST_SENT].request == [SetBoolRequest(data=True)]
    assert by_kind[Info.RESPONSE_SENT].response == [SetBoolResponse(success=True, message="set")]
    assert any(by_kind[Info.REQUEST_SENT].info.client_gid)  # the client's session id
    assert by_kind[Info.REQUEST_SENT].info.sequence_number == 1
    assert all(e.info.stamp.sec > 0 for e in events.items)
    assert ros_name_of(event_type_of(SetBool)) == "std_srvs/srv/SetBool_Event"


def test_metadata_leaves_the_messages_out_and_off_stops(make_node: Any) -> None:
    server_node, srv, client, events = _rig(make_node)
    srv.configure_introspection(server_node.get_clock(), None, State.METADATA)
    assert srv.events.wait_for_subscribers(1, 10)
    client.call(SetBoolRequest(data=False), timeout=10)
    assert events.wait(2, 10)
    assert all(e.request == [] and e.response == [] for e in events.items)
    assert [e.info.event_type for e in events.items] == [Info.REQUEST_RECEIVED,
                                                         Info.RESPONSE_SENT]
    srv.configure_introspection(server_node.get_clock(), None, State.OFF)
    assert wait_for(lambda: not server_node.graph.publishers("/flag/_service_event"), 10)
    client.call(SetBoolRequest(data=True), timeout=10)
    assert len(events.items) == 2
