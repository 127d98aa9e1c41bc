"""The ASR board: outputs 0-3 set all or none, inputs 4-7 refused, PWM and servo limits, the
servos turning at their speed, the update rate; the device's state and service."""

from __future__ import annotations

import pytest
from zenros.msgs.zenros_msgs import SetAsrBoardRequest
from zenros.services.chassis.asr_board import AsrBoard, AsrError
from zenros.services.chassis.devices import AsrDevice


def test_outputs_pwm_and_servos_within_the_boards_limits() -> None:
    board = AsrBoard(servo_speed=100.0)
    assert board.set_io({0: True, 3: True}, now=0.0)
    assert board.io == [True, False, False, True] + [False] * 4
    assert not board.set_io({0: True}, now=1.0)  # no change
    for levels, words in (({5: True}, "port 5 is an input"), ({9: True}, "no port 9"),
                          ({0: True, 6: False}, "port 6 is an input"),
                          ({1: 1}, "true or false"), ({}, "at least one")):
        with pytest.raises(AsrError, match=words):
            board.set_io(levels, now=2.0)  # type: ignore[arg-type]
    assert board.io[:4] == [True, False, False, True]  # all or none
    with pytest.raises(AsrError, match="at most 100 updates a second"):
        board.set_io({1: True}, now=1.005)
    board.set_pwm(2, 1000, 25, now=3.0)
    assert (board.pwm_freq, board.pwm_percent) == ([0, 0, 1000, 0], [0, 0, 25, 0])
    for args, words in (((4, 10, 10), "no channel 4"), ((0, 200_000, 10), "freq must be"),
                        ((0, 10, 101), "percent must be 0-100")):
        with pytest.raises(AsrError, match=words):
            board.set_pwm(*args, now=4.0)
    board.set_servo(1, 180.0, now=5.0)
    assert board.moving
    assert not board.step(0.5) and board.servo_angle[1] == pytest.approx(140.0)
    assert board.step(0.5) and board.servo_angle[1] == 180.0 and not board.moving
    with pytest.raises(AsrError, match="angle must be 0-180"):
        board.set_servo(0, 181.0, now=6.0)


def test_the_device_serves_and_publishes_the_board() -> None:
    from test_chassis_actuators import build_device

    device, (chassis, node) = build_device(AsrDevice, {"camera_rate": 0.0})
    assert node.publishers["asr/state"].sent[-1].io == [False] * 8  # latched at start
    setb = node.services["asr/set"]
    ok = setb(SetAsrBoardRequest(kind="io", ports=[2], levels=[True]))
    assert ok.success and ok.state.io[2] and node.publishers["asr/state"].sent[-1].io[2]
    bad = setb(SetAsrBoardRequest(kind="io", ports=[2, 3], levels=[True]))
    assert not bad.success and "2 ports but 1 levels" in bad.message
    unknown = setb(SetAsrBoardRequest(kind="laser"))
    assert not unknown.success and "not one of io, pwm, servo" in unknown.message
    import time
    time.sleep(0.011)  # the board's 100 updates a second
    servo = setb(SetAsrBoardRequest(kind="servo", port=0, angle=0.0))
    assert servo.success, servo.message
    for _ in range(30):  # 90 degrees at 300 deg/s: 0.3 s
        chassis.step(0.02)
    assert device.state().servo_angle[0] == 0.0 and device.changed()
    device.publish(device.state().header.stamp)
    assert node.publishers["asr/state"].sent[-1].servo_angle[0] == 0.0 and not device.changed()
    off, (_, bare) = build_device(AsrDevice, {"camera_rate": 0.0, "asr_board": False})
    assert off.rate == 0 and "asr/set" not in bare.services
