"""Benchmark env steps per second of the bbgym envs against Gymnasium's CartPole.

    python scripts/bench.py [--steps 20000] [--num-envs 1024] [--seconds S] [--json PATH]

Measures, in one run, CartPole-v1 and each bbgym env as single envs with random actions
(resetting at episode end), then CartPole-v1's native vector env and each bbgym env's
native vector env with ``--num-envs`` sub-envs. Actions are sampled before timing. Each
measurement is warmed up, repeated ``--repeats`` times, and the best is kept. Vector rates
count env-steps (``num_envs`` per vector step). A step of the throw envs is one throw,
flown until the ball rests (hundreds of physics substeps), so the loops are time-capped.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the envs)

BBGYM_ENVS = ("BeachballSail-v0", "BeachballThrow-v0", "BeachballCurve-v0", "BeachballTopple-v0")


def time_single(env_id: str, steps: int, seconds: float | None, seed: int) -> float:
    """Env-steps per second of one env; ``seconds`` caps the timed loop."""
    env = gym.make(env_id)
    env.action_space.seed(seed)
    actions = [env.action_space.sample() for _ in range(steps)]
    env.reset(seed=seed)
    for action in actions[: min(200, steps)]:  # warm-up
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    env.reset(seed=seed)
    done_steps = 0
    start = time.perf_counter()
    deadline = start + seconds if seconds else None
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        done_steps += 1
        if terminated or truncated:
            env.reset()
        if deadline is not None and done_steps % 256 == 0 and time.perf_counter() > deadline:
            break
    elapsed = time.perf_counter() - start
    env.close()
    return done_steps / elapsed


def make_vector(env_id: str, num_envs: int) -> gym.vector.VectorEnv:
    return gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")


def time_vector(env_id: str, num_envs: int, steps: int, seconds: float | None, seed: int) -> float:
    """Env-steps per second (``num_envs`` per vector step) of a native vector env."""
    env = make_vector(env_id, num_envs)
    env.action_space.seed(seed)
    vector_steps = max(1, steps // num_envs)
    actions = [env.action_space.sample() for _ in range(vector_steps)]
    env.reset(seed=seed)
    for action in actions[: min(2, vector_steps)]:  # warm-up; autoreset is built in
        env.step(action)
    done_steps = 0
    start = time.perf_counter()
    deadline = start + seconds if seconds else None
    for action in actions:
        env.step(action)
        done_steps += 1
        if deadline is not None and time.perf_counter() > deadline:
            break
    elapsed = time.perf_counter() - start
    env.close()
    return done_steps * num_envs / elapsed


def machine_info() -> dict[str, Any]:
    return {
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "cpu_count": os.cpu_count(),
        "numpy": np.__version__,
        "gymnasium": gym.__version__,
    }


def format_table(results: list[dict[str, Any]]) -> str:
    lines = ["| env | kind | steps/s | ratio to CartPole |", "|---|---|---:|---:|"]
    for r in results:
        lines.append(
            f"| {r['env']} | {r['kind']} | {r['steps_per_s']:,.0f} | {r['ratio_to_cartpole']:.3f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--steps", type=int, default=20000, help="env-steps per measurement (single and vector)"
    )
    parser.add_argument("--vector-steps", type=int, default=None, help="env-steps for vector runs")
    parser.add_argument("--num-envs", type=int, default=1024, help="sub-envs of vector runs")
    parser.add_argument(
        "--seconds",
        type=float,
        default=5.0,
        help="cap each timed loop at this many seconds (0: no cap)",
    )
    parser.add_argument("--repeats", type=int, default=3, help="repeats; the best is kept")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", type=Path, default=None, help="write results to this path")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.num_envs < 1 or args.repeats < 1:
        parser.error("--steps, --num-envs and --repeats must be >= 1")
    if args.seconds is not None and args.seconds < 0:
        parser.error("--seconds must be >= 0")
    vector_steps = args.vector_steps or max(args.steps, 200 * args.num_envs)

    def best(fn, *fn_args) -> float:
        return max(fn(*fn_args) for _ in range(args.repeats))

    t0 = time.perf_counter()
    n = args.num_envs
    cart_single = best(time_single, "CartPole-v1", args.steps, args.seconds, args.seed)
    results = [{"env": "CartPole-v1", "kind": "single", "steps_per_s": cart_single}]
    for env_id in BBGYM_ENVS:
        rate = best(time_single, env_id, args.steps, args.seconds, args.seed)
        results.append({"env": env_id, "kind": "single", "steps_per_s": rate})
    cart_vector = best(time_vector, "CartPole-v1", n, vector_steps, args.seconds, args.seed)
    results.append({"env": "CartPole-v1", "kind": f"vector x{n}", "steps_per_s": cart_vector})
    for env_id in BBGYM_ENVS:
        rate = best(time_vector, env_id, n, vector_steps, args.seconds, args.seed)
        results.append({"env": env_id, "kind": f"vector x{n}", "steps_per_s": rate})
    total = time.perf_counter() - t0
    for r in results:
        reference = cart_single if r["kind"] == "single" else cart_vector
        r["ratio_to_cartpole"] = r["steps_per_s"] / reference

    info = machine_info()
    print(format_table(results))
    print()
    print(
        f"machine: {info['platform']}, {info['cpu_count']} CPUs, python {info['python']}, "
        f"numpy {info['numpy']}, gymnasium {info['gymnasium']}"
    )
    print(
        f"settings: {args.steps} steps single, {vector_steps} env-steps vector "
        f"({vector_steps // n} vector steps x {n} envs), best of {args.repeats}, "
        f"timed loops capped at {args.seconds or 'no'} s; total {total:.1f} s"
    )
    if args.json is not None:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        payload = {
            "results": results,
            "machine": info,
            "settings": {
                "steps": args.steps,
                "vector_steps": vector_steps,
                "num_envs": n,
                "repeats": args.repeats,
                "seconds": args.seconds,
            },
        }
        args.json.write_text(json.dumps(payload, indent=2) + "\n")
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
