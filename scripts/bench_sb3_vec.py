"""Developer tool: steps/s of SB3's ``make_vec_env`` (single envs in a DummyVecEnv) against
``bbgym.sb3.make_sb3_vec_env`` (the native vector env), random actions, best of
``--repeats`` runs with the two interleaved (the SB3 table of docs/pages/training.md).

    python scripts/bench_sb3_vec.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from stable_baselines3.common.env_util import make_vec_env

import bbgym  # noqa: F401  (registers the envs)
from bbgym.sb3 import make_sb3_vec_env

CASES = (
    ("BeachballSail-v0", 8, 1000),
    ("BeachballSail-v0", 64, 200),
    ("BeachballThrow-v0", 8, 60),
    ("BeachballThrow-v0", 64, 20),
)
"""(env id, number of envs, vector steps timed)."""


def rate(env, steps: int) -> float:
    """Env steps per second of ``steps`` vector steps with one fixed random action batch."""
    env.reset()
    actions = np.stack([env.action_space.sample() for _ in range(env.num_envs)])
    start = time.perf_counter()
    for _ in range(steps):
        env.step(actions)
    return steps * env.num_envs / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each, the best kept")
    args = parser.parse_args()
    makers = {"make_vec_env": make_vec_env, "bbgym.sb3": make_sb3_vec_env}
    for env_id, n, steps in CASES:
        best = dict.fromkeys(makers, 0.0)
        for _ in range(args.repeats):
            for name, make in makers.items():
                env = make(env_id, n_envs=n, seed=0)
                best[name] = max(best[name], rate(env, steps))
                env.close()
        ratio = best["bbgym.sb3"] / best["make_vec_env"]
        print(
            f"{env_id} {n} envs: "
            + ", ".join(f"{k} {v:.0f}/s" for k, v in best.items())
            + f", ratio {ratio:.1f}"
        )


if __name__ == "__main__":
    main()
