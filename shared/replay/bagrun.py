"""`replay_bag`: re-run services on a bag's inputs in a `DeterministicRun` and write their
outputs to an MCAP file (what ``zenros replay BAG --nodes ... -o OUT.mcap`` does)."""

from __future__ import annotations

import logging
import re
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..bag.reader import BagError, bag_files, iter_messages, resolve_bag
from ..errors import ConfigError
from .inputs import InputDecoder, UndecodableChannel
from .nodes import replayable
from .outbag import OutputBag
from .run import DeterministicRun

__all__ = ["DEFAULT_EXCLUDE", "ReplayResult", "replay_bag"]

_log = logging.getLogger("zenros.replay")

# Housekeeping topics left out of the output by default: log lines, parameter events, the
# lifecycle's bond (a random instance id) and transition events (wall-clock stamps), and
# diagnostics (the host's name, wall-clock rates). None carries what a node decided.
DEFAULT_EXCLUDE = (r"^/rosout$|^/parameter_events$|(^|/)bond$|/transition_event$"
                   r"|^/diagnostics(_agg)?$")


@dataclass
class ReplayResult:
    """What a replay did: counts, simulated and wall seconds, and the check's findings."""

    output: Path
    inputs: int = 0
    delivered: int = 0
    outputs: int = 0
    recorded: int = 0
    sim_seconds: float = 0.0
    wall_seconds: float = 0.0
    cpu_seconds: float = 0.0
    """The process's CPU time over the replay (all its threads): the box's load aside."""
    skipped_topics: dict[str, str] = field(default_factory=dict)
    wall_reads: list[tuple[str, str, int]] = field(default_factory=list)

    @property
    def rtf(self) -> float:
        """Simulated seconds per wall second."""
        return self.sim_seconds / self.wall_seconds if self.wall_seconds > 0 else 0.0

    @property
    def rtf_cpu(self) -> float:
        """Simulated seconds per CPU second of the process."""
        return self.sim_seconds / self.cpu_seconds if self.cpu_seconds > 0 else 0.0


def replay_bag(bag: str | Path, nodes: list[str], output: Path, *,
               params: dict[str, dict[str, Any]] | None = None,
               exclude: str | None = DEFAULT_EXCLUDE, tail: float = 0.0,
               compression: str = "zstd", check: bool = True,
               clock_topic: str | None = None) -> ReplayResult:
    """Replay ``bag`` into the services ``nodes`` and write their outputs to ``output``.

    Inputs are the bag's messages on topics the services subscribe to and none of them
    publishes, delivered in log-time order; the clock starts at the first message's log
    time. ``params``: per service, parameter overrides (nav's ``maps_dir`` defaults to a
    fresh temporary folder, so a replay never reads or changes the user's maps). ``tail``:
    seconds the clock runs on after the last message (timers only). ``clock_topic``
    (``/clock``): the simulated time is the bag's clock messages (rosgraph_msgs/Clock) instead
    of its log times, for a bag recorded live from a simulation: messages keep their
    log-time order and each is delivered at the last clock value before it (those before
    the first clock message at that first value), and timers fire up to each new value.

    Raises:
        BagError: the bag cannot be read. ConfigError: an unknown service, a bad pattern.
    """
    if not nodes:
        raise ConfigError("name at least one service to replay (--nodes nav)")
    specs = {n: replayable(n) for n in nodes}
    unknown = set(params or {}) - set(specs)
    if unknown:
        raise ConfigError(f"parameters for {', '.join(sorted(unknown))}, which is not "
                          f"replayed (--nodes {','.join(nodes)})")
    try:
        skip = re.compile(exclude) if exclude else None
    except re.error as exc:
        raise ConfigError(f"bad --exclude pattern {exclude!r}: {exc}") from None
    files = bag_files(resolve_bag(str(bag)))
    messages = iter_messages(files)
    first = next(messages, None)
    if first is None:
        raise BagError(f"{bag} holds no messages")
    decoder = InputDecoder()
    start = first.log_time
    if clock_topic:
        tick = next(iter_messages(files, topics=[clock_topic]), None)
        if tick is None:
            raise BagError(f"{bag} has no {clock_topic} messages (--clock-topic)")
        start = _clock_ns(decoder, tick)
    result = ReplayResult(output)
    out = OutputBag(output, compression)
    qos: dict[str, str] = {}

    def on_output(topic: str, msg: Any, t: int) -> None:
        result.outputs += 1
        if skip is not None and skip.search(topic):
            return
        out.add(topic, msg, t, qos.get(topic, "rel+10"))
        result.recorded += 1

    exempt = {k: v for s in specs.values() for k, v in s.exempt.items()}
    classes = {name: spec.load() for name, spec in specs.items()}  # imports: not the replay's
    wall, cpu = time.perf_counter(), time.process_time()
    with tempfile.TemporaryDirectory(prefix="zenros-replay-") as scratch:
        run = DeterministicRun(start, on_output, check=check, exempt=exempt)
        try:
            for name in specs:
                overrides = dict((params or {}).get(name, {}))
                if name == "nav":
                    overrides.setdefault("maps_dir", str(Path(scratch) / "maps"))
                node = run.add_node(classes[name], parameter_overrides=overrides)
                for ep in node._endpoints:
                    if hasattr(ep, "publish") and hasattr(ep, "qos"):
                        qos.setdefault(ep.topic, ep.qos.tag)
            for m in _chain(first, messages):
                result.inputs += 1
                topic = m.channel.topic
                if clock_topic and topic == clock_topic:
                    t = _clock_ns(decoder, m)
                    if t > run.now_ns:  # a clock that went back (a restarted sim) waits
                        run.advance_to(t)
                    continue
                at = run.now_ns if clock_topic else m.log_time
                if topic in result.skipped_topics or not run.subscribed(topic):
                    run.advance_to(at)
                    continue
                try:
                    msg = decoder.decode(m)
                except UndecodableChannel as exc:
                    result.skipped_topics[topic] = str(exc)
                    _log.warning("replay: %s; the topic is not fed", exc)
                    continue
                except (ValueError, TypeError) as exc:
                    _log.warning("replay: a message on %s at %d does not decode (%s); skipped",
                                 topic, m.log_time, exc)
                    continue
                if run.deliver(topic, msg, at, decoder.type_name(m)):
                    result.delivered += 1
            end = run.now_ns + int(tail * 1e9)
            run.advance_to(end)
            result.sim_seconds = (end - start) / 1e9
        finally:
            run.close()
            out.close()
    result.wall_seconds = time.perf_counter() - wall
    result.cpu_seconds = time.process_time() - cpu
    result.wall_reads = [tuple(r) for r in run.check.reads]  # type: ignore[misc]
    return result


def _clock_ns(decoder: InputDecoder, m: Any) -> int:
    try:
        t: int = decoder.decode(m).clock.nanoseconds
    except (UndecodableChannel, ValueError, TypeError, AttributeError) as exc:
        raise BagError(f"{m.channel.topic} at {m.log_time}: not a rosgraph_msgs/Clock "
                       f"({exc})") from None
    return t


def _chain(first: Any, rest: Any) -> Any:
    yield first
    yield from rest
