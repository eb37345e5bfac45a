"""How close Topple's interval comes to a fine integration: v1's substeps of 0.01 s and
v2's RK4 steps of 0.05 s (``interval_integrator="rk4_events"``) against v1's substeps at
0.001 s, over one throw per env at walls 3-5 m away in a gusty onshore breeze (NumPy).

    python scripts/topple_accuracy.py [--envs 512] [--seeds 0 1 2]

Prints, per scheme, the p95 of each throw's largest difference of the wall's lean over
the 3 s (sampled every 0.05 s), the share of walls ending in the reference's state and
of throws hitting as in it, the p95 of the hit's height difference and of the ball's
position over its first 0.6 s, and the time of the interval (NumPy, one run).
``tests/topple/test_topple_events.py`` asserts these bounds on 128 envs."""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from bbgym.envs.functional import InitialNoise
from bbgym.envs.topple.task import ToppleTask

V2 = {"interval_integrator": "rk4_events", "sim_dt": 0.05}
"""Topple-v2's interval (its other kwargs are v1's)."""
SCHEMES = {
    "v1: Euler substeps of 0.01 s": {},
    "v2: RK4 steps of 0.05 s, events located": V2,
    "Euler substeps of 0.05 s": {"sim_dt": 0.05},
}
REFERENCE = {"sim_dt": 0.001}


def accuracy_run(n: int = 128, seed: int = 0, **kwargs) -> dict:
    """One throw per env at walls 3-5 m away in an onshore breeze with gusts: the wall's
    lean every 0.05 s, the ball's position, and the outcome."""
    rng = np.random.default_rng(seed)
    uniform = [rng.uniform(0, 1, n) for _ in range(3)]
    normal = [rng.standard_normal(n) for _ in range(2)]
    stream = [rng.standard_normal(n) for _ in range(2)]
    action = np.zeros((n, 6))
    action[:, 0] = rng.uniform(0.15, 0.7, n)
    action[:, 1] = rng.uniform(-0.04, 0.04, n)
    action[:, 2] = rng.uniform(-0.1, 0.6, n)
    action[:, 3:] = rng.uniform(-0.3, 0.3, (n, 3))
    task = ToppleTask(
        wall_distance_range=(3.0, 5.0), wind_from_range=(0.5 * math.pi, 1.5 * math.pi), **kwargs
    )
    noise = np.array([rng.standard_normal(n) for _ in range(2 * task.step_noise_pairs)])
    state = task.initial(InitialNoise(uniform, normal, stream), {}, np)
    state, events = task.transition(state, action, noise, np, record=True)
    rows = events.taken[:: task.record_every]
    return {
        "lean": np.array([row[7] for row in rows]),
        "ball": np.array([(row[0], row[2]) for row in rows]),
        "status": state.wall.status,
        "hit": state.hits > 0,
        "hit_height": state.hit_height,
    }


def errors_against(reference: dict, run: dict) -> dict:
    both = run["hit"] & reference["hit"]
    flight = np.hypot(*(run["ball"][:12] - reference["ball"][:12]).transpose(1, 0, 2))
    return {
        "lean": np.quantile(np.abs(run["lean"] - reference["lean"]).max(axis=0), 0.95),
        "status": np.mean(run["status"] == reference["status"]),
        "hit": np.mean(run["hit"] == reference["hit"]),
        "hit_height": np.quantile(np.abs(run["hit_height"] - reference["hit_height"])[both], 0.95),
        "flight": np.quantile(flight, 0.95),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--envs", type=int, default=512, help="throws per seed (default: 512)")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    args = parser.parse_args()
    for seed in args.seeds:
        reference = accuracy_run(args.envs, seed, **REFERENCE)
        print(
            f"seed {seed}, {args.envs} throws, {reference['hit'].mean():.0%} hit the wall, "
            f"{np.mean(reference['status'] != 0):.0%} brought it down"
        )
        for name, kwargs in SCHEMES.items():
            start = time.perf_counter()
            run = accuracy_run(args.envs, seed, **kwargs)
            seconds = time.perf_counter() - start
            e = errors_against(reference, run)
            print(
                f"  {name:42s} lean {e['lean']:.4f} rad, state {e['status']:.3f}, "
                f"hit {e['hit']:.3f}, hit height {e['hit_height']:.4f} m, "
                f"ball {e['flight']:.4f} m ({seconds:.2f} s)"
            )


if __name__ == "__main__":
    main()
