"""``png`` frames (services/gateway/rosbridge/png.py): written with zlib, read by Pillow as a
browser reads them, in the reference server's layout, whatever the text's length."""

from __future__ import annotations

import base64
import io
import json
import math
import zlib

import pytest
from PIL import Image
from zenros import json_chunks
from zenros.services.gateway.rosbridge.png import (
    DEFLATE_SLICE,
    LEVEL,
    _deflate,
    png_frame,
    png_text,
)


def _image(frame: bytes) -> Image.Image:
    obj = json.loads(frame)
    assert obj.keys() == {"op", "data"} and obj["op"] == "png"
    img = Image.open(io.BytesIO(base64.b64decode(obj["data"], validate=True)))
    img.load()  # checks every chunk's CRC and the deflate stream
    return img


@pytest.mark.parametrize("n", [1, 2, 3, 4, 47, 3000, 100_003])
def test_any_length_round_trips_in_the_reference_layout(n: int) -> None:
    text = json.dumps({"op": "publish", "topic": "/t", "msg": {"data": "x" * n}}).encode()
    frame = png_frame(text)
    img = _image(frame)
    assert img.format == "PNG" and img.mode == "RGB"
    width, height = img.size
    assert width == max(1, math.floor(math.sqrt(len(text) / 3)))
    assert height == math.ceil(math.ceil(len(text) / 3) / width)
    raw = img.tobytes()
    assert raw[:len(text)] == text and set(raw[len(text):]) <= {ord("\n")}
    assert png_text(json.loads(frame)["data"]).decode() == text.decode()


def test_a_map_sized_text_is_compressed() -> None:
    cells = ",".join(["-1"] * 400_000 + ["0"] * 1_000_000 + ["100"] * 50_000)
    text = f'{{"op":"publish","topic":"/map","msg":{{"data":[{cells}]}}}}'.encode()
    frame = png_frame(text)
    assert len(frame) < len(text) / 20
    assert json.loads(png_text(json.loads(frame)["data"]))["msg"]["data"][-1] == 100


def test_png_text_refuses_what_is_not_a_png() -> None:
    with pytest.raises(ValueError):
        png_text("not base64!")
    with pytest.raises(OSError):  # Pillow's UnidentifiedImageError
        png_text(base64.b64encode(b"GIF89a").decode())


def test_a_large_text_is_deflated_in_paced_slices(monkeypatch: pytest.MonkeyPatch) -> None:
    """A map's text is deflated `DEFLATE_SLICE` bytes at a time, with a rest after each (the
    same stream as one `zlib.compress`), so its deflating does not take the CPU from the
    other clients in one go."""
    rests: list[float] = []
    monkeypatch.setattr(json_chunks.time, "sleep", rests.append)
    text = b"1,0,-1,100," * 200_000  # 2.2 MB
    frame = png_frame(text)
    assert png_text(json.loads(frame)["data"]) == text
    assert len(rests) == math.ceil(len(text) / DEFLATE_SLICE) + 1  # the slices and the flush
    assert _deflate(text) == zlib.compress(text, LEVEL)
