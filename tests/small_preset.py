"""A shipped preset with a tiny budget, for tests that train (shared by the test files)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from bbgym.config import CONFIG_DIR


def write_small_preset(
    path: Path, name: str = "beachball_sail.yaml", *, ppo: dict[str, Any], train: dict[str, Any]
) -> Path:
    """``path``: the shipped preset ``name`` with its ``ppo`` and ``train`` sections updated."""
    preset = yaml.safe_load((CONFIG_DIR / name).read_text())
    preset["ppo"].update(ppo)
    preset["train"].update(train)
    path.write_text(yaml.safe_dump(preset))
    return path
