"""``polynav bench slam`` without the public logs fails with where to get them."""

from __future__ import annotations

from pathlib import Path

import pytest

from polynav.cli import main


def test_bench_slam_without_logs_says_where_to_get_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["bench", "slam", "--data", str(tmp_path)]) == 2
    out = capsys.readouterr()
    text = out.out + out.err
    assert f"No SLAM logs found in {tmp_path}" in text
    assert "intel.relations" in text and "--data DIR" in text
