"""The data shipped in ``data/`` is whole and byte for byte what ``SHA256SUMS`` says."""

from __future__ import annotations

import hashlib
import importlib.util
from pathlib import Path
from types import ModuleType

import pytest

from tests.conftest import DATA, REPO


def _sync_tool() -> ModuleType:
    spec = importlib.util.spec_from_file_location("sync_data", REPO / "tools" / "sync_data.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_shipped_file_matches_its_checksum() -> None:
    sums = _sync_tool().read_sums()
    assert len(sums) >= 70
    for name, digest in sums.items():
        assert hashlib.sha256((DATA / name).read_bytes()).hexdigest() == digest, name


def test_every_data_file_is_listed_in_the_checksums() -> None:
    tool = _sync_tool()
    listed = set(tool.read_sums())
    found = {p.relative_to(DATA).as_posix() for p in tool.shipped_files()}
    assert found == listed


def test_the_readme_table_is_made_from_the_checksums() -> None:
    tool = _sync_tool()
    readme = (DATA / "README.md").read_text()
    assert readme.endswith(tool.files_table())


def test_the_licences_the_data_asks_for_are_shipped() -> None:
    assert "Apache License" in (DATA / "nav2" / "LICENSE").read_text()
    assert "National Institute of Advanced Industrial Science and Technology" in (
        DATA / "movingai" / "LICENCE.txt"
    ).read_text()
    readme = (DATA / "README.md").read_text()
    for needle in ("ODC-By", "Apache-2.0", "MIT", "5eecd971b4a1c76421dd957e906013628bb4fe0b",
                   "a3a97043ee93d92fe8d70ec56d183933169beb1c"):
        assert needle in readme


def test_the_endpoint_lists_of_every_dialect_are_shipped() -> None:
    names = {p.name for p in (DATA / "spec").glob("*.endpoints.json")}
    assert {"yunji-api.endpoints.json", "galileo-http-a.endpoints.json",
            "galileo-http-b.endpoints.json", "puwei-api.endpoints.json",
            "ros1-nav-iface.endpoints.json"} <= names


def test_check_reports_a_changed_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    tool = _sync_tool()
    data = tmp_path / "data"
    (data / "movingai").mkdir(parents=True)
    (data / "movingai" / "a.map").write_text("type octile\n")
    monkeypatch.setattr(tool, "DATA", data)
    monkeypatch.setattr(tool, "SUMS", data / "SHA256SUMS")
    monkeypatch.setattr(tool, "README", data / "README.md")
    monkeypatch.setattr(tool, "SHARED", tmp_path / "no-shared")
    (data / "README.md").write_text("# data\n\n## Files\n")
    tool.write_sums()
    (data / "README.md").write_text(tool._readme_with_table())
    assert tool.check() == 0
    (data / "movingai" / "a.map").write_text("type octile\nheight 1\n")
    assert tool.check() == 1
