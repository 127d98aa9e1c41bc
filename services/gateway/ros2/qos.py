"""ROS 2 (DDS) QoS <-> zenros QoS: reliability, durability (transient local = latched), depth.

DDS discovery does not carry a writer's history depth, so a topic from DDS gets ``depth``
(default 10) unless the writer's durability service names a larger keep-last depth.
"""

from __future__ import annotations

from cyclonedds.core import Policy, Qos
from zenros.qos import Durability, QoSProfile, Reliability

__all__ = ["dds_qos", "zenros_qos"]

_INFINITE = 9223372036854775807


def zenros_qos(qos: Qos, depth: int = 10) -> QoSProfile:
    """The zenros profile of a discovered DDS endpoint's QoS."""
    reliable = not repr(qos[Policy.Reliability]).startswith("Policy.Reliability.BestEffort")
    latched = repr(qos[Policy.Durability]).split("(")[0] in (
        "Policy.Durability.TransientLocal", "Policy.Durability.Transient",
        "Policy.Durability.Persistent")
    svc = qos[Policy.DurabilityService]
    if latched and svc is not None and isinstance(svc.history, Policy.History.KeepLast):
        depth = svc.history.depth
    return QoSProfile(depth=max(1, min(depth, 1000)),
                      reliability=Reliability.RELIABLE if reliable else Reliability.BEST_EFFORT,
                      durability=Durability.TRANSIENT_LOCAL if latched else Durability.VOLATILE)


def dds_qos(profile: QoSProfile, type_hash: str = "", *, writer: bool) -> Qos:
    """The DDS QoS of a zenros profile, as rmw_fastrtps would set it for a ROS 2 endpoint
    (``typehash=RIHS01_...;`` in USER_DATA, as ROS 2 Iron and later write it)."""
    policies = [
        Policy.Reliability.Reliable(max_blocking_time=100_000_000)
        if profile.reliability == Reliability.RELIABLE else Policy.Reliability.BestEffort,
        Policy.Durability.TransientLocal if profile.latched else Policy.Durability.Volatile,
        Policy.History.KeepLast(profile.depth),
        Policy.IgnoreLocal.Participant,  # never read back what this participant wrote
    ]
    if type_hash:
        policies.append(Policy.Userdata(f"typehash={type_hash};".encode()))
    if writer:
        policies.append(Policy.WriterDataLifecycle(autodispose=True))
    return Qos(*policies)
