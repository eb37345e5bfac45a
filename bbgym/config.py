"""Load env presets from ``configs/*.yaml`` (needs PyYAML, in the ``dev`` extra)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

CONFIG_DIR = Path(__file__).resolve().parent.parent / "configs"


def load_preset(path: str | Path) -> tuple[str, dict[str, Any]]:
    """Return ``(env_id, kwargs)`` of a preset file, ready for ``gym.make(env_id, **kwargs)``.

    Lists become tuples (ranges), so the kwargs compare equal to the code's defaults.
    """
    import yaml

    with open(path, encoding="utf-8") as f:
        preset = yaml.safe_load(f)
    if not isinstance(preset, dict) or "env_id" not in preset or "env" not in preset:
        raise ValueError(f"{path}: a preset needs 'env_id' and 'env' keys")

    def tuples(value: Any) -> Any:
        if isinstance(value, list):
            return tuple(value)
        if isinstance(value, dict):
            return {k: tuples(v) for k, v in value.items()}
        return value

    kwargs = tuples(preset["env"])
    # (The ``ppo`` and ``train`` sections are read by :func:`load_training`.)
    if "max_episode_steps" in preset:
        kwargs["max_episode_steps"] = preset["max_episode_steps"]
    return preset["env_id"], kwargs


TRAIN_DEFAULTS = {
    "n_envs": 8,
    "total_timesteps": 100_000,
    "eval_every_timesteps": 20_000,
    "eval_episodes": 20,
    "checkpoint_every_timesteps": 100_000,
}


def load_training(path: str | Path) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(ppo_kwargs, train_settings)`` of a preset file: the keyword arguments of
    stable-baselines3's ``PPO`` (``policy`` included) and the run settings, with defaults
    for what the file leaves out."""
    import yaml

    with open(path, encoding="utf-8") as f:
        preset = yaml.safe_load(f)
    ppo = dict(preset.get("ppo") or {})
    ppo.setdefault("policy", "MlpPolicy")
    train = {**TRAIN_DEFAULTS, **(preset.get("train") or {})}
    unknown = sorted(set(train) - set(TRAIN_DEFAULTS))
    if unknown:
        known = sorted(TRAIN_DEFAULTS)
        raise ValueError(f"{path}: unknown train settings {unknown}; known: {known}")
    return ppo, train
