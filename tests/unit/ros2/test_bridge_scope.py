"""The two ROS 2 bridges' shared parameters: the domain from ROS_DOMAIN_ID, and which names
they bridge (allow, deny; deny wins)."""

from __future__ import annotations

import pytest
from zenros.ros2.domain import BridgeScope, NameFilter


def test_deny_wins_and_an_empty_deny_denies_nothing() -> None:
    wanted = NameFilter(BridgeScope(allow="/robot1/.*", deny="/robot1/secret.*"))
    assert wanted("/robot1/odom") and not wanted("/robot1/secret_map")
    assert not wanted("/robot2/odom")  # the whole name must match allow
    assert NameFilter(BridgeScope())("/anything")


@pytest.mark.parametrize(("env", "domain"), [("7", 7), ("", 0), (None, 0)])
def test_the_domain_defaults_to_ros_domain_id(monkeypatch: pytest.MonkeyPatch,
                                              env: str | None, domain: int) -> None:
    if env is None:
        monkeypatch.delenv("ROS_DOMAIN_ID", raising=False)
    else:
        monkeypatch.setenv("ROS_DOMAIN_ID", env)
    assert BridgeScope().domain_id == domain
