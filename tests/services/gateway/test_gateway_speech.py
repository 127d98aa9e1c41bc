"""`Speech` (playing for len/15 s of a given clock, stop) and `AudioStore` (aliases and
volume persisted)."""

from __future__ import annotations

from pathlib import Path

import pytest
from zenros.services.gateway.state.speech import CHARS_PER_SECOND, AudioStore, Speech


def test_speech_lasts_by_length() -> None:
    t = [100.0]
    speech = Speech(lambda: t[0])
    assert not speech.playing()
    assert speech.say("x" * 30) == pytest.approx(30 / CHARS_PER_SECOND)
    assert speech.playing()
    t[0] += 1.9
    assert speech.playing()
    t[0] += 0.2
    assert not speech.playing()
    speech.say("hello there")
    assert speech.stop() and not speech.playing() and not speech.stop()


def test_audio_store_persists(tmp_path: Path) -> None:
    path = tmp_path / "d" / "audio.json"
    store = AudioStore(path)
    assert store.current.volume == 50 and store.aliases() == {}
    store.replace_aliases({"hello": "hello there"})
    assert store.update_aliases({"bye": "goodbye"}) == {"hello": "hello there", "bye": "goodbye"}
    assert store.apply_alias("hello") == "hello there" and store.apply_alias("hi") == "hi"
    with pytest.raises(ValueError, match="over 1000"):
        store.update_aliases({f"k{i}": "v" for i in range(999)})
    assert len(store.aliases()) == 2   # refused whole
    store.set_volume(80)
    with pytest.raises(ValueError, match="0-100"):
        store.set_volume(101)
    again = AudioStore(path)
    assert again.current.volume == 80 and again.aliases()["bye"] == "goodbye"
    path.write_text("{\"volume\": \"loud\"}")
    with pytest.raises(ValueError, match="audio.json"):
        AudioStore(path)
