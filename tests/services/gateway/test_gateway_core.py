"""Pure pieces of the gateway: dead-man, status composition, config, tokens, settings,
the docs/robot-api.md §6.6/§6.8 text formats and the WebSocket slot."""

from __future__ import annotations

import asyncio
from pathlib import Path

import msgspec
import pytest
from zenros.services.gateway.http.path_data import (
    format_areas,
    format_nav_points,
    format_walls,
    parse_areas,
    parse_nav_points,
    parse_points,
    parse_walls,
)
from zenros.services.gateway.ports.topic_hub import Slot
from zenros.services.gateway.state.config import GatewayConfig, load_config
from zenros.services.gateway.state.deadman import DeadMan
from zenros.services.gateway.state.settings import Settings, SettingsPatch
from zenros.services.gateway.state.status import (
    GoalState,
    RobotState,
    compose_status,
    system_status_name,
)
from zenros.services.gateway.state.tokens import TokenStore


class Clock:
    t = 0.0

    def __call__(self) -> float:
        return self.t


def test_deadman_holds_then_stops_once() -> None:
    clock = Clock()
    d = DeadMan(0.5, clock)
    assert d.tick() is None
    d.command(0.2, 0.0, 0.1)
    assert d.tick() == (0.2, 0.0, 0.1) and d.current() == (0.2, 0.0, 0.1)
    clock.t = 0.49
    assert d.tick() == (0.2, 0.0, 0.1)
    clock.t = 0.6
    assert d.current() == (0.0, 0.0, 0.0)
    assert d.tick() == (0.0, 0.0, 0.0)
    assert d.tick() is None


def test_deadman_calls_on_arm_for_the_first_command_after_a_quiet_tick() -> None:
    clock = Clock()
    d = DeadMan(0.5, clock)
    armed: list[int] = []
    d.on_arm = lambda: armed.append(1)
    d.command(0.2, 0.0, 0.0)
    assert armed == []  # the ticker never stopped: nothing to start
    assert d.tick() == (0.2, 0.0, 0.0)
    clock.t = 0.6
    assert d.tick() == (0.0, 0.0, 0.0)
    assert armed == []
    assert d.tick() is None  # quiet: the ticker may stop now
    d.command(0.1, 0.0, 0.0)
    d.command(0.1, 0.0, 0.0)
    assert armed == [1]  # once, not for each command while it runs
    assert d.tick() == (0.1, 0.0, 0.0)


def test_compose_status_and_names() -> None:
    s = RobotState(voltage=37.0, speed_x=0.1, charging=True)
    st = compose_status(s, 5, 1_500_000_000_250, now=0.0)
    assert st.header.seq == 5 and st.header.stamp.secs == 1500 and st.header.stamp.nsecs == 250
    assert st.visualStatus == -1 and st.currentPosX == -1 and st.chargeStatus == 1
    assert system_status_name(st) == "Free"
    s.nav_open, s.pose, s.pose_time = True, (1.0, 2.0, 0.5), 10.0
    s.goal = GoalState(num_id=3, status=1, distance=2.0, angle_status=0)
    st = compose_status(s, 6, 0, now=11.0)
    assert (st.visualStatus, st.currentPosX, st.targetNumID, st.navStatus) == (1, 1.0, 3, 1)
    assert system_status_name(st) == "Navigating"
    assert compose_status(s, 7, 0, now=20.0).visualStatus == 2  # pose gone stale: lost
    s.mapping = True
    assert system_status_name(compose_status(s, 8, 0, now=11.0)) == "Mapping"
    s.mapping, s.nav_open, s.busy = False, False, True
    assert system_status_name(compose_status(s, 9, 0, now=11.0)) == "Busy"


def test_config_file(tmp_path: Path) -> None:
    assert load_config(tmp_path / "missing.json") == GatewayConfig()
    f = tmp_path / "config.json"
    f.write_text('{"username": "u", "no_token_check": true, "extra": 1}')
    cfg = load_config(f)
    assert cfg.username == "u" and cfg.no_token_check and cfg.password == "admin"
    f.write_text('{"no_token_check": "yes"}')
    with pytest.raises(ValueError, match="no_token_check"):
        load_config(f)
    f.write_text("{nope")
    with pytest.raises(ValueError, match="not JSON"):
        load_config(f)


def test_tokens() -> None:
    store = TokenStore(GatewayConfig(), capacity=2)
    assert store.issue("admin", "x") is None
    a, _b, c = (store.issue("admin", "admin") for _ in range(3))
    assert a and len(a) == 32 and store.problem(c) is None
    assert store.problem(a) == "invalid token"  # the oldest was forgotten
    assert "missing token" in (store.problem(None) or "")
    assert TokenStore(GatewayConfig(no_token_check=True)).problem(None) is None


def test_settings_persist_and_reset(tmp_path: Path) -> None:
    s = Settings(tmp_path / "s.json")
    s.update(msgspec.convert({"auto_charge": True, "navigation_speed": 1.5}, SettingsPatch))
    again = Settings(tmp_path / "s.json")
    assert again.current.auto_charge and again.current.navigation_speed == 1.5
    again.reset("auto_charge")
    assert not Settings(tmp_path / "s.json").current.auto_charge
    with pytest.raises(KeyError):
        again.reset("nope")


def test_path_data_round_trips_and_refusals() -> None:
    pts = parse_nav_points("0.5 -1 0 1.57 0.1 0.1 0 door\n2 2 0 0 0.1 0.1 1\n")
    assert pts[0].name == "door" and pts[1].direction == 1
    assert format_nav_points(pts) == "0.5 -1 0 1.57 0.1 0.1 0 door\n2 2 0 0 0.1 0.1 1\n"
    assert [p.x for p in parse_points("1 2 0\n\n3 4 0\n")] == [1.0, 3.0]
    walls = parse_walls("0 0\n1 0\n\n2 2\n2 3\n")
    assert len(walls) == 2 and format_walls(walls) == "0 0\n1 0\n\n2 2\n2 3\n"
    areas = parse_areas("9.89 19.98 12.03 20.96\n")
    assert format_areas(areas) == "9.89 19.98 12.03 20.96\n"
    for fn, text, word in [(parse_points, "1 2\n", "line 1"),
                           (parse_points, "1 x 0\n", "not a number"),
                           (parse_nav_points, "1 2 0 0 0 0 0.5\n", "direction"),
                           (parse_nav_points, "1 2 inf 0 0 0 0\n", "finite"),
                           (parse_walls, "1 1\n", "at least 2 points"),
                           (parse_areas, "1 1 1 5\n", "no area")]:
        with pytest.raises(ValueError, match=word):
            fn(text)


async def test_slot_keeps_only_the_newest() -> None:
    slot = Slot(asyncio.get_running_loop())
    for i in range(5):
        slot.put(str(i))
    assert await slot.get() == "4" and slot.dropped == 4
    waiter = asyncio.create_task(slot.get())
    await asyncio.sleep(0)
    slot.put("x")
    assert await asyncio.wait_for(waiter, 1) == "x"
