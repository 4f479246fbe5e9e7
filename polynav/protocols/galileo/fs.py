"""The file-system API (galileo-http-a §1.10, §3.18: E-86–E-96), confined to four folders.

The vendor opens four folders of the robot's home to the API (seed lines 2860-2865); polynav
maps each onto a folder of the robot's data directory, and nothing else is reachable:

==================================  ======================================
vendor path                         in the data directory
==================================  ======================================
``/home/xiaoqiang/Pictures``        ``media/photos`` (photos, camera snapshots)
``/home/xiaoqiang/Videos``          ``media/videos`` (recordings)
``/home/xiaoqiang/slamdb``          ``galileo/slamdb``
``/home/xiaoqiang/saved-slamdb``    ``galileo/saved-slamdb``
==================================  ======================================

A path must be absolute and start with one of the four; sub-folders are included (A-34). A path
with a ``..`` component, a NUL, or that leads elsewhere, and a path whose real location (after
following symlinks, of the path or of any folder on the way) is outside its folder, is refused
with HTTP 403 before anything is touched. The four folders themselves can be listed but not
deleted, renamed or moved. ``copy``/``cut`` put the item inside ``to`` when ``to`` is an existing
folder, else make ``to`` the new path (A-33); an existing target is not overwritten (409).
Listings give names, oldest first by change time; file times are Unix seconds (A-32). Uploads
are written atomically (temp file, fsync, rename).
"""

from __future__ import annotations

import functools
import mimetypes
import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path, PurePosixPath
from typing import Any

from starlette.responses import Response

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError, StorageError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Handler, Reply, RouteList
from polynav.protocols.galileo.http import GalileoJSON
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK

ROUTES = RouteList()

HOME = PurePosixPath("/home/xiaoqiang")
#: vendor folder name -> folder in the data directory.
FOLDERS = {
    "Pictures": ("media", "photos"),
    "Videos": ("media", "videos"),
    "slamdb": ("galileo", "slamdb"),
    "saved-slamdb": ("galileo", "saved-slamdb"),
}


class PathRefused(PolynavError):
    """A path outside the four open folders (answered 403)."""

    def __init__(self, field: str, path: object, reason: str) -> None:
        super().__init__(f"{field}: {path!r} {reason}; open folders: "
                         + ", ".join(str(HOME / name) for name in FOLDERS))


def _refusing(handler: Handler) -> Handler:
    @functools.wraps(handler)
    def run(ctx: Context, params: Params) -> Reply:
        try:
            return handler(ctx, params)
        except PathRefused as exc:
            return GalileoJSON({"status": "error", "description": str(exc)}, status_code=403)

    return run


def folder_root(ctx: Context, name: str) -> Path:
    """The data-directory folder behind vendor folder ``name`` (made on first use)."""
    root = ctx.data_dir.joinpath(*FOLDERS[name])
    root.mkdir(parents=True, exist_ok=True)
    return root


def resolve(ctx: Context, field: str, raw: object) -> tuple[Path, Path]:
    """(real path, its folder's real root) of a vendor path.

    Raises:
        PathRefused: not inside an open folder, as written or after following links.
        InvalidRequest: not a string.
    """
    if not isinstance(raw, str) or not raw:
        raise InvalidRequest(field, f"must be a path, got {raw!r}")
    if "\x00" in raw:
        raise PathRefused(field, raw, "holds a NUL")
    path = PurePosixPath(raw)
    if ".." in path.parts:
        raise PathRefused(field, raw, "climbs with '..'")
    if not path.is_absolute():
        raise PathRefused(field, raw, "is not absolute")
    try:
        rest = path.relative_to(HOME)
    except ValueError:
        raise PathRefused(field, raw, "is outside the open folders") from None
    if not rest.parts or rest.parts[0] not in FOLDERS:
        raise PathRefused(field, raw, "is outside the open folders")
    root = folder_root(ctx, rest.parts[0]).resolve()
    real = root.joinpath(*rest.parts[1:])
    # Links anywhere on the way must stay inside the folder.
    if os.path.commonpath([root, real.resolve()]) != str(root):
        raise PathRefused(field, raw, "leads outside its folder through a link")
    return real, root


def vendor_path(ctx: Context, real: Path) -> str:
    """The vendor path of a file in one of the open folders.

    Raises:
        ValueError: ``real`` is in none of them.
    """
    for name in FOLDERS:
        root = folder_root(ctx, name).resolve()
        try:
            rest = real.resolve().relative_to(root)
        except ValueError:
            continue
        return str(HOME / name / PurePosixPath(*rest.parts)) if rest.parts else str(HOME / name)
    raise ValueError(f"{real} is in no open folder")


def _existing(ctx: Context, field: str, raw: object) -> tuple[Path, Path]:
    real, root = resolve(ctx, field, raw)
    if not real.exists():
        raise NotFound("path", str(raw))
    return real, root


def _not_root(field: str, raw: object, real: Path, root: Path) -> None:
    if real == root:
        raise PathRefused(field, raw, "is an open folder itself, which stays")


def _times(real: Path) -> dict[str, Any]:
    st = real.stat()
    return {"mode": st.st_mode, "size": st.st_size, "atime": int(st.st_atime),
            "mtime": int(st.st_mtime), "ctime": int(st.st_ctime)}


def _mimetype(real: Path) -> str:
    if real.is_dir():
        return "inode/directory"
    return mimetypes.guess_type(real.name)[0] or "application/octet-stream"


def _target(ctx: Context, params: Params, source: Path) -> Path:
    """Where ``to`` puts ``source`` (inside an existing folder, else as the new path)."""
    raw = params.raw("to")
    real, root = resolve(ctx, "to", raw)
    if real.is_dir():
        real = real / source.name
    if real.exists() or real.is_symlink():
        raise Conflict(f"to: {raw!r} already exists")
    if not real.parent.is_dir():
        raise NotFound("folder", str(PurePosixPath(str(raw)).parent))
    if source.is_dir() and (real == source or source in real.parents):
        raise InvalidRequest("to", "a folder cannot go inside itself")
    # The final target must be inside a folder too (``to`` may name an existing folder).
    if os.path.commonpath([root, real.parent.resolve()]) != str(root):
        raise PathRefused("to", raw, "leads outside its folder through a link")
    return real


def _guarded(fn: Callable[[], Any], what: str) -> Any:
    try:
        return fn()
    except OSError as exc:
        raise StorageError(f"{what}: {exc.strerror or exc}") from exc


@ROUTES.get("/fs/file_api")
@_refusing
def get_file(ctx: Context, params: Params) -> Reply:
    """E-86: the file's bytes."""
    real, _ = _existing(ctx, "path", params.raw("path"))
    if not real.is_file():
        raise InvalidRequest("path", "is a folder: list it with dir_api")
    return Response(real.read_bytes(), media_type=_mimetype(real))


@ROUTES.post("/fs/file_api")
@_refusing
def post_file(ctx: Context, params: Params) -> Reply:
    """E-87: upload the ``file`` part to ``path`` (replacing a file there)."""
    real, root = resolve(ctx, "path", params.raw("path"))
    _not_root("path", params.raw("path"), real, root)
    upload = params.file("file")
    if real.is_dir():
        raise Conflict(f"path: {params.raw('path')!r} is a folder")
    if not real.parent.is_dir():
        raise NotFound("folder", str(PurePosixPath(str(params.raw("path"))).parent))

    def write() -> None:
        fd, tmp = tempfile.mkstemp(prefix=f".{real.name}.", dir=real.parent)
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(upload.content)
                f.flush()
                os.fsync(f.fileno())
            os.replace(tmp, real)
        except OSError:
            Path(tmp).unlink(missing_ok=True)
            raise

    _guarded(write, "upload")
    return {"status": OK}


@ROUTES.put("/fs/file_api")
@_refusing
def put_file(ctx: Context, params: Params) -> Reply:
    """E-88: rename ``name`` to ``new_name``."""
    source, root = _existing(ctx, "name", params.raw("name"))
    _not_root("name", params.raw("name"), source, root)
    target, troot = resolve(ctx, "new_name", params.raw("new_name"))
    _not_root("new_name", params.raw("new_name"), target, troot)
    if target.exists() or target.is_symlink():
        raise Conflict(f"new_name: {params.raw('new_name')!r} already exists")
    if not target.parent.is_dir():
        raise NotFound("folder", str(PurePosixPath(str(params.raw("new_name"))).parent))
    if source.is_dir() and source in target.parents:
        raise InvalidRequest("new_name", "a folder cannot go inside itself")
    _guarded(lambda: shutil.move(source, target), "rename")
    return {"status": OK}


@ROUTES.delete("/fs/file_api")
@_refusing
def delete_file(ctx: Context, params: Params) -> Reply:
    """E-89: delete a file."""
    real, _ = resolve(ctx, "path", params.raw("path"))
    if not (real.exists() or real.is_symlink()):
        raise NotFound("path", str(params.raw("path")))
    if real.is_dir() and not real.is_symlink():
        raise InvalidRequest("path", "is a folder: delete it with dir_api")
    _guarded(real.unlink, "delete")
    return {"status": OK}


@ROUTES.get("/fs/dir_api")
@_refusing
def get_dir(ctx: Context, params: Params) -> Reply:
    """E-90: ``{"files": [...], "directories": [...]}``, names oldest first."""
    real, _ = _existing(ctx, "path", params.raw("path"))
    if not real.is_dir():
        raise InvalidRequest("path", "is a file, not a folder")
    entries = sorted(real.iterdir(), key=lambda p: (p.lstat().st_ctime_ns, p.name))
    return {"files": [p.name for p in entries if not p.is_dir() and not p.name.startswith(".")],
            "directories": [p.name for p in entries if p.is_dir()]}


@ROUTES.post("/fs/dir_api")
@_refusing
def post_dir(ctx: Context, params: Params) -> Reply:
    """E-91: create a folder (its parent must exist)."""
    raw = params.raw("path")
    real, _ = resolve(ctx, "path", raw)
    if real.exists():
        raise Conflict(f"path: {raw!r} already exists")
    if not real.parent.is_dir():
        raise NotFound("folder", str(PurePosixPath(str(raw)).parent))
    _guarded(real.mkdir, "create folder")
    return {"status": OK}


@ROUTES.delete("/fs/dir_api")
@_refusing
def delete_dir(ctx: Context, params: Params) -> Reply:
    """E-92: delete a folder and what it holds."""
    raw = params.raw("path")
    real, root = _existing(ctx, "path", raw)
    _not_root("path", raw, real, root)
    if not real.is_dir() or real.is_symlink():
        raise InvalidRequest("path", "is not a folder: delete it with file_api")
    _guarded(lambda: shutil.rmtree(real), "delete folder")
    return {"status": OK}


@ROUTES.get("/fs/get_file_info")
@_refusing
def get_file_info(ctx: Context, params: Params) -> Reply:
    """E-93: mode, size, times [s] and MIME type."""
    real, _ = _existing(ctx, "path", params.raw("path"))
    return {**_times(real), "mimetype": _mimetype(real)}


@ROUTES.post("/fs/copy")
@_refusing
def post_copy(ctx: Context, params: Params) -> Reply:
    """E-94: copy ``from`` to ``to``."""
    source, _ = _existing(ctx, "from", params.raw("from"))
    target = _target(ctx, params, source)
    if source.is_dir():
        _guarded(lambda: shutil.copytree(source, target, symlinks=True), "copy")
    else:
        _guarded(lambda: shutil.copy2(source, target, follow_symlinks=False), "copy")
    return {"status": OK}


@ROUTES.post("/fs/delete")
@_refusing
def post_delete(ctx: Context, params: Params) -> Reply:
    """E-95: delete several files or folders: every path is checked before any is deleted."""
    paths = params.structure("delete")
    if not isinstance(paths, list) or not paths:
        raise InvalidRequest("delete", "must be a non-empty list of paths")
    found = []
    for raw in paths:
        real, root = _existing(ctx, "delete", raw)
        _not_root("delete", raw, real, root)
        found.append(real)
    for real in found:
        if real.is_dir() and not real.is_symlink():
            _guarded(lambda r=real: shutil.rmtree(r), "delete")  # type: ignore[misc]
        elif real.exists() or real.is_symlink():
            _guarded(real.unlink, "delete")
    return {"status": OK}


@ROUTES.post("/fs/cut")
@_refusing
def post_cut(ctx: Context, params: Params) -> Reply:
    """E-96: move ``from`` to ``to``."""
    raw = params.raw("from")
    source, root = _existing(ctx, "from", raw)
    _not_root("from", raw, source, root)
    target = _target(ctx, params, source)
    _guarded(lambda: shutil.move(source, target), "move")
    return {"status": OK}
