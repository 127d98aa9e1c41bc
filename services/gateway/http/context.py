"""`Context`: what the REST handlers work on, the gateway's state and its ports, built once by
the node; a handler reads it as ``call.ctx`` and keeps nothing of its own."""

from __future__ import annotations

from dataclasses import dataclass

from zenros.param_client import ParameterClient

from ..ports.asr_link import AsrLink
from ..ports.blockly_link import BlocklyLink
from ..ports.calibration_link import CalibrationLink
from ..ports.coverage_link import CoverageLink
from ..ports.elevator_link import ElevatorLink
from ..ports.fs_sandbox import FileRoot
from ..ports.host_commands import HostCommands
from ..ports.host_link import HostLink
from ..ports.io_link import IoLink
from ..ports.nav_actions import NavActions
from ..ports.nav_services import NavServices
from ..ports.people_link import PeopleLink
from ..ports.ptz_link import PtzLink
from ..ports.robot_topics import RobotTopics
from ..ports.slam_link import SlamPort
from ..ports.snapshots import Snapshots
from ..ports.tasks_link import TasksLink
from ..ports.topic_hub import TopicHub
from ..ports.updater import Updater
from ..ports.videos import Videos
from ..state.core import Core
from ..state.speech import AudioStore, Speech
from ..state.voices import VoiceStore

__all__ = ["Context"]


@dataclass(frozen=True)
class Context:
    """The state and the ports, one field per thing a handler uses."""

    core: Core
    tasks: TasksLink
    nav_actions: NavActions
    nav_services: NavServices
    io: IoLink
    topics: RobotTopics
    hub: TopicHub
    params: ParameterClient
    files: FileRoot
    speech: Speech
    audio: AudioStore
    coverage: CoverageLink
    slam: SlamPort | None = None   # the mapping node's port (None: no mapping)
    snapshots: Snapshots | None = None  # the cameras' pictures (None: no robot node)
    voices: VoiceStore | None = None  # the voice packages (None: no robot node)
    videos: Videos | None = None  # the cameras' recordings (None: no robot node)
    asr: AsrLink | None = None  # the ASR board (None: no robot node)
    calibration: CalibrationLink | None = None  # the chassis's calibrations (None: no robot)
    ptz: PtzLink | None = None  # the PTZ (ONVIF) camera (None: no robot node)
    people: PeopleLink | None = None  # following and greeting people (None: no robot node)
    host: HostLink | None = None
    commands: HostCommands | None = None  # the operator's host commands (None: no robot)
    updater: Updater | None = None  # software updates (None: no robot node)
    blockly: BlocklyLink | None = None  # the Blockly programs (None: no robot node)
    elevators: ElevatorLink | None = None  # the building's elevators (None: no robot node)
    tls_cert: str = ""  # the REST server's certificate (empty: plain HTTP)  # the launch supervising the robot (None: no robot node)
