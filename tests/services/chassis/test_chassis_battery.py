"""Battery: drain with time and motion, charge on the dock, full and empty."""

from __future__ import annotations

import pytest
from zenros.se2 import Pose2
from zenros.services.chassis.battery import Battery, BatteryConfig
from zenros.services.chassis.dock import Dock

CFG = BatteryConfig(capacity=10.0, idle_current=1.0, motion_current=4.0, turn_current=2.0,
                    charge_current=5.0, initial=0.5)


def test_drains_with_time_and_more_with_motion() -> None:
    idle, moving = Battery(CFG), Battery(CFG)
    idle.update(3600.0, 0.0, 0.0, docked=False)  # 1 A for an hour
    assert idle.charge == pytest.approx(4.0) and idle.current == pytest.approx(-1.0)
    moving.update(3600.0, 0.5, 0.5, docked=False)  # 1 + 2 + 1 A
    assert moving.charge == pytest.approx(1.0)
    assert not idle.charging and idle.percentage == pytest.approx(0.4)


def test_charges_while_docked_until_full_then_holds() -> None:
    b = Battery(CFG)
    b.update(360.0, 0.0, 0.0, docked=True)  # +5 - 1 = 4 A for 0.1 h
    assert b.charging and b.charge == pytest.approx(5.4)
    for _ in range(20):
        b.update(360.0, 0.0, 0.0, docked=True)
    assert b.full and not b.charging and b.percentage == pytest.approx(1.0)
    b.update(360.0, 0.0, 0.0, docked=True)
    assert b.percentage == pytest.approx(1.0) and b.current == 0.0
    b.update(360.0, 0.0, 0.0, docked=False)
    assert b.percentage < 1.0


def test_empty_stops_at_zero_and_voltage_follows() -> None:
    b = Battery(CFG)
    full_v = Battery(BatteryConfig(initial=1.0)).voltage
    b.update(10 * 3600.0, 1.0, 0.0, docked=False)
    assert b.empty and b.charge == 0.0 and b.voltage < full_v


def test_bad_config() -> None:
    with pytest.raises(ValueError, match="initial charge must be within 0..1"):
        BatteryConfig(initial=1.5)
    with pytest.raises(ValueError, match="battery capacity must be > 0"):
        BatteryConfig(capacity=0.0)


def test_docked_within_a_few_cm_and_degrees() -> None:
    d = Dock(Pose2(2.0, 1.0, -1.57), tolerance=0.05, yaw_tolerance=0.1)
    assert d.docked(Pose2(2.03, 0.98, -1.5))
    assert not d.docked(Pose2(2.06, 1.0, -1.57))
    assert not d.docked(Pose2(2.0, 1.0, -1.4))
    assert Dock(Pose2(0.0, 0.0, 3.1)).docked(Pose2(0.0, 0.0, -3.1))  # across +-pi
