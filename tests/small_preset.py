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


def write_tiny_sail_preset(path: Path, name: str = "beachball_sail.yaml") -> Path:
    """A sailing preset (``name``) on a budget of seconds: 8 envs, rollouts of 64, an
    evaluation of 2 episodes every 1024 steps (the main job's tests)."""
    return write_small_preset(
        path,
        name,
        ppo={"n_steps": 64, "batch_size": 256},
        train={"n_envs": 8, "eval_every_timesteps": 1024, "eval_episodes": 2,
               "checkpoint_every_timesteps": 100_000},
    )  # fmt: skip
