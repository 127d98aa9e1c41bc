"""`execute`: an `ElevatorCommandRequest` applied to its `Car`, answered as a response."""

from __future__ import annotations

from zenros.msgs.zenros_msgs.elevator import ElevatorCommandRequest, ElevatorCommandResponse

from .car import Car, CarError

__all__ = ["execute"]


def execute(car: Car, req: ElevatorCommandRequest, now: float) -> ElevatorCommandResponse:
    """Do ``req`` on ``car`` at ``now`` (s): success with what was done, or success false
    with why not."""
    try:
        match req.command:
            case "call":
                done = car.call(req.robot, req.level, now)
            case "go":
                done = car.go(req.robot, req.level, now)
            case "release":
                done = car.release(req.robot, now)
            case "to_level":
                done = car.to_level(req.level, now)
            case "open":
                done = car.open(now)
            case "close":
                done = car.close(now)
    except CarError as exc:
        return ElevatorCommandResponse(success=False, message=str(exc))
    return ElevatorCommandResponse(success=True, message=done)
