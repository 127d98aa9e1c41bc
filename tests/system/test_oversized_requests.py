"""Oversized requests against processes: master refuses them and keeps serving, a row stored
before the limits existed is skipped at startup, and a process whose Zenoh session broke
exits with code 4 so that supervision can restart it."""

from __future__ import annotations

import sqlite3
import sys
import textwrap
from pathlib import Path

import msgspec
import pytest
from zenros.context import Context
from zenros.errors import (
    InvalidNameError,
    InvalidParameterValueError,
    ServiceUnavailableError,
    ZenrosTimeout,
)
from zenros.msgs.std_srvs import Trigger
from zenros.names import MAX_NAME_LENGTH
from zenros.param_client import ParameterClient
from zenros.param_protocol import SET_PARAM, SetParam
from zenros.rpc import Client
from zenros.runtime import EXIT_SESSION_FAILED
from zenros.services.master.param_value import MAX_VALUE_BYTES
from zenros.testing import Proc

pytestmark = pytest.mark.system

HUGE = 5_000_000


def start_master(router: str, prefix: str, home: Path) -> Proc:
    proc = Proc([sys.executable, "-m", "zenros.services.master", "-e", router, "--prefix", prefix],
                env={"ZENROS_HOME": str(home)})
    assert proc.wait_line("started", 15), proc.output
    return proc


def test_master_refuses_a_5_mb_name_and_a_2_mib_value_and_keeps_serving(
    router: str, prefix: str, tmp_path: Path, observer: Context, procs: list[Proc]
) -> None:
    procs.append(master := start_master(router, prefix, tmp_path))
    params = ParameterClient(observer, timeout=5.0)
    assert params.wait_for_master(10)
    raw = Client(observer, SetParam, SET_PARAM)
    res = raw.call(SetParam.Request(name="/" + "a" * HUGE, value=1), timeout=10)
    assert res.error_type == "InvalidNameError"
    assert f"the limit is {MAX_NAME_LENGTH}" in res.error and len(res.error) < 300
    with pytest.raises(InvalidNameError, match="the limit is 1000"):
        params.set("/" + "b" * (MAX_NAME_LENGTH + 1), 1)
    with pytest.raises(InvalidParameterValueError, match=f"the limit is {MAX_VALUE_BYTES}"):
        params.set("/blob", b"x" * (2 * MAX_VALUE_BYTES))
    with pytest.raises(InvalidNameError, match="the limit is 1000"):
        params.set("/ns", {"k" * (MAX_NAME_LENGTH + 1): 1})  # a leaf name built from a dict
    params.set("/ok", 1)
    assert params.get("/ok") == 1 and params.list() == ["/ok"]
    assert master.popen.poll() is None


def test_a_stored_oversized_name_is_skipped_at_startup(
    router: str, prefix: str, tmp_path: Path, observer: Context, procs: list[Proc]
) -> None:
    procs.append(master := start_master(router, prefix, tmp_path))
    params = ParameterClient(observer, timeout=5.0)
    assert params.wait_for_master(10)
    params.set("/kept", 1)
    assert master.stop() == 0
    db = sqlite3.connect(tmp_path / "params.db")  # as an older master stored it
    try:
        with db:
            db.execute("INSERT INTO params VALUES (?, ?, ?, 0, ?)",
                       ("/" + "a" * 200_000, (1 << 40).to_bytes(8, "big"), "old",
                        msgspec.msgpack.encode(1)))
    finally:
        db.close()
    procs.append(master := start_master(router, prefix, tmp_path))
    assert master.wait_line("skipping a stored parameter whose name is 200001 characters", 5)
    assert params.wait_for_master(10)
    replies = list(observer.session.get(f"{observer.keys.param('/')}**", timeout=5.0))
    assert [str(r.ok.key_expr) for r in replies if r.ok is not None] == [
        observer.keys.param("/kept")]
    params.set("/after", 2)
    assert params.list() == ["/after", "/kept"]


BOOM = textwrap.dedent("""
    from zenros.msgs.std_srvs import Trigger
    from zenros.node import Node
    from zenros.runtime import run


    class Boom(Node):
        node_name = "boom"
        uses_parameter_server = False

        def setup(self):
            self.create_service(Trigger, "boom", self.boom)

        def boom(self, req):
            # A key expression larger than a transport batch: zenoh 1.10 panics sending it
            # and the session's transport stays poisoned.
            keys = self.context.keys
            self.context.session.put(keys.topic("/big/" + "a" * 5_000_000), b"x")
            return Trigger.Response(success=True)


    run(Boom)
""")


def test_a_process_whose_session_broke_exits_with_code_4(
    router: str, prefix: str, tmp_path: Path, observer: Context, procs: list[Proc]
) -> None:
    script = tmp_path / "boom.py"
    script.write_text(BOOM)
    procs.append(boom := Proc([sys.executable, str(script), "-e", router, "--prefix", prefix]))
    assert boom.wait_line("started", 15), boom.output
    client = Client(observer, Trigger, "/boom")
    assert client.wait_for_service(10)
    with pytest.raises((ServiceUnavailableError, ZenrosTimeout)):
        client.call(Trigger.Request(), timeout=3)
    assert boom.wait(10) == EXIT_SESSION_FAILED, boom.output[-2000:]
    assert "the Zenoh session failed" in boom.output
    assert "exiting with code 4" in boom.output
