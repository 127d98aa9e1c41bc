"""`Robot`: one robot's side of the gateway: its state, its ports on a node of its namespace
and the REST `Api` over them; `RobotView`, the node a fleet gateway builds one robot on."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from zenros.context import Context as ZenrosContext
from zenros.errors import ConfigError
from zenros.msgs.std_msgs import String
from zenros.names import validate_namespace
from zenros.node import Node
from zenros.param_client import ParameterClient

from .http.api import Api
from .http.app import build_api
from .http.context import Context
from .ports.asr_link import AsrLink
from .ports.audio_recordings import AudioRecordings
from .ports.blockly_link import BlocklyLink
from .ports.calibration_link import CalibrationLink
from .ports.config_service import ConfigService
from .ports.coverage_link import CoverageLink
from .ports.elevator_link import ElevatorLink
from .ports.fs_sandbox import FileRoot
from .ports.host_commands import HostCommands
from .ports.host_link import HostLink
from .ports.io_link import IoLink
from .ports.media_service import MediaService
from .ports.nav_actions import NavActions
from .ports.nav_services import NavServices
from .ports.people_link import PeopleLink
from .ports.ptz_link import OnvifAddress, PtzLink
from .ports.robot_topics import RobotTopics
from .ports.slam_link import SlamLink
from .ports.snapshots import Snapshots
from .ports.tasks_link import TasksLink
from .ports.topic_hub import TopicHub
from .ports.updater import Updater
from .ports.videos import Videos
from .state.config import GatewayConfig
from .state.core import Core, make_identity
from .state.settings import Settings
from .state.speech import AudioStore, Speech
from .state.tokens import TokenStore
from .state.voices import VoiceStore

__all__ = ["Robot", "RobotOptions", "RobotView", "robot_name"]

CONFIG_WHERE = ("the gateway's configuration file (its config_file parameter; "
                "$ZENROS_HOME/galileo_api/config.json by default)")


def robot_name(name: object) -> str:
    """``name`` as a fleet's robot name: a namespace of one chunk (``robot1``, ``/robot1``).

    Raises:
        ConfigError: not a string, empty, several chunks, or not a valid namespace.
    """
    text = name.strip("/") if isinstance(name, str) else ""
    if not text or "/" in text:
        raise ConfigError(f"robot name {name!r}: expected a namespace of one chunk, "
                          "e.g. robot1")
    try:
        validate_namespace("/" + text)
    except ValueError as exc:
        raise ConfigError(f"robot name {name!r}: {exc}") from exc
    return text


@dataclass(frozen=True)
class RobotOptions:
    """What every robot of one gateway shares: its configuration and its limits."""

    config: GatewayConfig
    tokens: TokenStore
    files: FileRoot
    version: str
    rest_port: int
    status_rate: float = 30.0
    deadman_timeout: float = 0.5
    startup_grace: float = 30.0
    max_body: int = 64 * 1024
    launch_control: str = "/launch"
    tls_cert: str = ""


class Robot:
    """The state (`Core`), the ports and the `Api` of the robot in ``node``'s namespace.

    Args:
        node: a node in the robot's namespace; the ports' endpoints are its own.
        data_dir: where this robot's settings and audio list live.
        options: what the gateway's robots share (tokens, configuration, file root).
    """

    def __init__(self, node: Node, data_dir: Path, options: RobotOptions) -> None:
        self.name = node.namespace.strip("/")
        self.namespace = node.namespace
        self.core = Core(options.config, Settings(data_dir / "settings.json"),
                         make_identity(node.namespace, options.version, options.rest_port),
                         options.deadman_timeout, options.startup_grace, options.tokens)
        self.topics = RobotTopics(node, self.core, options.status_rate)
        self.tasks = TasksLink(node, self.core.presence)
        self.hub = TopicHub(node)
        self.nav_actions = NavActions(node, self.core)
        self.nav_actions.tasks = self.tasks
        self.core.nav = self.nav_actions
        self.nav_services = NavServices(node, self.core.presence)
        presence = self.core.presence
        presence.watch("nav", self.nav_actions.available)
        presence.watch("tasks", self.tasks.available)
        node.on_close(node.context.graph.add_listener(lambda ev, tok: presence.refresh()))
        self.core.services["maps"] = self.nav_services.maps
        self.io = IoLink(node)
        self.speech = Speech(lambda: node.now().nanoseconds / 1e9)
        self.audio = AudioStore(data_dir / "audio.json")
        self.slam = SlamLink(node, self.core, lambda: self.nav_services.grid)
        self.videos = Videos(node, data_dir / "Videos")
        node.on_close(self.videos.close)  # a recording under way keeps what it has
        self.snapshots = Snapshots(node, data_dir / "Pictures")
        self.audios = AudioRecordings(node, data_dir / "Audios")
        self.media = MediaService(node, self.snapshots, self.videos,  # media/save, for tasks
                                  self.audios)
        self.config = ConfigService(node, self.core.settings)  # system/set_config, for tasks
        self.context = Context(
            core=self.core, tasks=self.tasks, nav_actions=self.nav_actions,
            nav_services=self.nav_services, io=self.io, topics=self.topics, hub=self.hub,
            params=ParameterClient(node.context, node=node.fqn), files=options.files,
            speech=self.speech, audio=self.audio,
            coverage=CoverageLink(node, self.core.presence), slam=self.slam,
            snapshots=self.snapshots,
            host=HostLink(node, options.launch_control), asr=AsrLink(node),
            calibration=CalibrationLink(node),
            people=PeopleLink(node, self.speak, lambda: node.now().nanoseconds / 1e9),
            ptz=PtzLink(node, _onvif_address(options.config), lambda: self.core.identity.port),
            videos=self.videos, voices=VoiceStore(data_dir / "voices"),
            commands=_host_commands(options.config.host_commands),
            updater=Updater(options.config.update_source, options.config.update_package,
                            options.config.allow_update, data_dir),
            tls_cert=options.tls_cert, blockly=BlocklyLink(node, self.core.presence),
            elevators=ElevatorLink(node))
        self.api: Api = build_api(self.context, options.max_body, node.logger)

    def speak(self, text: str) -> None:
        """Say ``text`` (its alias if it has one) as ``PUT /system/tts`` does: on ``tts``."""
        said = self.audio.apply_alias(text)
        self.speech.say(said)
        self.topics.tts_pub.publish(String(data=said))


def _onvif_address(config: GatewayConfig) -> OnvifAddress:
    if not 0 <= config.onvif_port <= 65535:
        raise ConfigError(f"{CONFIG_WHERE}: onvif_port must be 0 (the REST port) to 65535, "
                          f"got {config.onvif_port}")
    return OnvifAddress(config.onvif_ip, config.onvif_port, config.onvif_username,
                        config.onvif_password)


def _host_commands(table: dict[str, list[str]]) -> HostCommands:
    try:
        return HostCommands(table, CONFIG_WHERE)
    except ValueError as exc:
        raise ConfigError(f"{CONFIG_WHERE}: {exc}") from exc


class RobotView(Node):
    """A fleet gateway's node for one robot (``/<robot>/gateway``, on the gateway's session):
    the robot's ports live on it, so their names resolve in the robot's namespace."""

    node_name = "gateway"
    uses_parameter_server = False  # it declares nothing: the fleet gateway holds the settings

    def __init__(self, namespace: str, context: ZenrosContext, data_dir: Path,
                 options: RobotOptions) -> None:
        self._data_dir = data_dir
        self._options = options
        super().__init__(namespace=namespace, context=context)

    def setup(self) -> None:
        self.robot = Robot(self, self._data_dir, self._options)
