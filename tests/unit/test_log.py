"""log: configure_logging, level names, RosoutHandler (publishes Log, never raises), Throttle."""

from __future__ import annotations

import io
import logging
import types
from collections.abc import Iterator
from typing import Any

import pytest
import zenros.log as zlog
from zenros.log import (
    LogOnce,
    RosoutHandler,
    Throttle,
    configure_logging,
    level_from_name,
    node_logger,
)
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.rcl_interfaces import Log


@pytest.fixture
def zenros_logger(monkeypatch: pytest.MonkeyPatch) -> Iterator[logging.Logger]:
    """The 'zenros' logger, restored (handlers, level) after the test; stderr captured."""
    root = logging.getLogger("zenros")
    saved_handlers, saved_level = list(root.handlers), root.level
    root.handlers = [h for h in root.handlers if not getattr(h, "_zenros", False)]
    monkeypatch.delenv("ZENROS_LOG_LEVEL", raising=False)
    monkeypatch.setattr(zlog.sys, "stderr", io.StringIO())
    yield root
    root.handlers = saved_handlers
    root.setLevel(saved_level)


def zenros_handlers(root: logging.Logger) -> list[logging.Handler]:
    return [h for h in root.handlers if getattr(h, "_zenros", False)]


# ------------------------------------------------------------------ levels


@pytest.mark.parametrize(
    ("name", "level"),
    [("debug", logging.DEBUG), ("INFO", logging.INFO), ("warn", logging.WARNING),
     ("Warning", logging.WARNING), ("error", logging.ERROR), ("fatal", logging.CRITICAL),
     ("critical", logging.CRITICAL)],
)
def test_level_from_name(name: str, level: int) -> None:
    assert level_from_name(name) == level


@pytest.mark.parametrize("name", ["loud", "", "10", "information"])
def test_unknown_level_lists_the_valid_ones(name: str) -> None:
    with pytest.raises(ValueError, match=f"unknown log level {name!r}; use one of debug, info"):
        level_from_name(name)


# ------------------------------------------------------------------ configure_logging


def test_configure_logging_is_idempotent(zenros_logger: logging.Logger) -> None:
    configure_logging("debug")
    configure_logging("warn")
    configure_logging()
    assert len(zenros_handlers(zenros_logger)) == 1
    assert zenros_logger.level == logging.INFO  # the last call sets the level


def test_configure_logging_reads_the_environment(
    zenros_logger: logging.Logger, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("ZENROS_LOG_LEVEL", "error")
    configure_logging()
    assert zenros_logger.level == logging.ERROR
    configure_logging("debug")  # an explicit level wins over the environment
    assert zenros_logger.level == logging.DEBUG


def test_configure_logging_rejects_unknown_levels(zenros_logger: logging.Logger) -> None:
    with pytest.raises(ValueError, match="unknown log level 'chatty'"):
        configure_logging("chatty")


def test_records_are_formatted_with_level_and_node(zenros_logger: logging.Logger) -> None:
    configure_logging("info")
    [handler] = zenros_handlers(zenros_logger)
    stream = io.StringIO()
    assert isinstance(handler, logging.StreamHandler)
    handler.setStream(stream)
    node_logger("/robot1/chassis").warning("battery at %d%%", 12)
    node_logger("/robot1/chassis").debug("hidden")
    line = stream.getvalue().strip()
    assert line.startswith("[WARNING] [")
    assert "robot1/chassis]: battery at 12%" in line
    assert "hidden" not in stream.getvalue()


def test_node_logger_names() -> None:
    assert node_logger("/robot1/chassis").name == "zenros.node.robot1.chassis"
    assert node_logger("/talker") is node_logger("/talker")
    assert node_logger("/talker").parent is not None


# ------------------------------------------------------------------ RosoutHandler


@pytest.fixture
def node_log() -> Iterator[logging.Logger]:
    logger = logging.getLogger("zenros.test_log_node")
    saved_handlers, saved_level = list(logger.handlers), logger.level
    logger.setLevel(logging.DEBUG)
    logger.propagate = False
    yield logger
    logger.handlers = saved_handlers
    logger.setLevel(saved_level)
    logger.propagate = True


@pytest.mark.parametrize(
    ("method", "ros_level"),
    [("debug", Log.DEBUG), ("info", Log.INFO), ("warning", Log.WARN), ("error", Log.ERROR),
     ("critical", Log.FATAL)],
)
def test_rosout_handler_publishes_a_log(
    node_log: logging.Logger, method: str, ros_level: int
) -> None:
    published: list[Any] = []
    stamp = Time(sec=12, nanosec=34)
    node_log.addHandler(RosoutHandler("/robot1/chassis", published.append, lambda: stamp))
    getattr(node_log, method)("speed %.1f", 0.5)
    [log] = published
    assert isinstance(log, Log)
    assert log.level == ros_level
    assert (log.name, log.msg, log.stamp) == ("/robot1/chassis", "speed 0.5", stamp)
    assert log.file.endswith("test_log.py")
    assert log.function == "test_rosout_handler_publishes_a_log"
    assert log.line > 0


def test_rosout_handler_maps_custom_levels_to_info(node_log: logging.Logger) -> None:
    published: list[Any] = []
    node_log.addHandler(RosoutHandler("/n", published.append, Time))
    node_log.log(25, "between info and warning")
    assert published[0].level == Log.INFO


def test_rosout_handler_never_raises(node_log: logging.Logger) -> None:
    def publish(_msg: Any) -> None:
        raise RuntimeError("session closed")

    def stamp() -> Time:
        raise RuntimeError("no clock")

    node_log.addHandler(RosoutHandler("/n", publish, Time))
    node_log.addHandler(RosoutHandler("/n", lambda m: None, stamp))
    node_log.error("still fine")  # no exception reaches the caller


def test_rosout_handler_does_not_recurse(node_log: logging.Logger) -> None:
    published: list[Any] = []

    def publish(msg: Any) -> None:
        node_log.warning("publishing logs about itself")  # would loop forever
        published.append(msg)

    node_log.addHandler(RosoutHandler("/n", publish, Time))
    node_log.info("once")
    assert [m.msg for m in published] == ["once"]


def test_rosout_handler_works_again_after_a_failure(node_log: logging.Logger) -> None:
    calls: list[str] = []

    def publish(msg: Any) -> None:
        calls.append(msg.msg)
        if len(calls) == 1:
            raise RuntimeError("first one fails")

    node_log.addHandler(RosoutHandler("/n", publish, Time))
    node_log.info("a")
    node_log.info("b")
    assert calls == ["a", "b"]


# ------------------------------------------------------------------ Throttle


class FakeTime:
    def __init__(self) -> None:
        self.now = 1000.0

    def monotonic(self) -> float:
        return self.now


@pytest.fixture
def fake_time(monkeypatch: pytest.MonkeyPatch) -> FakeTime:
    fake = FakeTime()
    monkeypatch.setattr(zlog, "time", types.SimpleNamespace(monotonic=fake.monotonic))
    return fake


def test_throttle_allows_one_per_period_and_counts_the_rest(fake_time: FakeTime) -> None:
    th = Throttle(period=5.0)
    assert th.allow("decode /odom")
    assert not th.allow("decode /odom")
    assert not th.allow("decode /odom")
    assert th.suppressed == {"decode /odom": 2}
    fake_time.now += 4.999
    assert not th.allow("decode /odom")
    fake_time.now += 0.001
    assert th.allow("decode /odom")
    assert th.suppressed == {"decode /odom": 3}


def test_throttle_keys_are_independent(fake_time: FakeTime) -> None:
    th = Throttle(period=1.0)
    assert th.allow(("/odom", "sender1"))
    assert th.allow(("/odom", "sender2"))
    assert not th.allow(("/odom", "sender1"))
    assert th.suppressed == {("/odom", "sender1"): 1}


def test_throttle_period_zero_allows_everything(fake_time: FakeTime) -> None:
    th = Throttle(period=0.0)
    assert all(th.allow("k") for _ in range(5))
    assert th.suppressed == {}


def test_throttle_default_period() -> None:
    assert Throttle().period == 5.0


def test_log_once_logs_the_first_report_of_a_key_and_counts_all(
        caplog: pytest.LogCaptureFixture) -> None:
    once = LogOnce(logging.getLogger("test.log_once"))
    with caplog.at_level(logging.WARNING, logger="test.log_once"):
        for _ in range(3):
            once("bad a", "bad sample from %s", "a")
        once("bad b", "bad sample from %s", "b")
    assert [r.getMessage() for r in caplog.records] == ["bad sample from a", "bad sample from b"]
    assert once.counts == {"bad a": 3, "bad b": 1}
