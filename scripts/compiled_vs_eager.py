"""Developer tool: does the installed torch compile the step right? For each env and way of
compiling it (``step_graph``), the largest difference between the compiled and the eager
torch backend over the same episode (float64, observations, rewards, terminations and
truncations), and the first step's time.

    python scripts/compiled_vs_eager.py [--envs BeachballSail-v1 ...] [--graphs parts one]
        [--steps 40] [--num-envs 16]

Run it under a torch other than the one the project pins (a GPU machine's own, say) before
timing anything there: a compiler bug shows here as an error or a difference far above
float64 rounding (docs/pages/speed-method.md, "The first GPU lease", has what it found under
torch 2.11).
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np
import torch

import bbgym  # noqa: F401  (registers the envs)


def episode(env_id: str, graph: str, compile: bool, steps: int, num_envs: int) -> list:
    """Reset (seed 3) and ``steps`` seeded random actions: every output, as NumPy."""
    env = gym.make_vec(
        env_id,
        num_envs=num_envs,
        vectorization_mode="vector_entry_point",
        backend="torch",
        dtype="float64",
        compile=compile,
        step_graph=graph,
    )
    env.action_space.seed(1)
    out = [env.reset(seed=3)[0]]
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        out += [obs, reward, terminated, truncated]
    env.close()
    return [np.asarray(x, dtype=np.float64) for x in out]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--envs", nargs="+", default=["BeachballSail-v1", "BeachballThrow-v1"])
    parser.add_argument("--graphs", nargs="+", choices=("parts", "one"), default=["parts", "one"])
    parser.add_argument("--steps", type=int, default=12)
    parser.add_argument("--num-envs", type=int, default=16)
    args = parser.parse_args()
    torch.set_num_threads(1)
    print(f"torch {torch.__version__}")
    for env_id in args.envs:
        for graph in args.graphs:
            eager = episode(env_id, graph, False, args.steps, args.num_envs)
            start = time.perf_counter()
            compiled = episode(env_id, graph, True, args.steps, args.num_envs)
            diff = max(float(np.max(np.abs(a - b))) for a, b in zip(eager, compiled, strict=True))
            took = time.perf_counter() - start
            print(
                f"{env_id} {graph}: max |compiled - eager| {diff:.1e} over {args.steps} "
                f"steps ({took:.0f} s with the compile)",
                flush=True,
            )


if __name__ == "__main__":
    main()
