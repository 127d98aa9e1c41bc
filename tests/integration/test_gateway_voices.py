"""docs/robot-api.md §3.7 voice packages through a real server, with files a recorder makes
(the standard `wave` module's WAV, hand-built MPEG Layer III frames): phrases added and listed
with their md5sum and length, a package selected and played by /system/tts for the
recording's length, a zipped package uploaded, deletions; bad uploads refused with the reason
and nothing written outside the package's folder."""

from __future__ import annotations

import hashlib
import io
import json
import struct
import wave
import zipfile
from pathlib import Path

import httpx
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for


def wav(seconds: float, rate: int = 8000) -> bytes:
    out = io.BytesIO()
    with wave.open(out, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(struct.pack("<h", 0) * int(seconds * rate))
    return out.getvalue()


def mp3(frames: int) -> bytes:
    """MPEG-1 Layer III, 128 kbit/s, 44.1 kHz: 417-byte frames of 1152 samples."""
    return (b"\xff\xfb\x90\x64" + bytes(413)) * frames


def _refused(r: httpx.Response, status: int, words: str) -> None:
    assert r.status_code == status, r.text
    assert words in r.json()["description"], r.text


def test_phrases_packages_and_playing_a_recording(gw: GatewayNode, http: httpx.Client,
                                                  tmp_path: Path) -> None:
    assert http.get("/system/tts/records").json() == {
        "packages": [], "records": [], "current_package": ""}
    welcome = wav(1.5)
    r = http.post("/system/tts/records", data={"package_name": "Jenny", "text": "Welcome"},
                  files={"audio_file": ("welcome.wav", welcome, "audio/wav")})
    assert r.status_code == 200, r.text
    assert r.json() == {"status": "ok", "md5sum": hashlib.md5(welcome).hexdigest()}
    r = http.post("/system/tts/records", data={"package_name": "Jenny", "text": "Goodbye"},
                  files={"audio_file": ("bye.mp3", mp3(100), "audio/mpeg")})
    assert r.status_code == 200, r.text
    got = http.get("/system/tts/records", params={"package_name": "Jenny"}).json()
    assert got["packages"] == ["Jenny"] and got["current_package"] == ""
    records = {rec["text"]: rec for rec in got["records"]}
    assert records["Welcome"]["duration"] == 1.5
    assert records["Goodbye"]["duration"] == round(100 * 1152 / 44100, 3)
    assert records["Welcome"]["md5sum"] == hashlib.md5(welcome).hexdigest()
    assert records["Welcome"]["active_count"] == 0
    # select the package, then speaking its phrase plays the recording for its length
    r = http.post("/system/tts/records", json={"package_name": "Jenny"})
    assert r.json() == {"status": "ok"}, r.text
    assert http.get("/system/tts/records").json()["current_package"] == "Jenny"
    r = http.get("/system/tts", params={"text": "Welcome"})
    assert r.json() == {"status": "ok", "recording": records["Welcome"]["md5sum"]}
    assert http.get("/system/tts/playing").json() == {"status": True}
    assert wait_for(lambda: http.get("/system/tts/playing").json() == {"status": False}, 10)
    r = http.get("/system/tts", params={"text": "Something else"})
    assert r.json() == {"status": "ok"}  # synthesised: no recording
    rec = {x["text"]: x for x in http.get("/system/tts/records").json()["records"]}["Welcome"]
    assert rec["active_count"] == 1 and rec["last_active"] > 0
    # a package as a zip, its name in another script; records.json names files by base name
    archive = io.BytesIO()
    with zipfile.ZipFile(archive, "w") as zf:
        zf.writestr("pkg/records.json", json.dumps([
            {"text": "你好", "file": "../../hello.wav", "tags": ["welcome-mode"],
             "i18n": {"en": "Hello"}}]))
        zf.writestr("pkg/hello.wav", wav(0.5))
    r = http.post("/system/tts/records", data={"package_name": "中文"},
                  files={"package_file": ("pkg.zip", archive.getvalue(), "application/zip")})
    assert r.status_code == 200 and r.json() == {"status": "ok", "records": 1}, r.text
    got = http.get("/system/tts/records", params={"package_name": "中文"}).json()
    assert got["packages"] == ["Jenny", "中文"]
    [hello] = got["records"]
    assert hello["text"] == "你好" and hello["tags"] == ["welcome-mode"]
    assert hello["i18n"] == {"en": "Hello"} and hello["file"].endswith(".wav")
    assert not (tmp_path / "hello.wav").exists()
    # deletions
    assert http.delete("/system/tts/records", params={"text": "Goodbye"}).json() == {
        "status": "ok"}
    assert [x["text"] for x in http.get("/system/tts/records").json()["records"]] == [
        "Welcome"]
    _refused(http.delete("/system/tts/records", params={"text": "Goodbye"}), 404,
             "has no phrase 'Goodbye'")
    assert http.delete("/system/tts/records", params={"package_name": "中文"}).json() == {
        "status": "ok"}
    assert http.get("/system/tts/records").json()["packages"] == ["Jenny"]


def test_bad_uploads_are_refused_with_the_reason(gw: GatewayNode, http: httpx.Client) -> None:
    def phrase(name: str, data: bytes, package: str = "p", text: str = "t") -> httpx.Response:
        return http.post("/system/tts/records", data={"package_name": package, "text": text},
                         files={"audio_file": (name, data, "application/octet-stream")})

    _refused(phrase("x.wav", b"not a wav at all"), 400, "not a PCM WAV file")
    _refused(phrase("x.mp3", b"ID3\x03\x00\x00\x00\x00\x00\x00garbage"), 400, "not an MP3")
    _refused(phrase("x.ogg", wav(0.1)), 400, "a .wav or an .mp3")
    _refused(phrase("x.wav", wav(0.1), package="../etc"), 400, "package_name")
    _refused(phrase("x.wav", wav(0.1), package=".hidden"), 400, "package_name")
    _refused(phrase("x.wav", wav(0.1), text=""), 400, "give `package_file`")
    _refused(phrase("big.wav", wav(600, rate=8000)), 413, "over")
    _refused(http.post("/system/tts/records", json={"package_name": "nope"}), 404,
             "no voice package 'nope'")
    _refused(http.post("/system/tts/records", json={"name": "x"}), 400, "invalid body")
    _refused(http.post("/system/tts/records", content=b"plain", headers={
        "content-type": "text/plain"}), 400, "multipart/form-data")
    _refused(http.post("/system/tts/records", data={"package_name": "p"},
                       files={"package_file": ("p.zip", b"PK not really", "application/zip")}),
             400, "not a zip archive")
    archive = io.BytesIO()
    with zipfile.ZipFile(archive, "w") as zf:
        zf.writestr("records.json", json.dumps([{"text": "a", "file": "missing.wav"}]))
    _refused(http.post("/system/tts/records", data={"package_name": "p"},
                       files={"package_file": ("p.zip", archive.getvalue(), "application/zip")}),
             400, "not in the archive")
    _refused(http.delete("/system/tts/records"), 400, "give `package_name`")
    _refused(http.delete("/system/tts/records", params={"text": "x"}), 409, "no voice package")
    assert http.get("/system/tts/records").json()["packages"] == []  # nothing was kept
