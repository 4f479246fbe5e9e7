from __future__ import annotations

import io
import json
import wave
import zipfile
from pathlib import Path

import pytest

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.robot.sim.devices.speaker import SimSpeaker, speech_duration, synthesize
from polynav.robot.sim.devices.voice_library import VoiceLibrary, text_md5


def _wav_seconds(data: bytes) -> float:
    with wave.open(io.BytesIO(data)) as w:
        return w.getnframes() / w.getframerate()


def test_speech_takes_longer_for_longer_text_and_cjk_syllables_count_more() -> None:
    assert speech_duration("欢迎光临") == pytest.approx(0.6 + 4 * 0.25)
    assert speech_duration("Welcome") == pytest.approx(0.6 + 7 * 0.07)
    assert speech_duration("Start charging now") > speech_duration("Start")


def test_the_synthesized_audio_is_a_wav_as_long_as_the_speech() -> None:
    data = synthesize("开始充电")
    assert _wav_seconds(data) == pytest.approx(speech_duration("开始充电"), abs=1e-3)


def test_the_speaker_plays_for_the_duration_and_a_new_sentence_or_stop_cuts_it() -> None:
    speaker = SimSpeaker()
    speaker.say(10.0, "hello", 2.0)
    assert speaker.playing(11.9) and not speaker.playing(12.0)
    speaker.say(20.0, "a", 5.0)
    assert speaker.stop(21.0) is True
    assert not speaker.playing(21.0) and speaker.stop(21.0) is False


def test_volume_is_an_integer_percent() -> None:
    speaker = SimSpeaker()
    speaker.set_volume(35)
    assert speaker.volume == 35
    for bad in (-1, 101, 50.5, True):
        with pytest.raises(InvalidRequest):
            speaker.set_volume(bad)  # type: ignore[arg-type]
    assert speaker.volume == 35


def test_playing_makes_the_audio_once_and_counts_the_plays(tmp_path: Path) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    assert lib.packages() == ["default"] and lib.current == "default"
    path = lib.play("欢迎光临", 1000)
    assert path.name == text_md5("欢迎光临") + ".wav"
    made = path.stat().st_mtime_ns
    lib.play("欢迎光临", 2000)
    assert path.stat().st_mtime_ns == made
    (record,) = lib.records()
    assert (record.text, record.active_count, record.last_active) == ("欢迎光临", 2, 2000)
    assert record.md5sum == text_md5("欢迎光临") and record.codenames == ["all"]
    with pytest.raises(InvalidRequest):
        lib.play("  ", 3000)


def test_a_package_exports_and_imports_as_a_zip_and_becomes_current(tmp_path: Path) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    lib.play("hello", 1)
    archive = lib.export("default")
    names = zipfile.ZipFile(io.BytesIO(archive)).namelist()
    assert sorted(names) == sorted([text_md5("hello") + ".wav", "records.json"])
    lib.import_archive("Jenny", archive)
    assert lib.packages() == ["Jenny", "default"] and lib.current == "Jenny"
    assert lib.audio_path("Jenny", "hello").read_bytes() == synthesize("hello")


def test_loose_audio_files_make_a_package_named_by_their_texts(tmp_path: Path) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    lib.import_files("mine", {"hello.wav": b"RIFF1", "bye.mp3": b"ID3"})
    assert lib.current == "mine"
    assert lib.audio_path("mine", "bye").suffix == ".mp3"
    assert {r.text for r in lib.records()} == {"hello", "bye"}
    lib.replace_audio("mine", "hello", "new.ogg", b"OggS")
    assert lib.audio_path("mine", "hello").read_bytes() == b"OggS"
    lib.reset_text("hello", "mine")
    assert lib.audio_path("mine", "hello").read_bytes() == synthesize("hello")


def test_deleting_the_current_package_falls_back_to_the_default(tmp_path: Path) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    lib.import_files("mine", {"hi.wav": b"RIFF"})
    lib.delete_package("mine")
    assert lib.packages() == ["default"] and lib.current == "default"
    with pytest.raises(NotFound):
        lib.delete_package("mine")
    with pytest.raises(Conflict):
        lib.delete_package("default")


@pytest.mark.parametrize("name", ["", "..", "a/b", "../x", "x\x00"])
def test_package_names_that_are_not_plain_names_are_refused(tmp_path: Path, name: str) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    with pytest.raises(InvalidRequest):
        lib.import_files(name, {"hi.wav": b"RIFF"})
    assert lib.packages() == ["default"]
    assert not (tmp_path / "x").exists()


def test_bad_uploads_are_refused_and_change_nothing(tmp_path: Path) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    with pytest.raises(InvalidRequest):
        lib.import_archive("x", b"not a zip")
    empty = io.BytesIO()
    with zipfile.ZipFile(empty, "w") as z:
        z.writestr("readme.txt", "no audio")
    with pytest.raises(InvalidRequest):
        lib.import_archive("x", empty.getvalue())
    with pytest.raises(InvalidRequest):
        lib.import_files("x", {"notes.txt": b"text"})
    assert lib.packages() == ["default"] and lib.current == "default"


def test_archive_members_with_folders_land_inside_the_package(tmp_path: Path) -> None:
    archive = io.BytesIO()
    with zipfile.ZipFile(archive, "w") as z:
        z.writestr("../../evil.wav", b"RIFF")
    lib = VoiceLibrary(tmp_path / "voice")
    lib.import_archive("p", archive.getvalue())
    assert lib.audio_path("p", "evil").parent == tmp_path / "voice" / "packages" / "p"
    assert not (tmp_path / "evil.wav").exists()


def test_aliases_replace_all_or_update_some(tmp_path: Path) -> None:
    lib = VoiceLibrary(tmp_path / "voice")
    assert lib.aliases() == {}
    assert lib.set_aliases({"你好": "你好啊"}, replace_all=True) == {"你好": "你好啊"}
    table = lib.set_aliases({"再见": "拜拜"}, replace_all=False)
    assert table == {"你好": "你好啊", "再见": "拜拜"}
    # The original now sounds as its replacement.
    assert lib.audio_path("default", "再见").read_bytes() == synthesize("拜拜")
    assert lib.set_aliases({"a": "b"}, replace_all=True) == {"a": "b"}
    with pytest.raises(InvalidRequest):
        lib.set_aliases({"a": 3}, replace_all=True)  # type: ignore[dict-item]
    assert json.loads((tmp_path / "voice" / "aliases.json").read_text()) == {"a": "b"}
