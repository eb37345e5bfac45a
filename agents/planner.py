"""Privileged planners: which episodes can be won at all (the ceiling of every baseline).

A planner may read what no policy sees: the true wind (mean and the gust of the moment),
the target, the env's state and its own random stream. An episode it wins is winnable for
certain; one it loses is unwinnable as far as its search reaches, so its success rate is a
lower bound of the winnable fraction.

- Throw and Curve (:class:`ThrowPlanner`): each throw is solved in the true wind of that
  moment (:func:`~bbgym.agents.throw_solver.solve_throw`) and the candidates are
  *verified* by stepping a deep copy of the env, which draws the very gusts the real step
  would.
- Topple (:class:`TopplePlanner`): a beam search over the episode's remaining steps (wait,
  or one of a grid of throws), each step of every branch a batched transition of the
  task's own functional core on NumPy, fed the noise the env's stream will give it: the
  gusts the real steps will meet. The plan it finds is then played on the real env.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import gymnasium as gym
import numpy as np

from bbgym.envs.functional import tree_map
from bbgym.envs.topple import ToppleTask
from bbgym.physics.namespace import floats
from bbgym.physics.wall import FALLEN_AWAY, FALLEN_TOWARD, LOOSE
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
            task=base.task,
            target=target,
            wind=(float(wind_x), float(wind_y)),
            screen=bool(scenario.screen),
            refine=refine,
            seed=k,
        ).action
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


# -- Topple: beam search through the functional core ----------------------------------------
TOPPLE_SPEEDS_MPS = (12.0, 14.0, 16.0, 18.0)
TOPPLE_ELEVATIONS_DEG = tuple(range(0, 55, 5))
TOPPLE_AZIMUTHS_RAD = tuple(float(a) for a in np.linspace(-0.3, 0.3, 11))
TOPPLE_BACKSPIN = (0.0, 1.0)
"""The throws the Topple planner tries (as fractions of ``max_spin``: none, or full
backspin, whose Magnus lift hits the face higher); a wait is always a candidate too."""
RATE_HORIZON_S = 0.3
"""A standing branch's score is its lean ``rate_horizon`` seconds ahead at its present
rate: how far it is on its way over."""


def topple_candidates(task: object) -> np.ndarray:
    """``(1 + n, 6)`` actions: a wait (row 0), then every speed x elevation x azimuth x
    backspin of the grid, aimed along +x (at the wall) and spun about the horizontal axis
    across the throw."""
    rows = [np.zeros(6)]
    for speed in TOPPLE_SPEEDS_MPS:
        for elevation in np.radians(TOPPLE_ELEVATIONS_DEG):
            for azimuth in TOPPLE_AZIMUTHS_RAD:
                for spin in TOPPLE_BACKSPIN:
                    v = speed * np.array(
                        [
                            np.cos(elevation) * np.cos(azimuth),
                            np.cos(elevation) * np.sin(azimuth),
                            np.sin(elevation),
                        ]
                    )
                    # Backspin of a ball flying +x turns about -y (its Magnus force, w x v, up).
                    w = (spin * np.sin(azimuth), -spin * np.cos(azimuth), 0.0)
                    rows.append(np.concatenate([v / task.max_speed, w]))
    return np.array(rows)


def _batch(state: object, n: int) -> object:
    """A single env's state (Python floats, ints, bools) as a batch of ``n`` equal rows."""

    def rows(leaf: object) -> np.ndarray:
        value = np.asarray(leaf)
        return np.full(n, value.item(), dtype=value.dtype if value.dtype != object else float)

    return tree_map(rows, state)


def _rows(state: object, index: np.ndarray) -> object:
    return tree_map(lambda leaf: np.asarray(leaf)[index], state)


@dataclass
class TopplePlan:
    """A planned rest of a Topple episode: its actions, and whether the core says they win."""

    actions: list[np.ndarray]
    wins: bool


def plan_topple(env: gym.Env, beam: int = 6) -> TopplePlan:
    """Search the rest of a BeachballTopple episode from the env's state.

    Depth by depth (one per step left), every branch of the beam tries every candidate of
    :func:`topple_candidates` in one batched NumPy transition of the task core, each
    branch fed the noise pairs the env's stream holds after the pairs its earlier steps
    used (peeked from a copy of the stream: the env itself is not touched). The first
    branch whose wall falls away or breaks loose is the plan. Otherwise the beam keeps the
    branch that only waited (a later gust may serve) and the ``beam - 1`` best others by
    lean ``RATE_HORIZON_S`` ahead; walls fallen toward the thrower are dropped. When
    nothing wins, the plan is the best branch's."""
    base = env.unwrapped
    task = base.task
    pairs = task.step_noise_pairs
    steps = int(base.state.throws_left)
    stream = copy.deepcopy(base.streams).peek(np.ones(1, dtype=bool), pairs * steps)
    flat = stream[..., 0].reshape(-1)  # pair k: entries 2k, 2k + 1 (as the env reads it)
    candidates = topple_candidates(task)
    n = len(candidates)
    states, used, plans = _batch(base.state, 1), np.zeros(1, dtype=np.int64), [[]]
    best: list[np.ndarray] = [candidates[0]]
    for _ in range(steps):
        width = len(plans)
        tried = tree_map(lambda leaf: np.repeat(leaf, n), states)
        offset = np.repeat(used, n)
        window = tuple(flat[np.minimum(2 * offset + r, flat.size - 1)] for r in range(2 * pairs))
        new, events = task.transition(tried, np.tile(candidates, (width, 1)), window, np)
        status = new.wall.status
        won = np.flatnonzero((status == FALLEN_AWAY) | (status == LOOSE))
        if won.size:
            j = int(won[0])
            return TopplePlan([*plans[j // n], candidates[j % n]], True)
        score = np.where(
            status == FALLEN_TOWARD, -np.inf, new.wall.angle + RATE_HORIZON_S * new.wall.rate
        )
        # Row 0 is branch 0 waiting again: branch 0 is the one that has only waited, for
        # as long as that branch stands.
        keep = [0] if np.isfinite(score[0]) else []
        keep += [int(i) for i in np.argsort(-score) if np.isfinite(score[i]) and i != 0]
        keep = np.array(keep[:beam], dtype=np.int64)
        if keep.size == 0:
            break
        plans = [[*plans[i // n], candidates[i % n]] for i in keep]
        top = int(keep[np.argmax(score[keep])])
        best = [*plans[list(keep).index(top)]]
        states = _rows(new, keep)
        used = offset[keep] + np.asarray(events.noise_used)[keep]
    return TopplePlan(best, False)


class TopplePlanner:
    """The privileged Topple planner as a policy (``bbgym evaluate --policies planner``):
    ``planner(obs)`` ignores ``obs``, plans the rest of the episode from the env's state
    (:func:`plan_topple`) and plays that plan; it plans again when the env is not where
    the plan expects (a new episode)."""

    name = "planner"

    def __init__(self, env: gym.Env, beam: int = 6) -> None:
        self.env, self.beam = env, beam
        self._plan: list[np.ndarray] = []
        self._at = -1  # throws_left when the plan's next action is due

    def reset(self) -> None:
        self._plan, self._at = [], -1

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        throws_left = int(self.env.unwrapped.state.throws_left)
        if not self._plan or throws_left != self._at:
            self._plan = list(plan_topple(self.env, self.beam).actions)
            self._at = throws_left
        self._at -= 1
        return self._plan.pop(0).astype(np.float32)


def plan_topple_episode(env: gym.Env, seed: int, beam: int = 6) -> PlannedEpisode:
    """One Topple episode from ``reset(seed=seed)``: plan once, play the plan on the env
    (what counts is what the env then does)."""
    env.reset(seed=seed)
    plan = plan_topple(env, beam)
    info: dict = {}
    for action in plan.actions:
        _, _, terminated, truncated, info = env.step(action.astype(np.float32))
        if terminated or truncated:
            break
    return PlannedEpisode(won=bool(info["is_success"]), throws=int(info["throws"]))


def winnable_fraction(env_id: str, episodes: int, seed: int = 0, **kwargs) -> dict:
    """The planner over ``episodes`` seeded episodes (``seed .. seed+episodes-1``): the
    fraction won, and the seeds it lost. ``kwargs``: the planner's (``refine``,
    ``candidates`` for the throw envs; ``beam`` for Topple)."""
    env = gym.make(env_id)
    topple = isinstance(env.unwrapped.task, ToppleTask)
    play = plan_topple_episode if topple else plan_throw_episode
    results = [play(env, seed + k, **kwargs) for k in range(episodes)]
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
