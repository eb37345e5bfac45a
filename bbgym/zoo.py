"""RL Baselines3 Zoo hyperparameters of the bbgym envs, generated from the presets.

    python -m rl_zoo3.train --algo ppo --env ENV_ID --gym-packages bbgym \\
        --conf-file "$(python -m bbgym.zoo --path)"

    python -m rl_zoo3.train --algo sac --env ENV_ID --gym-packages bbgym \\
        --conf-file "$(python -m bbgym.zoo --path --algo sac)"

The shipped files ``bbgym/configs/ppo.yml`` and ``sac.yml`` (the repository's
``configs/``, paths :data:`ZOO_FILES`) are RL Zoo's own format, one per algorithm as RL
Zoo keeps them: one top-level key per env id whose preset trains that algorithm (its
``algo``), each with ``n_envs``, ``n_timesteps``, ``policy``, the algorithm's keyword
arguments, ``policy_kwargs`` as the string RL Zoo evaluates and ``env_kwargs``. They are
generated from the presets (``configs/beachball_*.yaml``) by :func:`zoo_hyperparams`;
after changing a preset, regenerate them with ``python -m bbgym.zoo`` (``--check`` tells
whether they are up to date). ``--conf-file bbgym.zoo`` works too: RL Zoo imports a
module name and reads its ``hyperparams`` (every env id's).

The mapping: the preset's algorithm section (``ppo`` or ``sac``) gives ``policy`` and
the algorithm's arguments (``lin_<x>`` schedules are RL Zoo's notation already),
``train.n_envs`` gives ``n_envs``, ``train.total_timesteps`` gives ``n_timesteps``,
``train.normalize_reward`` gives ``normalize`` (rewards only, as RL Zoo's string), and
``env`` (with ``max_episode_steps`` and the env id's registered arguments, such as
the Curve version's screen) gives ``env_kwargs``. The preset's evaluation and checkpoint
periods have no key in RL Zoo's file: they are its command-line flags,
:func:`zoo_train_flags`.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import yaml

from bbgym.config import (
    ALGORITHMS,
    CONFIG_DIR,
    eval_env_count,
    load_preset,
    load_training,
    preset_files,
    preset_path,
)

NORMALIZE_REWARD = "dict(norm_obs=False, norm_reward=True)"
"""RL Zoo's ``normalize`` value for a preset's ``train.normalize_reward``."""

ZOO_FILES = {algo: CONFIG_DIR / f"{algo}.yml" for algo in ALGORITHMS}
"""RL Zoo's hyperparameter file of each algorithm, shipped in the package (``configs/``)."""
ZOO_FILE = ZOO_FILES["ppo"]
"""RL Zoo's hyperparameter file of PPO (``configs/ppo.yml``)."""

HEADER = """\
# RL Baselines3 Zoo hyperparameters of {ALGO} for the bbgym envs (rl_zoo3's format).
# GENERATED from the presets (configs/beachball_*.yaml) by bbgym.zoo: do not edit by hand.
# After changing a preset, regenerate with: python -m bbgym.zoo  (--check: is it current?)
# Train:
#   python -m rl_zoo3.train --algo {algo} --env {env_id} --gym-packages bbgym \\
#       --conf-file "$(python -m bbgym.zoo --path --algo {algo})" --device cpu
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
    files = preset_files()
    if env_id not in files:
        raise ValueError(f"no preset for {env_id!r}; known: {sorted(files)}")
    _, train = load_training(env_id)  # fills the defaults of the train section
    with open(preset_path(env_id), encoding="utf-8") as f:
        section = dict(yaml.safe_load(f).get(train["algo"]) or {})  # schedules stay "lin_<x>"
    # A version that shares its base's preset: the preset's kwargs plus its registered ones.
    _, env_kwargs = load_preset(env_id)
    out: dict[str, Any] = {
        "n_envs": int(train["n_envs"]),
        "n_timesteps": int(train["total_timesteps"]),
        "policy": section.pop("policy", "MlpPolicy"),
    }
    policy_kwargs = section.pop("policy_kwargs", None)
    out.update(_plain(section))
    if policy_kwargs:
        out["policy_kwargs"] = policy_kwargs_string(policy_kwargs)
    if train["normalize_reward"]:
        # RL Zoo's notation for VecNormalize on the rewards alone (it adds the gamma).
        out["normalize"] = NORMALIZE_REWARD
    out["env_kwargs"] = _plain(env_kwargs)
    return out


def preset_algorithm(env_id: str) -> str:
    """The algorithm an env id's preset trains (its ``algo``)."""
    return load_training(env_id)[1]["algo"]


def zoo_hyperparams(algo: str | None = None) -> dict[str, dict[str, Any]]:
    """RL Zoo's hyperparameter dict ``{env_id: hyperparameters}`` of the env ids of
    :func:`bbgym.config.preset_files` whose preset trains ``algo`` (what ``yaml.safe_load``
    of ``ZOO_FILES[algo]`` gives); every env id's when ``algo`` is None."""
    if algo is not None and algo not in ALGORITHMS:
        raise ValueError(f"algo must be one of {list(ALGORITHMS)}, got {algo!r}")
    return {
        env_id: env_hyperparams(env_id)
        for env_id in preset_files()
        if algo is None or preset_algorithm(env_id) == algo
    }


def zoo_train_flags(env_id: str) -> list[str]:
    """RL Zoo's command-line flags for the preset's ``train`` settings that its file cannot
    hold: evaluation period and episodes (on as many envs as ``bbgym train``,
    :func:`bbgym.config.eval_env_count`) and the checkpoint period, all in total timesteps
    as RL Zoo counts them (it divides by ``n_envs`` itself)."""
    _, train = load_training(env_id)
    n_eval_envs = eval_env_count(train)
    return [
        "--eval-freq",
        str(train["eval_every_timesteps"]),
        "--eval-episodes",
        str(train["eval_episodes"]),
        "--n-eval-envs",
        str(n_eval_envs),
        "--save-freq",
        str(train["checkpoint_every_timesteps"]),
    ]


class _Dumper(yaml.SafeDumper):
    """Block style, but lists of numbers on one line (``[3.0, 7.0]``), as the presets."""


def _represent_list(dumper: Any, data: list[Any]) -> Any:
    flow = all(not isinstance(v, (list, dict)) for v in data)
    return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=flow)


_Dumper.add_representer(list, _represent_list)


def zoo_text(algo: str = "ppo") -> str:
    """The text of ``ZOO_FILES[algo]``: :data:`HEADER`, then per env id a comment with the
    preset's flags (:func:`zoo_train_flags`) and its YAML block."""
    hyperparams = zoo_hyperparams(algo)
    example = next(iter(hyperparams), "ENV_ID")
    blocks = [HEADER.format(ALGO=algo.upper(), algo=algo, env_id=example)]
    for env_id, params in hyperparams.items():
        block = yaml.dump(
            {env_id: params}, Dumper=_Dumper, sort_keys=False, default_flow_style=False
        )
        blocks.append(
            f"# {env_id}: from configs/{preset_files()[env_id].name}; its evaluation and "
            "checkpoints:\n"
            f"#   {' '.join(zoo_train_flags(env_id))}\n{block}"
        )
    return "\n".join(blocks)


def write_zoo_file(path: str | Path | None = None, algo: str = "ppo") -> Path:
    """Write RL Zoo's hyperparameter file of ``algo`` (:func:`zoo_text`) to ``path``
    (default ``ZOO_FILES[algo]``); return the path."""
    path = Path(path) if path is not None else ZOO_FILES[algo]
    path.write_text(zoo_text(algo), encoding="utf-8")
    return path


def __getattr__(name: str) -> Any:
    # ``--conf-file bbgym.zoo``: RL Zoo imports the module and reads ``hyperparams``.
    if name == "hyperparams":
        return zoo_hyperparams()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Write RL Zoo's files from the presets.")
    parser.add_argument(
        "--algo",
        choices=ALGORITHMS,
        default=None,
        help="one algorithm's file (default: every one; --path: ppo)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="file to write (with --algo; default: the shipped file)",
    )
    parser.add_argument("--check", action="store_true", help="exit 1 if a file is stale")
    parser.add_argument("--path", action="store_true", help="print the shipped file's path")
    args = parser.parse_args(argv)
    if args.path:
        print(ZOO_FILES[args.algo or "ppo"])
        return 0
    if args.out is not None and args.algo is None:
        parser.error("--out needs --algo (one file)")
    algos = [args.algo] if args.algo else list(ALGORITHMS)
    if args.check:
        stale = []
        for algo in algos:
            path = args.out or ZOO_FILES[algo]
            current = path.read_text(encoding="utf-8") if path.exists() else None
            if current != zoo_text(algo):
                stale.append(str(path))
        if stale:
            print(f"{', '.join(stale)} stale: run python -m bbgym.zoo", file=sys.stderr)
            return 1
        return 0
    for algo in algos:
        print(write_zoo_file(args.out, algo))
    return 0


if __name__ == "__main__":
    sys.exit(main())
