"""`Speech` and `AudioStore`: speech as text on a robot without a speaker, and its settings.

The simulated robot cannot make sound: a spoken text is published on ``tts`` and counts as
*playing* for ``len(text) / CHARS_PER_SECOND`` seconds of the robot's clock (simulated time
when it runs), or until stopped. `AudioStore` keeps the alias table (docs/robot-api.md §3.7) and the
speaker volume in one JSON file, written atomically on every change.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping
from pathlib import Path

import msgspec

from .json_file import load_struct, save_struct

__all__ = ["CHARS_PER_SECOND", "MAX_ALIASES", "AudioSettings", "AudioStore", "Speech"]

CHARS_PER_SECOND = 15.0
"""Speaking rate of the model: about 150 words per minute."""
MAX_ALIASES = 1000


class Speech:
    """What is being said now, by the clock ``now`` (seconds)."""

    def __init__(self, now: Callable[[], float], rate: float = CHARS_PER_SECOND) -> None:
        self._now = now
        self.rate = rate
        self.text = ""
        self._until = float("-inf")
        self._lock = threading.Lock()

    def say(self, text: str, duration: float | None = None) -> float:
        """Start saying ``text`` (it replaces what was playing) for ``duration`` s (a
        recording's length; None: as long as synthesised speech takes); returns it."""
        if duration is None:
            duration = len(text) / self.rate
        with self._lock:
            self.text = text
            self._until = self._now() + duration
        return duration

    def playing(self) -> bool:
        with self._lock:
            return self._now() < self._until

    def stop(self) -> bool:
        """End the speech now; returns whether something was playing."""
        with self._lock:
            was = self._now() < self._until
            self._until = float("-inf")
            return was


class AudioSettings(msgspec.Struct, forbid_unknown_fields=True):
    volume: int = 50
    alias: dict[str, str] = msgspec.field(default_factory=dict)


class AudioStore:
    """The alias table and volume, persisted in ``path`` (None: memory only)."""

    def __init__(self, path: Path | None) -> None:
        self.path = path
        self._lock = threading.Lock()
        self.current = load_struct(path, AudioSettings)

    def apply_alias(self, text: str) -> str:
        """The text to speak: the alias of ``text`` when it has one (whole-text match)."""
        with self._lock:
            return self.current.alias.get(text, text)

    def aliases(self) -> dict[str, str]:
        with self._lock:
            return dict(self.current.alias)

    def replace_aliases(self, table: Mapping[str, str]) -> None:
        with self._lock:
            self.current.alias = dict(table)
            self._save()

    def update_aliases(self, table: Mapping[str, str]) -> dict[str, str]:
        """Add or change the given aliases; ValueError past `MAX_ALIASES` in all."""
        with self._lock:
            if len(self.current.alias.keys() | table.keys()) > MAX_ALIASES:
                raise ValueError(f"the alias table would hold over {MAX_ALIASES} entries")
            self.current.alias.update(table)
            self._save()
            return dict(self.current.alias)

    def set_volume(self, value: int) -> None:
        if not 0 <= value <= 100:
            raise ValueError(f"volume {value} is out of range 0-100")
        with self._lock:
            self.current.volume = value
            self._save()

    def _save(self) -> None:
        save_struct(self.path, self.current)
