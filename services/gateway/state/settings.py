"""`Settings`: the docs/robot-api.md §3.6 navigation configuration (``/system/config``), persisted
as JSON."""

from __future__ import annotations

import threading
from pathlib import Path
from typing import Annotated, Any

import msgspec

from .json_file import load_struct, save_struct

__all__ = ["RobotSettings", "Settings", "SettingsPatch"]

Speed = Annotated[float, msgspec.Meta(ge=0.0, le=5.0)]
Gain = Annotated[float, msgspec.Meta(ge=-1000.0, le=1000.0)]
Dist = Annotated[float, msgspec.Meta(ge=0.0, le=100.0)]
Percent = Annotated[float, msgspec.Meta(ge=0.0, le=100.0)]
Name = Annotated[str, msgspec.Meta(max_length=128)]


class RobotSettings(msgspec.Struct, forbid_unknown_fields=True):
    """The 6.x keys of §3.6 that the simulated robot keeps (``maps`` is filled from nav)."""

    default_map: Name = ""
    navigation_speed: Speed = 0.5
    max_control_speed: Speed = 1.0
    auto_charge: bool = False
    go_charge_percentage: Percent = 20.0
    slam_type: Annotated[str, msgspec.Meta(pattern="^(camera|lidar)$")] = "lidar"
    lf_linear_v: Speed = 0.5
    lf_theta_max: Speed = 1.0
    lf_k2: Gain = 1.0
    lf_kp: Gain = 1.0
    lf_ki: Gain = 0.0
    lf_kd: Gain = 0.0
    lf_look_ahead_dist: Dist = 0.6
    robot_radius: Dist = 0.25
    lf_xy_goal_tolerance: Dist = 0.1
    lf_yaw_goal_tolerance: Annotated[float, msgspec.Meta(ge=0.0, le=6.3)] = 0.2
    astar_path_changeability: bool = True
    lf_bar_distance_min: Dist = 0.4
    lf_forward_max_dist: Dist = 1.5
    lf_move_direction: Annotated[int, msgspec.Meta(ge=0, le=2)] = 0
    use_smooth_switch_map: bool = False


def _patch_type() -> type[Any]:
    fields = [(f.name, f.type | msgspec.UnsetType, msgspec.UNSET)
              for f in msgspec.structs.fields(RobotSettings)]
    return msgspec.defstruct("SettingsPatch", fields, forbid_unknown_fields=True)


SettingsPatch = _patch_type()
"""POST /system/config body: any subset of `RobotSettings`' keys."""

KEYS = tuple(f.name for f in msgspec.structs.fields(RobotSettings))


class Settings:
    """The current settings, written through to ``path`` (atomically) on every change."""

    def __init__(self, path: Path | None) -> None:
        self.path = path
        self._lock = threading.Lock()
        self.current = load_struct(path, RobotSettings)

    def as_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = msgspec.to_builtins(self.current)
        return out

    def update(self, patch: Any) -> dict[str, Any]:
        changes = {k: v for k, v in msgspec.structs.asdict(patch).items()
                   if v is not msgspec.UNSET}
        with self._lock:
            self.current = msgspec.structs.replace(self.current, **changes)
            self._save()
        return self.as_dict()

    def reset(self, key: str) -> None:
        if key not in KEYS:
            raise KeyError(key)
        with self._lock:
            default = getattr(RobotSettings(), key)
            self.current = msgspec.structs.replace(self.current, **{key: default})
            self._save()

    def _save(self) -> None:
        save_struct(self.path, self.current)
