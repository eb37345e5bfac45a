"""Privileged planners: which episodes can be won at all (the ceiling of every baseline).

A planner may read what no policy sees: the true wind (mean and the gust of the moment),
the target, the env's own random stream. It searches candidate actions through the physics
(:func:`~bbgym.agents.throw_solver.solve_throw` in the true wind at the moment of the throw)
and then *verifies* the best ones by stepping a deep copy of the env, which draws the very
gusts the real step would. An episode it wins is winnable for certain; one it loses is
unwinnable as far as its search reaches (a lower bound of the winnable fraction).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import gymnasium as gym
import numpy as np

from bbgym.physics.backend import floats
from bbgym.physics.wind import wind_vector

from .throw_solver import solve_throw


@dataclass
class PlannedEpisode:
    """The planner's episode: whether it won, and its throws' verified outcomes."""

    won: bool
    throws: int
    misses_m: list[float] = field(default_factory=list)


class ThrowPlanner:
    """The privileged throw planner as a policy for ``bbgym evaluate --policies planner``:
    ``planner(obs)`` ignores ``obs`` and plans the next throw from the env's state (see
    :func:`plan_throw`). Built for one env (it reads and copies that env)."""

    name = "planner"

    def __init__(self, env: gym.Env, refine: int = 3, candidates: int = 6) -> None:
        self.env, self.refine, self.candidates = env, refine, candidates

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        return plan_throw(self.env, self.refine, self.candidates)[0]


def plan_throw(env: gym.Env, refine: int = 3, candidates: int = 6) -> tuple[np.ndarray, bool]:
    """The next throw of BeachballThrow/Curve with full knowledge, and whether it hits:
    solve it in the true wind of this moment (solver seeds ``0 .. candidates-1`` give
    different throws), step a deep copy of the env with each (the same random stream, so
    the same gusts in flight) and return the first that hits, else the one that missed
    least."""
    base = env.unwrapped
    state = base.state
    scenario = state.scenario
    wind_x, wind_y, _, _ = wind_vector(
        scenario.wind_speed, scenario.wind_from, state.gust, floats
    )  # the air's velocity now, gust included
    target = (float(scenario.target_x), float(scenario.target_y))
    best_action, best_miss = None, math.inf
    for k in range(candidates):
        action = solve_throw(
            task=base.task, target=target, wind=(float(wind_x), float(wind_y)),
            screen=bool(scenario.screen), refine=refine, seed=k,
        ).action  # fmt: skip
        trial = copy.deepcopy(env)
        _, _, _, _, info = trial.step(action)
        trial.close()
        if info["is_success"]:
            return action, True
        if float(info["miss_distance"]) < best_miss:
            best_action, best_miss = action, float(info["miss_distance"])
    return best_action, False


def plan_throw_episode(
    env: gym.Env, seed: int, refine: int = 3, candidates: int = 6
) -> PlannedEpisode:
    """One episode from ``reset(seed=seed)`` played by :func:`plan_throw`."""
    env.reset(seed=seed)
    misses: list[float] = []
    done, info = False, {}
    while not done:
        action, _ = plan_throw(env, refine, candidates)
        _, _, terminated, truncated, info = env.step(action)
        misses.append(float(info["miss_distance"]))
        done = terminated or truncated
    return PlannedEpisode(won=bool(info["is_success"]), throws=len(misses), misses_m=misses)


def winnable_fraction(env_id: str, episodes: int, seed: int = 0, **kwargs) -> dict:
    """The planner over ``episodes`` seeded episodes (``seed .. seed+episodes-1``): the
    fraction won, and the seeds it lost."""
    env = gym.make(env_id)
    results = [plan_throw_episode(env, seed + k, **kwargs) for k in range(episodes)]
    env.close()
    lost = [seed + k for k, r in enumerate(results) if not r.won]
    return {
        "env": env_id,
        "episodes": episodes,
        "seeds": [seed, seed + episodes - 1],
        "winnable": 1.0 - len(lost) / episodes,
        "lost_seeds": lost,
        "mean_throws": float(np.mean([r.throws for r in results])),
    }
