"""Safe YAML through libyaml: the same documents as PyYAML's pure-Python safe loader on every
YAML file polynav ships, the same refusals (no Python objects), the same error type."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from polynav import safe_yaml

PACKAGE = Path(__file__).resolve().parents[2] / "polynav"
SHIPPED = sorted(PACKAGE.rglob("*.yaml"))


def test_polynav_ships_yaml_to_read() -> None:
    assert len(SHIPPED) >= 5


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_a_shipped_file_reads_as_the_python_loader_reads_it(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    assert safe_yaml.load(text) == yaml.safe_load(text)


def test_python_objects_are_refused() -> None:
    with pytest.raises(yaml.YAMLError):
        safe_yaml.load("!!python/object/apply:os.system ['true']")


def test_broken_yaml_is_a_yaml_error() -> None:
    with pytest.raises(yaml.YAMLError):
        safe_yaml.load("a: [1, 2\nb: 3")


def test_bytes_and_scalars_read_as_safe_load_reads_them() -> None:
    text = "resolution: 0.05\norigin: [-1.5, 2, 0.0]\nnegate: 0\nflag: yes\nwhen: 2026-11-29\n"
    assert safe_yaml.load(text.encode()) == yaml.safe_load(text)
