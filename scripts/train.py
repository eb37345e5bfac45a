"""Train stable-baselines3 PPO on a bbgym env from its preset in configs/.

    python scripts/train.py --env BeachballSail-v0 [--config configs/beachball_sail.yaml]
        [--timesteps N] [--seed 0] [--out runs/ppo/BeachballSail-v0-seed0] [--resume]

The preset gives the env's arguments (``env``), PPO's keyword arguments (``ppo``) and the
run settings (``train``: number of envs, budget, evaluation and checkpoint periods).
Training runs on the env's native vector env through :mod:`bbgym.sb3`, with a progress
bar, TensorBoard logs in ``<out>/tb``, a periodic evaluation on separate seeds (success
rate and return in ``<out>/eval``, the best model as ``<out>/best_model.zip``) and
checkpoints in ``<out>/checkpoints``. The final model is ``<out>/model.zip``; ``--resume``
continues from it. Needs the ``train`` extra.
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
import time
from pathlib import Path

import bbgym  # noqa: F401  (registers the envs)
from bbgym.config import CONFIG_DIR, load_preset, load_training

PRESETS = {
    "BeachballSail-v0": "beachball_sail.yaml",
    "BeachballThrow-v0": "beachball_throw.yaml",
    "BeachballCurve-v0": "beachball_throw.yaml",
    "BeachballTopple-v0": "beachball_topple.yaml",
}
CURVE = {"screen": True, "target_distance_range": (7.0, 10.0)}
EVAL_SEED_OFFSET = 10_000
"""Evaluation episodes use seeds far from the training ones."""


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", required=True, choices=sorted(PRESETS))
    parser.add_argument("--config", type=Path, default=None, help="preset YAML (env's default)")
    parser.add_argument("--timesteps", type=int, default=None, help="override the budget")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=None, help="run folder")
    parser.add_argument("--resume", action="store_true", help="continue from <out>/model.zip")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    args.config = args.config or CONFIG_DIR / PRESETS[args.env]
    args.out = args.out or Path("runs") / "ppo" / f"{args.env}-seed{args.seed}"
    if args.timesteps is not None and args.timesteps < 1:
        parser.error("--timesteps must be >= 1")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import CheckpointCallback, EvalCallback
    from stable_baselines3.common.vec_env import VecMonitor

    from bbgym.sb3 import make_sb3_vec_env

    preset_id, env_kwargs = load_preset(args.config)
    env_kwargs.pop("max_episode_steps", None)  # the registered limit applies
    if args.env == "BeachballCurve-v0":
        env_kwargs.update(CURVE)
    elif preset_id != args.env:
        raise SystemExit(f"{args.config} is a preset of {preset_id}, not {args.env}")
    ppo_kwargs, train = load_training(args.config)
    budget = args.timesteps or train["total_timesteps"]
    n_envs = train["n_envs"]

    args.out.mkdir(parents=True, exist_ok=True)
    shutil.copy(args.config, args.out / "config.yaml")
    env = VecMonitor(make_sb3_vec_env(args.env, n_envs=n_envs, seed=args.seed, **env_kwargs))
    # Several envs evaluate at once: a native vector env of one is NumPy on one element.
    n_eval = min(n_envs, train["eval_episodes"])
    eval_env = VecMonitor(
        make_sb3_vec_env(args.env, n_envs=n_eval, seed=args.seed + EVAL_SEED_OFFSET, **env_kwargs)
    )
    callbacks = [
        EvalCallback(
            eval_env,
            n_eval_episodes=train["eval_episodes"],
            eval_freq=max(1, train["eval_every_timesteps"] // n_envs),
            best_model_save_path=str(args.out),
            log_path=str(args.out / "eval"),
            deterministic=True,
        ),
        CheckpointCallback(
            save_freq=max(1, train["checkpoint_every_timesteps"] // n_envs),
            save_path=str(args.out / "checkpoints"),
            name_prefix="ppo",
        ),
    ]
    model_path = args.out / "model.zip"
    if args.resume and model_path.exists():
        model = PPO.load(model_path, env=env, device="cpu", tensorboard_log=str(args.out / "tb"))
        print(f"resuming from {model_path} at {model.num_timesteps} timesteps")
    else:
        policy = ppo_kwargs.pop("policy")
        model = PPO(
            policy, env, seed=args.seed, device="cpu", tensorboard_log=str(args.out / "tb"),
            verbose=0, **ppo_kwargs,
        )  # fmt: skip
    start = time.perf_counter()
    model.learn(
        total_timesteps=budget,
        callback=callbacks,
        progress_bar=not args.no_progress,
        reset_num_timesteps=not args.resume,
    )
    wall = time.perf_counter() - start
    model.save(model_path)
    summary = {
        "env": args.env,
        "seed": args.seed,
        "timesteps": int(model.num_timesteps),
        "wall_time_s": wall,
        "timesteps_per_s": budget / wall,
        "config": str(args.config),
        "model": str(model_path),
    }
    (args.out / "train.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(json.dumps(summary, indent=2))
    env.close()
    eval_env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
