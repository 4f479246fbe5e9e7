"""The simulated speaker: a sentence "plays" for as long as it would take to say it.

:func:`speech_duration` estimates that time from the text (a CJK character is a syllable, about
a quarter of a second; other scripts about 14 characters a second), and :func:`synthesize`
makes the audio file a text-to-speech engine would have downloaded: a mono WAV of that length,
one soft tone per syllable with pitch from the character, so the file is real audio of the
right length that any player opens.
"""

from __future__ import annotations

import io
import math
import wave

import numpy as np

from polynav.errors import InvalidRequest

LEAD = 0.3  # [s] silence an engine puts before and after a sentence
CJK_SYLLABLE = 0.25  # [s] per CJK character
LATIN_CHAR = 0.07  # [s] per other character
RATE = 16_000  # [Hz] sample rate of the audio files


def speech_duration(text: str) -> float:
    """How long saying ``text`` takes [s]."""
    cjk = sum(1 for ch in text if _is_cjk(ch))
    other = sum(1 for ch in text if not _is_cjk(ch) and not ch.isspace())
    spaces = sum(1 for ch in text if ch.isspace())
    return round(2 * LEAD + CJK_SYLLABLE * cjk + LATIN_CHAR * (other + 0.5 * spaces), 3)


def synthesize(text: str) -> bytes:
    """A WAV file (16 kHz, 16-bit mono) of ``speech_duration(text)`` seconds for ``text``."""
    total = int(round(speech_duration(text) * RATE))
    samples = np.zeros(total, dtype=np.float64)
    chars = [ch for ch in text if not ch.isspace()] or [" "]
    start, end = int(LEAD * RATE), total - int(LEAD * RATE)
    span = max(1, (end - start) // len(chars))
    t = np.arange(span) / RATE
    envelope = np.sin(np.pi * np.arange(span) / span) ** 2
    for k, ch in enumerate(chars):
        pitch = 140.0 + (ord(ch) % 97) * 2.0
        tone = np.sin(2 * math.pi * pitch * t) + 0.3 * np.sin(4 * math.pi * pitch * t)
        samples[start + k * span:start + (k + 1) * span] = 0.3 * envelope * tone
    pcm = (np.clip(samples, -1.0, 1.0) * 32767).astype("<i2")
    out = io.BytesIO()
    with wave.open(out, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(RATE)
        w.writeframes(pcm.tobytes())
    return out.getvalue()


class SimSpeaker:
    """Implements :class:`~polynav.robot.devices.Speaker` on the runtime's clock."""

    def __init__(self, volume: int = 60) -> None:
        self._volume = volume
        self._until = -math.inf
        self.text: str | None = None  # what plays, or played last

    def say(self, now: float, text: str, duration: float) -> None:
        """Play ``text`` for ``duration`` seconds, cutting off whatever plays."""
        self.text = text
        self._until = now + duration

    def stop(self, now: float) -> bool:
        was = self.playing(now)
        self._until = -math.inf
        return was

    def playing(self, now: float) -> bool:
        return now < self._until

    @property
    def volume(self) -> int:
        return self._volume

    def set_volume(self, percent: int) -> None:
        """Raises: InvalidRequest: not an integer in 0..100."""
        if isinstance(percent, bool) or not isinstance(percent, int) or not 0 <= percent <= 100:
            raise InvalidRequest("value", f"volume must be an integer 0..100, got {percent!r}")
        self._volume = percent


def _is_cjk(ch: str) -> bool:
    code = ord(ch)
    return 0x3040 <= code <= 0x30FF or 0x3400 <= code <= 0x9FFF or 0xAC00 <= code <= 0xD7AF
