"""The charging dock: whether the robot sits on it (read by the battery and chassis/state)."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.se2 import Pose2

from ..device import Chassis, Device
from ..dock import Dock
from ..param_types import NonNegative, PoseList, pose_from

__all__ = ["DockDevice", "DockParameters"]


class DockParameters(msgspec.Struct, kw_only=True, frozen=True):
    dock_pose: PoseList = msgspec.field(default_factory=list)
    dock_tolerance: Annotated[NonNegative, Meta(
        description="docked within this distance of the dock pose (m)")] = 0.05
    dock_yaw_tolerance: Annotated[NonNegative, Meta(
        description="docked within this angle of the dock pose (rad)")] = 0.1

    def __post_init__(self) -> None:
        pose_from("dock_pose", self.dock_pose)

    def pose(self) -> Pose2 | None:
        return pose_from("dock_pose", self.dock_pose)


class DockDevice(Device[DockParameters]):
    """The dock at ``dock_pose``, else the map folder's ``dock`` pose, else none (the robot
    cannot charge: logged at start)."""

    Parameters = DockParameters

    def __init__(self, params: DockParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        poses = chassis.poses
        pose = params.pose() or (Pose2(*poses.dock) if poses.dock else None)
        if pose is None:
            chassis.logger.warning(
                "no dock pose (parameter dock_pose or %s): the robot cannot charge",
                chassis.map_path.parent / "poses.yaml")
        self.dock = (Dock(pose, params.dock_tolerance, params.dock_yaw_tolerance)
                     if pose is not None else None)
        # the last pose and dock asked about, and whether the body was docked
        self._at: tuple[Pose2 | None, Dock | None, bool] = (None, None, False)

    @property
    def docked(self) -> bool:
        """Whether the body is on the dock now (asked again only when the body moved:
        several devices ask at every step)."""
        dock = self.dock
        if dock is None:
            return False
        truth, at = self.chassis.sim.truth, self._at
        if at[0] is not truth or at[1] is not dock:
            at = self._at = (truth, dock, dock.docked(truth))
        return at[2]
