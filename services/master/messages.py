"""The master's own wire types: the registry services and replica synchronisation.

The parameter services that nodes and the CLI call live in `zenros.param_protocol`.
"""

from __future__ import annotations

import msgspec
from zenros.message import Message, ServiceType, define_service
from zenros.msgs.builtin_interfaces import Time

from .param_tree import Entry

__all__ = [
    "GET_PUBLISHED_TOPICS",
    "GET_SYSTEM_STATE",
    "GET_TOPIC_TYPES",
    "LOOKUP_NODE",
    "REPLICATION_TOPIC",
    "SYNC",
    "EndpointState",
    "GetPublishedTopics",
    "GetSystemState",
    "GetTopicTypes",
    "LookupNode",
    "NodeState",
    "ParamRows",
    "Sync",
    "TopicState",
    "TopicType",
]

GET_SYSTEM_STATE = "/master/get_system_state"
LOOKUP_NODE = "/master/lookup_node"
GET_TOPIC_TYPES = "/master/get_topic_types"
GET_PUBLISHED_TOPICS = "/master/get_published_topics"
SYNC = "/master/sync"
REPLICATION_TOPIC = "/master/replication"


# ---------------------------------------------------------------- registry


class NodeState(Message):
    """One node instance: where it runs and since when."""

    __msgtype__ = "zenros_msgs/NodeState"
    name: str = ""
    host: str = ""
    pid: int = 0
    zid: str = ""
    start: Time = msgspec.field(default_factory=Time)


class TopicState(Message):
    __msgtype__ = "zenros_msgs/TopicState"
    name: str = ""
    types: list[str] = msgspec.field(default_factory=list)
    publishers: list[str] = msgspec.field(default_factory=list)
    subscribers: list[str] = msgspec.field(default_factory=list)


class EndpointState(Message):
    """A service or an action: its types and the nodes serving it."""

    __msgtype__ = "zenros_msgs/EndpointState"
    name: str = ""
    types: list[str] = msgspec.field(default_factory=list)
    servers: list[str] = msgspec.field(default_factory=list)


class TopicType(Message):
    __msgtype__ = "zenros_msgs/TopicType"
    name: str = ""
    types: list[str] = msgspec.field(default_factory=list)


class GetSystemStateRequest(Message):
    __msgtype__ = "zenros_msgs/GetSystemStateRequest"


class GetSystemStateResponse(Message):
    __msgtype__ = "zenros_msgs/GetSystemStateResponse"
    nodes: list[NodeState] = msgspec.field(default_factory=list)
    topics: list[TopicState] = msgspec.field(default_factory=list)
    services: list[EndpointState] = msgspec.field(default_factory=list)
    actions: list[EndpointState] = msgspec.field(default_factory=list)
    type_conflicts: list[TopicType] = msgspec.field(default_factory=list)
    duplicate_nodes: list[str] = msgspec.field(default_factory=list)


class LookupNodeRequest(Message):
    __msgtype__ = "zenros_msgs/LookupNodeRequest"
    name: str = ""


class LookupNodeResponse(Message):
    __msgtype__ = "zenros_msgs/LookupNodeResponse"
    found: bool = False
    node: NodeState = msgspec.field(default_factory=NodeState)


class GetTopicTypesRequest(Message):
    __msgtype__ = "zenros_msgs/GetTopicTypesRequest"


class GetTopicTypesResponse(Message):
    __msgtype__ = "zenros_msgs/GetTopicTypesResponse"
    topics: list[TopicType] = msgspec.field(default_factory=list)


class GetPublishedTopicsRequest(Message):
    __msgtype__ = "zenros_msgs/GetPublishedTopicsRequest"
    subgraph: str = "/"


class GetPublishedTopicsResponse(Message):
    __msgtype__ = "zenros_msgs/GetPublishedTopicsResponse"
    topics: list[TopicType] = msgspec.field(default_factory=list)


GetSystemState: ServiceType = define_service(
    "zenros_msgs/GetSystemState", GetSystemStateRequest, GetSystemStateResponse
)
LookupNode: ServiceType = define_service(
    "zenros_msgs/LookupNode", LookupNodeRequest, LookupNodeResponse
)
GetTopicTypes: ServiceType = define_service(
    "zenros_msgs/GetTopicTypes", GetTopicTypesRequest, GetTopicTypesResponse
)
GetPublishedTopics: ServiceType = define_service(
    "zenros_msgs/GetPublishedTopics", GetPublishedTopicsRequest, GetPublishedTopicsResponse
)


# ---------------------------------------------------------------- replicas


class ParamRows(Message):
    """Rows a replica committed, pushed to the others (who merge them)."""

    __msgtype__ = "zenros_msgs/ParamRows"
    __bulk__ = True
    source: str = ""
    entries: list[Entry] = msgspec.field(default_factory=list)


class SyncRequest(Message):
    """Anti-entropy: the asker's id and digest; replicas that differ send all their rows."""

    __msgtype__ = "zenros_msgs/SyncRequest"
    source: str = ""
    digest: str = ""


class SyncResponse(Message):
    __msgtype__ = "zenros_msgs/SyncResponse"
    __bulk__ = True
    source: str = ""
    digest: str = ""
    entries: list[Entry] = msgspec.field(default_factory=list)


Sync: ServiceType = define_service("zenros_msgs/Sync", SyncRequest, SyncResponse)
