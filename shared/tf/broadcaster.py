"""`TransformBroadcaster` (``/tf``) and `StaticTransformBroadcaster` (latched ``/tf_static``)."""

from __future__ import annotations

import threading
from collections.abc import Iterable
from typing import TYPE_CHECKING

from ..msgs.geometry_msgs import TransformStamped
from ..msgs.tf2_msgs import TFMessage
from ..qos import Durability, QoSProfile

if TYPE_CHECKING:
    from ..node import Node
    from ..pubsub import Publisher

__all__ = [
    "DYNAMIC_BROADCASTER_QOS",
    "STATIC_BROADCASTER_QOS",
    "StaticTransformBroadcaster",
    "TransformBroadcaster",
]

DYNAMIC_BROADCASTER_QOS = QoSProfile(depth=100)
"""``/tf``: reliable, volatile, depth 100 (tf2_ros's default)."""

STATIC_BROADCASTER_QOS = QoSProfile(depth=1, durability=Durability.TRANSIENT_LOCAL)
"""``/tf_static``: reliable, latched, depth 1; one message carries every static link."""

Transforms = TransformStamped | Iterable[TransformStamped]


def _as_list(transforms: Transforms) -> list[TransformStamped]:
    if isinstance(transforms, TransformStamped):
        return [transforms]
    out = list(transforms)
    for t in out:
        if not isinstance(t, TransformStamped):
            raise TypeError(f"expected TransformStamped messages, got {type(t).__name__}")
    return out


class TransformBroadcaster:
    """Sends dynamic links on ``/tf`` (tf2_ros.TransformBroadcaster).

    Args:
        node: the node that publishes (the links' authority).
        qos: the publisher's QoS (default reliable, depth 100).
    """

    def __init__(self, node: Node, qos: QoSProfile | int = DYNAMIC_BROADCASTER_QOS) -> None:
        self._node = node
        self._pub: Publisher[TFMessage] = node.create_publisher(TFMessage, "/tf", qos)

    def send_transform(self, transform: Transforms) -> None:
        """Publish one link or several (in one message).

        Raises:
            TypeError: something other than `TransformStamped` messages was given.
        """
        self._pub.publish(TFMessage(transforms=_as_list(transform)))

    sendTransform = send_transform  # tf2_ros's name

    def close(self) -> None:
        """Stop publishing (destroys the publisher)."""
        self._node.destroy(self._pub)


class StaticTransformBroadcaster:
    """Sends static links on latched ``/tf_static`` (tf2_ros.StaticTransformBroadcaster).

    The broadcaster keeps every link it was given, one per child frame (a new link for a
    child replaces the old one, as tf2's C++ broadcaster does), and each send republishes
    the whole set in one message. With depth-1 latching, a listener that joins later still
    gets every static link of this broadcaster.

    Args:
        node: the node that publishes.
        qos: the publisher's QoS (default reliable, transient local, depth 1).
    """

    def __init__(self, node: Node, qos: QoSProfile | int = STATIC_BROADCASTER_QOS) -> None:
        self._node = node
        self._pub: Publisher[TFMessage] = node.create_publisher(TFMessage, "/tf_static", qos)
        self._links: dict[str, TransformStamped] = {}
        self._lock = threading.Lock()

    def send_transform(self, transform: Transforms) -> None:
        """Add (or replace, by child frame) one link or several, then publish them all.

        Raises:
            TypeError: something other than `TransformStamped` messages was given.
        """
        new = _as_list(transform)
        with self._lock:
            for t in new:
                self._links[t.child_frame_id.removeprefix("/")] = t
            self._pub.publish(TFMessage(transforms=list(self._links.values())))

    sendTransform = send_transform  # tf2_ros's name

    @property
    def transforms(self) -> list[TransformStamped]:
        """The links this broadcaster holds, in the order they were first sent."""
        with self._lock:
            return list(self._links.values())

    def close(self) -> None:
        """Stop publishing; late joiners no longer get these links."""
        self._node.destroy(self._pub)
