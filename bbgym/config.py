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
    if "max_episode_steps" in preset:
        kwargs["max_episode_steps"] = preset["max_episode_steps"]
    return preset["env_id"], kwargs
