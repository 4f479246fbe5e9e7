"""Voice endpoints: speech, voice packages and records, aliases, greeting mode, volume
(galileo-http-a §3.8: E-31–E-43, E-55, E-56).

Speech plays on the robot's speaker for as long as the sentence takes
(:mod:`~polynav.runtime.device_commands`); the first time a text is spoken its audio is made in
the current voice package, as the vendor's robot downloads it. The four operations on
``/system/tts/records`` that the document gives no method (A-01) are told apart by method and
parameters: ``POST`` with audio file parts uploads a package as loose files (E-35), ``POST`` or
``PUT`` with ``package_file`` imports an exported package (E-36), ``PUT`` with ``text`` and
``audio_file`` replaces one text's audio (E-37), ``DELETE`` with ``text`` resets that text's
voice (E-39), ``DELETE`` with only ``package_name`` deletes the package (E-38). A package
downloads as a zip of its audio files and their records (A-35). ``tts/stop`` is ``ok`` whether
or not something played (stopping is idempotent). ``last_active`` in records is the runtime's
clock in milliseconds (simulated time on the simulator).
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any
from urllib.parse import quote

from starlette.responses import Response

from polynav.errors import InvalidRequest
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK
from polynav.robot.sim.devices.voice_library import VoiceLibrary, check_package_name

ROUTES = RouteList()

_MEDIA_TYPES = {".wav": "audio/wav", ".mp3": "audio/mpeg", ".ogg": "audio/ogg",
                ".flac": "audio/flac", ".m4a": "audio/mp4", ".aac": "audio/aac"}


@ROUTES.get("/system/tts")
def get_tts(ctx: Context, params: Params) -> Reply:
    """E-31: speak ``text``."""
    ctx.runtime.peripherals.say(params.text("text"))
    return {"status": OK}


@ROUTES.get("/system/tts/playing")
def get_tts_playing(ctx: Context, params: Params) -> Reply:
    """E-32: ``{"status": <bool>}``."""
    return {"status": ctx.runtime.peripherals.speaking()}


@ROUTES.get("/system/tts/stop")
def get_tts_stop(ctx: Context, params: Params) -> Reply:
    """E-33."""
    ctx.runtime.peripherals.stop_speaking()
    return {"status": OK}


@ROUTES.get("/system/tts/records")
def get_tts_records(ctx: Context, params: Params) -> Reply:
    """E-34: the records; a package's zip; or one text's audio."""
    peripherals = ctx.runtime.peripherals
    if "package_name" not in params:
        packages, records, current = peripherals.voice_records()
        return {"packages": packages, "records": [asdict(r) for r in records],
                "current_package": current}
    package = check_package_name(params.text("package_name"))
    if "text" in params:
        text = params.text("text")
        # Read between ticks too, so a concurrent replace or delete cannot pull it away.
        suffix, data = peripherals.voice_library(lambda lib: _read(lib, package, text))
        return Response(data, media_type=_MEDIA_TYPES.get(suffix, "application/octet-stream"))
    archive = peripherals.voice_library(lambda lib: lib.export(package))
    return Response(archive, media_type="application/zip", headers={
        "Content-Disposition": f"attachment; filename*=UTF-8''{quote(package, safe='')}.zip"})


def _read(lib: VoiceLibrary, package: str, text: str) -> tuple[str, bytes]:
    path = lib.audio_path(package, text)
    return path.suffix, path.read_bytes()


@ROUTES.post("/system/tts/records")
def post_tts_records(ctx: Context, params: Params) -> Reply:
    """E-35 (audio files), or E-36 when a ``package_file`` is sent."""
    package = check_package_name(params.text("package_name"))
    if "package_file" in params.files:
        return _import_archive(ctx, package, params)
    files = {f.filename: f.content for f in params.files.values()}
    ctx.runtime.peripherals.voice_library(lambda lib: lib.import_files(package, files))
    return {"status": OK}


@ROUTES.put("/system/tts/records")
def put_tts_records(ctx: Context, params: Params) -> Reply:
    """E-36 (``package_file``) or E-37 (``text`` + ``audio_file``)."""
    package = check_package_name(params.text("package_name"))
    if "package_file" in params.files:
        return _import_archive(ctx, package, params)
    if "audio_file" not in params.files:
        raise InvalidRequest("package_file", "send package_file, or text and audio_file")
    text = params.text("text")
    upload = params.file("audio_file")
    ctx.runtime.peripherals.voice_library(
        lambda lib: lib.replace_audio(package, text, upload.filename, upload.content))
    return {"status": OK}


def _import_archive(ctx: Context, package: str, params: Params) -> dict[str, Any]:
    archive = params.file("package_file").content
    ctx.runtime.peripherals.voice_library(lambda lib: lib.import_archive(package, archive))
    return {"status": OK}


@ROUTES.delete("/system/tts/records")
def delete_tts_records(ctx: Context, params: Params) -> Reply:
    """E-39 (``text``: reset its voice) or E-38 (``package_name``: delete the package)."""
    if "text" in params:
        text = params.text("text")
        package = params.text("package_name", None)

        def reset(lib: VoiceLibrary) -> None:
            lib.reset_text(text, package)

        ctx.runtime.peripherals.voice_library(reset)
        return {"status": OK}
    package = check_package_name(params.text("package_name"))
    ctx.runtime.peripherals.voice_library(lambda lib: lib.delete_package(package))
    return {"status": OK}


def _alias_body(params: Params) -> dict[str, str]:
    if not isinstance(params.body, dict):
        raise InvalidRequest("body", "must be a JSON object: {original text: replacement}")
    return dict(params.body)


@ROUTES.get("/system/tts/alias")
def get_tts_alias(ctx: Context, params: Params) -> Reply:
    """E-40: ``{original: replacement}``."""
    return ctx.runtime.peripherals.voice_library(lambda lib: lib.aliases())


@ROUTES.post("/system/tts/alias")
def post_tts_alias(ctx: Context, params: Params) -> Reply:
    """E-41: replace every alias."""
    table = _alias_body(params)
    ctx.runtime.peripherals.voice_library(lambda lib: lib.set_aliases(table, replace_all=True))
    return {"status": OK}


@ROUTES.put("/system/tts/alias")
def put_tts_alias(ctx: Context, params: Params) -> Reply:
    """E-42: update the given aliases (their texts get the new voice); the whole table."""
    table = _alias_body(params)
    return ctx.runtime.peripherals.voice_library(
        lambda lib: lib.set_aliases(table, replace_all=False))


@ROUTES.put("/system/greeting")
def put_greeting(ctx: Context, params: Params) -> Reply:
    """E-43: greeting mode on or off."""
    on = params.boolean("greeting")
    ctx.runtime.peripherals.set_greeting(on)
    return {"greeting": on}


@ROUTES.get("/system/volume", inline=True)
def get_volume(ctx: Context, params: Params) -> Reply:
    """E-55: ``{"value": <percent>}``."""
    return {"value": ctx.runtime.peripherals.volume}


@ROUTES.put("/system/volume")
def put_volume(ctx: Context, params: Params) -> Reply:
    """E-56: set the volume (0..100)."""
    ctx.runtime.peripherals.set_volume(params.integer("value"))
    return {"status": OK}

