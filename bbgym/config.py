"""Load env presets: the YAML files of ``bbgym/configs`` (the repository's ``configs/``)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Any

CONFIG_DIR = Path(str(resources.files("bbgym.configs")))
"""The presets' folder, inside the installed package (a wheel ships them)."""


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


SCHEDULED = ("learning_rate", "clip_range")
"""PPO arguments that may be given as ``"lin_<initial value>"`` (RL Zoo's notation)."""


class LinearSchedule:
    """``progress_remaining -> initial * progress_remaining``: decays linearly from the
    initial value at the start of training to 0 at its end (SB3 passes the fraction of
    the budget still to go). A class rather than a closure, so saved models pickle it."""

    def __init__(self, initial: float) -> None:
        self.initial = float(initial)

    def __call__(self, progress_remaining: float) -> float:
        return self.initial * progress_remaining

    def __repr__(self) -> str:
        return f"lin_{self.initial:g}"


def linear_schedule(text: str, name: str = "schedule") -> LinearSchedule:
    """Parse ``"lin_<float>"`` (for example ``"lin_0.001"``) into a :class:`LinearSchedule`."""
    prefix = "lin_"
    try:
        if not text.startswith(prefix):
            raise ValueError
        initial = float(text[len(prefix) :])
    except ValueError:
        raise ValueError(f"{name} must be a number or 'lin_<number>', got {text!r}") from None
    if not (initial > 0.0 and initial < float("inf")):
        raise ValueError(f"{name}: the initial value must be finite and > 0, got {text!r}")
    return LinearSchedule(initial)


def load_training(path: str | Path) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(ppo_kwargs, train_settings)`` of a preset file: the keyword arguments of
    stable-baselines3's ``PPO`` (``policy`` included) and the run settings, with defaults
    for what the file leaves out."""
    import yaml

    with open(path, encoding="utf-8") as f:
        preset = yaml.safe_load(f)
    ppo = dict(preset.get("ppo") or {})
    ppo.setdefault("policy", "MlpPolicy")
    for key in SCHEDULED:
        if isinstance(ppo.get(key), str):
            ppo[key] = linear_schedule(ppo[key], f"{path}: ppo.{key}")
    train = {**TRAIN_DEFAULTS, **(preset.get("train") or {})}
    unknown = sorted(set(train) - set(TRAIN_DEFAULTS))
    if unknown:
        known = sorted(TRAIN_DEFAULTS)
        raise ValueError(f"{path}: unknown train settings {unknown}; known: {known}")
    return ppo, train
