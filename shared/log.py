"""Logging: node-prefixed records on stderr, levels, and every record published on /rosout."""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

__all__ = ["ErrorLog", "LogOnce", "RosoutHandler", "Throttle", "configure_logging", "level_from_name",
           "node_logger"]

_LEVELS = {
    "debug": logging.DEBUG,
    "info": logging.INFO,
    "warn": logging.WARNING,
    "warning": logging.WARNING,
    "error": logging.ERROR,
    "fatal": logging.CRITICAL,
    "critical": logging.CRITICAL,
}
_ROS_LEVEL = {logging.DEBUG: 10, logging.INFO: 20, logging.WARNING: 30, logging.ERROR: 40,
              logging.CRITICAL: 50}


def level_from_name(name: str) -> int:
    try:
        return _LEVELS[name.lower()]
    except KeyError:
        raise ValueError(f"unknown log level {name!r}; use one of {', '.join(_LEVELS)}") from None


def configure_logging(level: str | None = None) -> None:
    """Send zenros records to stderr as ``[LEVEL] [time] [node]: message``, once per process."""
    root = logging.getLogger("zenros")
    lvl = level_from_name(level or os.environ.get("ZENROS_LOG_LEVEL", "info"))
    root.setLevel(lvl)
    if not any(getattr(h, "_zenros", False) for h in root.handlers):
        handler = logging.StreamHandler(sys.stderr)
        handler.setFormatter(
            logging.Formatter("[%(levelname)s] [%(created).3f] [%(rosname)s]: %(message)s")
        )
        handler.addFilter(_default_rosname)
        handler._zenros = True  # type: ignore[attr-defined]
        root.addHandler(handler)


def _default_rosname(record: logging.LogRecord) -> bool:
    if not hasattr(record, "rosname"):
        record.rosname = record.name.removeprefix("zenros.node.").replace(".", "/")
    return True


def node_logger(fqn: str) -> logging.Logger:
    """The logger of a node; its records carry ``rosname`` (the node's FQN)."""
    logger = logging.getLogger("zenros.node" + fqn.replace("/", "."))
    return logger


class RosoutHandler(logging.Handler):
    """Publishes each record of one node's logger as an `rcl_interfaces/Log` on /rosout."""

    def __init__(self, fqn: str, publish: Callable[[Any], None], stamp: Callable[[], Any]) -> None:
        super().__init__(logging.DEBUG)
        self.fqn = fqn
        self._publish = publish
        self._stamp = stamp
        self._local = threading.local()

    def emit(self, record: logging.LogRecord) -> None:
        if getattr(self._local, "busy", False):  # publishing must not log into itself
            return
        from .msgs.rcl_interfaces import Log

        self._local.busy = True
        try:
            self._publish(
                Log(
                    stamp=self._stamp(),
                    level=_ROS_LEVEL.get(record.levelno, 20),
                    name=self.fqn,
                    msg=record.getMessage(),
                    file=record.pathname,
                    function=record.funcName,
                    line=record.lineno,
                )
            )
        except Exception:  # noqa: BLE001, S110 (logging must never raise into the caller)
            pass
        except BaseException as exc:  # a broken Zenoh session panics on every put
            if type(exc).__name__ != "PanicException":
                raise
        finally:
            self._local.busy = False


class Throttle:
    """Allows one event per key per ``period`` seconds; counts the rest."""

    def __init__(self, period: float = 5.0) -> None:
        self.period = period
        self._last: dict[Any, float] = {}
        self.suppressed: dict[Any, int] = {}

    def allow(self, key: Any) -> bool:
        now = time.monotonic()
        last = self._last.get(key)
        if last is None or now - last >= self.period:
            self._last[key] = now
            return True
        self.suppressed[key] = self.suppressed.get(key, 0) + 1
        return False


class ErrorLog:
    """Counts the errors of one endpoint and logs them, at most once per key per ``period``.

    A hostile or broken peer can send thousands of bad requests a second: each one is
    counted (``count``), but only the first per key (usually the sender or the error kind)
    in each period is logged, with how many were suppressed since.
    """

    def __init__(self, logger: logging.Logger, period: float = 5.0) -> None:
        self.count = 0
        self._logger = logger
        self._throttle = Throttle(period)
        self._lock = threading.Lock()

    def report(self, key: Any, level: int, msg: str, *args: Any,
               exc_info: BaseException | None = None) -> None:
        with self._lock:
            self.count += 1
            if not self._throttle.allow(key):
                return
            extra = self._throttle.suppressed.pop(key, 0)
        if extra:
            msg += f" ({extra} more suppressed)"
        self._logger.log(level, msg, *args, exc_info=exc_info)


class LogOnce:
    """Logs a warning the first time each key is reported and counts every report (a bridge's
    "logged once per sender": a broken peer's thousandth bad sample is counted, not logged)."""

    def __init__(self, logger: logging.Logger) -> None:
        self.logger = logger
        self.counts: dict[str, int] = {}
        self._lock = threading.Lock()

    def __call__(self, key: str, fmt: str, *args: Any) -> None:
        with self._lock:
            n = self.counts.get(key, 0)
            self.counts[key] = n + 1
        if n == 0:
            self.logger.warning(fmt, *args)
