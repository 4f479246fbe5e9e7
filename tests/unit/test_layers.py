"""DESIGN §1's layers, read off the package's imports: dependencies point down only."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "polynav"

Imports = list[tuple[str, str]]

CORE = ("geometry", "maps", "planning", "control")
ABOVE_CORE = ("runtime", "protocols", "api", "fleet", "fleet_api", "house", "web", "cli")


def _module(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports() -> list[tuple[str, str]]:
    """(importing module, imported module) for every polynav import in the package."""
    found = []
    for path in PACKAGE.rglob("*.py"):
        module = _module(path)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            found += [(module, n) for n in names if n.startswith("polynav.")]
    return found


def _top(module: str) -> str:
    return module.split(".")[1] if module.count(".") else ""


def _sub(module: str, depth: int) -> str:
    parts = module.split(".")
    return parts[depth] if len(parts) > depth else ""


@pytest.fixture(scope="module")
def imports() -> Imports:
    """Read when the module's first test runs, not at collection (every worker collects)."""
    return _imports()


def test_the_package_has_imports_to_check(imports: Imports) -> None:
    assert len(imports) > 1000


@pytest.mark.parametrize("layer", CORE)
def test_core_imports_nothing_above_it(layer: str, imports: Imports) -> None:
    bad = sorted({(a, b) for a, b in imports if _top(a) == layer and _top(b) in ABOVE_CORE})
    assert bad == []


def test_no_adapter_imports_another(imports: Imports) -> None:
    """Shared protocol code lives in ``polynav/protocols/*.py``; each package there is one
    dialect."""
    dialects = {p.name for p in (PACKAGE / "protocols").iterdir() if (p / "__init__.py").exists()}
    assert {"galileo", "yunji"} <= dialects
    bad = sorted({(a, b) for a, b in imports
                  if _top(a) == "protocols" and _top(b) == "protocols"
                  and _sub(a, 2) in dialects and _sub(b, 2) in dialects
                  and _sub(a, 2) != _sub(b, 2)})
    assert bad == []


def test_only_the_composition_and_the_fleet_import_the_fleet(imports: Imports) -> None:
    """Issue 36 item 3: the fleet holds what a fleet manager and a vehicle run; composing a
    site (the house, the command line) is above it, and nothing below imports it."""
    allowed = {"fleet", "fleet_api", "house", "cli"}
    bad = sorted({(a, b) for a, b in imports if _top(b) == "fleet" and _top(a) not in allowed})
    assert bad == []


def test_the_fleet_api_is_an_adapter_of_the_fleet_only_the_composition_imports(
        imports: Imports) -> None:
    """The fleet manager's API (issue 36 item 2) adapts ``polynav.fleet`` as ``polynav.api``
    adapts one robot: it may import the fleet, and only the house and the command line import
    it (never the robot's API, nor the fleet itself)."""
    bad = sorted({(a, b) for a, b in imports if _top(b) == "fleet_api" and _top(a) not in
                  {"fleet_api", "house", "cli"}})
    assert bad == []
    into_robot_api = sorted({(a, b) for a, b in imports
                             if _top(a) == "fleet_api" and _top(b) in ("api", "house")})
    assert into_robot_api == []


def test_only_the_command_line_imports_the_house(imports: Imports) -> None:
    bad = sorted({(a, b) for a, b in imports if _top(b) == "house" and _top(a) not in
                  {"house", "cli"}})
    assert bad == []
