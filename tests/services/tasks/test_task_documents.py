"""Task and action documents: creation, validation errors, progress, update."""

from __future__ import annotations

from typing import Any

import pytest
from zenros.services.tasks.documents import (
    DocumentError,
    kind_of,
    leaves,
    new_task,
    progress_of,
    reset,
    substitute,
    update_task,
)


def test_create_body_of_the_spec() -> None:
    doc = new_task({"name": "task", "loop_flag": False, "sub_tasks": [
        {"type": "nav_action", "x": 0, "y": 0, "theta": 0},
        {"type": "nav_action", "x": 1, "y": 1, "theta": 1}]})
    assert doc.state == "WAITTING" and doc.progress == 0 and doc.current_task is None
    assert [a.state for a in doc.sub_tasks] == ["WAITTING", "WAITTING"]
    assert doc.sub_tasks[1].x == 1.0 and doc.sub_tasks[0].current_distance == -1
    assert len({doc.id, *(a.id for a in doc.sub_tasks)}) == 3


@pytest.mark.parametrize("body, words", [
    ({"sub_tasks": [{"type": "fly_action"}]}, ["unknown action type 'fly_action'",
                                               "sub_tasks[0]", "sleep_action"]),
    ({"sub_tasks": [{"wait_time": 1}]}, ["missing field 'type'"]),
    ({"sub_tasks": [{"type": "sleep_action"}]}, ["wait_time"]),
    ({"sub_tasks": [{"type": "sleep_action", "wait_time": "x"}]}, ["wait_time"]),
    ({"sub_tasks": [{"type": "sleep_action", "wait_time": -1}]}, ["wait_time"]),
    ({"sub_tasks": [{"type": "sleep_action", "wait_time": 1, "colour": 1}]}, ["colour"]),
    ({"sub_tasks": [{"type": "nav_action", "x": 1}]}, ["x and y, or a nav point index"]),
    ({"sub_tasks": [{"type": "callback_action", "url": "file:///etc/passwd"}]}, ["http"]),
    ({"sub_tasks": [{"type": "callback_action", "url": "http://a", "method": "EVAL"}]},
     ["method"]),
    ({"name": 3}, ["'name' must be str"]),
    ({"loop_flag": "yes"}, ["'loop_flag' must be bool"]),
    ({"sub_tasks": {}}, ["'sub_tasks' must be list"]),
    ({"control_type": "dance"}, ["unknown control_type 'dance'"]),
    ({"control_type": "flip", "sub_tasks": []}, ["exactly 1"]),
    ({"bogus": 1}, ["unknown field 'bogus'"]),
    ({"control_type": "loop", "target_loop_count": 0,
      "sub_tasks": [{"type": "sleep_action", "wait_time": 0}]}, ["target_loop_count"]),
    ([], ["expected an object"]),
])
def test_bad_bodies_name_the_field(body: Any, words: list[str]) -> None:
    with pytest.raises(DocumentError) as err:
        new_task(body)
    for w in words:
        assert w in str(err.value)


def test_nested_tasks_and_progress() -> None:
    doc = new_task({"sub_tasks": [
        {"type": "sleep_action", "wait_time": 1},
        {"name": "inner", "sub_tasks": [{"type": "tts_action", "text": "a"},
                                        {"type": "tts_action", "text": "b"}]}]})
    acts = leaves(doc)
    assert [kind_of(a) for a in acts] == ["sleep_action", "tts_action", "tts_action"]
    acts[0].state = "COMPLETE"
    acts[1].progress = 0.5
    assert progress_of(doc) == pytest.approx(0.5)
    reset(doc)
    assert progress_of(doc) == 0 and all(a.state == "WAITTING" for a in acts)


def test_update_keeps_ids_and_validates() -> None:
    doc = new_task({"name": "a", "sub_tasks": [{"type": "sleep_action", "wait_time": 1}]})
    fresh = update_task(doc, {"name": "b", "loop_flag": True})
    assert fresh.id == doc.id and fresh.name == "b" and fresh.loop_flag is True
    assert fresh.sub_tasks[0].wait_time == 1
    assert [a.id for a in fresh.sub_tasks] == [a.id for a in doc.sub_tasks]
    old = doc.sub_tasks[0]
    again = update_task(doc, {"sub_tasks": [old, {"type": "tts_action", "text": "x"}]})
    assert again.sub_tasks[0].id == old.id
    assert again.sub_tasks[1].id != old.id
    with pytest.raises(DocumentError, match="state"):
        update_task(doc, {"state": "COMPLETE"})


def test_blackboard_substitution() -> None:
    assert substitute({"text": "{who} says {what}", "n": 1}, {"who": "bot", "what": "hi"}) == {
        "text": "bot says hi", "n": 1}
