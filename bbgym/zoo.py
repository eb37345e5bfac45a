"""RL Baselines3 Zoo hyperparameters of the bbgym envs, generated from the presets.

    python -m rl_zoo3.train --algo ppo --env BeachballSail-v0 --gym-packages bbgym \\
        --conf-file "$(python -m bbgym.zoo --path)"

The shipped file ``bbgym/configs/ppo.yml`` (the repository's ``configs/ppo.yml``, path
:data:`ZOO_FILE`) is RL Zoo's own format: one top-level key per env id, each with
``n_envs``, ``n_timesteps``, ``policy``, PPO's keyword arguments, ``policy_kwargs`` as the
string RL Zoo evaluates and ``env_kwargs``. It is generated from the presets
(``configs/beachball_*.yaml``) by :func:`zoo_hyperparams`; after changing a preset,
regenerate it with ``python -m bbgym.zoo`` (``--check`` tells whether it is up to date).
``--conf-file bbgym.zoo`` works too: RL Zoo imports a module name and reads its
``hyperparams``.

The mapping: the preset's ``ppo`` section gives ``policy`` and PPO's arguments (``lin_<x>``
schedules are RL Zoo's notation already), ``train.n_envs`` gives ``n_envs``,
``train.total_timesteps`` gives ``n_timesteps``, ``train.normalize_reward`` gives
``normalize`` (rewards only, as RL Zoo's string), and ``env`` (with ``max_episode_steps``
and the env id's registered arguments, such as BeachballCurve-v0's screen) gives
``env_kwargs``. The preset's evaluation and checkpoint periods have no key in RL Zoo's
file: they are its command-line flags, :func:`zoo_train_flags`.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import yaml

from bbgym.config import CONFIG_DIR, PRESET_FILES, load_preset, load_training, preset_path

NORMALIZE_REWARD = "dict(norm_obs=False, norm_reward=True)"
"""RL Zoo's ``normalize`` value for a preset's ``train.normalize_reward``."""

ZOO_FILE = CONFIG_DIR / "ppo.yml"
"""RL Zoo's hyperparameter file of PPO, shipped in the package (``configs/ppo.yml``)."""

HEADER = """\
# RL Baselines3 Zoo hyperparameters of PPO for the bbgym envs (rl_zoo3's format).
# GENERATED from the presets (configs/beachball_*.yaml) by bbgym.zoo: do not edit by hand.
# After changing a preset, regenerate with: python -m bbgym.zoo  (--check: is it current?)
# Train:
#   python -m rl_zoo3.train --algo ppo --env BeachballSail-v0 --gym-packages bbgym \\
#       --conf-file "$(python -m bbgym.zoo --path)" --device cpu
# RL Zoo steps n_envs single envs (gym.make) in a DummyVecEnv, not the native vector env
# of `bbgym train`; --vec-env subproc spreads them over processes.
"""


def _plain(value: Any) -> Any:
    """YAML-ready value: tuples become lists (RL Zoo reads the file with ``yaml.safe_load``)."""
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def policy_kwargs_string(policy_kwargs: dict[str, Any]) -> str:
    """RL Zoo's string form of ``policy_kwargs``, e.g. ``"dict(net_arch=[64, 64])"``
    (RL Zoo evaluates it as Python)."""
    for key in policy_kwargs:
        if not key.isidentifier():
            raise ValueError(f"policy_kwargs key {key!r} is not a Python identifier")
    items = ", ".join(f"{k}={_plain(v)!r}" for k, v in policy_kwargs.items())
    return f"dict({items})"


def env_hyperparams(env_id: str) -> dict[str, Any]:
    """RL Zoo's hyperparameters of one env id, from its preset (see the module's doc)."""
    if env_id not in PRESET_FILES:
        raise ValueError(f"no preset for {env_id!r}; known: {sorted(PRESET_FILES)}")
    with open(preset_path(env_id), encoding="utf-8") as f:
        ppo = dict(yaml.safe_load(f).get("ppo") or {})  # raw: schedules stay "lin_<x>"
    _, train = load_training(env_id)  # fills the defaults of the train section
    # BeachballCurve-v0's kwargs are the throw preset's plus its registered ones.
    _, env_kwargs = load_preset(env_id)
    out: dict[str, Any] = {
        "n_envs": int(train["n_envs"]),
        "n_timesteps": int(train["total_timesteps"]),
        "policy": ppo.pop("policy", "MlpPolicy"),
    }
    policy_kwargs = ppo.pop("policy_kwargs", None)
    out.update(_plain(ppo))
    if policy_kwargs:
        out["policy_kwargs"] = policy_kwargs_string(policy_kwargs)
    if train["normalize_reward"]:
        # RL Zoo's notation for VecNormalize on the rewards alone (it adds PPO's gamma).
        out["normalize"] = NORMALIZE_REWARD
    out["env_kwargs"] = _plain(env_kwargs)
    return out


def zoo_hyperparams() -> dict[str, dict[str, Any]]:
    """RL Zoo's hyperparameter dict of PPO: ``{env_id: hyperparameters}`` for every env id
    of :data:`bbgym.config.PRESET_FILES`, what ``yaml.safe_load`` of :data:`ZOO_FILE` gives."""
    return {env_id: env_hyperparams(env_id) for env_id in PRESET_FILES}


def zoo_train_flags(env_id: str) -> list[str]:
    """RL Zoo's command-line flags for the preset's ``train`` settings that its file cannot
    hold: evaluation period and episodes (on ``min(n_envs, eval_episodes)`` envs, as
    ``bbgym train``) and the checkpoint period, all in total timesteps as RL Zoo
    counts them (it divides by ``n_envs`` itself)."""
    _, train = load_training(env_id)
    n_eval_envs = min(train["n_envs"], train["eval_episodes"])
    return [
        "--eval-freq", str(train["eval_every_timesteps"]),
        "--eval-episodes", str(train["eval_episodes"]),
        "--n-eval-envs", str(n_eval_envs),
        "--save-freq", str(train["checkpoint_every_timesteps"]),
    ]  # fmt: skip


class _Dumper(yaml.SafeDumper):
    """Block style, but lists of numbers on one line (``[3.0, 7.0]``), as the presets."""


def _represent_list(dumper: Any, data: list[Any]) -> Any:
    flow = all(not isinstance(v, (list, dict)) for v in data)
    return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=flow)


_Dumper.add_representer(list, _represent_list)


def zoo_text() -> str:
    """The text of :data:`ZOO_FILE`: :data:`HEADER`, then per env id a comment with the
    preset's flags (:func:`zoo_train_flags`) and its YAML block."""
    blocks = [HEADER]
    for env_id, params in zoo_hyperparams().items():
        block = yaml.dump(
            {env_id: params}, Dumper=_Dumper, sort_keys=False, default_flow_style=False
        )
        blocks.append(
            f"# {env_id}: from configs/{PRESET_FILES[env_id]}; its evaluation and checkpoints:\n"
            f"#   {' '.join(zoo_train_flags(env_id))}\n{block}"
        )
    return "\n".join(blocks)


def write_zoo_file(path: str | Path = ZOO_FILE) -> Path:
    """Write RL Zoo's hyperparameter file (:func:`zoo_text`) to ``path``; return the path."""
    path = Path(path)
    path.write_text(zoo_text(), encoding="utf-8")
    return path


def __getattr__(name: str) -> Any:
    # ``--conf-file bbgym.zoo``: RL Zoo imports the module and reads ``hyperparams``.
    if name == "hyperparams":
        return zoo_hyperparams()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Write RL Zoo's PPO file from the presets.")
    parser.add_argument("--out", type=Path, default=ZOO_FILE, help="file to write")
    parser.add_argument("--check", action="store_true", help="exit 1 if the file is stale")
    parser.add_argument("--path", action="store_true", help="print the shipped file's path")
    args = parser.parse_args(argv)
    if args.path:
        print(ZOO_FILE)
        return 0
    if args.check:
        current = args.out.read_text(encoding="utf-8") if args.out.exists() else None
        if current != zoo_text():
            print(f"{args.out} is stale: run python -m bbgym.zoo", file=sys.stderr)
            return 1
        return 0
    print(write_zoo_file(args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
