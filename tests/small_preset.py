"""A shipped preset with a tiny budget, for tests that train (shared by the test files)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from bbgym.config import CONFIG_DIR

TINY = {
    "ppo": {"n_steps": 64, "batch_size": 256},
    "sac": {"learning_starts": 256, "buffer_size": 4096},
}
"""Per algorithm, what makes it learn within a budget of seconds: PPO's rollouts of 64
steps; SAC's updates from the 256th step, into a buffer of that budget's size."""


def write_small_preset(
    path: Path,
    name: str = "beachball_sail.yaml",
    *,
    ppo: dict[str, Any] | None = None,
    sac: dict[str, Any] | None = None,
    train: dict[str, Any],
) -> Path:
    """``path``: the shipped preset ``name`` with its algorithm's section (``ppo`` or
    ``sac``, the one given for the preset's ``algo``) and ``train`` updated."""
    preset = yaml.safe_load((CONFIG_DIR / name).read_text())
    algo = preset.get("algo", "ppo")
    given = {"ppo": ppo, "sac": sac}
    assert all(v is None for a, v in given.items() if a != algo), f"{name} trains {algo}"
    preset[algo].update(given[algo] or {})
    preset["train"].update(train)
    path.write_text(yaml.safe_dump(preset))
    return path


def write_tiny_sail_preset(path: Path, name: str = "beachball_sail.yaml") -> Path:
    """A sailing preset (``name``, PPO or SAC) on a budget of seconds: 8 envs, the
    algorithm's :data:`TINY` settings, an evaluation of 2 episodes on 2 envs every 1024
    steps (the main job's tests)."""
    algo = yaml.safe_load((CONFIG_DIR / name).read_text()).get("algo", "ppo")
    return write_small_preset(
        path,
        name,
        **{algo: TINY[algo]},
        train={
            "n_envs": 8,
            "eval_every_timesteps": 1024,
            "eval_episodes": 2,
            "eval_envs": 2,
            "checkpoint_every_timesteps": 100_000,
        },
    )
