"""The formatter decides the layout: no line of the repository's Python holds itself out of
``ruff format`` (``make test`` runs ``ruff format --check`` over what is left)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SOURCES = ("bbgym", "agents", "configs", "tests", "scripts", "docs")
MARKER = re.compile(r"#\s*fmt:\s*(skip|off|on)\b")


def python_files() -> list[Path]:
    return sorted(p for top in SOURCES for p in (ROOT / top).rglob("*.py"))


def test_no_line_is_held_out_of_the_formatter():
    held = [
        f"{path.relative_to(ROOT)}:{number}"
        for path in python_files()
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if MARKER.search(line)
    ]
    assert len(python_files()) > 100
    assert held == [], f"format these with ruff instead: {held[:10]}"
