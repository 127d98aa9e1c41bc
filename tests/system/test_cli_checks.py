"""The CLI never fails silently: no router, nothing on a topic, the wrong type for a service,
topic or action, a parameter value of the wrong type; and every served type is callable."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator

import pytest
from zenros.testing import Proc, free_port, unique_prefix

pytestmark = pytest.mark.system


def zenros(*args: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", *args], capture_output=True,
                          text=True, timeout=timeout, check=False)


@pytest.fixture(scope="module")
def robot(tmp_path_factory: pytest.TempPathFactory) -> Iterator[list[str]]:
    """A router, master, talker, add_two_ints and fibonacci servers (shared by the module's
    tests, which only read, or set /talker/rate); yields the session flags."""
    router = f"tcp/127.0.0.1:{free_port()}"
    flags = ["-e", router, "--prefix", unique_prefix()]
    home = str(tmp_path_factory.mktemp("home"))
    procs = [Proc([sys.executable, "-m", "zenros.router", "-l", router])]
    try:
        assert procs[0].wait_line("router listening", 15), procs[0].output
        for mod, extra in [
            ("zenros.services.master", []),
            ("zenros.examples.talker", ["-p", "rate:=2.0"]),
            ("zenros.examples.add_two_ints_server", []),
            ("zenros.examples.fibonacci_server", []),
        ]:
            procs.append(Proc([sys.executable, "-m", mod, *flags, *extra],
                              env={"ZENROS_HOME": home}))
        for p in procs[1:]:
            assert p.wait_line("started", 20), p.output
        yield flags
    finally:
        for p in reversed(procs):
            p.stop()


@pytest.mark.parametrize("verb, explicit", [(["node", "list"], False), (["topic", "list"], True),
                                            (["param", "list"], False)])
def test_no_router_says_nothing_answered_with_exit_3(verb: list[str], explicit: bool) -> None:
    """Whether the endpoint came from -e or (as by default) from the environment."""
    dead = f"tcp/127.0.0.1:{free_port()}"
    r = subprocess.run([sys.executable, "-m", "zenros.cli", *verb, *(["-e", dead] * explicit)],
                       capture_output=True, text=True, timeout=30, check=False,
                       env={**_env(), "ZENROS_CONNECT": dead})
    assert r.returncode == 3, (r.stdout, r.stderr)
    assert f"nothing answered at {dead}" in r.stderr and "zenros router" in r.stderr
    assert r.stdout == "" and "Traceback" not in r.stderr


def test_a_waiting_verb_says_what_it_waits_for_without_a_router() -> None:
    dead = f"tcp/127.0.0.1:{free_port()}"
    r = subprocess.run([sys.executable, "-m", "zenros.cli", "topic", "echo", "/odom", "--once",
                        "--timeout", "1"], capture_output=True, text=True, timeout=30,
                       check=False, env={**_env(), "ZENROS_CONNECT": dead})
    assert r.returncode == 1, r.stderr
    assert f"waiting for messages on /odom: nothing answered at {dead}" in r.stderr
    assert "no message on /odom: it has no publisher within 1 s" in r.stderr


def test_echo_timeout_says_why(robot: list[str]) -> None:
    r = zenros("topic", "echo", "/odom", "--once", "--timeout", "1", *robot)
    assert r.returncode == 1 and r.stdout == ""
    assert "no publisher on /odom yet; waiting for one (at most 1 s)" in r.stderr
    assert "zenros topic: no message on /odom: it has no publisher within 1 s" in r.stderr


@pytest.mark.parametrize(
    "args, needle",
    [
        (["service", "call", "/add_two_ints", "std_srvs/Trigger", "{}"],
         "service /add_two_ints has type example_interfaces/AddTwoInts, not std_srvs/Trigger"),
        (["topic", "pub", "/chatter", "geometry_msgs/Twist", "{}", "-1"],
         "topic /chatter has type std_msgs/String, not geometry_msgs/Twist"),
        (["action", "send_goal", "/fibonacci", "zenros_msgs/Patrol", "{}"],
         "action /fibonacci has type example_interfaces/Fibonacci, not"),
        (["param", "set", "/talker/rate", "fast"],
         "/talker declared 'rate' as float; 'fast' is str (--force stores it anyway)"),
        (["topic", "pub", "/cmd_vel", "geometry_msgs/Twst", "{}", "-1"],
         "unknown message type 'geometry_msgs/Twst'; did you mean geometry_msgs/Twist?"),
    ],
)
def test_the_wrong_type_is_refused_at_the_caller(
    robot: list[str], args: list[str], needle: str
) -> None:
    r = zenros(*args, *robot)
    assert r.returncode == 1, (r.stdout, r.stderr)
    assert needle in r.stderr and "Traceback" not in r.stderr


def test_param_set_force_and_a_live_rate_change(robot: list[str]) -> None:
    """`--force` stores what the check refuses; README's `param set /talker/rate` is live."""
    r = zenros("param", "set", "/talker/rate", "'10'", "--force", *robot)
    assert r.returncode == 0, r.stderr
    r = zenros("param", "get", "/talker/rate", *robot)
    assert r.stdout.strip() == '"10"'
    r = zenros("param", "set", "/talker/rate", "20.0", *robot)
    assert r.returncode == 0, r.stderr
    r = zenros("topic", "hz", "/chatter", "--count", "2", *robot)
    rate = float(r.stdout.split("average rate:")[-1].split()[0])
    assert 10 < rate < 30, r.stdout


def test_every_served_type_is_callable_with_a_short_name(robot: list[str]) -> None:
    r = zenros("service", "list", "-t", *robot)
    pairs = [line.split(" [") for line in r.stdout.splitlines()]
    assert ["/master/get_system_state", "zenros_msgs/GetSystemState]"] in pairs
    r = zenros("service", "call", "/master/lookup_node", "LookupNode", "{name: /talker}",
               *robot)
    assert r.returncode == 0, r.stderr
    assert "pid:" in r.stdout


def test_pub_without_rate_or_once_says_how_it_publishes(robot: list[str]) -> None:
    p = Proc([sys.executable, "-m", "zenros.cli", "topic", "pub", "/greeting", "std_msgs/String",
              "{data: hi}", *robot])
    try:
        assert p.wait_line("publishing std_msgs/String on /greeting at 1 Hz until Ctrl-C", 15), \
            p.output
    finally:
        p.stop()


def _env() -> dict[str, str]:
    import os

    return {k: v for k, v in os.environ.items() if k != "ZENROS_CONNECT"}
