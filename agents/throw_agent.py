"""Scripted throwers for BeachballThrow-v0 / BeachballCurve-v0 and BeachballTopple-v0.

Both aim by simulating candidate throws with the env's own physics (a documented part of
the env: its ``task``), under the wind their windsock shows; they see nothing else.
"""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np

from bbgym.envs.throw.task import DISTANCE_SCALE_M, WIND_SCALE_MPS, ThrowTask

from .throw_solver import solve_throw, solve_throw_robust

SCREEN_DROP_M = 1.5
"""A landing short of this far past the screen (along the line to the target) counts as
stopped by it."""


class ThrowSolverAgent:
    """``agent(obs) -> action`` for the throw envs (one obs ``(19,)`` or a batch).

    Each throw is solved by :func:`agents.throw_solver.solve_throw` for the target, in the
    wind the windsock reads (noisy, and gusts change it between throws). After a miss the
    agent aims its next throw off the target by minus the miss it saw, which also takes
    out what the windsock got wrong. With a screen in the way it throws the curve with the
    most room to spare (:func:`~agents.throw_solver.solve_throw_robust`, over winds within
    the windsock's noise and the gusts' spread of the reading), and a throw stopped by the
    screen teaches it nothing about the wind: the next one aims at the target again.
    """

    def __init__(self, task: ThrowTask, refine: int = 2) -> None:
        self.task = task
        self.refine = refine
        self._aims: np.ndarray | None = None

    def reset(self) -> None:
        self._aims = None

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        o = np.atleast_2d(np.asarray(obs, dtype=np.float64))
        if self._aims is None or self._aims.shape[0] != o.shape[0]:
            self._aims = np.full((o.shape[0], 2), np.nan)
        actions = np.zeros((o.shape[0], 6), dtype=np.float32)
        for i, row in enumerate(o):
            target = row[0:2] * DISTANCE_SCALE_M
            sock = row[2:4] * WIND_SCALE_MPS
            miss = row[4:6] * DISTANCE_SCALE_M  # last landing minus target
            thrown = row[7] > 0.5
            screen = bool(row[14] > 0.5)
            if screen and thrown:
                # Stopped by the screen, the ball dropped at its foot or bounced back: along
                # the line to the target, it landed short of just past the screen.
                line = target / np.hypot(*target)
                landing = target + miss
                centre = row[15:17] * DISTANCE_SCALE_M
                thrown = float(landing @ line) > float(centre @ line) + SCREEN_DROP_M
            aim = self._aims[i] - miss if thrown and np.isfinite(self._aims[i]).all() else target
            self._aims[i] = aim
            if screen:
                wind_std = self.task.windsock_noise + self.task.gust_params.speed_std * np.hypot(
                    *sock
                )
                solution = solve_throw_robust(
                    self.task, tuple(aim), tuple(sock), wind_std, screen=True, refine=self.refine
                )
            else:
                solution = solve_throw(self.task, tuple(aim), tuple(sock), refine=self.refine)
            actions[i] = solution.action
        return actions[0] if np.ndim(obs) == 1 else actions


class ToppleAgent:
    """``agent(obs) -> action`` for BeachballTopple-v0 (one obs ``(19,)``; batches row by
    row).

    It finds the throw that rocks the wall hardest by trying candidates (speed x
    elevation, straight at the wall) in a copy of the env in the wind its windsock reads,
    then throws it when the wind helps (a tailwind, pushing the wall away) or when only two
    throws are left; otherwise it waits. A wall already rocking away is hit again at once.
    """

    SPEEDS = (12.0, 14.0, 16.0, 18.0)
    ELEVATIONS_DEG = (5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0)

    def __init__(self, env_kwargs: dict | None = None) -> None:
        self.env_kwargs = dict(env_kwargs or {})
        n = len(self.SPEEDS) * len(self.ELEVATIONS_DEG)
        self._trial = gym.make_vec(
            "BeachballTopple-v0",
            num_envs=n,
            vectorization_mode="vector_entry_point",
            **self.env_kwargs,
        )
        grid = [(s, math.radians(e)) for s in self.SPEEDS for e in self.ELEVATIONS_DEG]
        v = np.array([(s * math.cos(e), 0.0, s * math.sin(e)) for s, e in grid])
        task = self._trial.unwrapped.task
        self._candidates = np.concatenate([v / task.max_speed, np.zeros((n, 3))], axis=1)
        self._cache: dict[tuple, np.ndarray] = {}

    def reset(self) -> None:
        self._cache.clear()

    def best_throw(self, distance: float, wind_x: float) -> np.ndarray:
        """The candidate that leans the wall farthest away, in a steady wind along x."""
        key = (round(distance, 2), round(wind_x, 1))
        if key not in self._cache:
            self._trial.reset(
                seed=0, options={"wall_distance": distance, "wind": (wind_x, 0.0), "gusts": False}
            )
            _, _, _, _, info = self._trial.step(self._candidates.astype(np.float32))
            reach = [
                np.max(samples)
                if state == "standing"
                else (10.0 if state != "fallen_toward" else -10.0)
                for samples, state in zip(
                    info["wall_angle_samples"], info["wall_state"], strict=True
                )
            ]
            self._cache[key] = self._candidates[int(np.argmax(reach))].astype(np.float32)
        return self._cache[key]

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        o = np.atleast_2d(np.asarray(obs, dtype=np.float64))
        actions = np.zeros((o.shape[0], 6), dtype=np.float32)
        for i, row in enumerate(o):
            lean, rate, distance = row[0], row[1], row[2] * 10.0
            wind_x = row[5] * 10.0
            throws_left = row[7] * self._trial.unwrapped.task.throws_per_episode
            tailwind = wind_x > 0.5
            if tailwind or throws_left <= 2.5 or (lean > 0.0 and rate > 0.0):
                actions[i] = self.best_throw(distance, max(wind_x, 0.0))
        return actions[0] if np.ndim(obs) == 1 else actions

    def close(self) -> None:
        self._trial.close()
