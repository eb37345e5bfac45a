"""Aim a beach-ball throw by simulating candidates with the physics core.

:func:`solve_throw` searches launch speed, elevation, aim off the target's bearing, side
spin and backspin: a coarse grid flown as one batch, then random refinement around the
best candidates. It is what a careful thrower does: "if I throw like this, with this wind,
where does it land?".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import product

import numpy as np

from bbgym.envs.throw.task import ThrowScenario, ThrowTask
from bbgym.physics.wind import GustState


@dataclass
class Solution:
    action: np.ndarray
    """The env action (6,) in [-1, 1]."""
    predicted_miss_m: float
    """Miss distance of that throw in the simulated (gust-free) wind."""


def _actions(
    task: ThrowTask, bearing: float, speed, elevation, aim, side_spin, back_spin
) -> np.ndarray:
    """Env actions from throw parameters (arrays of equal length)."""
    heading = bearing + aim
    cos_el = np.cos(elevation)
    velocity = np.stack(
        [
            speed * cos_el * np.cos(heading),
            speed * cos_el * np.sin(heading),
            speed * np.sin(elevation),
        ],
        axis=1,
    )
    # Backspin turns about the horizontal axis to the right of the throw: -left.
    left_x, left_y = -np.sin(heading), np.cos(heading)
    spin = np.stack([-back_spin * left_x, -back_spin * left_y, side_spin], axis=1)
    return np.concatenate([velocity / task.max_speed, spin / task.max_spin], axis=1)


def _miss(task: ThrowTask, actions: np.ndarray, target, wind, screen: bool) -> np.ndarray:
    n = actions.shape[0]
    speed, wind_from = math.hypot(*wind), math.atan2(-wind[1], -wind[0])
    scenario = ThrowScenario(
        target_x=np.full(n, float(target[0])),
        target_y=np.full(n, float(target[1])),
        wind_speed=np.full(n, speed),
        wind_from=np.full(n, wind_from),
        gusts=np.zeros(n, dtype=bool),
        screen=np.full(n, screen),
    )
    calm = GustState(*(np.zeros(n) for _ in range(4)))
    velocity, spin = task.launch(actions)
    result, _, _ = task.throw(velocity, spin, scenario, calm)
    miss, _, _ = task.score(result, scenario)
    return miss


def solve_throw(
    task: ThrowTask,
    target: tuple[float, float],
    wind: tuple[float, float] = (0.0, 0.0),
    screen: bool = False,
    use_spin: bool = True,
    refine: int = 3,
    seed: int = 0,
) -> Solution:
    """Best throw found at ``target`` in a steady ``wind`` (m/s, where the air moves)."""
    bearing, params, miss = _search(task, target, wind, screen, use_spin, refine, seed)
    i = int(np.argmin(miss))
    action = np.clip(_actions(task, bearing, *params[i : i + 1].T)[0], -1.0, 1.0)
    return Solution(action=action.astype(np.float32), predicted_miss_m=float(miss[i]))


def solve_throw_robust(
    task: ThrowTask,
    target: tuple[float, float],
    wind: tuple[float, float],
    wind_std: float,
    screen: bool = False,
    refine: int = 3,
    seed: int = 0,
    shortlist: int = 128,
    winds: int = 24,
) -> Solution:
    """The throw most likely to land in the ring when the wind is only known to within
    ``wind_std`` (m/s per component, e.g. a noisy windsock in gusts): the ``shortlist``
    best throws for the estimate ``wind`` (:func:`solve_throw`'s search) are flown again
    in ``winds`` winds drawn around it, and the one that lands inside the ring in most of
    them wins (ties: the smaller mean miss). A throw curved close past a screen's edge is
    the best for the estimate and the first to hit the screen when the wind is a little
    off; this picks the one with room to spare. ``predicted_miss_m``: its mean miss."""
    bearing, params, miss = _search(task, target, wind, screen, True, refine, seed, keep_all=True)
    # Half the shortlist bends the ball left, half right: which way round a screen has the
    # more room depends on the wind.
    left = params[:, 3] > 0.0
    rows = np.concatenate(
        [params[side][np.argsort(miss[side])[: shortlist // 2]] for side in (left, ~left)]
    )
    rng = np.random.default_rng(seed)
    drawn = np.asarray(wind) + rng.normal(0.0, wind_std, (winds, 2))
    actions = np.clip(_actions(task, bearing, *rows.T), -1.0, 1.0)
    misses = np.stack([_miss(task, actions, target, tuple(w), screen) for w in drawn])
    hits = (misses <= task.target_radius).sum(axis=0)
    i = int(np.lexsort((misses.mean(axis=0), -hits))[0])
    return Solution(
        action=actions[i].astype(np.float32), predicted_miss_m=float(misses[:, i].mean())
    )


def _search(
    task: ThrowTask,
    target: tuple[float, float],
    wind: tuple[float, float],
    screen: bool,
    use_spin: bool,
    refine: int,
    seed: int,
    keep_all: bool = False,
) -> tuple[float, np.ndarray, np.ndarray]:
    """The search of :func:`solve_throw`: ``(bearing, throw parameters, misses)`` of its
    last population, or of every throw it flew (``keep_all``); rows: speed, elevation, aim,
    side spin, backspin."""
    bearing = math.atan2(target[1], target[0])
    spins = np.linspace(-1.0, 1.0, 7) * task.max_spin if use_spin else [0.0]
    backs = (0.0, 0.5 * task.max_spin) if use_spin else (0.0,)
    grid = np.array(
        list(
            product(
                np.linspace(0.4, 1.0, 7) * task.max_speed,
                np.radians(np.linspace(5.0, 75.0, 8)),
                np.radians(np.linspace(-60.0, 60.0, 13)),
                spins,
                backs,
            )
        )
    )
    params = grid
    miss = _miss(task, _actions(task, bearing, *params.T), target, wind, screen)
    flown, flown_miss = [params], [miss]
    rng = np.random.default_rng(seed)
    scale = np.array([1.5, math.radians(6.0), math.radians(6.0), 10.0, 10.0])
    if not use_spin:
        scale[3:] = 0.0
    for _ in range(refine):
        best = params[np.argsort(miss)[:8]]
        trials = np.repeat(best, 60, axis=0) + rng.normal(0.0, 1.0, (480, 5)) * scale
        trials[:, 0] = np.clip(trials[:, 0], 0.0, task.max_speed)
        trials[:, 1] = np.clip(trials[:, 1], 0.0, math.radians(89.0))
        trials[:, 3:] = np.clip(trials[:, 3:], -task.max_spin, task.max_spin)
        trial_miss = _miss(task, _actions(task, bearing, *trials.T), target, wind, screen)
        params = np.concatenate([best, trials])
        miss = np.concatenate([np.sort(miss)[:8], trial_miss])
        flown.append(trials)
        flown_miss.append(trial_miss)
        scale = scale * 0.5
    if keep_all:
        return bearing, np.concatenate(flown), np.concatenate(flown_miss)
    return bearing, params, miss
