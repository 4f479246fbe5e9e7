"""Which test covers which entry of a vendor's entry list.

Each test module of a dialect's test package names what it covers in a module-level ``COVERED``
dict: entry key -> the name of a test function in that module that exercises it over the real
wire. A coverage test gathers them with :func:`covered_entries` and compares with the spec's
entries and its to-do list (strict both ways).
"""

from __future__ import annotations

import importlib
import pkgutil
from types import ModuleType


def covered_entries(
    package: ModuleType, *, skip: str = "test_coverage"
) -> dict[str, tuple[str, str]]:
    """entry key -> (test module, test name), from every ``test_*`` module of ``package``
    (and its sub-packages); an entry covered twice or a name that is no test fails."""
    out: dict[str, tuple[str, str]] = {}
    prefix = package.__name__ + "."
    for info in pkgutil.walk_packages(package.__path__, prefix):
        leaf = info.name.rsplit(".", 1)[-1]
        if info.ispkg or not leaf.startswith("test_") or leaf == skip:
            continue
        module = importlib.import_module(info.name)
        for key, test_name in getattr(module, "COVERED", {}).items():
            assert key not in out, f"{key} is covered twice: {out[key]} and {info.name}"
            assert callable(getattr(module, test_name, None)), f"{key}: no {info.name}.{test_name}"
            out[key] = (info.name, test_name)
    return out
