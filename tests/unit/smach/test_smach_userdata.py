"""UserData and the key-restricted Remapper view each state receives."""

from __future__ import annotations

import threading

import pytest
from zenros.errors import UserDataError
from zenros.smach import Remapper, UserData


def test_item_and_attribute_access() -> None:
    ud = UserData({"a": 1})
    ud["b"] = 2
    ud.c = 3
    assert (ud.a, ud["b"], ud.get("c"), ud.get("zz", 9)) == (1, 2, 3, 9)
    assert ud.keys() == ["a", "b", "c"] and list(ud) == ["a", "b", "c"] and len(ud) == 3
    assert "a" in ud and "zz" not in ud
    del ud["a"]
    assert "a" not in ud


def test_missing_key_lists_the_set_keys() -> None:
    ud = UserData({"goal": 1, "speed": 2}, owner="container /NAV")
    with pytest.raises(UserDataError, match="container /NAV has no userdata key 'gaol'; set keys: goal, speed"):
        ud["gaol"]
    with pytest.raises(KeyError):  # UserDataError is a KeyError too
        _ = ud.gaol
    with pytest.raises(UserDataError, match="no userdata key 'x'"):
        del ud["x"]


def test_private_attributes_are_not_keys() -> None:
    ud = UserData()
    with pytest.raises(AttributeError):
        ud._missing  # noqa: B018
    with pytest.raises(UserDataError, match="use ud\\['keys'\\]"):
        setattr(ud, "keys", 1)  # noqa: B010
    with pytest.raises(UserDataError, match="non-empty strings"):
        ud[""] = 1


def test_update_and_snapshot() -> None:
    ud = UserData({"a": 1})
    ud.update({"b": 2})
    ud.update(UserData({"a": 5}))
    snap = ud.snapshot()
    snap["c"] = 3
    assert ud.snapshot() == {"a": 5, "b": 2}
    assert "UserData({'a': 5, 'b': 2})" == repr(ud)


def test_concurrent_writers_do_not_lose_keys() -> None:
    ud = UserData()

    def write(prefix: str) -> None:
        for i in range(500):
            ud[f"{prefix}{i}"] = i

    threads = [threading.Thread(target=write, args=(p,)) for p in "abcd"]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(ud) == 2000


def view(ud: UserData, inputs: tuple[str, ...] = ("a",), outputs: tuple[str, ...] = ("b",),
         remapping: dict[str, str] | None = None) -> Remapper:
    return Remapper(ud, "/SM/FOO (Foo)", inputs, outputs, remapping)


def test_remapper_reads_declared_inputs_through_the_remapping() -> None:
    ud = UserData({"counter": 4})
    v = view(ud, inputs=("foo_in",), outputs=("foo_out",),
             remapping={"foo_in": "counter", "foo_out": "counter"})
    assert v["foo_in"] == 4 and v.foo_in == 4 and v.get("foo_in") == 4
    v.foo_out = 5
    assert ud["counter"] == 5
    assert v.keys() == ["foo_in"] and "foo_in" in v and "counter" not in v


def test_reading_an_undeclared_key_names_state_and_key() -> None:
    v = view(UserData({"secret": 1}))
    with pytest.raises(UserDataError, match=r"state /SM/FOO \(Foo\) read userdata key 'secret'.*"
                       r"did not declare as an input key; its input keys: a"):
        v["secret"]
    with pytest.raises(UserDataError, match="'secret'"):
        v.get("secret")
    with pytest.raises(UserDataError):
        v.secret  # noqa: B018


def test_output_only_keys_are_not_readable() -> None:
    v = view(UserData({"b": 1}))
    with pytest.raises(UserDataError, match="read userdata key 'b'"):
        v["b"]


def test_writing_an_input_only_key_names_state_and_key() -> None:
    v = view(UserData({"a": 1}))
    with pytest.raises(UserDataError, match=r"state /SM/FOO \(Foo\) wrote userdata key 'a'.*"
                       r"its output keys: b"):
        v["a"] = 2
    with pytest.raises(UserDataError, match="wrote userdata key 'a'"):
        v.a = 2


def test_declared_but_unset_input_says_so() -> None:
    v = view(UserData({"x": 1}), remapping={"a": "goal"})
    with pytest.raises(UserDataError, match=r"read input key 'a' \(remapped to 'goal'\), which is"
                       r" not set; set keys: x"):
        v["a"]
    assert v.get("a", "default") == "default"
    assert "a" not in v


def test_remapper_protects_its_own_attributes() -> None:
    v = view(UserData())
    with pytest.raises(AttributeError):
        v._nothing  # noqa: B018
    with pytest.raises(UserDataError, match="cannot be set as an attribute"):
        setattr(v, "keys", 1)  # noqa: B010
    assert "Remapper(/SM/FOO (Foo)" in repr(v)
