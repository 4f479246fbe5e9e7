"""Voice packages, play records and text aliases, kept in a folder of the data directory.

Layout of ``root``::

    packages/<package>/<md5 of the text>.<ext>   one audio file per text of the package
    records.json     {"current_package": ..., "records": [...]}: every text ever played
    aliases.json     {original text: text shown instead}

A text plays from the current package; the first time, its audio is "downloaded" (made by
:func:`~polynav.robot.sim.devices.speaker.synthesize`) into the package. A package can be
exported as a zip of its audio files and ``records.json``, imported from such a zip or from
loose audio files (the file name without extension is the text), and one text's audio can be
replaced by an uploaded file. Every write is atomic (temp file, fsync, rename). Package names
are one plain path component; archives are read member by member with a size cap, and only
plain file names are taken from them, so nothing lands outside ``root``.
"""

from __future__ import annotations

import hashlib
import io
import json
import logging
import os
import shutil
import tempfile
import zipfile
from collections.abc import Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any

from polynav.errors import Conflict, InvalidRequest, NotFound, StorageError
from polynav.robot.sim.devices.speaker import synthesize

log = logging.getLogger(__name__)

DEFAULT_PACKAGE = "default"
AUDIO_EXTENSIONS = (".wav", ".mp3", ".ogg", ".flac", ".m4a", ".aac")
MAX_ARCHIVE_BYTES = 64 * 1024 * 1024  # uncompressed, over all members
MAX_AUDIO_BYTES = 16 * 1024 * 1024


@dataclass(slots=True)
class VoiceRecord:
    """A text the robot has spoken (fields as Galileo's voice records name them)."""

    text: str
    md5sum: str
    tags: list[str] = field(default_factory=list)
    codenames: list[str] = field(default_factory=lambda: ["all"])
    i18n: dict[str, str] = field(default_factory=dict)
    mode: list[str] = field(default_factory=lambda: ["all"])
    last_active: int = 0  # [ms]
    active_count: int = 0


def text_md5(text: str) -> str:
    return hashlib.md5(text.encode("utf-8")).hexdigest()


def check_package_name(name: str) -> str:
    """Raises: InvalidRequest: not a plain, non-empty file name."""
    if (not isinstance(name, str) or not name.strip() or name in (".", "..") or "/" in name
            or "\\" in name or "\x00" in name or len(name.encode()) > 128):
        raise InvalidRequest("package_name", f"must be a plain name, got {name!r}")
    return name


class VoiceLibrary:
    """The voice packages, records and aliases under ``root`` (created on first use)."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self._packages = root / "packages"
        self._records_file = root / "records.json"
        self._aliases_file = root / "aliases.json"

    # -- reads -----------------------------------------------------------------------------

    def packages(self) -> list[str]:
        self._ensure()
        return sorted(p.name for p in self._packages.iterdir() if p.is_dir())

    @property
    def current(self) -> str:
        return str(self._load_records()["current_package"])

    def records(self) -> list[VoiceRecord]:
        return [VoiceRecord(**r) for r in self._load_records()["records"]]

    def aliases(self) -> dict[str, str]:
        self._ensure()
        if not self._aliases_file.exists():
            return {}
        data = json.loads(self._aliases_file.read_text("utf-8"))
        return {str(k): str(v) for k, v in data.items()}

    def audio_path(self, package: str, text: str) -> Path:
        """The audio file of ``text`` in ``package``.

        Raises:
            NotFound: no such package, or no audio for the text in it.
        """
        folder = self._package_dir(package)
        for ext in AUDIO_EXTENSIONS:
            path = folder / (text_md5(text) + ext)
            if path.is_file():
                return path
        raise NotFound("voice", f"{package}/{text}")

    def export(self, package: str) -> bytes:
        """``package`` as a zip of its audio files and the records of their texts."""
        folder = self._package_dir(package)
        md5s = {p.stem for p in folder.iterdir() if p.is_file()}
        records = [asdict(r) for r in self.records() if r.md5sum in md5s]
        out = io.BytesIO()
        with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
            for path in sorted(folder.iterdir()):
                if path.is_file():
                    z.write(path, path.name)
            z.writestr("records.json", json.dumps(records, ensure_ascii=False))
        return out.getvalue()

    # -- playing ---------------------------------------------------------------------------

    def play(self, text: str, now_ms: int) -> Path:
        """Record that ``text`` is spoken now; its audio in the current package (made the
        first time).

        Raises:
            InvalidRequest: an empty text.
        """
        if not isinstance(text, str) or not text.strip():
            raise InvalidRequest("text", "nothing to say")
        package = self.current
        try:
            path = self.audio_path(package, text)
        except NotFound:
            path = self._package_dir(package) / (text_md5(text) + ".wav")
            _write_atomic(path, synthesize(text))
        data = self._load_records()
        record = self._record_in(data, text)
        record["last_active"] = now_ms
        record["active_count"] = int(record["active_count"]) + 1
        self._save_records(data)
        return path

    # -- packages --------------------------------------------------------------------------

    def import_files(self, package: str, files: Mapping[str, bytes]) -> None:
        """Make ``package`` from loose audio files (file name without extension = the text)
        and switch to it.

        Raises:
            InvalidRequest: no files, a file that is not audio or too big.
        """
        check_package_name(package)
        if not files:
            raise InvalidRequest("file", "no audio files uploaded")
        staged: dict[str, tuple[str, bytes]] = {}
        for name, data in files.items():
            stem, ext = _audio_name(name)
            if len(data) > MAX_AUDIO_BYTES:
                raise InvalidRequest("file", f"{name!r} is over {MAX_AUDIO_BYTES} bytes")
            staged[stem] = (ext, data)
        self._replace_package(package, staged, merge=True)

    def import_archive(self, package: str, archive: bytes) -> None:
        """Make or replace ``package`` from an exported zip and switch to it.

        Raises:
            InvalidRequest: not a zip, too big, or no audio in it.
        """
        check_package_name(package)
        try:
            z = zipfile.ZipFile(io.BytesIO(archive))
        except zipfile.BadZipFile as exc:
            raise InvalidRequest("package_file", "is not a zip archive") from exc
        staged: dict[str, tuple[str, bytes]] = {}
        texts: dict[str, dict[str, Any]] = {}
        total = 0
        with z:
            for info in z.infolist():
                if info.is_dir():
                    continue
                total += info.file_size
                if total > MAX_ARCHIVE_BYTES:
                    raise InvalidRequest("package_file", "unpacks to too much data")
                name = PurePosixPath(info.filename).name
                data = z.read(info)
                if name == "records.json":
                    try:
                        texts = {str(r["md5sum"]): r for r in json.loads(data)}
                    except (ValueError, TypeError, KeyError) as exc:
                        raise InvalidRequest("package_file", "bad records.json") from exc
                    continue
                try:
                    stem, ext = _audio_name(name)
                except InvalidRequest:
                    continue  # not audio: ignored
                staged[stem] = (ext, data)
        if not staged:
            raise InvalidRequest("package_file", "holds no audio files")
        # Files are named by md5 in an exported package; a record gives each its text.
        named = {str(texts[s]["text"]) if s in texts else s: v for s, v in staged.items()}
        self._replace_package(package, named, merge=False)

    def replace_audio(self, package: str, text: str, name: str, data: bytes) -> None:
        """Replace the audio of ``text`` in ``package`` by an uploaded file.

        Raises:
            NotFound: no such package. InvalidRequest: not audio, too big, empty text.
        """
        folder = self._package_dir(package)
        if not text:
            raise InvalidRequest("text", "is required")
        _, ext = _audio_name(name)
        if len(data) > MAX_AUDIO_BYTES:
            raise InvalidRequest("audio_file", f"is over {MAX_AUDIO_BYTES} bytes")
        self._remove_audio(folder, text)
        _write_atomic(folder / (text_md5(text) + ext), data)
        records = self._load_records()
        self._record_in(records, text)
        self._save_records(records)

    def delete_package(self, package: str) -> None:
        """Raises: NotFound: no such package. Conflict: the default package."""
        folder = self._package_dir(package)
        if package == DEFAULT_PACKAGE:
            raise Conflict("the default voice package cannot be deleted")
        shutil.rmtree(folder)
        data = self._load_records()
        if data["current_package"] == package:
            data["current_package"] = DEFAULT_PACKAGE
            self._save_records(data)

    def reset_text(self, text: str, package: str | None = None) -> None:
        """Give ``text`` its default (synthesized) voice again in ``package`` (the current
        one by default).

        Raises:
            NotFound: no such package, or the text has no voice there.
        """
        package = package or self.current
        folder = self._package_dir(package)
        if not self._remove_audio(folder, text):
            raise NotFound("voice", f"{package}/{text}")
        _write_atomic(folder / (text_md5(text) + ".wav"), synthesize(text))

    # -- aliases ---------------------------------------------------------------------------

    def set_aliases(self, aliases: Mapping[str, str], *, replace_all: bool) -> dict[str, str]:
        """Replace every alias (the texts shown instead, nothing else changes), or update the
        given ones, whose original texts then sound as their replacements in the current
        package; returns the whole table.

        Raises:
            InvalidRequest: a key or value that is not a non-empty string.
        """
        for key, value in aliases.items():
            if not (isinstance(key, str) and key and isinstance(value, str) and value):
                raise InvalidRequest("alias", f"{key!r}: {value!r} is not text -> text")
        table = dict(aliases) if replace_all else {**self.aliases(), **aliases}
        if not replace_all:
            # The original text now sounds as its replacement: its audio is made anew.
            folder = self._package_dir(self.current)
            for key, value in aliases.items():
                self._remove_audio(folder, key)
                _write_atomic(folder / (text_md5(key) + ".wav"), synthesize(value))
        _write_atomic(self._aliases_file, json.dumps(table, ensure_ascii=False).encode())
        return table

    # -- internals -------------------------------------------------------------------------

    def _ensure(self) -> None:
        (self._packages / DEFAULT_PACKAGE).mkdir(parents=True, exist_ok=True)

    def _package_dir(self, package: str) -> Path:
        check_package_name(package)
        self._ensure()
        folder = self._packages / package
        if not folder.is_dir():
            raise NotFound("voice package", package)
        return folder

    def _load_records(self) -> dict[str, Any]:
        self._ensure()
        if not self._records_file.exists():
            return {"current_package": DEFAULT_PACKAGE, "records": []}
        try:
            data: dict[str, Any] = json.loads(self._records_file.read_text("utf-8"))
        except ValueError as exc:
            raise StorageError(f"{self._records_file}: {exc}") from exc
        return data

    def _save_records(self, data: dict[str, Any]) -> None:
        _write_atomic(self._records_file, json.dumps(data, ensure_ascii=False).encode())

    @staticmethod
    def _record_in(data: dict[str, Any], text: str) -> dict[str, Any]:
        for record in data["records"]:
            if record["text"] == text:
                found: dict[str, Any] = record
                return found
        record = asdict(VoiceRecord(text, text_md5(text)))
        data["records"].append(record)
        return record

    @staticmethod
    def _remove_audio(folder: Path, text: str) -> bool:
        removed = False
        for ext in AUDIO_EXTENSIONS:
            path = folder / (text_md5(text) + ext)
            if path.exists():
                path.unlink()
                removed = True
        return removed

    def _replace_package(
        self, package: str, files: Mapping[str, tuple[str, bytes]], *, merge: bool
    ) -> None:
        self._ensure()
        final = self._packages / package
        staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=self._packages))
        try:
            if merge and final.is_dir():
                for path in final.iterdir():
                    shutil.copy2(path, staging / path.name)
            for text, (ext, data) in files.items():
                self._remove_audio(staging, text)
                (staging / (text_md5(text) + ext)).write_bytes(data)
            old = None
            if final.exists():
                old = final.with_name(f".old-{package}")
                shutil.rmtree(old, ignore_errors=True)
                final.rename(old)
            staging.rename(final)
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
        except OSError as exc:
            shutil.rmtree(staging, ignore_errors=True)
            raise StorageError(f"voice package {package!r}: {exc}") from exc
        records = self._load_records()
        for text in files:
            self._record_in(records, text)
        records["current_package"] = package
        self._save_records(records)
        log.info("voice package %r imported (%d texts), now current", package, len(files))


def _audio_name(name: str) -> tuple[str, str]:
    path = PurePosixPath(name.replace("\\", "/"))
    ext = path.suffix.lower()
    if ext not in AUDIO_EXTENSIONS or not path.stem:
        raise InvalidRequest(
            "file", f"{name!r} is not an audio file ({', '.join(AUDIO_EXTENSIONS)})")
    return path.stem, ext


def _write_atomic(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise StorageError(f"{path}: {exc}") from exc
