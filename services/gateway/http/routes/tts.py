"""REST speech as text (docs/robot-api.md §3.7): ``/system/tts`` with aliases, playing/stop, and the
volume."""

from __future__ import annotations

import asyncio
from typing import Annotated

import msgspec
from zenros.msgs.std_msgs import String

from ...state.speech import MAX_ALIASES
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_tts_routes"]

Phrase = Annotated[str, msgspec.Meta(min_length=1, max_length=2000)]
AliasTable = Annotated[dict[Phrase, Phrase], msgspec.Meta(max_length=MAX_ALIASES)]


class TtsQuery(msgspec.Struct, forbid_unknown_fields=True):
    text: Phrase


class VolumeBody(msgspec.Struct, forbid_unknown_fields=True):
    value: Annotated[int, msgspec.Meta(ge=0, le=100)]


async def tts(call: Call[None, TtsQuery]) -> Answer:
    """Speak ``text`` (its alias if it has one): published on ``tts`` (std_msgs/String).

    When the active voice package has a recording of the text, the recording is played: it
    counts as playing for its length; otherwise (synthesised) for len(text) / 15 s, of the
    robot's clock. ``recording`` names the recording played (its md5sum), if any.
    """
    link, speech, store, voices = call.ctx.topics, call.ctx.speech, call.ctx.audio, \
        call.ctx.voices
    text = store.apply_alias(call.query.text)
    found = await asyncio.to_thread(voices.match, text) if voices is not None else None
    speech.say(text, found[0].duration if found is not None else None)
    link.tts_pub.publish(String(data=text))
    if found is not None:
        return {"status": "ok", "recording": found[0].md5sum}
    return {"status": "ok"}


async def playing(call: Call[None, None]) -> Answer:
    """Whether speech is playing: ``status`` bool."""
    speech = call.ctx.speech
    return {"status": speech.playing()}


async def stop(call: Call[None, None]) -> Answer:
    """Stop speaking."""
    speech = call.ctx.speech
    speech.stop()
    return {"status": "ok"}


async def get_alias(call: Call[None, None]) -> Answer:
    """The alias table ``{text: text spoken instead}``."""
    store = call.ctx.audio
    return store.aliases()


async def post_alias(call: Call[AliasTable, None]) -> Answer:
    """Replace the whole alias table."""
    store = call.ctx.audio
    store.replace_aliases(call.body)
    return {"status": "ok"}


async def put_alias(call: Call[AliasTable, None]) -> Answer:
    """Add or change the given aliases; returns the whole table."""
    store = call.ctx.audio
    try:
        return store.update_aliases(call.body)
    except ValueError as exc:
        raise ApiError(400, str(exc)) from exc


async def get_volume(call: Call[None, None]) -> Answer:
    """Speaker volume ``value`` (0-100; kept, though the simulated robot is silent)."""
    store = call.ctx.audio
    return {"value": store.current.volume}


async def put_volume(call: Call[VolumeBody, None]) -> Answer:
    """Set the speaker volume ``value`` (0-100)."""
    store = call.ctx.audio
    store.set_volume(call.body.value)
    return {"status": "ok"}


def add_tts_routes(api: Api) -> None:
    """Route TTS, its alias table, playing/stop and the volume."""
    api.add("GET", "/system/tts", tts)
    api.add("GET", "/system/tts/playing", playing)
    api.add("GET", "/system/tts/stop", stop)
    api.add("GET", "/system/tts/alias", get_alias)
    api.add("POST", "/system/tts/alias", post_alias)
    api.add("PUT", "/system/tts/alias", put_alias)
    api.add("GET", "/system/volume", get_volume)
    api.add("PUT", "/system/volume", put_volume)
