"""Many races at once, every boat a sub-env: a Gymnasium ``VectorEnv`` of ``num_races x
num_boats`` boats for one shared policy (self-play), stepped as one batch on the NumPy or
the torch backend (:mod:`bbgym.backends`)."""

from __future__ import annotations

from contextlib import nullcontext
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv

from bbgym import backends
from bbgym.envs.common import check_box_action, vector_info, vector_seeds
from bbgym.envs.functional import tree_map, tree_select
from bbgym.envs.race.parallel import race_boat
from bbgym.envs.race.task import RaceState, RaceTask
from bbgym.physics.namespace import replaced


class BeachballRaceFleetEnv(VectorEnv):
    """``num_races`` races of ``num_boats`` boats as one Gymnasium ``VectorEnv`` of
    ``num_races * num_boats`` sub-envs, boat ``k`` of race ``r`` at ``r * num_boats + k``:
    what a shared policy learns from when every boat is its own player (self-play), as
    stable-baselines3's or TorchRL's single-agent learners take it.

    Each sub-env's observation, action and reward are its boat's in
    :class:`~bbgym.envs.race.parallel.BeachballRaceEnv` (the same spaces and the same races:
    race ``r`` reset with ``seed=s`` is the PettingZoo env reset with ``seed=s + r``, under
    the same actions). A boat's episode ends when it finishes or capsizes (terminated) or
    when its race's time is up (truncated). Until its race ends it then sits out: zero
    observations, reward 0, no ends (what PettingZoo's multi-agent learners call "black
    death"), and at its race's end that wait ends too (truncated). A race restarts, all its
    boats at once, on the step after it ended (``AutoresetMode.NEXT_STEP``: that step
    returns the new race's first observations, with reward 0). Infos are arrays (per
    boat), with Gymnasium's ``_key`` masks; keyword arguments are the race env's.

    ``backend="torch"`` steps the races on torch (``device``, ``dtype`` float64 or float32,
    ``compile``: one ``torch.compile``d graph a step, else eager; ``output="torch"`` returns
    observations, rewards and ends as tensors on ``device``, infos stay NumPy), and
    ``backend="jax"`` on JAX (one ``jax.jit`` program a step; ``output="jax"``): the same
    core and the same random draws (each race's own NumPy generator, a few numbers a
    step), so in float64 a race sails as on NumPy to rounding.
    ``reset`` takes an int (race ``r`` seeded ``seed + r``), a seed per race, or a seed per
    boat (each race takes its first boat's). :meth:`reset_envs` restarts at once what a
    step ended, for stable-baselines3 through :class:`bbgym.sb3.NativeVecEnvAdapter`.
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_races: int = 16,
        *,
        backend: str = "numpy",
        device: str | None = None,
        dtype: str = "float64",
        output: str = "numpy",
        compile: bool = True,
        **kwargs: Any,
    ) -> None:
        if isinstance(num_races, bool) or not isinstance(num_races, (int, np.integer)):
            raise TypeError(f"num_races must be an int, got {num_races!r}")
        if num_races < 1:
            raise ValueError(f"num_races must be at least 1, got {num_races}")
        self.task = RaceTask(boat=race_boat(kwargs.pop("boat", None)), **kwargs)
        self.backend = backends.resolve_backend(backend, device, dtype, output, compile)
        self.xp = self.backend.xp
        self.num_races, self.num_boats = int(num_races), self.task.num_boats
        self.num_envs = self.num_races * self.num_boats
        self.single_observation_space = self.task.observation_space
        self.single_action_space = self.task.action_space
        obs_shape = (self.num_envs, *self.single_observation_space.shape)
        self.observation_space = spaces.Box(-1.0, 1.0, obs_shape, np.float32)
        action_shape = (self.num_envs, *self.single_action_space.shape)
        self.action_space = spaces.Box(-1.0, 1.0, action_shape, np.float32)
        self.state: RaceState | None = None
        self._generators = [seeding.np_random(None)[0] for _ in range(self.num_races)]
        self._ended = np.zeros(self.num_races, dtype=bool)
        self._cold = True
        """No step yet: on torch with ``compile`` the first compiles (logged, it is slow)."""
        self._sitting_out = np.zeros((self.num_races, self.num_boats), dtype=bool)
        self._advance = backends.compiled(self._advance_races, self.backend)
        self._observation = backends.compiled(self._observation_of, self.backend)

    def _fresh(self, races: np.ndarray, options: dict[str, Any]) -> RaceState:
        """New races for every race (draws only for those in ``races``, so each race's
        random stream is its own)."""
        k = self.num_boats
        uniform = np.full((self.num_races, 2 + 4 * k), 0.5)
        normal = np.zeros((self.num_races, 2))
        for r in np.flatnonzero(races):
            uniform[r] = self._generators[r].uniform(size=2 + 4 * k)
            normal[r] = self._generators[r].standard_normal(size=2)
        state = self.task.initial(self._array(uniform), self._array(normal), options, self.xp)
        if self.xp is np or self.backend.name == "jax":  # JAX arrays are values: no aliasing
            return state
        # Leaves of a new state share arrays (one zeros for many fields); a compiled step
        # guards on which inputs are the same tensor and would compile again for the
        # states after it, which share none.
        return tree_map(lambda a: a.clone(), state)

    def _array(self, values: np.ndarray) -> Any:
        """NumPy values on the backend (floats in its dtype, on its device)."""
        if self.xp is np:
            return values
        dtype = self.backend.float_dtype if values.dtype.kind == "f" else None
        if self.backend.name == "jax":
            import jax

            return jax.device_put(self.xp.asarray(values, dtype=dtype), self.backend.jax_device)
        return self.xp.asarray(values, dtype=dtype, device=self.backend.device)

    def _select(self, races: np.ndarray, fresh: RaceState, old: RaceState) -> RaceState:
        """``fresh`` for the races in ``races``, ``old`` for the others (the boats, flat,
        by each boat's race)."""
        xp = self.xp
        each = self._array(np.repeat(races, self.num_boats))
        boats = tree_select(each, fresh.boats, old.boats, xp)
        # the rest by race (the boats the same object on both sides: left as they are)
        rest = tree_select(self._array(races), replaced(fresh, boats=old.boats), old, xp)
        return replaced(rest, boats=boats)

    def _advance_races(self, state: RaceState, action: Any, gust_noise: Any) -> tuple:
        """One step of every race, pure (compiled as one graph on torch): the new state,
        each boat's reward and whether it is out, each race's time being up."""
        xp = self.xp
        moved = self.task.transition(state, action, gust_noise, xp)
        return (
            moved,
            self.task.reward(moved, xp),
            self.task.terminal(moved, xp),
            self.task.timed_out(moved, xp),
        )

    def _observation_of(self, state: RaceState) -> Any:
        return self.task.observation(state, self.xp)

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple:
        with self.backend.context():
            return self._reset(seed, options)

    def _reset(self, seed: Any, options: dict[str, Any] | None) -> tuple:
        if not isinstance(seed, (int, np.integer)) and seed is not None:
            seed = list(seed)
            if len(seed) == self.num_envs:  # a seed per boat: each race takes its first's
                seed = seed[:: self.num_boats]
        for r, s in enumerate(vector_seeds(seed, self.num_races)):
            if s is not None or seed is not None:
                self._generators[r] = seeding.np_random(s)[0]
        checked = self.task.check_options(options)
        self.state = self._fresh(np.ones(self.num_races, dtype=bool), checked)
        self._ended[:] = False
        self._sitting_out[:] = False
        return self._observe(), self._info()

    def step(self, actions: Any) -> tuple:
        if self.state is None:
            raise RuntimeError("step() called before reset()")
        with self.backend.context():
            return self._step(actions)

    def _step(self, actions: Any) -> tuple:
        if backends.is_jax_array(actions):
            actions = np.asarray(actions)  # checked on the host, as a NumPy batch is
        if hasattr(actions, "detach") and self.xp is not np:  # a learner's tensor, kept there
            action = actions.to(device=self.backend.device, dtype=self.backend.float_dtype)
            if tuple(action.shape) != self.action_space.shape:
                raise ValueError(
                    f"actions must have shape {self.action_space.shape}, got {tuple(action.shape)}"
                )
            action = action.clamp(-1.0, 1.0)  # a NaN check would cost a sync on a GPU
        else:
            try:
                size = self.single_action_space.shape[0]
                action = self._array(check_box_action(actions, size, self.num_envs))
            except ValueError as error:
                raise ValueError(f"actions: {error}") from None
        restarting = self._ended.copy()
        gust_noise = np.stack(
            [
                g.standard_normal(size=2) if not restarting[r] else np.zeros(2)
                for r, g in enumerate(self._generators)
            ]
        )
        before = self.state
        noise = self._array(gust_noise)
        compiling = self._cold and self.backend.name != "numpy" and self.backend.compile
        logged = backends.compile_logged("the race step", self.backend, self.num_envs)
        with logged if compiling else nullcontext():
            moved, reward, out, timed_out = self._advance(before, action, noise)
        self._cold = False
        to_numpy = backends.to_numpy
        reward, out, timed_out = to_numpy(reward), to_numpy(out), to_numpy(timed_out)
        out_now = out & ~to_numpy(before.out)
        sitting_out = self._sitting_out.copy()
        ended = np.all(out, axis=1) | timed_out
        terminated = out_now & ~sitting_out
        # boats still racing at the time limit, and those sitting out, stop at the race's end
        truncated = ended[:, None] & ~terminated
        reward = np.where(sitting_out, 0.0, reward)
        self.state = moved
        self._sitting_out = sitting_out | out_now
        if restarting.any():  # those races start anew; their step reports the reset
            fresh = self._fresh(restarting, {})
            self.state = self._select(restarting, fresh, moved)
            reward[restarting] = 0.0
            terminated[restarting] = False
            truncated[restarting] = False
            self._sitting_out[restarting] = False
            ended[restarting] = False
        self._ended = ended
        obs = self._observe(sitting_out & ~restarting[:, None])
        return (
            obs,
            self._output(reward.reshape(-1)),
            self._output(terminated.reshape(-1)),
            self._output(truncated.reshape(-1)),
            self._info(),
        )

    def reset_envs(self, mask: Any) -> np.ndarray:
        """Restart at once what a step just ended, for a learner that restarts an env on
        the step that ends its episode (stable-baselines3's ``VecEnv``, through
        :class:`bbgym.sb3.NativeVecEnvAdapter`): the races that ended start anew (all their
        boats; the draws are those the next step would make), and a boat ``mask`` names
        whose race goes on begins its wait (zero observations). Returns every boat's
        observation."""
        if self.state is None:
            raise RuntimeError("reset_envs() called before reset()")
        with self.backend.context():
            return self._reset_envs()

    def _reset_envs(self) -> Any:
        ended = self._ended.copy()
        if ended.any():
            self.state = self._select(ended, self._fresh(ended, {}), self.state)
            self._ended[ended] = False
            self._sitting_out[ended] = False
        return self._observe(self._sitting_out)

    @property
    def races_ended(self) -> np.ndarray:
        """The races that ended on the last step ``(num_races,)``: the next step (or
        :meth:`reset_envs`) starts them anew. A copy."""
        return self._ended.copy()

    def _observe(self, blank: np.ndarray | None = None) -> Any:
        """Every boat's observation, as :attr:`backend` outputs it; ``blank`` boats' zero."""
        xp = self.xp
        obs = self._observation(self.state)
        if blank is not None:
            obs = xp.where(self._array(blank)[:, :, None], xp.zeros_like(obs), obs)
        obs = xp.reshape(obs, (self.num_envs, -1))
        return obs if self.backend.output != "numpy" else backends.to_numpy(obs)

    def _output(self, values: np.ndarray) -> Any:
        """A NumPy result as :attr:`backend` outputs it."""
        if self.backend.output == "numpy":
            return values
        if self.backend.name == "jax":
            import jax

            return jax.device_put(values, self.backend.jax_device)
        return self.xp.asarray(values, device=self.backend.device)

    def _info(self) -> dict[str, Any]:
        def flat(a: Any) -> np.ndarray:
            a = np.asarray(backends.to_numpy(a))
            return a.reshape(self.num_envs, *a.shape[2:])

        return vector_info(tree_map(flat, self.task.info(self.state, self.xp)), self.num_envs)
