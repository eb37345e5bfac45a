"""Load env presets: the YAML files of ``bbgym/configs`` (the repository's ``configs/``)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Any

CONFIG_DIR = Path(str(resources.files("bbgym.configs")))
"""The presets' folder, inside the installed package (a wheel ships them)."""


def preset_files() -> dict[str, Path]:
    """The shipped preset file of each registered env id that declares one
    (:attr:`bbgym.spec.Version.preset`). A version of a base task may share the base's
    preset: its registered kwargs go on top (see :func:`load_preset`)."""
    import bbgym  # noqa: F401  (registers the ids)
    from bbgym.spec import specs

    return {
        v.env_id: _preset_file(v.preset)
        for spec in specs()
        for v in spec.versions
        if v.preset is not None
    }


def _preset_file(preset: str | Path) -> Path:
    """A spec's preset: a shipped preset's name (``bbgym/configs/<name>.yaml``) or a path."""
    if isinstance(preset, Path):
        return preset
    return CONFIG_DIR / (preset if preset.endswith((".yaml", ".yml")) else f"{preset}.yaml")


def preset_path(preset: str | Path) -> Path:
    """The preset file named by ``preset``: a registered env id, a shipped
    preset's name (``"beachball_sail"`` or ``"beachball_sail.yaml"``) or a path to a file."""
    text = str(preset)
    files = preset_files()
    if text in files:
        return files[text]
    shipped = CONFIG_DIR / (text if text.endswith((".yaml", ".yml")) else f"{text}.yaml")
    if "/" not in text and shipped.is_file():
        return shipped
    path = Path(preset)
    if path.is_file():
        return path
    names = sorted(p.stem for p in CONFIG_DIR.glob("*.yaml"))
    raise ValueError(
        f"preset {text!r} is neither an env id ({', '.join(files)}), a shipped preset "
        f"({', '.join(names)}) nor a file"
    )


def load_preset(preset: str | Path) -> tuple[str, dict[str, Any]]:
    """Return ``(env_id, kwargs)`` of a preset, ready for ``gym.make(env_id, **kwargs)``.

    ``preset`` is an env id, a shipped preset's name or a file (see :func:`preset_path`).
    Given an env id, the kwargs are that id's: a version that shares its base task's preset
    gets its registered kwargs on top. Lists become tuples (ranges), so the kwargs
    compare equal to the code's defaults.
    """
    import yaml

    path = preset_path(preset)
    with open(path, encoding="utf-8") as f:
        preset_data = yaml.safe_load(f)
    if not isinstance(preset_data, dict) or "env_id" not in preset_data or "env" not in preset_data:
        raise ValueError(f"{path}: a preset needs 'env_id' and 'env' keys")
    env_id, kwargs = _env_kwargs(preset_data)
    if str(preset) in preset_files() and str(preset) != env_id:
        import gymnasium as gym

        import bbgym  # noqa: F401  (registers the ids)

        env_id = str(preset)
        kwargs.update(gym.spec(env_id).kwargs)
    return env_id, kwargs


def env_preset(env_id: str, preset: str | Path | None = None) -> tuple[Path, dict[str, Any]]:
    """``(preset file, env kwargs)`` that ``env_id`` trains with: ``preset`` (an env id, a
    shipped preset's name or a file; default ``env_id``'s shipped preset), its kwargs without
    ``max_episode_steps`` (the registered limit applies). A preset of the base task (one a
    version shares with its base) gets the id's registered kwargs on top, since its own
    values would otherwise override them; a preset of another env raises ``ValueError``."""
    import gymnasium as gym

    import bbgym  # noqa: F401  (registers the ids)

    name = env_id if preset is None else preset
    files = preset_files()
    if preset is None and env_id not in files:
        raise ValueError(f"{env_id} has no shipped preset; known: {', '.join(files)}")
    path = preset_path(name)
    preset_id, kwargs = load_preset(name)
    kwargs.pop("max_episode_steps", None)
    if preset_id != env_id:
        base, wanted = gym.spec(preset_id), gym.spec(env_id)
        if base.entry_point != wanted.entry_point or base.kwargs:
            raise ValueError(f"preset {preset} is a preset of {preset_id}, not {env_id}")
        kwargs.update(wanted.kwargs)
    return path, kwargs


def _env_kwargs(preset: dict[str, Any]) -> tuple[str, dict[str, Any]]:
    """``(env_id, kwargs)`` of a parsed preset file."""

    def tuples(value: Any) -> Any:
        if isinstance(value, list):
            return tuple(value)
        if isinstance(value, dict):
            return {k: tuples(v) for k, v in value.items()}
        return value

    kwargs = tuples(preset["env"])
    # (The ``algo``, its section and ``train`` are read by :func:`load_training`.)
    if "max_episode_steps" in preset:
        kwargs["max_episode_steps"] = preset["max_episode_steps"]
    return preset["env_id"], kwargs


ALGORITHMS = ("ppo", "sac")
"""The stable-baselines3 algorithms a preset may train: its top-level ``algo`` (default
``ppo``) names one, and the section of that name holds its keyword arguments."""

TRAIN_DEFAULTS = {
    "n_envs": 8,
    "total_timesteps": 100_000,
    "eval_every_timesteps": 20_000,
    "eval_episodes": 20,
    "checkpoint_every_timesteps": 100_000,
    "normalize_reward": False,
    "evaluate_model": "best",
    "eval_envs": None,
}

EVALUATED_MODELS = {"best": "best_model.zip", "final": "model.zip"}
"""``train.evaluate_model``: which saved model of a training run ``bbgym baseline``
evaluates, records and reports: ``best`` (the default) the evaluation during training with
the best mean return, ``final`` the model at the end of the budget."""


SCHEDULED = ("learning_rate", "clip_range")
"""Arguments that may be given as ``"lin_<initial value>"`` (RL Zoo's notation)."""


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


def load_training(preset: str | Path) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(algo_kwargs, train_settings)`` of a preset (an env id, a shipped preset's name or
    a file): the keyword arguments of the stable-baselines3 algorithm the preset trains
    (``policy`` included; the section named by its ``algo``, PPO's ``ppo`` by default) and
    the run settings, with defaults for what the file leaves out and ``algo`` added."""
    import yaml

    path = preset_path(preset)
    with open(path, encoding="utf-8") as f:
        preset = yaml.safe_load(f)
    algo = preset.get("algo", "ppo")
    if algo not in ALGORITHMS:
        raise ValueError(f"{path}: algo must be one of {list(ALGORITHMS)}, got {algo!r}")
    stray = [name for name in ALGORITHMS if name != algo and name in preset]
    if stray:
        raise ValueError(f"{path}: the preset trains {algo} (algo) but has a {stray[0]} section")
    kwargs = dict(preset.get(algo) or {})
    kwargs.setdefault("policy", "MlpPolicy")
    for key in SCHEDULED:
        if isinstance(kwargs.get(key), str):
            kwargs[key] = linear_schedule(kwargs[key], f"{path}: {algo}.{key}")
    train = {**TRAIN_DEFAULTS, **(preset.get("train") or {})}
    unknown = sorted(set(train) - set(TRAIN_DEFAULTS))
    if unknown:
        known = sorted(TRAIN_DEFAULTS)
        raise ValueError(f"{path}: unknown train settings {unknown}; known: {known}")
    if train["evaluate_model"] not in EVALUATED_MODELS:
        raise ValueError(
            f"{path}: train.evaluate_model must be one of {list(EVALUATED_MODELS)}, "
            f"got {train['evaluate_model']!r}"
        )
    eval_envs = train["eval_envs"]
    if eval_envs is not None and (
        isinstance(eval_envs, bool)
        or not isinstance(eval_envs, int)
        or not 1 <= eval_envs <= train["eval_episodes"]
    ):
        raise ValueError(
            f"{path}: train.eval_envs must be a whole number from 1 to eval_episodes "
            f"({train['eval_episodes']}), got {eval_envs!r}"
        )
    return kwargs, {**train, "algo": algo}


def eval_env_count(train: dict[str, Any]) -> int:
    """How many envs the evaluation during training steps at once: the preset's
    ``train.eval_envs``, or by default ``min(n_envs, eval_episodes)``. On a native vector
    env many envs cost little more than a few (one batched step serves them all), so a
    preset whose evaluations are slow may give each episode an env. The episodes drawn
    differ with the number (each env runs on from its own seed): the choice is part of the
    preset, and a preset that keeps its best model ranks its evaluations with it."""
    if train["eval_envs"] is not None:
        return int(train["eval_envs"])
    return min(int(train["n_envs"]), int(train["eval_episodes"]))


TORCHRL_DEFAULTS: dict[str, Any] = {
    "num_envs": 1024,
    "n_steps": 32,
    "total_timesteps": 5_000_000,
    "minibatch_size": 8192,
    "n_epochs": 4,
    "learning_rate": 3e-4,
    "gamma": 0.99,
    "gae_lambda": 0.95,
    "clip_range": 0.2,
    "ent_coef": 0.0,
    "vf_coef": 0.5,
    "max_grad_norm": 0.5,
    "log_std_init": -1.0,
    "use_sde": False,
    "sde_sample_freq": 8,
    "squash_output": True,
    "net_arch": [128, 128],
    "normalize_reward": False,
    "dtype": "float32",
    "compile_step": True,
    "eval_every_timesteps": 500_000,
    "eval_episodes": 50,
}
"""The ``torchrl`` section of a preset (``bbgym train --engine torchrl``: TorchRL's PPO on
the env's device) and what it leaves out. Names follow stable-baselines3's where the
meaning is the same; ``num_envs x n_steps`` frames make one batch, ``minibatch_size`` of
them one gradient step, ``log_std_init`` the state-independent log standard deviation of
the policy's Gaussian (with ``use_sde``, of generalized state-dependent exploration's
noise matrix, drawn anew every ``sde_sample_freq`` steps), ``squash_output`` whether the
Gaussian is squashed by tanh into the action bounds (else its samples are clipped to them,
stable-baselines3's PPO default; :class:`bbgym.torchrl.GaussianPolicyNet`), and
``learning_rate`` may be ``"lin_<initial>"`` (decaying linearly to zero);
``compile_step: false`` runs the env's step eagerly (no compile time, a slower step)."""


def load_torchrl(preset: str | Path) -> dict[str, Any]:
    """The ``torchrl`` section of a preset (an env id, a shipped preset's name or a file)
    with :data:`TORCHRL_DEFAULTS` for what it leaves out; ``ValueError`` naming the setting
    (``torchrl.<name>``) for an unknown or invalid one, or where the preset has no such
    section."""
    import yaml

    path = preset_path(preset)
    with open(path, encoding="utf-8") as f:
        section = yaml.safe_load(f).get("torchrl")
    if not isinstance(section, dict):
        raise ValueError(f"{path}: no torchrl section (the settings of --engine torchrl)")
    unknown = sorted(set(section) - set(TORCHRL_DEFAULTS))
    if unknown:
        raise ValueError(
            f"{path}: unknown torchrl settings {unknown}; known: {sorted(TORCHRL_DEFAULTS)}"
        )
    settings = {**TORCHRL_DEFAULTS, **section}
    for name in (
        "num_envs",
        "n_steps",
        "total_timesteps",
        "minibatch_size",
        "n_epochs",
        "eval_every_timesteps",
        "eval_episodes",
        "sde_sample_freq",
    ):
        value = settings[name]
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ValueError(f"{path}: torchrl.{name} must be a positive int, got {value!r}")
    for name in (
        "gamma",
        "gae_lambda",
        "clip_range",
        "ent_coef",
        "vf_coef",
        "max_grad_norm",
        "log_std_init",
    ):
        value = settings[name]
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or not (float("-inf") < value < float("inf"))
        ):
            raise ValueError(f"{path}: torchrl.{name} must be a finite number, got {value!r}")
        settings[name] = float(value)
    for name in ("gamma", "gae_lambda"):
        if not 0.0 < settings[name] <= 1.0:
            raise ValueError(f"{path}: torchrl.{name} must be in (0, 1], got {settings[name]}")
    for name in ("clip_range", "max_grad_norm"):
        if settings[name] <= 0.0:
            raise ValueError(f"{path}: torchrl.{name} must be > 0, got {settings[name]}")
    if settings["ent_coef"] < 0.0 or settings["vf_coef"] < 0.0:
        raise ValueError(f"{path}: torchrl.ent_coef and torchrl.vf_coef must be >= 0")
    arch = settings["net_arch"]
    if not (
        isinstance(arch, list)
        and arch
        and all(isinstance(w, int) and not isinstance(w, bool) and w > 0 for w in arch)
    ):
        raise ValueError(f"{path}: torchrl.net_arch must be a list of positive ints, got {arch!r}")
    if settings["dtype"] not in ("float32", "float64"):
        raise ValueError(
            f"{path}: torchrl.dtype must be float32 or float64, got {settings['dtype']!r}"
        )
    for name in ("normalize_reward", "use_sde", "squash_output", "compile_step"):
        if not isinstance(settings[name], bool):
            raise ValueError(f"{path}: torchrl.{name} must be true or false")
    rate = settings["learning_rate"]
    if isinstance(rate, str):
        settings["learning_rate"] = linear_schedule(rate, f"{path}: torchrl.learning_rate")
    elif isinstance(rate, bool) or not isinstance(rate, (int, float)) or not 0.0 < rate < 1.0:
        raise ValueError(
            f"{path}: torchrl.learning_rate must be in (0, 1) or 'lin_<number>', got {rate!r}"
        )
    return settings


REJAX_DEFAULTS: dict[str, Any] = {
    "algo": "sac",
    "total_timesteps": 200_000,
    "eval_every_timesteps": 20_000,
    "eval_episodes": 50,
    "dtype": "float32",
}
"""The ``rejax`` section of a preset (``bbgym train --engine rejax``: rejax's PPO or SAC with
the env in one ``jax.jit`` program, :mod:`bbgym.rejax`): bbgym's own settings and their
defaults. ``algo`` is ``ppo`` or ``sac``; every other key of the section is a setting of
that rejax algorithm under rejax's own name (``num_envs``, ``learning_rate``,
``hidden_layer_sizes``, ``fill_buffer``, ...), checked against its fields when training
starts. ``eval_every_timesteps`` is rejax's ``eval_freq``: the policy is evaluated inside
the program on ``eval_episodes`` episodes (:func:`bbgym.rejax.train`)."""


def load_rejax(preset: str | Path) -> dict[str, Any]:
    """The ``rejax`` section of a preset (an env id, a shipped preset's name or a file)
    with :data:`REJAX_DEFAULTS` for what it leaves out.

    Args:
        preset: an env id, a shipped preset's name or a YAML file.

    Returns:
        The settings: bbgym's (:data:`REJAX_DEFAULTS`) and the algorithm's own.

    Raises:
        ValueError: naming the setting (``rejax.<name>``) for an invalid bbgym setting, or
            where the preset has no ``rejax`` section.
    """
    import yaml

    path = preset_path(preset)
    with open(path, encoding="utf-8") as f:
        section = yaml.safe_load(f).get("rejax")
    if not isinstance(section, dict):
        raise ValueError(f"{path}: no rejax section (the settings of --engine rejax)")
    settings = {**REJAX_DEFAULTS, **section}
    if settings["algo"] not in ALGORITHMS:
        raise ValueError(
            f"{path}: rejax.algo must be one of {ALGORITHMS}, got {settings['algo']!r}"
        )
    for name in ("total_timesteps", "eval_every_timesteps", "eval_episodes"):
        value = settings[name]
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise ValueError(f"{path}: rejax.{name} must be a positive int, got {value!r}")
    if settings["dtype"] not in ("float32", "float64"):
        raise ValueError(
            f"{path}: rejax.dtype must be float32 or float64, got {settings['dtype']!r}"
        )
    return settings
