"""Train PPO on a bbgym env, evaluate it beside random and scripted play, write a run folder.

    python scripts/baseline.py --env BeachballSail-v0 [--config configs/beachball_sail.yaml]
        [--timesteps N] [--seed 0] [--episodes 100] [--out runs/baseline/<env>-seed<seed>]
    [--no-train]

The main job (``make run``) is this script on BeachballSail-v0 with the default preset.
Steps, each reported as it goes (PPO shows a progress bar):

1. train PPO with ``scripts/train.py`` (the preset's ``ppo`` and ``train`` sections);
   ``--no-train`` skips this and evaluates the model already in the run folder;
2. evaluate the best model of training (chosen on the evaluation seeds 10000+), a uniform
   random policy and the env's scripted agent (the VMG autopilot for sailing) over the
   same ``--episodes`` seeded episodes (seeds ``0 .. episodes-1``, apart from training's);
3. write into the run folder: ``model.zip`` / ``best_model.zip``, ``results.md`` and
   ``results.json`` (success with a 95% interval, return, length, time to mark and time /
   oracle time), ``learning_curve.png`` (evaluation success and return against
   timesteps, with random and scripted as reference lines), ``episode.gif`` (one episode
   of the trained policy) and ``summary.json`` (budget, wall times, steps per second).
"""

from __future__ import annotations

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import evaluate  # noqa: E402  (scripts/evaluate.py)
import record  # noqa: E402  (scripts/record.py)
import train  # noqa: E402  (scripts/train.py)

from bbgym.config import CONFIG_DIR, load_training  # noqa: E402

POLICIES = ("random", "scripted", "ppo")


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="BeachballSail-v0", choices=sorted(train.PRESETS))
    parser.add_argument("--config", type=Path, default=None, help="preset YAML (env's default)")
    parser.add_argument("--timesteps", type=int, default=None, help="override the budget")
    parser.add_argument("--seed", type=int, default=0, help="training seed")
    parser.add_argument("--episodes", type=int, default=100, help="evaluation episodes")
    parser.add_argument("--out", type=Path, default=None, help="run folder")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--no-train", action="store_true", help="skip training: evaluate the run folder's model"
    )
    args = parser.parse_args(argv)
    args.config = args.config or CONFIG_DIR / train.PRESETS[args.env]
    args.out = args.out or Path("runs") / "baseline" / f"{args.env}-seed{args.seed}"
    if args.no_train and not (args.out / "train.json").exists():
        parser.error(f"--no-train needs a trained run in {args.out}")
    if args.episodes < 1:
        parser.error("--episodes must be >= 1")
    if args.timesteps is not None and args.timesteps < 1:
        parser.error("--timesteps must be >= 1")
    return args


def plot_learning_curve(run: Path, results: dict[str, dict], env_id: str, out: Path) -> None:
    """Evaluation success rate and mean return against timesteps, with the reference
    policies' evaluation results as horizontal lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = np.load(run / "eval" / "evaluations.npz")
    steps = data["timesteps"]
    fig, (ax_success, ax_return) = plt.subplots(1, 2, figsize=(11, 4), constrained_layout=True)
    if "successes" in data and data["successes"].size:
        ax_success.plot(steps, 100 * data["successes"].mean(axis=1), "o-", label="PPO")
    returns = data["results"]
    mean, std = returns.mean(axis=1), returns.std(axis=1)
    ax_return.plot(steps, mean, "o-", label="PPO")
    ax_return.fill_between(steps, mean - std, mean + std, alpha=0.2)
    colors = {"random": "tab:gray", "scripted": "tab:green"}
    for name, color in colors.items():
        if name in results:
            r = results[name]
            ax_success.axhline(100 * r["success_rate"], color=color, ls="--", label=name)
            ax_return.axhline(r["mean_return"], color=color, ls="--", label=name)
    ax_success.set(xlabel="timesteps", ylabel="success (%)", ylim=(-3, 103))
    ax_success.set_title(f"{env_id}: evaluation success ({data['results'].shape[1]} episodes)")
    ax_return.set(xlabel="timesteps", ylabel="episode return")
    ax_return.set_title("evaluation return (mean +- std)")
    for ax in (ax_success, ax_return):
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right")
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    _, settings = load_training(args.config)
    budget = args.timesteps or settings["total_timesteps"]
    print(f"[1/4] training PPO on {args.env}: {budget} timesteps, {settings['n_envs']} envs")
    start = time.perf_counter()
    train_argv = ["--env", args.env, "--config", str(args.config), "--seed", str(args.seed),
                  "--out", str(args.out), "--timesteps", str(budget)]  # fmt: skip
    if args.no_train:
        print(f"      (--no-train: using the model already in {args.out})")
    else:
        train.main(train_argv + (["--no-progress"] if args.no_progress else []))
    train_log = json.loads((args.out / "train.json").read_text())
    train_wall = train_log["wall_time_s"] if args.no_train else time.perf_counter() - start
    budget = train_log["timesteps"]

    print(f"[2/4] evaluating random, scripted and PPO over {args.episodes} seeded episodes")
    model = args.out / "best_model.zip"
    start = time.perf_counter()
    results = {
        name: evaluate.evaluate(args.env, name, args.episodes, 0, model if name == "ppo" else None)
        for name in POLICIES
    }
    if args.env.startswith("BeachballSail"):
        for result in results.values():
            result["time_vs_oracle"] = evaluate.time_vs_oracle(result, results["scripted"])
    eval_wall = time.perf_counter() - start
    table = evaluate.format_table(list(results.values()))
    print(table)
    (args.out / "results.md").write_text(table + "\n")
    (args.out / "results.json").write_text(json.dumps(list(results.values()), indent=2) + "\n")

    print("[3/4] plotting the learning curve")
    plot_learning_curve(args.out, results, args.env, args.out / "learning_curve.png")

    print("[4/4] recording an episode of the trained policy")
    animation = args.out / "episode.gif"
    record.main(["--env", args.env, "--policy", "ppo", "--model", str(model), "--seed", "0",
                 "--frame-skip", "2", "--out", str(animation)])  # fmt: skip

    summary = {
        "env": args.env,
        "config": str(args.config),
        "seed": args.seed,
        "timesteps": budget,
        "n_envs": settings["n_envs"],
        "train_wall_time_s": train_wall,
        "train_timesteps_per_s": budget / train_wall,
        "eval_wall_time_s": eval_wall,
        "eval_episodes": args.episodes,
        "eval_seeds": [0, args.episodes - 1],
        "success_rate": {name: r["success_rate"] for name, r in results.items()},
    }
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"run folder {args.out}: " + ", ".join(sorted(p.name for p in args.out.iterdir())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
