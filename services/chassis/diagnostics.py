"""The chassis's diagnostics (``/diagnostics``): motors, battery and laser, as a driver
reports them through an `Updater` (docs/diagnostics.md)."""

from __future__ import annotations

from typing import Any

from zenros.diagnostics import ERROR, OK, WARN, DiagnosticStatusWrapper, Updater

from .devices.battery import BatteryDevice
from .devices.laser import LaserDevice

__all__ = ["chassis_diagnostics"]

BATTERY_LOW = 20.0  # percent: WARN below
BATTERY_CRITICAL = 5.0  # percent: ERROR below


def chassis_diagnostics(node: Any) -> Updater:
    """An Updater on ``node`` (a `ChassisNode`) with one task per part it has."""
    up = Updater(node)
    up.setHardwareID(f"sim-chassis{node.fqn}")
    sim = node.sim

    def motors(stat: DiagnosticStatusWrapper) -> None:
        drive = sim.drive
        if drive.estop:
            stat.summary(ERROR, "e-stop engaged")
        elif not sim.powered:
            stat.summary(ERROR, "no power (battery empty)")
        elif sim.bumper:
            stat.summary(WARN, "bumper pressed: stopped at contact")
        else:
            stat.summary(OK, "idle" if drive.timed_out(sim.time) else "driving")
        stat.add("linear (m/s)", f"{drive.linear:.3f}")
        stat.add("angular (rad/s)", f"{drive.angular:.3f}")
        stat.add("e-stop", drive.estop)
        stat.add("bumper", sim.bumper)

    up.add("motors", motors)
    battery = node.device(BatteryDevice)
    if battery is not None:
        def pack(stat: DiagnosticStatusWrapper) -> None:
            b = battery.battery
            pct = b.percentage * 100
            if pct < BATTERY_CRITICAL:
                stat.summary(ERROR, f"battery critical: {pct:.0f}%")
            elif pct < BATTERY_LOW:
                stat.summary(WARN, f"battery low: {pct:.0f}%")
            else:
                stat.summary(OK, f"{pct:.0f}%{', charging' if b.charging else ''}")
            stat.add("percentage", f"{pct:.1f}")
            stat.add("voltage (V)", f"{b.voltage:.2f}")
            stat.add("current (A)", f"{b.current:.2f}")
            stat.add("charging", b.charging)

        up.add("battery", pack)
    laser = node.device(LaserDevice)
    if laser is not None:
        def scanner(stat: DiagnosticStatusWrapper) -> None:
            c = laser.laser.config
            stat.summary(OK, f"{c.beams} beams at {laser.rate:g} Hz")
            stat.add("range (m)", f"{c.range_min:g}..{c.range_max:g}")
            stat.add("frame", laser.params.laser_frame)

        up.add("laser", scanner)
    return up
