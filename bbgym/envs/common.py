"""What the envs share: argument validation, batch/element conversion, rendering set-up
and the native vector env machinery."""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import fields
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from bbgym.physics import backend


def check_option_keys(options: Mapping[str, Any] | None, known: tuple[str, ...]) -> dict:
    """``reset`` options as a dict; ``None`` is empty. A non-mapping or an unknown key
    raises ``TypeError`` naming it (as an unknown keyword argument does)."""
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise TypeError(f"options must be a dict, got {options!r}")
    for key in options:
        if key not in known:
            raise TypeError(f"options got an unexpected key {key!r}; known keys: {list(known)}")
    return dict(options)


def option_path(key: str) -> str:
    """How errors name a reset option: ``options['speed']``."""
    return f"options[{key!r}]"


def check_multiple(name: str, value: float, base_name: str, base: float) -> int:
    """How many ``base`` steps make ``value``; ``value`` must be a whole multiple."""
    count = round(value / base)
    if count < 1 or abs(count * base - value) > 1e-9 * max(1.0, value):
        raise ValueError(f"{name} ({value!r}) must be a whole multiple of {base_name} ({base!r})")
    return count


def mean_wind(
    options: Mapping[str, Any], speed_range: tuple[float, float], speed_draw: Any, from_draw: Any
) -> tuple[Any, Any]:
    """Mean wind ``(speed, from)``: the ``wind`` option (a vector, where the air moves) if
    given, else a speed uniform in ``speed_range`` from a uniform direction (draws in [0, 1))."""
    if "wind" in options:
        wx, wy = options["wind"]
        return math.hypot(wx, wy), math.atan2(-wy, -wx)
    lo, hi = speed_range
    return lo + (hi - lo) * speed_draw, 2.0 * math.pi * from_draw


def check_box_action(action: Any, size: int, batch: int) -> np.ndarray:
    """Actions as float64 ``(size,)`` (``batch == 0``: one env) or ``(batch, size)``,
    clipped to [-1, 1]; a wrong shape or a NaN/inf raises ``ValueError``."""
    try:
        a = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"action must be numeric, got {action!r}") from None
    expected = (size,) if batch == 0 else (batch, size)
    if a.shape != expected:
        raise ValueError(f"action must have shape {expected}, got {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"action must be finite, got {action!r}")
    return np.clip(a, -1.0, 1.0)


def element(obj: Any, i: int) -> Any:
    """Element ``i`` of a batch dataclass or NamedTuple, as Python scalars."""
    names = obj._fields if isinstance(obj, tuple) else [f.name for f in fields(obj)]
    return type(obj)(**{name: getattr(obj, name)[i].item() for name in names})


def vector_seeds(seed: int | list[int | None] | None, num_envs: int) -> list[int | None]:
    """Per-sub-env seeds: ``seed + i`` for an int (Gymnasium's convention), a list as given,
    or fresh entropy for ``None``."""
    if seed is None:
        return [None] * num_envs
    if isinstance(seed, (int, np.integer)):
        return [int(seed) + i for i in range(num_envs)]
    seeds = list(seed)
    if len(seeds) != num_envs:
        raise ValueError(f"seed must have {num_envs} entries, got {len(seeds)}")
    return seeds


def vector_info(info: dict[str, Any], num_envs: int) -> dict[str, Any]:
    """Gymnasium's vector info layout: every key with a ``_key`` mask (all envs report)."""
    mask = np.ones(num_envs, dtype=bool)
    out: dict[str, Any] = {}
    for key, value in info.items():
        out[key] = vector_info(value, num_envs) if isinstance(value, dict) else value
        out[f"_{key}"] = mask
    return out


def check_render_mode(render_mode: str | None, modes: list[str]) -> None:
    """``None`` or one of ``modes``, else ``ValueError`` naming ``render_mode``."""
    if render_mode is not None and render_mode not in modes:
        raise ValueError(f"render_mode must be one of {modes}, got {render_mode!r}")


def ensure_renderer(env: Any) -> Any:
    """The env's renderer, made on first use by ``env._make_renderer()`` (so pygame is
    imported only then); ``None``, with a warning, for an env without a ``render_mode``."""
    if env.render_mode is None:
        gym.logger.warn(
            "render() called without a render_mode; pass render_mode='rgb_array' or 'human'."
        )
        return None
    started = env.started if hasattr(env, "started") else env._sim.started
    if not started:
        raise gym.error.ResetNeeded("Call reset() before render()")
    if env._renderer is None:
        env._renderer = env._make_renderer()
    return env._renderer


def without_renderer(attributes: dict[str, Any]) -> dict[str, Any]:
    """An env's attributes for pickling and deep copies: a window or pygame surface does not
    copy, so the renderer is left out and made again on the next ``render()``."""
    state = dict(attributes)
    state["_renderer"] = None
    return state


class NativeVectorEnv(VectorEnv):
    """What bbgym's native vector envs share: one batched simulation of ``num_envs`` envs.

    A subclass sets ``task_class`` and ``sim_class`` and implements ``_make_renderer`` and
    ``_render_env``. The simulation object (``sim_class(task, num_envs)``) provides
    ``started``, ``seed(seeds)``, ``reset(mask, options)``, ``step(actions, active)`` ->
    ``(reward, terminated)``, ``observation()`` and ``info()``.

    Sub-env ``i`` reset with ``seed=s`` follows a single env reset with ``seed=s + i``
    under the same actions. Finished sub-envs reset on the next ``step``
    (``AutoresetMode.NEXT_STEP``), which returns the new episode's first observation with
    reward 0 for them. The time limit (``max_episode_steps``) is applied here, since
    ``gym.make_vec`` adds no ``TimeLimit`` wrapper to a native vector env. Infos are arrays
    with Gymnasium's ``_key`` masks.
    """

    metadata: dict[str, Any] = {
        "render_modes": ["rgb_array", "human"],
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }
    task_class: type
    sim_class: type
    default_max_episode_steps: int = 1000
    """The registered time limit, applied when ``max_episode_steps`` is not given."""

    def __init__(
        self,
        num_envs: int = 1,
        render_mode: str | None = None,
        max_episode_steps: int | None = None,
        **kwargs: Any,
    ) -> None:
        if max_episode_steps is None:
            max_episode_steps = self.default_max_episode_steps
        if not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs must be an int >= 1, got {num_envs!r}")
        if not isinstance(max_episode_steps, (int, np.integer)) or max_episode_steps < 1:
            raise ValueError(f"max_episode_steps must be an int >= 1, got {max_episode_steps!r}")
        check_render_mode(render_mode, self.metadata["render_modes"])
        self.task = self.task_class(**kwargs)
        self.num_envs = int(num_envs)
        self.max_episode_steps = int(max_episode_steps)
        self.render_mode = render_mode
        self.single_action_space = self.task.action_space
        self.single_observation_space = self.task.observation_space
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._sim = self.sim_class(self.task, self.num_envs)
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._renderer: Any = None

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        if seed is not None or not self._sim.started:
            seeds = vector_seeds(seed, self.num_envs)
            self._sim.seed(seeds)
            if seed is not None:
                self._np_random, self._np_random_seed = seeding.np_random(seeds[0])
        everyone = np.ones(self.num_envs, dtype=bool)
        self._sim.reset(everyone, options)
        self._steps[:] = 0
        self._autoreset[:] = False
        self._on_reset(everyone)
        return self._sim.observation(), vector_info(self._sim.info(), self.num_envs)

    def step(
        self, actions: Any
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        if not self._sim.started:
            raise gym.error.ResetNeeded("Call reset() before step()")
        a = self.task.check_action(actions, self.num_envs)
        restarting = self._autoreset.copy()
        reward, terminated = self._sim.step(a, ~restarting)
        self._steps += 1
        if restarting.any():
            # Next-step autoreset: the finished envs start anew and ignore this action.
            self._sim.reset(restarting, None)
            self._steps[restarting] = 0
            reward = np.where(restarting, 0.0, reward)
            terminated = terminated & ~restarting
            self._on_reset(restarting)
        truncated = (self._steps >= self.max_episode_steps) & ~terminated
        self._autoreset = terminated | truncated
        self._on_step(a)
        info = vector_info(self._sim.info(), self.num_envs)
        return self._sim.observation(), reward.astype(np.float64), terminated, truncated, info

    def reset_envs(self, mask: np.ndarray) -> np.ndarray:
        """Restart the envs in ``mask`` now, without seeds (each continues its own random
        stream), and return every env's observation. Adapters whose API resets on the
        step that ends an episode (stable-baselines3) use this instead of waiting for the
        next ``step``."""
        mask = np.asarray(mask, dtype=bool)
        if mask.any():
            self._sim.reset(mask, None)
            self._steps[mask] = 0
            self._autoreset[mask] = False
            self._on_reset(mask)
        return self._sim.observation()

    def _on_reset(self, mask: np.ndarray) -> None:
        """Hook: envs in ``mask`` have just been reset."""

    def _on_step(self, actions: np.ndarray) -> None:
        """Hook: a step with ``actions`` has just been taken."""

    def render(self) -> tuple[np.ndarray, ...] | None:
        """Frames of the first (up to 4) sub-envs; ``human`` shows the first in a window."""
        renderer = ensure_renderer(self)
        if renderer is None:
            return None
        count = 1 if self.render_mode == "human" else min(self.num_envs, 4)
        frames = tuple(self._render_env(renderer, i) for i in range(count))
        return None if self.render_mode == "human" else frames

    def _make_renderer(self) -> Any:
        raise NotImplementedError

    def _render_env(self, renderer: Any, i: int) -> np.ndarray | None:
        raise NotImplementedError

    def __getstate__(self) -> dict[str, Any]:
        return without_renderer(self.__dict__)

    def close_extras(self, **kwargs: Any) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


class TaskSim:
    """What the task simulations share: the task, the batch size, the array namespace
    (Python floats for one env, NumPy for a batch) and each env's random stream. A
    subclass sets ``scenario`` at its first ``reset``."""

    def __init__(self, task: Any, batch: int, scalar: bool = False) -> None:
        self.task = task
        self.batch = batch
        self.scalar = scalar
        self.xp = backend.scalar if scalar else np
        self.streams = NormalStreams(batch)
        self.scenario: Any = None

    @property
    def started(self) -> bool:
        return self.scenario is not None

    def __getstate__(self) -> dict[str, Any]:
        # A module does not pickle: keep which namespace, not the namespace itself.
        state = dict(self.__dict__)
        del state["xp"]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self.xp = backend.scalar if self.scalar else np

    def seed(self, seeds: list[int | None]) -> None:
        self.streams.seed(seeds)


class NormalStreams:
    """Each env's own random stream of standard normal pairs, drawn in blocks.

    An env's randomness comes from its own ``numpy.random.Generator`` (so sub-env ``i`` of
    a vector env matches a single env seeded ``seed + i``). Drawing from thousands of
    generators one by one every step is a Python loop over the batch; instead each env
    draws ``block`` pairs of standard normals at once and hands them out in order,
    drawing the next block when they run out (the stream is the generator's normals in
    order, whatever the calls). The single env uses the same blocks, so both see the same
    numbers. A reset discards an env's unused pairs.

    A pure function that may use up to ``k`` pairs per env (Topple's interval: one pair per
    gust update while the env runs) gets them from :meth:`peek` and reports how many it
    used, which :meth:`advance` then consumes.
    """

    def __init__(self, batch: int, block: int = 64) -> None:
        self.rngs: list[np.random.Generator] = [seeding.np_random(None)[0] for _ in range(batch)]
        self.block = block
        self._buffer = np.zeros((batch, block, 2))
        self._next = np.zeros(batch, dtype=np.int64)  # next unused row
        self._end = np.zeros(batch, dtype=np.int64)  # rows drawn (unused: _next.._end)
        # Rows up to _drawn come from the env's generator; rows beyond, up to _end, were
        # peeked from a copy of it (:meth:`peek`) and are drawn for real only when used.
        self._drawn = np.zeros(batch, dtype=np.int64)
        self._ahead: dict[int, np.random.Generator] = {}
        self._rows = np.arange(batch)
        self._block0: list | None = None  # env 0's rows as floats, for one()

    def seed(self, seeds: list[int | None]) -> None:
        for i, s in enumerate(seeds):
            self.set(i, seeding.np_random(s)[0])

    def set(self, i: int, rng: np.random.Generator) -> None:
        """Give env ``i`` the generator ``rng`` (a single env's ``np_random``)."""
        self.rngs[i] = rng
        self.discard(self._rows == i)

    def discard(self, mask: np.ndarray) -> None:
        """Throw away the unused pairs of the envs in ``mask`` (a reset): their next pair
        starts a new block, drawn from the generator after whatever the reset drew."""
        self._end = np.where(mask, self._drawn, self._end)
        self._next = np.where(mask, self._end, self._next)
        for i in np.flatnonzero(mask):
            self._ahead.pop(int(i), None)

    def one(self, draw: bool) -> tuple[float, float]:
        """The single env's next pair as Python floats (zeros if not ``draw``), from the
        same stream as :meth:`pairs`."""
        if not draw:
            return (0.0, 0.0)
        k = int(self._next[0])
        if k >= self._end[0]:
            self._refill(0, 1, use_now=True)
            k = 0
        if self._block0 is None:
            self._block0 = self._buffer[0].tolist()
        self._next[0] = k + 1
        if k >= self._drawn[0]:
            self._commit()
        first, second = self._block0[k]
        return (first, second)

    def pairs(self, mask: np.ndarray) -> np.ndarray:
        """One pair of standard normals per env where ``mask``, zeros elsewhere: ``(2, batch)``.

        Envs outside ``mask`` draw nothing, so no env's numbers depend on another's."""
        mask = np.asarray(mask, dtype=bool)
        for i in np.flatnonzero(mask & (self._next >= self._end)):
            self._refill(i, 1, use_now=True)
        picked = self._buffer[self._rows, np.minimum(self._next, self._buffer.shape[1] - 1)]
        self.advance(mask)
        return np.where(mask[:, None], picked, 0.0).T

    def peek(self, mask: np.ndarray, count: int) -> np.ndarray:
        """The next ``count`` pairs of each env in ``mask`` without using them (zeros
        elsewhere): ``(count, 2, batch)``. :meth:`advance` uses them. Pairs beyond the
        env's current block come from a copy of its generator, which itself draws them
        only once they are used: a reset in between leaves the stream as if never peeked."""
        mask = np.asarray(mask, dtype=bool)
        for i in np.flatnonzero(mask & (self._end - self._next < count)):
            self._refill(i, count)
        take = self._next[:, None] + np.arange(count)
        picked = self._buffer[self._rows[:, None], np.minimum(take, self._buffer.shape[1] - 1)]
        return np.where(mask[:, None, None], picked, 0.0).transpose(1, 2, 0)

    def advance(self, used: np.ndarray) -> None:
        """Use up ``used[i]`` pairs of env ``i`` (at most what :meth:`peek` showed)."""
        self._next = self._next + np.asarray(used, dtype=np.int64)
        if (self._next > self._drawn).any():
            self._commit()

    def _commit(self) -> None:
        """The generator draws, for real, every peeked block that is now in use."""
        for i in np.flatnonzero(self._next > self._drawn):
            while self._drawn[i] < self._next[i]:
                self.rngs[i].standard_normal((self.block, 2))  # the same values as peeked
                self._drawn[i] += self.block
            if self._drawn[i] >= self._end[i]:
                self._ahead.pop(int(i), None)

    def _refill(self, i: int, count: int, use_now: bool = False) -> None:
        """Give env ``i`` at least ``count`` unused pairs: blocks after its unused ones
        (the stream stays in the generator's order). A block the env starts using now is
        drawn from its generator (``use_now``); the others, from a copy (see :meth:`peek`)."""
        self._block0 = None
        left = self._buffer[i, self._next[i] : self._end[i]].copy()
        drawn_left = max(int(self._drawn[i] - self._next[i]), 0)
        blocks = -(-(count - len(left)) // self.block)
        rows = len(left) + blocks * self.block
        if rows > self._buffer.shape[1]:
            grown = np.zeros((self._buffer.shape[0], rows, 2))
            grown[:, : self._buffer.shape[1]] = self._buffer
            self._buffer = grown
        self._buffer[i, : len(left)] = left
        for b in range(blocks):
            start = len(left) + b * self.block
            if use_now and start == 0 and not drawn_left:
                source = self.rngs[i]  # used at once: the generator itself
                drawn_left = self.block
            else:
                if i not in self._ahead:
                    self._ahead[i] = copy.deepcopy(self.rngs[i])
                source = self._ahead[i]
            self._buffer[i, start : start + self.block] = source.standard_normal((self.block, 2))
        self._next[i], self._end[i], self._drawn[i] = 0, rows, drawn_left


class SingleEnv(gym.Env[np.ndarray, np.ndarray]):
    """What bbgym's single envs share: the task's simulation run for one env on Python
    floats (``sim_class(task, 1, scalar=True)``), seeded from the env's ``np_random``.

    A subclass sets ``metadata``, ``task_class`` and ``sim_class``, implements
    ``_make_renderer`` and ``render``, and may use the ``_on_reset`` / ``_on_step`` hooks.
    In human mode every reset and step is shown; ``_animate`` tells ``render`` that a step
    just happened (envs whose step spans seconds of simulated time play it back).
    """

    metadata: dict[str, Any] = {"render_modes": ["human", "rgb_array"]}
    task_class: type
    sim_class: type

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        check_render_mode(render_mode, self.metadata["render_modes"])
        self.task = self.task_class(**kwargs)
        self.render_mode = render_mode
        self.action_space = self.task.action_space
        self.observation_space = self.task.observation_space
        self._sim = self.sim_class(self.task, 1, scalar=True)
        self._renderer: Any = None
        self._animate = False

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self._sim.streams.set(0, self.np_random)
        self._sim.reset(np.ones(1, dtype=bool), options)
        self._on_reset()
        if self.render_mode == "human":
            self.render()
        return self._sim.observation(), self._sim.info()

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if not self._sim.started:
            raise gym.error.ResetNeeded("Call reset() before step()")
        a = self.task.check_action(action, 0)
        reward, terminated = self._sim.step(a)
        self._on_step(a)
        if self.render_mode == "human":
            self._animate = True
            self.render()
        return self._sim.observation(), float(reward), bool(terminated), False, self._sim.info()

    def _on_reset(self) -> None:
        """Hook: the env has just been reset."""

    def _on_step(self, action: Any) -> None:
        """Hook: a step with ``action`` has just been taken."""

    def _make_renderer(self) -> Any:
        raise NotImplementedError

    def __getstate__(self) -> dict[str, Any]:
        return without_renderer(self.__dict__)

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
