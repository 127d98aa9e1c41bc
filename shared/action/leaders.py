"""`RequestThreads`: an action server's request threads (leader/followers, handed over late).

One thread at a time, the leader, takes requests from the queryable's channel and handles them
in arrival order. A request that starts a goal returns it as a job, and the leader runs the job
itself: a short goal thus runs start to end on the thread that accepted it, with no thread
hand-off on its path (as a ROS executor runs an execute callback on the thread that took the
goal). A goal still running ``delay`` seconds later is *detached*: a watchdog thread calls
``overdue(job)`` (the server sends the acceptance it held back) and hands the lead to a waiting
thread (started if none waits), which goes on reading requests. So no request waits more than
about ``delay`` behind a goal; the detached thread finishes its goal and then waits to lead
again. A waiting thread idle for ``idle_timeout`` seconds ends (a detach starts one if none
waits).
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import zenoh

__all__ = ["DETACH_DELAY", "QueryQueue", "RequestThreads"]

DETACH_DELAY = 0.002  # seconds a goal runs on the leading thread before it is detached

J = TypeVar("J")
_CLOSED = object()


class QueryQueue:
    """A queryable's queue that its readers wait on without waking.

    A thread reading a zenoh-python channel wakes ten times a second (to check for
    signals), whether requests come or not: in a robot's process, with a dozen action
    servers, that was spent at rest for nothing. Here Zenoh's own channel (its default FIFO,
    no GIL on Zenoh's side) is read by zenoh-python's callback thread, which waits without
    waking and moves each query into a bounded Python queue (full: it waits, and Zenoh's
    channel pushes back, as before). `recv` raises `zenoh.ZError` once the queryable is
    undeclared and the queue drained, as a channel does.
    """

    def __init__(self, capacity: int) -> None:
        self._queue: queue.Queue[Any] = queue.Queue(capacity)
        self.handler = zenoh.handlers.Callback(self._queue.put, self._closed)

    def _closed(self) -> None:
        self._queue.put(_CLOSED)

    def recv(self) -> Any:
        item = self._queue.get()
        if item is _CLOSED:
            self._queue.put(_CLOSED)  # every other reader ends too
            raise zenoh.ZError("the queryable was undeclared")
        return item


class RequestThreads(Generic[J]):
    """Serves ``channel`` (a `QueryQueue`, or a Zenoh FIFO handler) with
    ``handle(query) -> job | None``.

    Args:
        run: runs a job (a goal's execute callback and its ending).
        overdue: called once for a job still running after ``delay`` (from the watchdog
            thread, before the lead moves on).
        on_failure: called with an exception other than Zenoh's "channel closed" (the server
            decides; a failed session makes the process exit).
    """

    def __init__(self, name: str, channel: Any, handle: Callable[[zenoh.Query], J | None],
                 run: Callable[[J], None], overdue: Callable[[J], None],
                 on_failure: Callable[[BaseException], None], logger: logging.Logger,
                 delay: float = DETACH_DELAY, idle_timeout: float = 30.0) -> None:
        self._name = name
        self._channel = channel
        self._handle = handle
        self._run_job = run
        self._overdue = overdue
        self._on_failure = on_failure
        self._logger = logger
        self._delay = delay
        self._idle_timeout = idle_timeout
        lock = threading.Lock()
        self._followers = threading.Condition(lock)  # threads waiting for the lead
        self._watch = threading.Condition(lock)  # the watchdog
        self._leader: threading.Thread | None = None
        self._job: tuple[float, J] | None = None  # the leader's job and when it is overdue
        self._waiting = 0
        self._watch_idle = False  # the watchdog waits without a timeout: a job must wake it
        self._watch_started = False
        self._threads: set[threading.Thread] = set()  # the ones not running a detached job
        self._count = 0
        self.closed = False

    def start(self) -> None:
        with self._followers:
            self._spawn()

    def _start_watchdog(self) -> None:
        """Locked: the watchdog starts with the first job (many servers never run one)."""
        t = threading.Thread(target=self._watchdog, daemon=True, name=f"{self._name}-watch")
        self._threads.add(t)
        self._watch_started = True
        t.start()

    # ------------------------------------------------------------------ request threads

    def _spawn(self) -> None:
        """Start a thread that waits for the lead (the lock is held)."""
        self._count += 1
        self._waiting += 1
        t = threading.Thread(target=self._run, daemon=True, name=f"{self._name}-{self._count}")
        self._threads.add(t)
        t.start()

    def _run(self) -> None:
        me = threading.current_thread()
        with self._followers:
            try:
                while self._wait_for_lead():
                    self._leader = me
                    self._followers.release()
                    try:
                        self._lead(me)
                    finally:
                        self._followers.acquire()
                    if self._leader is me:  # the channel closed (or failed) under this thread
                        self._leader = None
                        self._close()
                        return
                    self._waiting += 1
                    self._threads.add(me)
            finally:
                self._threads.discard(me)

    def _wait_for_lead(self) -> bool:
        """Wait (locked) until nobody leads; False if this thread should end instead."""
        while not self.closed:
            if self._leader is None:
                self._waiting -= 1
                return True
            if not self._followers.wait(self._idle_timeout) and self._leader is not None:
                break  # idle while another thread leads (a detach starts a new one if needed)
        self._waiting -= 1
        return False

    def _lead(self, me: threading.Thread) -> None:
        """Read and handle requests until this thread is detached with a job, the channel
        closes, or the session fails."""
        try:
            while True:
                job = self._handle(self._channel.recv())
                if job is None:
                    continue
                with self._watch:
                    self._job = (time.monotonic() + self._delay, job)
                    if self._watch_idle:
                        self._watch.notify()
                    elif not self._watch_started:
                        self._start_watchdog()
                try:
                    self._run_job(job)
                except Exception:  # the job reports its own failures; this is a last guard
                    self._logger.exception("%s: a goal's job raised", self._name)
                with self._watch:
                    if self._leader is not me:  # detached: someone else leads now
                        return
                    self._job = None
        except zenoh.ZError:  # the channel is empty and closed: the queryable was undeclared
            return
        except BaseException as exc:  # noqa: BLE001 the server decides (session failure: exit)
            self._on_failure(exc)

    def _close(self) -> None:
        """Locked: every thread ends (the channel closed)."""
        self.closed = True
        self._followers.notify_all()
        self._watch.notify_all()

    # ------------------------------------------------------------------ watchdog

    def _watchdog(self) -> None:
        linger = False
        with self._watch:
            try:
                while not self.closed:
                    entry = self._job
                    if entry is None:
                        if linger:  # stay awake one more period: a busy server needs no wake
                            linger = False
                            self._watch.wait(self._delay)
                        else:
                            self._watch_idle = True
                            self._watch.wait()
                            self._watch_idle = False
                        continue
                    linger = True
                    now = time.monotonic()
                    if now < entry[0]:
                        self._watch.wait(entry[0] - now)
                        continue
                    self._detach(entry[1])
            finally:
                self._threads.discard(threading.current_thread())

    def _detach(self, job: J) -> None:
        """Locked: the leader's job is overdue; the lead moves to a waiting thread."""
        leader = self._leader
        self._job = None
        self._leader = None
        if leader is not None:
            self._threads.discard(leader)
        if self._waiting == 0:
            self._spawn()
        else:
            self._followers.notify()
        self._watch.release()  # `overdue` takes the server's lock: never under this one
        try:
            self._overdue(job)
        except Exception:
            self._logger.exception("%s: overdue job handling raised", self._name)
        finally:
            self._watch.acquire()

    # ------------------------------------------------------------------ shutdown

    def join(self, timeout: float) -> None:
        """Wait (up to ``timeout`` s in all) for the threads not running a detached goal to
        end (the channel must be closed)."""
        me = threading.current_thread()
        with self._followers:
            threads = [t for t in self._threads if t is not me]
        deadline = time.monotonic() + timeout
        for t in threads:
            t.join(max(0.0, deadline - time.monotonic()))
