"""BeachballRace seen by one boat: a Gymnasium env in which ``boat_0`` learns and the other
boats are scripted racers (:class:`bbgym.agents.RaceRacer`), for single-agent learners
such as stable-baselines3."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np

from bbgym.envs.race.parallel import BeachballRaceEnv
from bbgym.envs.race.spec import SPEC

LEARNER = "boat_0"
SOLO_ENV_ID = SPEC.one_agent_env_id
"""Its Gymnasium id (``gym.make(SOLO_ENV_ID)`` after ``import bbgym``, which registers it
without importing PettingZoo: :mod:`bbgym.envs`); no time limit of Gymnasium's, the race's
own ``max_race_time_s`` truncates it."""


class BeachballRaceSoloEnv(gym.Env):
    """One boat (``boat_0``) racing a fleet of scripted racers (:class:`bbgym.agents.RaceRacer`)
    in a :class:`~bbgym.envs.race.parallel.BeachballRaceEnv`: a Gymnasium ``Env`` for
    single-agent learners.

    Its action, observation and reward are ``boat_0``'s (the race env's tables); the
    others sail by the racer. The episode terminates when ``boat_0`` finishes or capsizes
    and is truncated when the race's time is up; the infos are ``boat_0``'s (``is_success``:
    finished), with ``won`` (finished first). Every keyword argument but
    ``render_mode`` goes to the race env (``num_boats`` 4 by default: three opponents).
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 4}

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        from bbgym.agents import RaceRacer

        self.race = BeachballRaceEnv(render_mode=render_mode, **kwargs)
        self.render_mode = render_mode
        self.racer = RaceRacer.for_env(self.race)
        self.action_space = self.race.action_space(LEARNER)
        self.observation_space = self.race.observation_space(LEARNER)
        self._observations: dict[str, np.ndarray] = {}

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple:
        super().reset(seed=seed)
        self._observations, infos = self.race.reset(seed=seed, options=options)
        self.racer.reset()
        return self._observations[LEARNER], self._info(infos[LEARNER])

    def step(self, action: Any) -> tuple:
        others = [a for a in self.race.agents if a != LEARNER]
        actions = self.racer.actions(self._observations, others) if others else {}
        actions[LEARNER] = action
        observations, rewards, terminations, truncations, infos = self.race.step(actions)
        self._observations = observations
        info = self._info(infos[LEARNER])
        if terminations[LEARNER] or truncations[LEARNER]:
            self._observations = {}
        return (
            observations[LEARNER],
            rewards[LEARNER],
            terminations[LEARNER],
            truncations[LEARNER],
            info,
        )

    def _info(self, info: dict[str, Any]) -> dict[str, Any]:
        return info | {"won": info["place"] == 1}

    def render(self) -> np.ndarray | None:
        return self.race.render()

    def close(self) -> None:
        self.race.close()
