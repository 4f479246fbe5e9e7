"""The file-system API over real HTTP, confined to its four folders (galileo-http-a E-86–E-96,
issue item 6)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/fs/file_api": "test_a_file_is_uploaded_read_renamed_and_deleted",
    "POST /api/v1/fs/file_api": "test_a_file_is_uploaded_read_renamed_and_deleted",
    "PUT /api/v1/fs/file_api": "test_a_file_is_uploaded_read_renamed_and_deleted",
    "DELETE /api/v1/fs/file_api": "test_a_file_is_uploaded_read_renamed_and_deleted",
    "GET /api/v1/fs/dir_api": "test_folders_are_made_listed_and_deleted",
    "POST /api/v1/fs/dir_api": "test_folders_are_made_listed_and_deleted",
    "DELETE /api/v1/fs/dir_api": "test_folders_are_made_listed_and_deleted",
    "GET /api/v1/fs/get_file_info": "test_file_info_gives_mode_size_times_and_type",
    "POST /api/v1/fs/copy": "test_copy_and_cut_into_a_folder_or_to_a_new_path",
    "POST /api/v1/fs/cut": "test_copy_and_cut_into_a_folder_or_to_a_new_path",
    "POST /api/v1/fs/delete": "test_several_paths_are_deleted_all_or_none",
}

PICS = "/home/xiaoqiang/Pictures"
SLAM = "/home/xiaoqiang/slamdb"


def _upload(g: Harness, path: str, data: bytes) -> int:
    reply = g.request("POST", "/fs/file_api", params={"path": path},
                      files={"file": ("x.bin", data, "application/octet-stream")})
    return reply.status_code


def test_a_file_is_uploaded_read_renamed_and_deleted(galileo: Harness) -> None:
    assert _upload(galileo, f"{SLAM}/notes.txt", b"hello") == 200
    got = galileo.get("/fs/file_api", path=f"{SLAM}/notes.txt")
    assert got.content == b"hello" and got.headers["content-type"].startswith("text/plain")
    assert (galileo.server.ctx.data_dir / "galileo" / "slamdb" / "notes.txt").read_bytes() == (
        b"hello")
    assert _upload(galileo, f"{SLAM}/notes.txt", b"again") == 200  # replaces
    assert galileo.ok("PUT", "/fs/file_api", json={"name": f"{SLAM}/notes.txt",
                                                   "new_name": f"{PICS}/n.txt"}) == {
        "status": "ok"}
    assert galileo.get("/fs/file_api", path=f"{SLAM}/notes.txt").status_code == 404
    assert galileo.get("/fs/file_api", path=f"{PICS}/n.txt").content == b"again"
    assert galileo.ok("DELETE", "/fs/file_api", params={"path": f"{PICS}/n.txt"}) == {
        "status": "ok"}
    assert galileo.get("/fs/file_api", path=f"{PICS}/n.txt").status_code == 404
    assert _upload(galileo, f"{SLAM}/no/such/folder.txt", b"x") == 404
    assert galileo.request("POST", "/fs/file_api",
                           params={"path": f"{SLAM}/a.txt"}).status_code == 400  # no file
    assert galileo.get("/fs/file_api", path=SLAM).status_code == 400  # a folder


def test_folders_are_made_listed_and_deleted(galileo: Harness) -> None:
    assert galileo.ok("GET", "/fs/dir_api", params={"path": SLAM}) == {"files": [],
                                                                       "directories": []}
    assert galileo.ok("POST", "/fs/dir_api", json={"path": f"{SLAM}/maps"}) == {"status": "ok"}
    assert galileo.post("/fs/dir_api", {"path": f"{SLAM}/maps"}).status_code == 409
    for name in ("b.txt", "a.txt"):
        _upload(galileo, f"{SLAM}/{name}", b"x")
    listing = galileo.ok("GET", "/fs/dir_api", params={"path": SLAM})
    assert listing == {"files": ["b.txt", "a.txt"], "directories": ["maps"]}  # oldest first
    _upload(galileo, f"{SLAM}/maps/m.pgm", b"P5")
    assert galileo.ok("DELETE", "/fs/dir_api", params={"path": f"{SLAM}/maps"}) == {
        "status": "ok"}
    assert galileo.ok("GET", "/fs/dir_api", params={"path": SLAM})["directories"] == []
    assert galileo.delete("/fs/dir_api", path=SLAM).status_code == 403  # an open folder stays
    assert galileo.delete("/fs/dir_api", path=f"{SLAM}/a.txt").status_code == 400
    assert galileo.delete("/fs/dir_api", path=f"{SLAM}/gone").status_code == 404


def test_file_info_gives_mode_size_times_and_type(galileo: Harness) -> None:
    _upload(galileo, f"{PICS}/p.png", b"\x89PNG....")
    info = galileo.ok("GET", "/fs/get_file_info", params={"path": f"{PICS}/p.png"})
    assert set(info) == {"mode", "size", "atime", "mtime", "ctime", "mimetype"}
    assert info["size"] == 8 and info["mimetype"] == "image/png"
    assert all(isinstance(info[k], int) for k in ("mode", "size", "atime", "mtime", "ctime"))
    folder = galileo.ok("GET", "/fs/get_file_info", params={"path": PICS})
    assert folder["mimetype"] == "inode/directory"


def test_copy_and_cut_into_a_folder_or_to_a_new_path(galileo: Harness) -> None:
    _upload(galileo, f"{SLAM}/a.txt", b"A")
    galileo.ok("POST", "/fs/dir_api", json={"path": f"{SLAM}/d"})
    assert galileo.ok("POST", "/fs/copy", json={"from": f"{SLAM}/a.txt",
                                                "to": f"{SLAM}/d"}) == {"status": "ok"}
    assert galileo.ok("POST", "/fs/copy", json={"from": f"{SLAM}/a.txt",
                                                "to": f"{SLAM}/b.txt"}) == {"status": "ok"}
    assert galileo.get("/fs/file_api", path=f"{SLAM}/d/a.txt").content == b"A"
    assert galileo.post("/fs/copy", {"from": f"{SLAM}/a.txt",
                                     "to": f"{SLAM}/b.txt"}).status_code == 409
    assert galileo.post("/fs/copy", {"from": f"{SLAM}/d", "to": f"{SLAM}/d"}).status_code in (
        400, 409)
    assert galileo.ok("POST", "/fs/cut", json={"from": f"{SLAM}/d",
                                               "to": f"{PICS}/moved"}) == {"status": "ok"}
    assert galileo.get("/fs/file_api", path=f"{PICS}/moved/a.txt").content == b"A"
    assert galileo.ok("GET", "/fs/dir_api", params={"path": SLAM})["directories"] == []
    assert galileo.post("/fs/cut", {"from": PICS, "to": f"{SLAM}/x"}).status_code == 403
    assert galileo.post("/fs/cut", {"from": f"{SLAM}/gone", "to": SLAM}).status_code == 404


def test_several_paths_are_deleted_all_or_none(galileo: Harness) -> None:
    for name in ("a", "b"):
        _upload(galileo, f"{SLAM}/{name}", b"x")
    galileo.ok("POST", "/fs/dir_api", json={"path": f"{SLAM}/d"})
    bad = galileo.post("/fs/delete", {"delete": [f"{SLAM}/a", f"{SLAM}/missing"]})
    assert bad.status_code == 404
    outside = galileo.post("/fs/delete", {"delete": [f"{SLAM}/a", "/etc/passwd"]})
    assert outside.status_code == 403
    assert galileo.ok("GET", "/fs/dir_api", params={"path": SLAM}) == {
        "files": ["a", "b"], "directories": ["d"]}
    assert galileo.ok("POST", "/fs/delete", json={"delete": [f"{SLAM}/a", f"{SLAM}/d"]}) == {
        "status": "ok"}
    assert galileo.ok("GET", "/fs/dir_api", params={"path": SLAM}) == {"files": ["b"],
                                                                       "directories": []}
    assert galileo.post("/fs/delete", {"delete": []}).status_code == 400
    assert galileo.post("/fs/delete", {"delete": "a"}).status_code == 400


@pytest.mark.parametrize("path", [
    "/etc/passwd",
    "etc/passwd",
    "Pictures/x",
    "/home/xiaoqiang/Documents/x",
    "/home/xiaoqiang/Pictures/../../../etc/passwd",
    "/home/xiaoqiang/Pictures/../slamdb/x",
    "/home/xiaoqiang",
    "/home/xiaoqiang/Pictures/\x00x",
])
def test_escapes_are_refused_with_403(galileo: Harness, path: str) -> None:
    for reply in (
        galileo.get("/fs/file_api", path=path),
        galileo.get("/fs/dir_api", path=path),
        galileo.get("/fs/get_file_info", path=path),
        galileo.delete("/fs/file_api", path=path),
        galileo.post("/fs/dir_api", {"path": path}),
        galileo.post("/fs/copy", {"from": f"{PICS}", "to": path}),
    ):
        assert reply.status_code == 403, (path, reply.text)
        assert reply.json()["status"] == "error"


def test_symlinks_leading_outside_are_refused(galileo: Harness, tmp_path: Path) -> None:
    secret = tmp_path / "secret"
    secret.mkdir()
    (secret / "key.txt").write_text("do not read")
    pictures = galileo.server.ctx.data_dir / "media" / "photos"
    pictures.mkdir(parents=True, exist_ok=True)
    os.symlink(secret, pictures / "out")
    os.symlink(secret / "key.txt", pictures / "key.txt")
    for path in (f"{PICS}/out/key.txt", f"{PICS}/key.txt", f"{PICS}/out"):
        assert galileo.get("/fs/file_api", path=path).status_code == 403
        assert galileo.get("/fs/dir_api", path=path).status_code == 403
    assert _upload(galileo, f"{PICS}/out/new.txt", b"x") == 403
    assert galileo.post("/fs/copy", {"from": f"{PICS}/out", "to": f"{PICS}/copy"}
                        ).status_code == 403
    assert galileo.post("/fs/delete", {"delete": [f"{PICS}/out/key.txt"]}).status_code == 403
    assert (secret / "key.txt").read_text() == "do not read"
    assert not (secret / "new.txt").exists()
