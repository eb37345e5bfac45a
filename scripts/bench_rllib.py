"""Env steps per second of RLlib PPO training on a bbgym env, by number of env runners.

    python scripts/bench_rllib.py --env BeachballSail-v0 --runners 1,2 --iterations 3 \\
        --repeats 3 [--envs-per-runner 32] [--train-batch-size 4096] [--out bench.json]

One local Ray cluster (``--num-cpus``, default the largest runner count) serves every
measurement. Each measurement builds the algorithm from :func:`bbgym.rllib.ppo_config`
(the env's preset unless overridden), runs ``--warmup`` iterations (actors warm, first
episodes reset), then times ``--iterations`` of ``algo.train()``: the rate is the env
steps sampled in those iterations over their wall time, so it counts learning too, as
training does. The runner counts take turns within each repeat (1, 2, 1, 2, ...), so a
slow spell of a shared machine falls on all of them; the best repeat is reported. The
same train batch is split among the runners, so the rate shows what scaling out buys
for one configuration; RLlib's (smoothed) sampling and learner timers show where an
iteration goes. The learner runs in the driver with ``--learner-threads`` torch threads
(1, as :func:`bbgym.rllib.train` does by default).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

from bbgym import rllib
from bbgym.config import preset_files


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default="BeachballSail-v0", choices=sorted(preset_files()))
    parser.add_argument("--runners", default="1,2", help="comma-separated env runner counts")
    parser.add_argument("--iterations", type=int, default=3, help="timed iterations")
    parser.add_argument("--warmup", type=int, default=1, help="untimed iterations first")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--envs-per-runner", type=int, default=None, help="preset's n_envs")
    parser.add_argument("--train-batch-size", type=int, default=None, help="preset's")
    parser.add_argument("--num-cpus", type=int, default=None, help="local Ray's CPUs")
    parser.add_argument("--learner-threads", type=int, default=1, help="torch threads (driver)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=None, help="write the results as JSON")
    args = parser.parse_args(argv)
    try:
        args.runners = [int(r) for r in args.runners.split(",")]
    except ValueError:
        parser.error(f"--runners must be comma-separated ints, got {args.runners!r}")
    if any(r < 0 for r in args.runners):
        parser.error("--runners must be >= 0")
    for name in ("iterations", "repeats"):
        if getattr(args, name) < 1:
            parser.error(f"--{name} must be >= 1")
    if args.warmup < 0:
        parser.error("--warmup must be >= 0")
    return args


def measure(args: argparse.Namespace, runners: int) -> dict[str, Any]:
    """One build, warm-up and timed run with ``runners`` env runners."""
    from ray.rllib.utils.metrics import (
        ENV_RUNNER_RESULTS,
        ENV_RUNNER_SAMPLING_TIMER,
        LEARNER_UPDATE_TIMER,
        NUM_ENV_STEPS_SAMPLED_LIFETIME,
        TIMERS,
    )

    config = rllib.ppo_config(
        args.env,
        num_env_runners=runners,
        num_envs_per_env_runner=args.envs_per_runner,
        seed=args.seed,
        train_batch_size=args.train_batch_size,
    )
    algo = config.build_algo()
    try:

        def steps(results: dict[str, Any]) -> int:
            return int(results[ENV_RUNNER_RESULTS][NUM_ENV_STEPS_SAMPLED_LIFETIME])

        results: dict[str, Any] = {ENV_RUNNER_RESULTS: {NUM_ENV_STEPS_SAMPLED_LIFETIME: 0}}
        for _ in range(args.warmup):
            results = algo.train()
        start_steps = steps(results)
        start = time.perf_counter()
        for _ in range(args.iterations):
            results = algo.train()
        wall = time.perf_counter() - start
        sampled = steps(results) - start_steps
        timers = results.get(TIMERS, {})
        return {
            "runners": runners,
            "envs_per_runner": config.num_envs_per_env_runner,
            "train_batch_size": config.train_batch_size_per_learner,
            "env_steps": sampled,
            "wall_s": wall,
            "env_steps_per_s": sampled / wall,
            # RLlib's timers: per iteration, smoothed over the run (moving averages).
            "sampling_s": float(timers.get(ENV_RUNNER_SAMPLING_TIMER, float("nan"))),
            "learning_s": float(timers.get(LEARNER_UPDATE_TIMER, float("nan"))),
        }
    finally:
        algo.stop()


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    import ray
    import torch

    if args.learner_threads:
        torch.set_num_threads(args.learner_threads)
    cpus = args.num_cpus or max(1, *args.runners)
    ray.init(address="local", num_cpus=cpus, include_dashboard=False, log_to_driver=False)
    runs: list[dict[str, Any]] = []
    try:
        for repeat in range(args.repeats):
            for runners in args.runners:
                run = measure(args, runners)
                run["repeat"] = repeat
                runs.append(run)
                print(
                    f"repeat {repeat} runners {runners}: {run['env_steps_per_s']:8.0f} env steps/s"
                    f" ({run['env_steps']} steps in {run['wall_s']:.2f} s; per iteration"
                    f" sampling {run['sampling_s']:.2f} s, learning {run['learning_s']:.2f} s)",
                    flush=True,
                )
    finally:
        ray.shutdown()
    best = {
        r: max((x for x in runs if x["runners"] == r), key=lambda x: x["env_steps_per_s"])
        for r in args.runners
    }
    base = best[args.runners[0]]["env_steps_per_s"]
    print(f"\n{args.env}, best of {args.repeats}, {cpus} CPUs:")
    for r, run in best.items():
        speedup = run["env_steps_per_s"] / base
        print(
            f"  {r} env runner(s) x {run['envs_per_runner']} envs, batch "
            f"{run['train_batch_size']}: {run['env_steps_per_s']:8.0f} env steps/s "
            f"(x{speedup:.2f})"
        )
    if args.out is not None:
        report = {
            "env": args.env,
            "num_cpus": cpus,
            "ray_version": ray.__version__,
            "best": list(best.values()),
            "runs": runs,
        }
        args.out.write_text(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
