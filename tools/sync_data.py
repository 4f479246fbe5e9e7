"""Keep ``data/`` (the repository's copy of the benchmark maps and endpoint lists) in step with
the project workspace's ``../shared`` and with its own checksum list.

``data/`` is what the tests and benchmarks read, so a clone with nothing beside it is whole
(issue 20). The copies are byte for byte: ``data/SHA256SUMS`` lists every shipped data file, and
the test suite verifies it. Where ``../shared`` exists (the developers' workspace, CI before it
clones), ``--check`` also fails when a file there changed and was not copied over.

Usage::

    python tools/sync_data.py            # copy from ../shared into data/, rewrite SHA256SUMS
    python tools/sync_data.py --check    # exit 1 when data/ differs from ../shared or SHA256SUMS
"""

from __future__ import annotations

import argparse
import hashlib
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DATA = REPO / "data"
SHARED = REPO.parent / "shared"
SUMS = DATA / "SHA256SUMS"
README = DATA / "README.md"
TABLE_MARKER = "## Files"

# (folder under data/, folder under ../shared, file patterns). The SLAM logs are not shipped:
# their provenance gives no licence, or GPL (docs/decisions.md, "Data in the repository").
SOURCES = (
    ("movingai", "data/movingai", ("*.map", "*.scen")),
    ("nav2/maps", "data/nav2/maps", ("*.png", "*.yaml")),
    ("nav2/planner_benchmark", "data/nav2/planner_benchmark", ("*.png", "*.yaml")),
    ("spec", "spec", ("*.endpoints.json",)),
)


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def shipped_files() -> list[Path]:
    """Every data file under ``data/`` that SOURCES names, sorted (licences and READMEs aside)."""
    files: list[Path] = []
    for folder, _, patterns in SOURCES:
        for pattern in patterns:
            files.extend((DATA / folder).glob(pattern))
    return sorted(files)


def _source_files() -> dict[Path, Path]:
    """data/ path -> ../shared path for every file SOURCES names in ../shared."""
    pairs: dict[Path, Path] = {}
    for folder, source, patterns in SOURCES:
        for pattern in patterns:
            for path in (SHARED / source).glob(pattern):
                pairs[DATA / folder / path.name] = path
    return pairs


def read_sums() -> dict[str, str]:
    """``SHA256SUMS`` as {path relative to data/: hex digest}."""
    sums: dict[str, str] = {}
    for line in SUMS.read_text().splitlines():
        digest, name = line.split(maxsplit=1)
        sums[name.lstrip("*")] = digest
    return sums


def write_sums() -> None:
    lines = [f"{_digest(p)}  {p.relative_to(DATA).as_posix()}" for p in shipped_files()]
    SUMS.write_text("\n".join(lines) + "\n")


def files_table() -> str:
    """The README's table of files, made from SHA256SUMS so the two cannot disagree."""
    rows = ["| file | bytes | SHA-256 |", "|---|---:|---|"]
    for name, digest in read_sums().items():
        rows.append(f"| `{name}` | {(DATA / name).stat().st_size:,} | `{digest}` |")
    return "\n".join(rows) + "\n"


def _readme_with_table() -> str:
    text = README.read_text()
    head, marker, _ = text.partition(TABLE_MARKER)
    return head + marker + "\n\n" + files_table()


def sync() -> int:
    if not SHARED.is_dir():
        print(f"sync_data: {SHARED} not found", file=sys.stderr)
        return 1
    for target, source in sorted(_source_files().items()):
        target.parent.mkdir(parents=True, exist_ok=True)
        if not target.is_file() or target.read_bytes() != source.read_bytes():
            shutil.copyfile(source, target)
            print(f"copied {target.relative_to(REPO)}")
    write_sums()
    README.write_text(_readme_with_table())
    return 0


def check() -> int:
    problems: list[str] = []
    sums = read_sums()
    files = {p.relative_to(DATA).as_posix(): p for p in shipped_files()}
    for name in sorted(set(sums) - set(files)):
        problems.append(f"{name}: listed in SHA256SUMS but missing")
    for name, path in sorted(files.items()):
        if name not in sums:
            problems.append(f"{name}: not listed in SHA256SUMS")
        elif _digest(path) != sums[name]:
            problems.append(f"{name}: checksum differs from SHA256SUMS")
    if not problems and README.read_text() != _readme_with_table():
        problems.append("README.md: its table of files differs from SHA256SUMS")
    if SHARED.is_dir():
        for target, source in sorted(_source_files().items()):
            if not target.is_file() or target.read_bytes() != source.read_bytes():
                problems.append(f"{target.relative_to(REPO)}: differs from {source}")
    for line in problems:
        print(f"sync_data: {line}", file=sys.stderr)
    if problems:
        print("sync_data: run `python tools/sync_data.py` and commit data/", file=sys.stderr)
        return 1
    where = "SHA256SUMS and ../shared" if SHARED.is_dir() else "SHA256SUMS"
    print(f"sync_data: {len(files)} data files match {where}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="compare only, change nothing")
    args = parser.parse_args(argv)
    return check() if args.check else sync()


if __name__ == "__main__":
    sys.exit(main())
