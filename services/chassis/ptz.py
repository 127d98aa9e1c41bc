"""`PanTiltZoom`: a PTZ camera's three axes moving over sim time, their ONVIF normalised units
and its presets. No Zenoh here.

Pan (rad) is positive to the right (clockwise seen from above) and tilt (rad) positive up, as
ONVIF's ``x`` and ``y``; zoom is the magnification, 1 to ``zoom_max``. The normalised units
map linearly: ``x`` -1..1 onto ``pan_min..pan_max``, ``y`` -1..1 onto ``tilt_min..tilt_max``,
``zoom`` 0..1 onto 1..``zoom_max``. An absolute move drives each axis to its target at its top
speed (they arrive at different times); a continuous move drives each at a signed fraction
of its top speed until it reaches a limit (that axis stops there) or a stop.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["PanTiltZoom", "Preset", "PtzError", "PtzLimits", "UnknownPreset", "parse_presets"]


class PtzError(ValueError):
    """A move the camera refuses: a value out of its range, not a number."""


class UnknownPreset(PtzError):
    """A preset the camera does not have."""


@dataclass(frozen=True)
class Preset:
    """A named position (physical units)."""

    name: str
    pan: float
    tilt: float
    zoom: float


@dataclass(frozen=True)
class PtzLimits:
    """The ranges (rad; zoom: magnification) and top speeds (rad/s; zoom: x per s)."""

    pan_min: float
    pan_max: float
    tilt_min: float
    tilt_max: float
    zoom_max: float
    pan_speed: float
    tilt_speed: float
    zoom_speed: float

    def __post_init__(self) -> None:
        if not -math.pi <= self.pan_min < self.pan_max <= math.pi:
            raise ValueError(f"PTZ pan range [{self.pan_min:g}, {self.pan_max:g}] rad must be "
                             "a non-empty part of [-pi, pi]")
        if not -math.pi / 2 < self.tilt_min < self.tilt_max < math.pi / 2:
            raise ValueError(f"PTZ tilt range [{self.tilt_min:g}, {self.tilt_max:g}] rad must "
                             "be a non-empty part of (-pi/2, pi/2)")
        if not 1.0 < self.zoom_max <= 100.0:
            raise ValueError(f"PTZ zoom_max must be above 1 and at most 100, got "
                             f"{self.zoom_max:g}")
        for name in ("pan_speed", "tilt_speed", "zoom_speed"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"PTZ {name} must be > 0, got {value:g}")


def parse_presets(entries: list[str], limits: PtzLimits) -> list[Preset]:
    """Presets from ``name=pan,tilt,zoom`` strings (rad, rad, x).

    Raises:
        ValueError: a malformed entry, a duplicate name or a position out of ``limits``.
    """
    out: list[Preset] = []
    for entry in entries:
        name, sep, values = entry.partition("=")
        name = name.strip()
        try:
            pan, tilt, zoom = (float(v) for v in values.split(","))
        except ValueError:
            raise ValueError(f"PTZ preset {entry!r}: expected name=pan,tilt,zoom (rad, rad, "
                             "x), e.g. home=0,-0.17,1") from None
        if not sep or not name or name.isdigit():
            raise ValueError(f"PTZ preset {entry!r}: needs a name that is not a number "
                             "(numbers are the presets' tokens)")
        if any(p.name == name for p in out):
            raise ValueError(f"PTZ preset {name!r} is given twice")
        _check(limits, pan, tilt, zoom, f"PTZ preset {name!r}")
        out.append(Preset(name, pan, tilt, zoom))
    return out


def _check(limits: PtzLimits, pan: float, tilt: float, zoom: float, what: str) -> None:
    lim = limits
    for label, value, low, high in (("pan", pan, lim.pan_min, lim.pan_max),
                                    ("tilt", tilt, lim.tilt_min, lim.tilt_max),
                                    ("zoom", zoom, 1.0, lim.zoom_max)):
        if not (math.isfinite(value) and low - 1e-9 <= value <= high + 1e-9):
            raise PtzError(f"{what}: {label} {value:g} is outside [{low:g}, {high:g}]")


def _unit(value: float, low: float, high: float, name: str) -> float:
    """Check a normalised ``value`` is a number within [low, high]."""
    if not (math.isfinite(value) and low <= value <= high):
        raise PtzError(f"{name} must be a number in [{low:g}, {high:g}], got {value:g}")
    return value


@dataclass
class PanTiltZoom:
    """The head's position and motion; ``step(dt)`` moves it."""

    limits: PtzLimits
    presets: list[Preset] = field(default_factory=list)
    pan: float = 0.0
    tilt: float = 0.0
    zoom: float = 1.0
    target: tuple[float, float, float] | None = None  # an absolute move's
    speeds: tuple[float, float, float] = (0.0, 0.0, 0.0)  # a continuous move's, -1..1

    # ------------------------------------------------------------------ units

    def normalised(self) -> tuple[float, float, float]:
        """(x, y, zoom) in ONVIF's normalised units."""
        lim = self.limits
        x = 2 * (self.pan - lim.pan_min) / (lim.pan_max - lim.pan_min) - 1
        y = 2 * (self.tilt - lim.tilt_min) / (lim.tilt_max - lim.tilt_min) - 1
        return x, y, (self.zoom - 1) / (lim.zoom_max - 1)

    def physical(self, x: float, y: float, zoom: float) -> tuple[float, float, float]:
        """(pan, tilt, magnification) of the normalised ``x``, ``y``, ``zoom``.

        Raises:
            PtzError: x or y outside -1..1, zoom outside 0..1, or not numbers.
        """
        lim = self.limits
        _unit(x, -1, 1, "x (pan)")
        _unit(y, -1, 1, "y (tilt)")
        _unit(zoom, 0, 1, "zoom")
        return (lim.pan_min + (x + 1) / 2 * (lim.pan_max - lim.pan_min),
                lim.tilt_min + (y + 1) / 2 * (lim.tilt_max - lim.tilt_min),
                1 + zoom * (lim.zoom_max - 1))

    @property
    def moving(self) -> bool:
        return self.target is not None or any(self.speeds)

    # ------------------------------------------------------------------ commands

    def move(self, x: float, y: float, zoom: float) -> None:
        """Absolute move to the normalised ``x``, ``y``, ``zoom`` (see `physical`)."""
        self.move_to(*self.physical(x, y, zoom))

    def move_to(self, pan: float, tilt: float, zoom: float) -> None:
        """Absolute move to physical ``pan``, ``tilt`` (rad) and ``zoom`` (x)."""
        _check(self.limits, pan, tilt, zoom, "PTZ move")
        lim = self.limits
        self.speeds = (0.0, 0.0, 0.0)
        self.target = (min(max(pan, lim.pan_min), lim.pan_max),
                       min(max(tilt, lim.tilt_min), lim.tilt_max),
                       min(max(zoom, 1.0), lim.zoom_max))

    def move_speed(self, speed_x: float, speed_y: float, speed_zoom: float) -> None:
        """Continuous move at fractions (-1..1) of the top speeds; all zeros stop."""
        speeds = (_unit(speed_x, -1, 1, "speed_x"), _unit(speed_y, -1, 1, "speed_y"),
                  _unit(speed_zoom, -1, 1, "speed_zoom"))
        self.target = None
        self.speeds = speeds

    def stop(self) -> None:
        self.target = None
        self.speeds = (0.0, 0.0, 0.0)

    def preset(self, key: str) -> Preset:
        """The preset named ``key``, or with token ``key`` (``"1"`` is the first).

        Raises:
            UnknownPreset: no such name or token (lists the presets).
        """
        for i, p in enumerate(self.presets):
            if key in (p.name, str(i + 1)):
                return p
        known = ", ".join(f"{p.name} ({i + 1})" for i, p in enumerate(self.presets))
        raise UnknownPreset(f"no preset {key!r}; the presets are {known or 'none'}")

    def goto_preset(self, key: str) -> Preset:
        """Absolute move to the preset ``key`` (see `preset`); returns it."""
        p = self.preset(key)
        self.move_to(p.pan, p.tilt, p.zoom)
        return p

    # ------------------------------------------------------------------ motion

    def step(self, dt: float) -> bool:
        """Advance ``dt`` sim seconds; True when a move ended (arrived, or every axis of a
        continuous move reached its limit) in this step."""
        lim = self.limits
        bounds = ((lim.pan_min, lim.pan_max, lim.pan_speed),
                  (lim.tilt_min, lim.tilt_max, lim.tilt_speed),
                  (1.0, lim.zoom_max, lim.zoom_speed))
        now = [self.pan, self.tilt, self.zoom]
        if self.target is not None:
            for i, (goal, (_, _, top)) in enumerate(zip(self.target, bounds, strict=True)):
                gap = goal - now[i]
                now[i] = goal if abs(gap) <= top * dt else now[i] + math.copysign(top * dt, gap)
            self.pan, self.tilt, self.zoom = now
            if tuple(now) == self.target:
                self.target = None
                return True
            return False
        if not any(self.speeds):
            return False
        speeds = list(self.speeds)
        for i, (low, high, top) in enumerate(bounds):
            if speeds[i]:
                now[i] = min(max(now[i] + speeds[i] * top * dt, low), high)
                if now[i] in (low, high):
                    speeds[i] = 0.0
        self.pan, self.tilt, self.zoom = now
        self.speeds = (speeds[0], speeds[1], speeds[2])
        return not any(speeds)
