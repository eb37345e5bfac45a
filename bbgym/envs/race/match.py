"""Learning boats against scripted racers, many races at once: the fleet
(:class:`~bbgym.envs.race.fleet.BeachballRaceFleetEnv`) with some boats of every race sailed
by :class:`bbgym.agents.RaceRacer`, seen as a Gymnasium ``VectorEnv`` of the learning boats
alone; and the pairings count that scores learned boats against scripted ones."""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv

from bbgym.envs.common import check_box_action, vector_info
from bbgym.envs.race.fleet import BeachballRaceFleetEnv
from bbgym.physics.namespace import replaced


def learner_mask(num_races: int, num_boats: int, learners: int) -> np.ndarray:
    """Which boats learn ``(num_races, num_boats)``: the first ``learners`` of an even race,
    the last of an odd one. Boats start in slots along the line by their number (boat 0 at
    the committee boat's end), so alternating puts the learners at either end equally
    often."""
    mask = np.zeros((num_races, num_boats), dtype=bool)
    mask[0::2, :learners] = True
    mask[1::2, num_boats - learners :] = True
    return mask


class BeachballRaceMatchEnv(VectorEnv):
    """``num_races`` races in which ``learners`` boats of each are the learner's and the
    others sail by :class:`bbgym.agents.RaceRacer`: a Gymnasium ``VectorEnv`` of the
    ``num_races * learners`` learning boats, for a shared policy that races itself and
    scripted boats at once.

    The races, spaces, rewards, ends and autoreset are the fleet's
    (:class:`~bbgym.envs.race.fleet.BeachballRaceFleetEnv`, whose race ``r`` reset with
    ``seed=s`` is the PettingZoo env reset with ``seed=s + r``); :func:`learner_mask` says
    which boats learn. With ``residual=True`` a learning boat's action is added to the
    racer's for it (clipped to [-1, 1]): the policy learns a correction to the scripted
    racer (residual policy learning, Silver et al. 2018; Johannink et al. 2019), so a zero
    action sails as the racer does, and it sees the racer's action: its observation is the
    boat's with the racer's three action columns after it. With ``relative=True`` a learning
    boat's reward is the race's minus the mean of its race's scripted boats' rewards in the
    same step: what the wind and the course give every boat cancels, and what is left says
    how the boat sails against the scripted ones (the score it is judged by); it needs a
    scripted boat in every race. Infos are the learning boats';
    :attr:`fleet` holds every boat's state. :meth:`reset_envs` serves stable-baselines3 through
    :class:`bbgym.sb3.NativeVecEnvAdapter`. Keyword arguments are the fleet's (the race
    env's and the backend's; ``output`` NumPy).
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_races: int = 16,
        learners: int = 2,
        residual: bool = False,
        relative: bool = False,
        **kwargs: Any,
    ) -> None:
        from bbgym.agents import RaceRacer

        self.fleet = BeachballRaceFleetEnv(num_races, **kwargs)
        if self.fleet.backend.output != "numpy":
            raise ValueError(
                "output must be 'numpy' for a match (the scripted racer reads "
                f"NumPy observations), got {self.fleet.backend.output!r}"
            )
        boats = self.fleet.num_boats
        if isinstance(learners, bool) or not isinstance(learners, (int, np.integer)):
            raise TypeError(f"learners must be an int, got {learners!r}")
        if not 1 <= learners <= boats:
            raise ValueError(f"learners must be in [1, num_boats={boats}], got {learners}")
        for name, flag in (("residual", residual), ("relative", relative)):
            if not isinstance(flag, (bool, np.bool_)):
                raise TypeError(f"{name} must be a bool, got {flag!r}")
        if relative and learners == boats:
            raise ValueError(
                f"relative=True needs a scripted boat in each race: learners must "
                f"be below num_boats={boats}, got {learners}"
            )
        self.num_races, self.num_boats = self.fleet.num_races, boats
        self.learners, self.residual = int(learners), bool(residual)
        self.relative = bool(relative)
        self.mask = learner_mask(self.num_races, boats, self.learners)
        self.rows = np.flatnonzero(self.mask.reshape(-1))
        """Each learning boat's row in the fleet (``race * num_boats + boat``)."""
        self.num_envs = len(self.rows)
        self.racer = RaceRacer.for_env(self.fleet)
        size = self.fleet.single_observation_space.shape[0]
        if self.residual:
            size += self.fleet.single_action_space.shape[0]
        self.single_observation_space = spaces.Box(-1.0, 1.0, (size,), np.float32)
        self.single_action_space = self.fleet.single_action_space
        obs_shape = (self.num_envs, *self.single_observation_space.shape)
        self.observation_space = spaces.Box(-1.0, 1.0, obs_shape, np.float32)
        action_shape = (self.num_envs, *self.single_action_space.shape)
        self.action_space = spaces.Box(-1.0, 1.0, action_shape, np.float32)
        self._obs: np.ndarray | None = None
        self._racer_actions = np.zeros((self.fleet.num_envs, self.single_action_space.shape[0]))
        """The racer's actions for every boat's latest observation."""

    @property
    def task(self) -> Any:
        return self.fleet.task

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple:
        if seed is not None and not isinstance(seed, (int, np.integer)):
            seed = list(seed)
            if len(seed) == self.num_envs:  # a seed per learning boat: each race its first's
                seed = seed[:: self.learners]
        self._obs, info = self.fleet.reset(seed=seed, options=options)
        self.racer.reset()
        return self._observe(), self._pick(info)

    def step(self, actions: Any) -> tuple:
        if self._obs is None:
            raise RuntimeError("step() called before reset()")
        try:
            action = check_box_action(actions, self.single_action_space.shape[0], self.num_envs)
        except ValueError as error:
            raise ValueError(f"actions: {error}") from None
        restarting = self.fleet.races_ended
        every = self._racer_actions.copy()
        if self.residual:
            action = np.clip(every[self.rows] + action, -1.0, 1.0)
        every[self.rows] = action
        self._obs, reward, terminated, truncated, info = self.fleet.step(every)
        self._forget(restarting)
        learned = reward[self.rows]
        if self.relative:
            races = reward.reshape(self.num_races, self.num_boats)
            scripted = np.where(self.mask, 0.0, races).sum(axis=1) / (~self.mask).sum(axis=1)
            learned = learned - scripted[self.rows // self.num_boats]
        return (
            self._observe(),
            learned,
            terminated[self.rows],
            truncated[self.rows],
            self._pick(info),
        )

    def reset_envs(self, mask: Any) -> np.ndarray:
        """Restart at once what a step ended (the fleet's :meth:`reset_envs`, ``mask`` over
        the learning boats); returns the learning boats' observations."""
        if self._obs is None:
            raise RuntimeError("reset_envs() called before reset()")
        every = np.zeros(self.fleet.num_envs, dtype=bool)
        every[self.rows] = np.asarray(mask, dtype=bool)
        restarting = self.fleet.races_ended
        self._obs = self.fleet.reset_envs(every)
        self._forget(restarting)
        return self._observe()

    def _observe(self) -> np.ndarray:
        """The learning boats' observations, and the racer's actions for every boat (the
        racer called once per observation; called again on the same observation, as after
        :meth:`reset_envs`, it answers the same)."""
        self._racer_actions = self.racer(self._obs).astype(np.float64)
        obs = self._obs[self.rows]
        if self.residual:
            obs = np.concatenate([obs, self._racer_actions[self.rows].astype(np.float32)], axis=1)
        return obs

    def _forget(self, races: np.ndarray) -> None:
        """The racer forgets the tacks of the boats of races that start anew."""
        if races.any():
            self.racer.pilot.reset(np.flatnonzero(np.repeat(races, self.num_boats)))

    def _pick(self, info: dict[str, Any]) -> dict[str, Any]:
        """The learning boats' rows of the fleet's infos (nested ones too)."""

        def rows(tree: dict[str, Any]) -> dict[str, Any]:
            return {
                k: rows(v) if isinstance(v, dict) else v[self.rows]
                for k, v in tree.items()
                if not k.startswith("_")
            }

        return vector_info(rows(info), self.num_envs)


class MatchResult(NamedTuple):
    """Learned boats against scripted ones over a set of races (:func:`play_matches`)."""

    pairings: int
    """Pairs (a learned boat, a scripted boat) of one race."""
    ahead: int
    """Pairings the learned boat finished ahead in (it finished, and the scripted boat
    later or not at all)."""
    behind: int
    """Pairings the scripted boat finished ahead in (neither finishing counts for none)."""
    learned_finished: float
    scripted_finished: float
    """Shares of the boats that finished."""
    learned_fouls: float
    scripted_fouls: float
    """Fouls a boat, mean."""
    learned_place: float
    scripted_place: float
    """Mean place of the boats that finished."""
    learned_return: float = float("nan")
    """Mean return of a learning boat over its race (:func:`play_matches`)."""

    @property
    def ahead_share(self) -> float:
        return self.ahead / max(self.pairings, 1)


def score_matches(
    place: np.ndarray, finished: np.ndarray, fouls: np.ndarray, learned: np.ndarray
) -> MatchResult:
    """Score finished races ``(races, boats)``: each learned boat against each scripted one
    of its race."""
    finished = finished.astype(bool)
    rank = np.where(finished, place, np.inf)
    ahead = behind = pairings = 0
    for r in range(place.shape[0]):
        for i in np.flatnonzero(learned[r]):
            for j in np.flatnonzero(~learned[r]):
                pairings += 1
                ahead += int(rank[r, i] < rank[r, j])
                behind += int(rank[r, j] < rank[r, i])

    def mean(values: np.ndarray) -> float:
        return float(np.mean(values)) if values.size else float("nan")

    return MatchResult(
        pairings,
        ahead,
        behind,
        mean(finished[learned]),
        mean(finished[~learned]),
        mean(fouls[learned]),
        mean(fouls[~learned]),
        mean(place[learned & finished]),
        mean(place[~learned & finished]),
    )


def play_matches(
    policy: Any,
    num_races: int = 100,
    seed: int = 0,
    learners: int = 2,
    residual: bool = False,
    **kwargs: Any,
) -> MatchResult:
    """Sail ``num_races`` races (race ``r`` seeded ``seed + r``, as the PettingZoo env
    reset with that seed) with ``policy(observations) -> actions`` for the learning boats
    (:class:`BeachballRaceMatchEnv`'s, ``residual`` as there) and score them with
    :func:`score_matches` at each race's end, with the learning boats' mean return."""
    env = BeachballRaceMatchEnv(num_races, learners=learners, residual=residual, **kwargs)
    obs, _ = env.reset(seed=seed)
    shape = (env.num_races, env.num_boats)
    place, finished, fouls = np.zeros(shape), np.zeros(shape, bool), np.zeros(shape)
    done = np.zeros(env.num_races, dtype=bool)
    returns = np.zeros(env.num_envs)
    race_of = env.rows // env.num_boats
    while not done.all():
        obs, reward, *_ = env.step(policy(obs))
        returns += np.where(done[race_of], 0.0, reward)
        ended = env.fleet.races_ended & ~done
        state = env.fleet.state
        place[ended], finished[ended] = state.place[ended], state.finished[ended]
        fouls[ended] = state.fouls[ended]
        done |= ended
    env.close()
    scored = score_matches(place, finished, fouls, env.mask)
    return replaced(scored, learned_return=float(np.mean(returns)))
