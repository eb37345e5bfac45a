"""Self-play PPO for BeachballRace: one shared policy sails the learning boats of many races
at once against each other and against scripted racers, and is scored by how often a
learned boat finishes ahead of a scripted one (the race's baseline; the docs' Race page).

    python scripts/race_selfplay.py --seeds 5 --out runs/race_selfplay
    python scripts/race_selfplay.py --seeds 5 --plain --out runs/race_selfplay_plain

Each training seed trains stable-baselines3 PPO on :class:`bbgym.envs.race.match.
BeachballRaceMatchEnv` (``RACES`` races of four boats, two of each learning: one policy,
every learning boat a sub-env, through :class:`bbgym.sb3.NativeVecEnvAdapter`), with
residual actions (the policy corrects :class:`bbgym.agents.RaceRacer`; ``--plain``: the
policy sails alone) and relative rewards (a learning boat's reward less its race's scripted
boats' mean, ``relative=True``; ``--absolute``: the race's own). Then it sails the same
``--eval-races`` seeded races for every seed (race ``r`` seeded ``EVAL_SEED + r``, as the
PettingZoo env reset with that seed), two learned boats against two scripted racers in
each, and counts the pairings (a learned boat, a scripted boat) in which the learned boat
finished ahead (:func:`bbgym.envs.race.match.play_matches`). The scripted racer in the
learners' places is the reference row: about half by symmetry. The results go to
``OUT/selfplay.json`` (``--results`` copies them where the docs' table reads them).
``--reward NAME=WEIGHT`` trains with a reward weight of the race changed
(``foul_penalty=10``; the scoring races keep the race's own), ``--only-seed S`` trains one
seed (for tries), ``--curve STEPS`` scores the model saved every ``STEPS`` steps too (each
seed's ``curve`` in the JSON).
"""

from __future__ import annotations

import argparse
import json
import shutil
import time
from pathlib import Path
from typing import Any

import numpy as np

EVAL_SEED = 100_000
"""The evaluation races' first seed: far from any training race's (seeds 0 up)."""
RACES = 64
"""Races trained at once: 128 learning boats, 256 boats in all."""
PPO_KWARGS: dict[str, Any] = {
    "n_steps": 128,  # 32 s of racing per learning boat per update, 16k steps in all
    "batch_size": 2048,
    "n_epochs": 4,
    "learning_rate": 3e-4,
    # a race is about 800 steps of 0.25 s: a 50 s horizon sees a leg's end and the start
    "gamma": 0.995,
    "gae_lambda": 0.95,
    "clip_range": 0.2,
    "ent_coef": 0.0,
    # residual: the racer's action plus a correction explored at exp(-2) = 0.14 (over 3M
    # steps of seed 0 it kept the racer's return where 0.37 lost 7 of it; with gSDE most
    # learned boats stopped finishing)
    "policy_kwargs": {"log_std_init": -2.0, "net_arch": [64, 64]},
}
"""PPO's keyword arguments; the rewards are normalized (``VecNormalize``)."""
RESULTS = Path(__file__).resolve().parent.parent / "docs" / "results" / "race"
"""Where ``--results`` copies the results: ``selfplay.json`` for the baseline's settings,
``selfplay_absolute.json`` with ``--absolute``, ``selfplay_plain.json`` with ``--plain``."""


def interval(values: list[float]) -> list[float]:
    """A 95% t-interval of the mean (the baselines' convention)."""
    from bbgym.cli.evaluate import mean_interval

    return list(mean_interval(values))


def train(
    seed: int,
    timesteps: int,
    residual: bool,
    relative: bool,
    threads: int,
    out: Path,
    reward: dict[str, float] | None = None,
    curve: int = 0,
) -> Path:
    """Train one seed; with ``curve`` > 0 also save the model every ``curve`` steps (as
    ``OUT/curve_seed{seed}/ck_{steps}_steps.zip``)."""
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import CheckpointCallback
    from stable_baselines3.common.vec_env import VecNormalize

    from bbgym.envs.race.match import BeachballRaceMatchEnv
    from bbgym.sb3 import NativeVecEnvAdapter

    torch.set_num_threads(threads)
    match = BeachballRaceMatchEnv(RACES, residual=residual, relative=relative, **(reward or {}))
    venv = NativeVecEnvAdapter(match)
    venv.seed(seed)
    venv = VecNormalize(venv, norm_obs=False, norm_reward=True, gamma=PPO_KWARGS["gamma"])
    model = PPO("MlpPolicy", venv, seed=seed, device="cpu", verbose=0, **PPO_KWARGS)
    every = max(curve // venv.num_envs, 1)  # the callback counts vector steps
    folder = str(out / f"curve_seed{seed}")
    model.learn(timesteps, callback=CheckpointCallback(every, folder, "ck") if curve else None)
    path = out / f"seed_{seed}.zip"
    model.save(path)
    # how it races, for bbgym record --env bbgym/BeachballRace-v0 --policy ppo --model PATH
    path.with_suffix(".json").write_text(json.dumps({"learners": 2, "residual": residual}))
    venv.close()
    return path


def evaluate(policy: Any, races: int, residual: bool) -> dict[str, Any]:
    from bbgym.envs.race.match import play_matches

    result = play_matches(policy, num_races=races, seed=EVAL_SEED, residual=residual)
    return result._asdict() | {"ahead_share": result.ahead_share}


def score(path: Path, races: int, residual: bool) -> dict[str, Any]:
    """A saved model's learning boats sailed deterministically on the scoring races."""
    from stable_baselines3 import PPO

    model = PPO.load(path, device="cpu")
    return evaluate(lambda obs: model.predict(obs, deterministic=True)[0], races, residual)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--timesteps", type=int, default=5_000_000)
    parser.add_argument("--eval-races", type=int, default=100)
    parser.add_argument("--plain", action="store_true", help="no residual: the policy alone")
    parser.add_argument(
        "--absolute", action="store_true", help="train on the race's reward, not relative"
    )
    parser.add_argument(
        "--reward",
        action="append",
        default=[],
        metavar="NAME=WEIGHT",
        help="a reward weight of the race to train with (scored without)",
    )
    parser.add_argument("--only-seed", type=int, default=None, help="train this seed alone")
    parser.add_argument(
        "--curve",
        type=int,
        default=0,
        metavar="STEPS",
        help="also score the model saved every STEPS steps (a learning curve per seed)",
    )
    parser.add_argument("--torch-threads", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("runs/race_selfplay"))
    parser.add_argument("--results", action="store_true", help=f"copy to {RESULTS}/")
    args = parser.parse_args()
    from bbgym.agents import RaceRacer

    from bbgym.envs.race.match import BeachballRaceMatchEnv

    reward = {}
    for item in args.reward:  # checked here; the race checks the names and values
        name, _, value = item.partition("=")
        try:
            reward[name] = float(value)
        except ValueError:
            parser.error(f"--reward takes NAME=WEIGHT (a race reward argument), got {item!r}")
    args.out.mkdir(parents=True, exist_ok=True)
    residual = not args.plain
    racer = RaceRacer.for_env(BeachballRaceMatchEnv(1).fleet)
    began = time.perf_counter()
    reference = evaluate(racer, args.eval_races, residual=False)
    print(f"scripted in the learners' places: {reference['ahead_share']:.1%} ahead", flush=True)
    seeds = []
    for seed in range(args.seeds) if args.only_seed is None else [args.only_seed]:
        start = time.perf_counter()
        path = train(
            seed,
            args.timesteps,
            residual,
            not args.absolute,
            args.torch_threads,
            args.out,
            reward,
            args.curve,
        )
        trained = time.perf_counter() - start
        row = score(path, args.eval_races, residual)
        curve = []
        saved = (args.out / f"curve_seed{seed}").glob("ck_*_steps.zip") if args.curve else ()
        for checkpoint in sorted(saved, key=lambda p: int(p.stem.split("_")[1])):
            point = score(checkpoint, args.eval_races, residual)
            curve.append({"steps": int(checkpoint.stem.split("_")[1])} | point)
            print(f"  at {curve[-1]['steps']} steps: {point['ahead_share']:.1%}", flush=True)
        seeds.append(
            row
            | {"seed": seed, "train_s": round(trained, 1)}
            | ({"curve": curve} if args.curve else {})
        )
        print(
            f"seed {seed}: {row['ahead_share']:.1%} ahead, fouls {row['learned_fouls']:.2f} "
            f"vs {row['scripted_fouls']:.2f}, trained in {trained:.0f} s",
            flush=True,
        )
    shares = [s["ahead_share"] for s in seeds]
    results = {
        "command": "python scripts/race_selfplay.py --seeds {} --timesteps {}{}{}{}{}".format(
            args.seeds,
            args.timesteps,
            " --plain" if args.plain else "",
            " --absolute" if args.absolute else "",
            "".join(f" --reward {item}" for item in args.reward),
            "" if args.only_seed is None else f" --only-seed {args.only_seed}",
        )
        + (f" --curve {args.curve}" if args.curve else ""),
        "training_reward": reward,
        "relative_reward": not args.absolute,
        "policy": "residual PPO on RaceRacer" if residual else "PPO",
        "timesteps": args.timesteps,
        "races_trained_at_once": RACES,
        "eval_races": args.eval_races,
        "eval_seed": EVAL_SEED,
        "torch_threads": args.torch_threads,
        "ppo": PPO_KWARGS,
        "reference": reference,
        "seeds": seeds,
        "ahead_share_mean": float(np.mean(shares)),
        "ahead_share_worst": float(np.min(shares)),
        # one seed has no interval: null in the JSON (NaN is not JSON)
        "ahead_share_interval": interval(shares) if len(shares) > 1 else None,
        "learned_fouls_mean": float(np.mean([s["learned_fouls"] for s in seeds])),
        "scripted_fouls_mean": float(np.mean([s["scripted_fouls"] for s in seeds])),
        "wall_s": round(time.perf_counter() - began, 1),
    }
    (args.out / "selfplay.json").write_text(json.dumps(results, indent=2) + "\n")
    print(json.dumps({k: v for k, v in results.items() if k not in ("seeds", "ppo")}, indent=2))
    if args.results:
        name = "selfplay{}{}.json".format(
            "_plain" if args.plain else "", "_absolute" if args.absolute else ""
        )
        RESULTS.mkdir(parents=True, exist_ok=True)
        shutil.copy(args.out / "selfplay.json", RESULTS / name)


if __name__ == "__main__":
    main()
