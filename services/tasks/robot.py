"""`Robot`: what task actions need from the rest of the robot (nav, dock, maps, IO, actuators,
speech).

The tasks node implements it over zenros (actions and services of nav and chassis); unit
tests pass a double. Long calls take ``cancelled``, polled while they wait, and return an
`Outcome` with a reason.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal, NamedTuple, Protocol

from zenros.maps.maproute import Link
from zenros.msgs.zenros_msgs.blockly import BlocklyProgram

from .outcome import Outcome

if TYPE_CHECKING:
    from .elevator_link import ElevatorLink

__all__ = ["Feedback", "Outcome", "Robot"]

class Feedback(NamedTuple):
    """Where a navigating robot is and how far it still has to go (m)."""

    x: float
    y: float
    theta: float
    distance: float


class Robot(Protocol):
    elevators: ElevatorLink | None
    """The building's elevators (None: the tasks service knows no building)."""

    def now(self) -> float:
        """The node clock in seconds (simulated time when the robot runs on it)."""
        ...

    def nav_point(self, index: int, map_name: str, path_name: str) -> tuple[float, float, float]:
        """Nav point ``index`` of a path as (x, y, theta); LookupError if there is none.

        Empty ``map_name``: the current map; empty ``path_name``: the map's only path."""
        ...

    def navigate(self, x: float, y: float, theta: float, timeout: float,
                 feedback: Callable[[Feedback], None],
                 cancelled: Callable[[], bool]) -> Outcome:
        """Drive to (x, y, theta) in ``map``; ``timeout`` 0 means none."""
        ...

    def pass_through(self, x: float, y: float, theta: float, radius: float, timeout: float,
                     feedback: Callable[[Feedback], None],
                     cancelled: Callable[[], bool]) -> Outcome:
        """Drive toward (x, y, theta) in ``map``; complete once within ``radius`` m, the goal
        left running (the next goal replaces it; `stop_passing` stops it)."""
        ...

    def stop_passing(self) -> None:
        """Cancel the goal a completed `pass_through` left running, if it still runs."""
        ...

    def change_settings(self, settings: dict[str, Any], check_only: bool = False) -> Outcome:
        """Set ``/system/config`` keys (the gateway's settings), or only check them; an
        unknown key or a bad value is an error naming it."""
        ...

    def launch(self, launch_cmd: str, cancelled: Callable[[], bool]) -> tuple[Outcome, str]:
        """Start a launch file zenros ships, named by ``launch_cmd`` (``roslaunch <pkg>
        <file>.launch [name:=value ...]``), until its nodes are up: the outcome, and the key
        `stop_launch` takes ("" when nothing was started)."""
        ...

    def stop_launch(self, key: str) -> None:
        """Stop launch ``key`` and every process it started."""
        ...

    def charge(self, pose: tuple[float, float, float] | None, level: float, timeout: float,
               cancelled: Callable[[], bool]) -> Outcome:
        """Dock at ``pose`` (None: the map's charge pose) until charging, or ``level``."""
        ...

    def switch_map(self, name: str, path: str, start_index: int) -> Outcome:
        """Make map ``name`` current; relocalise at nav point ``start_index`` (>= 0)."""
        ...

    def current_map(self) -> str:
        """The map in use; LookupError when nav does not answer."""
        ...

    def point_connections(self) -> list[Link]:
        """The point connections (docs/robot-api.md §6.7); one whose point no longer exists is
        unavailable. LookupError when nav does not answer."""
        ...

    def pose(self) -> tuple[float, float, float] | None:
        """The robot's latest pose on the current map, if known."""
        ...

    def relocalise_landmarks(self) -> Outcome:
        """Fix the estimate on the reflectors in view (nav's ``relocalize_landmarks``):
        complete with what it matched, fail with why it could not."""
        ...

    def relocalise(self, x: float, y: float, theta: float) -> Outcome:
        """Tell localisation the robot is at (x, y, theta) now; complete once it agrees."""
        ...

    def drive(self, distance: float, speed: float, timeout: float,
              progress: Callable[[float], None], cancelled: Callable[[], bool]) -> Outcome:
        """Drive straight ``distance`` m (+ forward) at ``speed`` m/s without the planner;
        ``progress`` gets the metres travelled; ``timeout`` 0 means none."""
        ...

    def spin(self, angle: float, timeout: float, progress: Callable[[float], None],
             cancelled: Callable[[], bool]) -> Outcome:
        """Turn in place by ``angle`` rad (+ counter-clockwise); ``progress`` gets the
        radians turned."""
        ...

    def local_move_target(self, x: float, y: float, theta: float, frame_id: str,
                          xy_tolerance: float, yaw_tolerance: float, timeout: float,
                          start_rotate: bool, target_rotate: bool,
                          cancelled: Callable[[], bool]) -> Outcome:
        """A precise short move to (x, y, theta) in ``frame_id`` (map or base_link)."""
        ...

    def set_io(self, port: int, level: int) -> Outcome:
        """Set main-board output ``port`` (1..3) to ``level`` (0/1)."""
        ...

    def move_axis(self, axis: str, mode: int, target: float, speed: float, duration: float,
                  progress: Callable[[float], None],
                  cancelled: Callable[[], bool]) -> Outcome:
        """Move actuator ``axis`` (slide, jacking, jacking_rotation) in ``mode`` (0 homing,
        1 at ``speed`` for ``duration`` s, 2 stop, 3 to ``target`` at ``speed``) until it
        stops; ``progress`` gets the share done (0..1). A fault (a limit reached) is an
        error; cancelled stops the axis."""
        ...

    def ptz_move(self, x: float, y: float, zoom: float, progress: Callable[[float], None],
                 cancelled: Callable[[], bool]) -> Outcome:
        """Move the PTZ camera to ``x``, ``y`` (-1..1) and ``zoom`` (0..1) and wait until it
        stands there; ``progress`` gets the share of the way done. A refused value is an
        error; cancelled stops the camera where it is."""
        ...

    def save_media(self, kind: Literal["image", "video", "audio"], topic: str,
                   duration: float, filename: str, progress: Callable[[float], None],
                   cancelled: Callable[[], bool]) -> Outcome:
        """A snapshot (``kind`` image) or ``duration`` s of video of camera ``topic``, or of
        the microphone's sound (``audio``), into the robot's Pictures, Videos or Audios as
        ``filename`` (default: a timestamp), done once saved; a refusal (no camera, no
        microphone, a taken name) is an error with the reason."""
        ...

    def battery_percent(self) -> float | None:
        """The battery's charge, 0-100, if known."""
        ...

    def io_levels(self) -> tuple[list[int], list[int], list[int]]:
        """The IO levels (main-board outputs out1.., extension outputs, extension inputs);
        LookupError before the chassis has reported them."""
        ...

    def blockly_program(self, program_id: str) -> BlocklyProgram:
        """Blockly program ``program_id`` (docs/robot-api.md §10); LookupError if none."""
        ...

    def say(self, text: str) -> None:
        """Speak ``text`` (the simulated robot publishes it as text)."""
        ...

    def upload_map(self, server_id: str) -> Outcome:
        """Put the current map on schedule server ``server_id``."""
        ...

    def download_map(self, server_id: str, map_id: str) -> Outcome:
        """Get map ``map_id`` from schedule server ``server_id`` into the robot's maps."""
        ...
