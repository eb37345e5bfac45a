"""BeachballRace as a PettingZoo ``ParallelEnv`` (the ``race`` extra: PettingZoo)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding

try:
    from pettingzoo import ParallelEnv
    from pettingzoo.utils import OrderEnforcingWrapper
    from pettingzoo.utils.conversions import parallel_to_aec_wrapper
except ImportError as error:  # the fix, not a bare ModuleNotFoundError
    from bbgym._extras import install_hint

    raise ImportError(
        f"BeachballRace needs PettingZoo (the 'race' extra): {install_hint('race')}"
    ) from error

from bbgym.envs.common import check_box_action
from bbgym.envs.functional import tree_map
from bbgym.envs.race.spec import SPEC
from bbgym.envs.race.task import RaceState, RaceTask, boat_mapping

ENV_ID = SPEC.env_id
"""The race's id in PettingZoo's registries (``pettingzoo.make("parallel", ENV_ID)``)."""
BOAT_KEYS = ("sail_model", "dinghy", "initial_sheet")


def newest_boat() -> dict[str, Any]:
    """The sail family's newest version's boat (its sail model, dinghy and initial sheet),
    as its spec declares it: the race's default boat."""
    from bbgym.envs.sail.spec import SPEC

    kwargs = SPEC.versions[-1].kwargs
    return {key: kwargs[key] for key in BOAT_KEYS if key in kwargs}


def race_boat(boat: Any) -> dict[str, Any]:
    """The race's boat: :func:`newest_boat` with the user's ``boat`` over it, merged as
    ``gym.make`` merges a sail version's kwargs (:func:`bbgym.spec.merge_kwargs`): a
    ``dinghy`` mapping changes only the fields it names on the newest boat's (its sloop and
    calibration kept), a ``DinghyParams`` replaces it whole. ``boat`` that is no mapping,
    or has a key the race does not know, raises ``TypeError`` naming ``boat``; the values
    are checked by :class:`~bbgym.envs.race.task.RaceTask`."""
    from bbgym.envs.sail.spec import SPEC
    from bbgym.spec import merge_kwargs

    return merge_kwargs(SPEC, newest_boat(), boat_mapping(boat))


class BeachballRaceEnv(ParallelEnv):
    """A fleet of dinghies racing on one windward course: a start with a countdown, a
    windward mark, a leeward gate, laps and a finish, the wind shared by the fleet, each
    boat's sails shadowing the boats downwind of it, hulls that bounce off each other and
    the right-of-way rules. A PettingZoo ``ParallelEnv``: every boat acts at every step;
    :func:`bbgym.envs.race.env` gives the AEC form.

    Each boat is the sailing env's boat at its newest version (BeachballSail-v2's sloop,
    calibrated to a Laser) in still water; alone on the course it sails exactly as that
    env's boat does in the same wind. A step is 0.25 s.

    ## Agents

    ``boat_0`` .. ``boat_{K-1}`` (``num_boats`` K, default 4). A boat leaves ``agents``
    when it finishes or capsizes (terminated) or when the race's time is up (truncated).

    ## Action Space

    Per boat, ``Box(-1, 1, (3,), float32)``, the sail env's: rudder, main sheet, jib sheet
    (2 columns for a cat-rigged ``boat``).

    ## Observation Space

    Per boat, ``Box(-1, 1, (23 + 12 + 8 n,), float32)``, ``n`` the ``neighbours`` (3, at
    most ``num_boats - 1``); column names in :data:`bbgym.envs.race.task.RACE_COLUMNS` and
    :data:`~bbgym.envs.race.task.NEIGHBOUR_COLUMNS`:

    | index | observation | scale |
    |---|---|---|
    | 0-22 | BeachballSail-v2's observation, its mark the point steered for | as there |
    | 23 | time to the gun, a share of the countdown (1 at the reset, < 0 after) | `countdown_s` |
    | 24 | time since the gun | `max_race_time_s` |
    | 25 | started (1) or not (0) | - |
    | 26 | over the line early and not yet back (1) | - |
    | 27 | waypoints passed, as a share of all | - |
    | 28 | penalty owed: turns / 2 + seconds / 60 | - |
    | 29-31 | the committee boat: cos, sin of its bearing off the bow, distance | 200 m |
    | 32-34 | the pin, alike | 200 m |
    | 35 + 8 i | the i-th nearest other boat sailing: present (1) or not (0) | - |
    | 36-37 + 8 i | its position ahead and to port | 50 m |
    | 38-39 + 8 i | its velocity relative to this boat's, ahead and to port | 6 m/s |
    | 40-41 + 8 i | cos and sin of its heading relative to this boat's | - |
    | 42 + 8 i | right of way: -1 this boat keeps clear of it, 1 it of this boat | - |

    The point steered for: to start, a point level with the boat but at least 5 m inside
    the line's ends, 5 m above the line from below it between its ends, on the line from
    below it beyond an end (crossing the extension does not start), 10 m below the line
    from the course side (over early, or round an end); then a point 5 m above the
    windward mark and 5 m to its starboard side while the boat is on its port side, to its
    port side once the boat is on its starboard side (steering for it rounds the mark to
    port), the gate's centre, the finish line's centre. An absent neighbour's columns are
    zeros.

    ## Rewards

    Per boat, per step: progress toward the point it steers for after the gun (the sail
    env's, at most 1 a step), ``waypoint_bonus`` (5) for each waypoint passed (the start
    included), ``finish_bonus`` (20) times ``(K - place + 1) / K`` at the finish,
    ``-ocs_penalty`` (5) when over the line at the gun, ``-capsize_penalty`` (30) at a
    capsize, ``-foul_penalty`` (2) for each foul, ``-time_penalty`` (0.1) a step after the
    gun until it finishes. The infos' ``reward_terms`` hold each.

    ## Info

    Per boat, at every step it races, its last included (PettingZoo drops a boat from
    ``agents`` and from the next step's dicts once its race ends: keep each boat's last
    info to read its result):

    | key | meaning |
    |---|---|
    | `place` | 1 first, ...; 0: not finished (see below) |
    | `finished`, `is_success` | crossed the finish, any time penalty served |
    | `finish_time` | race clock at the finish, penalty included (s); `inf` before |
    | `race_clock` | time from the gun (s), negative during the countdown |
    | `leg` | the waypoint it sails to next (an index) |
    | `ocs` | over the line at the gun and not yet back |
    | `capsized` | capsized: its race is over |
    | `fouls`, `turns_owed` | fouls so far, penalty turns owed |
    | `penalty_owed` | time penalty owed (s) |
    | `touched` | its hull touched another's in the step |
    | `wind_factor` | the shadows on its wind over the step: speed over the race's |
    | `wind_bend` | ... and the turn they gave it (rad, counterclockwise) |
    | `reward_terms` | each reward term of the step |

    and the boat's state: `position`, `velocity`, `heading`, `boat_speed`, `heel`,
    `true_wind_speed`, `true_wind_angle`, `distance_to_waypoint`. ``place`` 0 is a boat
    still racing, or one whose race ended unfinished: it capsized, or it was still racing
    when the race clock reached ``max_race_time_s`` (truncated). Random actions seldom
    finish (a four-boat race seeded 0 ends with every place 0). ``finish_time`` ``inf`` is
    the one non-finite float a race returns, by design (the fuzz allows it there alone).

    ## The course and the rules sailed

    Laid square to the race's mean wind: a start line ``line_length_m`` (60 m) long, the
    committee boat at its starboard end; the windward mark ``leg_length_m`` (120 m) upwind of
    it, left to port (rounded counterclockwise); a gate ``gate_width_m`` (30 m) wide
    ``gate_depth_m`` (15 m) below the line. ``laps`` (1) times: the windward mark, then the
    gate, the last lap the finish (the start line crossed downwind). The start: the gun
    fires ``countdown_s`` (30 s) after the reset; a boat on the course side of the line (or
    its extensions) at the gun must return below it before it can start, crossing the line
    upwind between its ends. Hulls touching bounce (``collisions``, ``restitution`` 0.3).
    Rules 10 (port keeps clear of starboard), 12 (clear astern keeps clear), 11 (windward
    keeps clear) and a simplified 18 (the outside boat gives mark room): a boat that must
    keep clear and comes within ``keep_clear_m`` (0.5 m) of the other fouls her, and owes
    a full turn before her next waypoint (``penalty="turn"``) or ``penalty_time_s`` (30 s)
    on her finishing time (``penalty="time"``).

    ## Starting State

    The race's mean wind: speed uniform in ``wind_speed_range`` (3-7 m/s), from any
    direction, the gusts started in their stationary distribution (shared by the fleet).
    Each boat in its own slot along the line (K equal slots, a uniform place in its own),
    uniform in ``start_depth_range`` (10-40 m) behind it, heading anywhere, moving ahead at
    the sail env's initial speed (0.5-2 m/s), its sheets eased.

    ## Episode End

    A boat's episode terminates when it finishes (its time penalty served) or capsizes;
    every boat still racing is truncated when the race clock reaches ``max_race_time_s``
    (600 s).

    ## Arguments

    ``num_boats``, ``boat`` (a mapping of ``sail_model``, ``dinghy``, ``initial_sheet``,
    ``initial_speed_range`` for the sail core), ``laps``, ``line_length_m``,
    ``leg_length_m``, ``gate_depth_m``, ``gate_width_m``, ``countdown_s``,
    ``start_depth_range``, ``max_race_time_s``, ``wind_speed_range``, ``gusts``,
    ``gust_params``, ``shadow`` (on), ``shadow_params``
    (:class:`bbgym.physics.shadow.ShadowParams`), ``collisions`` (on), ``restitution``,
    ``keep_clear_m``, ``penalty``, ``penalty_time_s``, ``neighbours``, the reward weights
    above, ``render_mode`` (None, ``"rgb_array"`` or ``"human"``); an error names the path
    passed (``boat.dinghy.mass_kg``).

    ``reset(options=...)`` pins ``wind_speed``, ``wind_from`` (rad) and ``gusts``. Any
    other key is ignored, as PettingZoo's and Gymnasium's envs ignore options they do not
    take (PettingZoo's API test passes one), except a near miss of one of these three
    (``wind_sped``, ``gust``: a typo) or one of the sail env's options (``heading``,
    ``mark``, ...), which raise ``TypeError`` naming ``options[key]``: what was meant to be
    pinned would otherwise be drawn at random, silently.

    ``step(actions)`` takes a dict of every racing boat's action (``TypeError`` for
    anything else; ``ValueError`` naming ``actions['boat_k']`` for a boat missing, not
    racing, or a NaN, inf or wrongly shaped action). The AEC form checks each action at
    its boat's turn: a bad one raises ``ValueError`` naming the boat, which keeps its turn.

    ## Version History

    * v0: the first version.
    """

    metadata = {
        "name": "beachball_race_v0",
        "render_modes": ["human", "rgb_array"],
        "render_fps": 4,  # a frame a step of 0.25 s: real time
        "is_parallelizable": True,
    }

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be None or one of "
                f"{self.metadata['render_modes']}, got {render_mode!r}"
            )
        self._renderer: Any = None
        self.task = RaceTask(boat=race_boat(kwargs.pop("boat", None)), **kwargs)
        self.render_mode = render_mode
        self.possible_agents = [f"boat_{k}" for k in range(self.task.num_boats)]
        self.agents: list[str] = []
        self.state_: RaceState | None = None
        self._np_random, _ = seeding.np_random(None)

    @functools.cache  # noqa: B019 (PettingZoo's own idiom: one space per agent)
    def observation_space(self, agent: str) -> spaces.Box:
        return self.task.observation_space

    @functools.cache  # noqa: B019
    def action_space(self, agent: str) -> spaces.Box:
        return self.task.action_space

    def reset(self, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple:
        if seed is not None:
            self._np_random, _ = seeding.np_random(seed)
        checked = self.task.check_options(options)
        k = self.task.num_boats
        uniform = self._np_random.uniform(size=(1, 2 + 4 * k))
        normal = self._np_random.standard_normal(size=(1, 2))
        self.state_ = self.task.initial(uniform, normal, checked, np)
        self.agents = list(self.possible_agents)
        return self._observations(), self._infos()

    def check_action(self, agent: str, action: Any, path: str | None = None) -> np.ndarray:
        """``agent``'s action as float64 ``(size,)``, clipped to [-1, 1]: a wrong shape or a
        NaN/inf raises ``ValueError`` naming ``path`` (``actions['boat_k']`` by default),
        and so does an ``agent`` not racing; what ``check_box_action`` raises as a
        ``TypeError`` is one here too, named alike."""
        path = f"actions[{agent!r}]" if path is None else path
        if agent not in self.agents:
            raise ValueError(f"{path}: no such boat racing; racing: {self.agents}")
        try:
            return check_box_action(action, self.task.action_space.shape[0], 0)
        except (TypeError, ValueError) as error:
            raise type(error)(f"{path}: {error}") from None

    def step(self, actions: dict[str, Any]) -> tuple:
        if self.state_ is None or not self.agents:
            raise RuntimeError("step() called before reset() or after every boat's race ended")
        # A list in the agents' order would be a guess at which boat is which (and a
        # finished boat leaves it): only a mapping names its boats.
        if not isinstance(actions, Mapping):
            kind = type(actions).__name__
            raise TypeError(f"actions must be a dict keyed by agent names, got a {kind}")
        for agent in actions:
            if agent not in self.agents:
                raise ValueError(f"actions[{agent!r}]: no such boat racing; racing: {self.agents}")
        action = np.zeros((self.task.num_boats, self.task.action_space.shape[0]))
        for agent in self.agents:
            if agent not in actions:
                raise ValueError(f"actions[{agent!r}] is missing: every boat racing acts")
            action[self.possible_agents.index(agent)] = self.check_action(agent, actions[agent])
        gust_noise = self._np_random.standard_normal(size=(1, 2))
        state = self.task.transition(self.state_, action, gust_noise, np)
        self.state_ = state
        racing = list(self.agents)
        reward = self.task.reward(state, np)[0]
        out = self.task.terminal(state, np)[0]
        timed_out = bool(self.task.timed_out(state, np)[0])
        observations, infos = self._observations(racing), self._infos(racing)
        rewards, terminations, truncations = {}, {}, {}
        for agent in racing:
            k = self.possible_agents.index(agent)
            rewards[agent] = float(reward[k])
            terminations[agent] = bool(out[k])
            truncations[agent] = timed_out and not bool(out[k])
        self.agents = [a for a in racing if not (terminations[a] or truncations[a])]
        return observations, rewards, terminations, truncations, infos

    def _observations(self, agents: list[str] | None = None) -> dict[str, np.ndarray]:
        obs = self.task.observation(self.state_, np)[0]
        return {a: obs[self.possible_agents.index(a)] for a in agents or self.agents}

    def _infos(self, agents: list[str] | None = None) -> dict[str, dict[str, Any]]:
        info = self.task.info(self.state_, np)

        def boat(k: int) -> dict[str, Any]:
            def pick(leaf: Any) -> Any:
                value = np.asarray(leaf)[0, k]
                return value.item() if value.ndim == 0 else value

            return tree_map(pick, info)

        return {a: boat(self.possible_agents.index(a)) for a in agents or self.agents}

    def render(self) -> np.ndarray | None:
        """The race from above (:mod:`bbgym.envs.race.view`): an RGB frame
        ``(480, 640, 3)`` in ``rgb_array`` mode, a window in ``human`` mode (pygame, the
        ``render`` extra); nothing without a ``render_mode``."""
        if self.render_mode is None or self.state_ is None:
            return None
        from bbgym.envs.race.view import RaceRenderer, race_scene

        if self._renderer is None:
            self._renderer = RaceRenderer(self.render_mode, 640, 480, self.metadata["render_fps"])
        return self._renderer.render(race_scene(self.task, self.state_))

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def parallel_env(**kwargs: Any) -> BeachballRaceEnv:
    """A race as a PettingZoo ``ParallelEnv`` (:class:`BeachballRaceEnv`)."""
    return BeachballRaceEnv(**kwargs)


class RaceAECWrapper(parallel_to_aec_wrapper):
    """PettingZoo's ``parallel_to_aec_wrapper`` that checks each boat's action at its own
    turn. The stock wrapper stores the action and hands the stored actions to the parallel
    env at the last boat's turn: a bad action would raise there, at another boat's turn,
    and again at every later turn until a reset (it stays stored). Here it raises
    ``ValueError`` naming the boat before it is stored, and the boat keeps its turn."""

    def step(self, action: Any) -> None:
        agent = self.agent_selection
        # A boat out of the race steps with None (PettingZoo's dead step): not checked.
        if not (self.terminations[agent] or self.truncations[agent]):
            self.env.check_action(agent, action, f"action of {agent!r} (its turn)")
        super().step(action)


def env(**kwargs: Any) -> Any:
    """A race in PettingZoo's AEC form (boats act in turn): PettingZoo's ``parallel_to_aec``
    with each action checked at its boat's turn (:class:`RaceAECWrapper`)."""
    return OrderEnforcingWrapper(RaceAECWrapper(BeachballRaceEnv(**kwargs)))
