"""waiting: `wait_for`'s result explains a failed wait (the condition, the time, the last value)
and is true or false as the old bool was; `wait_until` raises with the same text."""

from __future__ import annotations

import asyncio

import pytest
from zenros.testing import Waited, WaitTimeout, wait_for, wait_for_async, wait_until
from zenros.waiting import describe


def test_a_met_condition_is_true_and_equal_to_true() -> None:
    got = [1, 2, 3]
    res = wait_for(lambda: len(got) == 3, 1)
    assert res and res == True  # existing call sites may compare with True
    assert isinstance(res, Waited) and res.value is True and res.polls == 1
    assert repr(res).startswith("<waited 0.00 s for `len(got) == 3`: True>")


def test_a_timeout_is_false_and_says_what_it_waited_for_and_saw() -> None:
    got: list[int] = []
    res = wait_for(lambda: len(got) >= 3, 0.05)
    assert not res and res == False
    text = repr(res)
    assert text.startswith("<timed out after 0.05 s waiting for `len(got) >= 3`: last False, ")
    assert text.endswith(" polls>")


def test_a_failing_assert_prints_the_explanation() -> None:
    """What a reader of a failed test sees: pytest's assert shows the result's repr."""
    seen = {"state": "DRIVING"}
    with pytest.raises(AssertionError) as exc:
        assert wait_for(lambda: seen["state"] == "ARRIVED", 0.02)
    assert "waiting for `seen[\"state\"] == \"ARRIVED\"`: last False" in str(exc.value)


def test_the_last_value_is_the_one_seen_at_the_time() -> None:
    values = [1]
    res = wait_for(lambda: values if len(values) > 5 else [], 0.02)
    values.append(2)
    assert "last []" in repr(res)


def test_a_function_or_a_description_names_the_condition() -> None:
    def robot_docked() -> bool:
        return False

    res = wait_for(robot_docked, 0.01)
    assert "waiting for test_a_function_or_a_description_names_the_condition.<locals>." \
        "robot_docked(): last False" in repr(res)
    res = wait_for(lambda: None, 0.01, what="the dock's contact")
    assert "waiting for the dock's contact: last None" in repr(res)


def test_the_innermost_lambda_of_a_line_is_described() -> None:
    xs = [1]
    a, b = (lambda: len(xs) > 2), (lambda: sorted(xs, key=lambda x: -x) == xs)
    assert describe(a) == "`len(xs) > 2`"
    assert describe(b) == "`sorted(xs, key=lambda x: -x) == xs`"


def test_wait_until_raises_with_the_explanation_and_returns_the_value() -> None:
    with pytest.raises(WaitTimeout, match=r"waiting for `0`: last 0, \d+ polls"):
        wait_until(lambda: 0, 0.01)
    assert wait_until(lambda: [7], 1).value == [7]
    assert issubclass(WaitTimeout, AssertionError)


def test_wait_for_async() -> None:
    async def run() -> tuple[Waited, Waited]:
        return (await wait_for_async(lambda: 5, 1),
                await wait_for_async(lambda: "", 0.02, what="a reply"))

    ok, late = asyncio.run(run())
    assert ok and ok.value == 5
    assert not late and "waiting for a reply: last ''" in repr(late)
