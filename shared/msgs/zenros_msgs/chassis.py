"""zenros_msgs for the chassis service (see DESIGN.md, "Robot interfaces").

- ``zenros_msgs/ChassisState`` on ``chassis/state``: e-stop, bumper, dock and charge flags,
  the dead-man state, and the simulator's requested and achieved real-time factor.
- ``zenros_msgs/Teleport`` (``sim/teleport``): set the robot's true pose in ``map``.
- ``zenros_msgs/SetObstacles`` (``sim/set_obstacles``): add, move, remove or replace the
  movable circles and boxes of the simulated world.
- ``zenros_msgs/IoState`` on ``chassis/io`` (latched): the IO ports' levels.
- ``zenros_msgs/SetIo`` (``chassis/set_io``): set one output of the main board or the
  extension board.
- ``zenros_msgs/ActuatorState`` on ``actuators/state`` and ``zenros_msgs/MoveActuator``
  (``actuators/move``): the slide rail, the jacking lift and its rotation.
- ``zenros_msgs/WindInfo`` on ``wind``: the wind sensor's speed, gust maximum, Beaufort
  level and direction (an outdoor robot's; the simulated one's is still air by default).
- ``zenros_msgs/AsrBoardState`` on ``asr/state`` (latched) and ``zenros_msgs/SetAsrBoard``
  (``asr/set``): the ASR (voice) board's IO, PWM and servo outputs.
- ``zenros_msgs/CalibrationState`` on ``calibration/state`` (latched) and
  ``zenros_msgs/Calibrate`` (``calibration/command``): the IMU's gyro bias and the laser's
  mount, measured by the robot and applied when the user says so.
- ``chassis/set_estop`` uses ``std_srvs/SetBool`` (``data: true`` engages the latched e-stop).
"""

from __future__ import annotations

from typing import Literal

import msgspec

from ...message import Message, define_service
from ..geometry_msgs import Pose2D
from ..std_msgs import Header

__all__ = [
    "ActuatorState",
    "AsrBoardState",
    "Calibrate",
    "CalibrateRequest",
    "CalibrateResponse",
    "CalibrationState",
    "ChassisState",
    "IoState",
    "MoveActuator",
    "MoveActuatorRequest",
    "MoveActuatorResponse",
    "Obstacle",
    "SetAsrBoard",
    "SetAsrBoardRequest",
    "SetAsrBoardResponse",
    "SetIo",
    "SetIoRequest",
    "SetIoResponse",
    "SetObstacles",
    "SetObstaclesRequest",
    "SetObstaclesResponse",
    "Teleport",
    "TeleportRequest",
    "TeleportResponse",
    "WindInfo",
]


class ChassisState(Message):
    """The base's safety and power flags, published on ``chassis/state`` (stamped in sim time).

    ``cmd_timeout`` is true while the dead-man stop holds (no valid ``cmd_vel`` for 0.5 s).
    ``speed`` is the requested real-time factor (1.0 follows the wall clock) and
    ``real_time_factor`` the one achieved over the last second; it is lower than ``speed``
    when the machine cannot keep up (the sim slows down rather than skip physics steps).
    """

    __msgtype__ = "zenros_msgs/ChassisState"
    header: Header = msgspec.field(default_factory=Header)
    estop: bool = False
    bumper: bool = False
    docked: bool = False
    charging: bool = False
    cmd_timeout: bool = True
    speed: float = 1.0
    real_time_factor: float = 0.0
    battery_percentage: float = 0.0


class Obstacle(Message):
    """A movable obstacle in the ``map`` frame: a circle (``radius``) or a box.

    A box is ``size_x`` by ``size_y`` metres centred on (x, y), turned by ``theta``
    (radians, counter-clockwise). ``id`` names it for later moves and removal.
    """

    __msgtype__ = "zenros_msgs/Obstacle"
    id: str = ""
    shape: Literal["circle", "box"] = "circle"
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    radius: float = 0.0
    size_x: float = 0.0
    size_y: float = 0.0


class SetObstaclesRequest(Message):
    """Change the movable obstacles.

    ``op``:
      - ``set`` (default): add each obstacle, or move/reshape the one with the same id;
      - ``remove``: remove the obstacles named in ``ids`` (and those in ``obstacles``);
      - ``replace``: the obstacles become exactly ``obstacles``;
      - ``clear``: remove them all.
    """

    __msgtype__ = "zenros_msgs/SetObstaclesRequest"
    op: Literal["set", "remove", "replace", "clear"] = "set"
    obstacles: list[Obstacle] = msgspec.field(default_factory=list)
    ids: list[str] = msgspec.field(default_factory=list)


class SetObstaclesResponse(Message):
    """Whether the change was applied, and the obstacles now in the world."""

    __msgtype__ = "zenros_msgs/SetObstaclesResponse"
    success: bool = False
    message: str = ""
    obstacles: list[Obstacle] = msgspec.field(default_factory=list)


class TeleportRequest(Message):
    """Put the robot at ``pose`` (x, y, theta in ``map``); it stops there."""

    __msgtype__ = "zenros_msgs/TeleportRequest"
    pose: Pose2D = msgspec.field(default_factory=Pose2D)


class TeleportResponse(Message):
    """``success`` false (with the reason) when the pose is outside the map or blocked."""

    __msgtype__ = "zenros_msgs/TeleportResponse"
    success: bool = False
    message: str = ""


Teleport = define_service("zenros_msgs/Teleport", TeleportRequest, TeleportResponse)
SetObstacles = define_service(
    "zenros_msgs/SetObstacles", SetObstaclesRequest, SetObstaclesResponse
)


class IoState(Message):
    """The IO ports' levels (0 low, 1 high), published latched on ``chassis/io``.

    ``outputs``: the main board's outputs out1..out3 (index 0 is out1). ``ext_outputs``
    (ports 0..7) and ``ext_inputs`` (0..15): the extension IO board, empty when the robot
    has none. Published on every change and once a second.
    """

    __msgtype__ = "zenros_msgs/IoState"
    header: Header = msgspec.field(default_factory=Header)
    outputs: list[int] = msgspec.field(default_factory=list)
    ext_outputs: list[int] = msgspec.field(default_factory=list)
    ext_inputs: list[int] = msgspec.field(default_factory=list)


class SetIoRequest(Message):
    """Set output ``port`` of ``board`` to ``level`` (0 or 1).

    ``board`` ``main``: ports 1..3 (out1..out3); ``ext``: the extension board, ports 0..7.
    """

    __msgtype__ = "zenros_msgs/SetIoRequest"
    board: str = "main"
    port: int = 1
    level: int = 0


class SetIoResponse(Message):
    """``success`` false with the reason for an unknown board, port or level; ``state``
    is the IO state after the request."""

    __msgtype__ = "zenros_msgs/SetIoResponse"
    success: bool = False
    message: str = ""
    state: IoState = msgspec.field(default_factory=IoState)


SetIo = define_service("zenros_msgs/SetIo", SetIoRequest, SetIoResponse)


class WindInfo(Message):
    """The wind sensor's reading, published at 1 Hz on ``wind``.

    ``current_speed``: m/s now; ``max_speed``: the strongest gust (m/s) of the last 10
    minutes; ``level``: the Beaufort force of ``current_speed`` (0 calm .. 12 hurricane);
    ``direction``: degrees, where the wind blows from, clockwise from north (the map's +y).
    """

    __msgtype__ = "zenros_msgs/WindInfo"
    header: Header = msgspec.field(default_factory=Header)
    current_speed: float = 0.0
    max_speed: float = 0.0
    level: float = 0.0
    direction: float = 0.0


class ActuatorState(Message):
    """The actuators' axes (``slide``, ``jacking``, ``jacking_rotation``), published on
    ``actuators/state`` at 10 Hz and when a move ends; ``actuators/joint_states``
    (sensor_msgs/JointState) carries the same positions for ROS tools.

    Per axis, index for index: ``position`` (m; rad for the rotation), ``velocity``,
    ``low``/``high`` (its travel), ``max_speed``, ``zero_status`` (0 homing, 1 homed, -1 homing error),
    ``moving``, ``fault`` (empty, or why its last move stopped short: a speed move that
    reached an end of the travel).
    """

    __msgtype__ = "zenros_msgs/ActuatorState"
    header: Header = msgspec.field(default_factory=Header)
    name: list[str] = msgspec.field(default_factory=list)
    position: list[float] = msgspec.field(default_factory=list)
    velocity: list[float] = msgspec.field(default_factory=list)
    low: list[float] = msgspec.field(default_factory=list)
    high: list[float] = msgspec.field(default_factory=list)
    max_speed: list[float] = msgspec.field(default_factory=list)
    zero_status: list[int] = msgspec.field(default_factory=list)
    moving: list[bool] = msgspec.field(default_factory=list)
    fault: list[str] = msgspec.field(default_factory=list)


class MoveActuatorRequest(Message):
    """Move axis ``name`` in ``mode`` (the robot API's codes, docs/robot-api.md §9.2
    ``slide_action``):

    - ``MODE_POSITION`` (the default): to ``position`` at ``speed`` (0: its default);
    - ``MODE_SPEED``: at ``speed`` (signed; 0: its default, upwards) for ``duration`` s;
    - ``MODE_HOME``: back to its home switch; ``MODE_STOP`` (or ``stop``): stop where it is.
    """

    __msgtype__ = "zenros_msgs/MoveActuatorRequest"
    name: str = ""
    position: float = 0.0
    speed: float = 0.0
    stop: bool = False
    mode: int = 3
    duration: float = 0.0

    MODE_HOME = 0
    MODE_SPEED = 1
    MODE_STOP = 2
    MODE_POSITION = 3


class MoveActuatorResponse(Message):
    """``success`` false with the reason in ``message`` (past the travel, too fast, not
    homed, an unknown axis); ``state``: the axes after the request."""

    __msgtype__ = "zenros_msgs/MoveActuatorResponse"
    success: bool = False
    message: str = ""
    state: ActuatorState = msgspec.field(default_factory=ActuatorState)


MoveActuator = define_service("zenros_msgs/MoveActuator", MoveActuatorRequest,
                              MoveActuatorResponse)


class AsrBoardState(Message):
    """The ASR (voice) board, published latched on ``asr/state`` at every change and at 10 Hz
    while a servo turns: ``io`` ports 0-7 (0-3 outputs, 4-7 inputs), PWM channels 0-3
    (``pwm_freq`` Hz, 0 off; ``pwm_percent`` duty), servos 0-3 (``servo_angle`` now and
    ``servo_target``, degrees 0-180)."""

    __msgtype__ = "zenros_msgs/AsrBoardState"
    header: Header = msgspec.field(default_factory=Header)
    io: list[bool] = msgspec.field(default_factory=list)
    pwm_freq: list[int] = msgspec.field(default_factory=list)
    pwm_percent: list[int] = msgspec.field(default_factory=list)
    servo_angle: list[float] = msgspec.field(default_factory=list)
    servo_target: list[float] = msgspec.field(default_factory=list)


class SetAsrBoardRequest(Message):
    """``kind`` ``io``: outputs ``ports`` to ``levels`` (index for index, all or none);
    ``pwm``: channel ``port`` at ``freq`` Hz and ``percent`` duty; ``servo``: servo ``port`` to
    ``angle`` degrees."""

    __msgtype__ = "zenros_msgs/SetAsrBoardRequest"
    kind: str = "io"
    ports: list[int] = msgspec.field(default_factory=list)
    levels: list[bool] = msgspec.field(default_factory=list)
    port: int = 0
    freq: int = 0
    percent: int = 0
    angle: float = 0.0


class SetAsrBoardResponse(Message):
    """``success`` false with the reason in ``message``; ``state``: the board after it."""

    __msgtype__ = "zenros_msgs/SetAsrBoardResponse"
    success: bool = False
    message: str = ""
    state: AsrBoardState = msgspec.field(default_factory=AsrBoardState)


SetAsrBoard = define_service("zenros_msgs/SetAsrBoard", SetAsrBoardRequest,
                             SetAsrBoardResponse)


class CalibrationState(Message):
    """One calibration (``device``: ``imu`` or ``laser``), latched on ``calibration/state`` at
    every change and at 2 Hz while it runs.

    ``state``: ``FREE`` (none running; the last result, if any, applied or dropped),
    ``CALIBRATING`` (measuring; ``progress`` 0..1), ``CALIBRATED`` (a result waits for
    ``complete``), ``FAILED`` (``message`` says why). ``accuracy`` 0..100 rates the result
    (100: the measurements agree exactly); ``values`` and ``names`` are the estimate (the
    IMU: ``gyro_bias_z`` rad/s; the laser: its mount ``x``, ``y`` m and ``yaw`` rad on the
    base), ``applied`` what is in force now."""

    __msgtype__ = "zenros_msgs/CalibrationState"
    header: Header = msgspec.field(default_factory=Header)
    device: str = ""
    state: str = "FREE"
    progress: float = 0.0
    accuracy: float = 0.0
    message: str = ""
    names: list[str] = msgspec.field(default_factory=list)
    values: list[float] = msgspec.field(default_factory=list)
    applied: list[float] = msgspec.field(default_factory=list)


class CalibrateRequest(Message):
    """``command`` ``start``, ``cancel``, ``complete`` (apply a ``CALIBRATED`` result) or
    ``status`` of the ``device``'s calibration (``imu``, ``laser``)."""

    __msgtype__ = "zenros_msgs/CalibrateRequest"
    device: str = ""
    command: str = "status"


class CalibrateResponse(Message):
    """``success`` false with the reason in ``message``; ``state``: the calibration after it."""

    __msgtype__ = "zenros_msgs/CalibrateResponse"
    success: bool = False
    message: str = ""
    state: CalibrationState = msgspec.field(default_factory=CalibrationState)


Calibrate = define_service("zenros_msgs/Calibrate", CalibrateRequest, CalibrateResponse)
