"""The bridge's DDS participant, on a domain configured to match ROS 2 endpoints by type name.

ROS 2 matches a reader with a writer on the topic's type name (and, from Iron on, the RIHS01
hash in USER_DATA, which the bridge checks itself). Fast DDS 3 also sends XTypes type
information; cyclonedds 11 then fetches Fast DDS's type objects and refuses those with a
sequence (its collection element flags have both "try construct" bits zero, which the XTypes
spec calls invalid: ``ddsi_xt_type_init_impl with invalid type object``), and even when told to
accept them (``AllowInvalidTryConstruct``) finds them not assignable to the type built from
zenros's definition, so a LaserScan reader never matched an rclpy writer. ``IgnoreTypeInformation``
for the DDS vendors ROS 2 runs on makes the check the type-name check ROS 2 itself does.
"""

from __future__ import annotations

import os

from cyclonedds.core import DDSException
from cyclonedds.domain import Domain, DomainParticipant

__all__ = ["VENDORS", "open_participant"]

VENDORS = "1.1,1.15,1.16"  # RTI Connext, eProsima Fast DDS, Eclipse Cyclone DDS

_CONFIG = ("<CycloneDDS><Domain><Compatibility><IgnoreTypeInformation>"
           f"{VENDORS}</IgnoreTypeInformation></Compatibility></Domain></CycloneDDS>")


def open_participant(domain_id: int) -> tuple[Domain | None, DomainParticipant]:
    """A participant on ``domain_id``, and the domain this call created (None if the process
    already had one: it keeps that domain's configuration). The user's ``CYCLONEDDS_URI``
    comes first; the type-information setting is added after it."""
    config = ",".join(c for c in (os.environ.get("CYCLONEDDS_URI", ""), _CONFIG) if c)
    domain: Domain | None
    try:
        domain = Domain(domain_id, config)
    except DDSException:
        domain = None
    return domain, DomainParticipant(domain_id)
