"""bbgym's envs for JAX users, in gymnax's shape: pure ``reset(key, params)`` and ``step(key,
state, action, params)`` over one env, that ``jax.jit``, ``jax.vmap`` and ``jax.lax.scan``
take like any gymnax env, so that a learner and its envs compile into one program
(PureJaxRL, rejax).

``env, params = bbgym.jax_env.make(env_id)`` gives the env and its default
params. The observation, the reward and the ends are those of the Gymnasium id: the same
task core runs in both (:mod:`bbgym.envs.functional`), and an episode here equals sub-env
``i`` of the native vector env on ``backend="jax"`` whose keys it shares
(:func:`vector_keys`), its autoreset steps left out.

What differs from the Gymnasium ids, as in gymnax:

- **Autoreset on the same step.** A step that ends an episode returns the reward and
  ``done`` of its last transition with the *next* episode's first observation and state;
  ``info["terminated"]``, ``info["truncated"]``, ``info["discount"]`` and the task's infos
  describe the step's last transition (before the restart).
- **The randomness is in the state.** ``reset`` turns its key into the env's 32-bit key;
  every later draw (gusts, the next episode's start) comes from that key and the state's
  step counter (:mod:`bbgym.backends`' counter-based generator), so an episode is a pure
  function of the reset key and the actions; ``step``'s key is not drawn from.
- **Params are a pytree.** :class:`EnvParams` holds the time limit and the arguments the
  family lets vary inside a program (its spec's ``jax_params``, e.g. the dinghy's mass
  or the wind's range): ``jax.vmap`` over a batch of them randomizes physical constants
  per env. Inside a program nothing can raise, so :meth:`JaxEnv.check_params` checks the
  concrete values first, naming the argument.
- **float32** by default (``dtype="float64"`` needs ``jax_enable_x64`` on in the process).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np

from bbgym import backends
from bbgym.envs.functional import (
    VectorStep,
    columns_to_observation,
    counter_initial_noise,
    rolled_chunks,
    tree_map,
    tree_select,
)


class EnvParams(NamedTuple):
    """An env's params (a pytree: ``jax.vmap`` batches every leaf).

    Attributes:
        max_steps_in_episode: the time limit in steps (the id's registered one).
        arguments: the task arguments that may vary, by their path as the Gymnasium id
            takes them (``{"dinghy": {"mass_kg": 100.0}, "wind_speed_range": (3.0, 7.0)}``).
    """

    max_steps_in_episode: Any
    arguments: dict[str, Any]


class EnvState(NamedTuple):
    """One env's state (a pytree of arrays, each with a leading axis of one).

    Attributes:
        task: the task core's state.
        key: the env's 32-bit key (uint32).
        counter: its step counter (uint32): draw ``k`` of step ``n`` is a hash of both.
        time: steps taken in the episode (int32).
    """

    task: Any
    key: Any
    counter: Any
    time: Any


class Box(NamedTuple):
    """A box space in gymnax's shape: ``low``, ``high``, ``shape``, ``dtype``,
    :meth:`sample` and :meth:`contains`.

    Attributes:
        low: the lower bound.
        high: the upper bound.
        shape: the shape of one element.
        dtype: the element type.
    """

    low: float
    high: float
    shape: tuple[int, ...]
    dtype: Any

    def sample(self, key: Any) -> Any:
        """A uniform draw in the box.

        Args:
            key: a ``jax.random`` key.

        Returns:
            An array of :attr:`shape`.
        """
        import jax

        return jax.random.uniform(key, self.shape, self.dtype, self.low, self.high)

    def contains(self, x: Any) -> Any:
        """Whether ``x`` lies in the box.

        Args:
            x: an array of :attr:`shape`.

        Returns:
            A bool array (traceable).
        """
        import jax.numpy as jnp

        return jnp.all((x >= self.low) & (x <= self.high))


def vector_keys(seed: int, num_envs: int) -> Any:
    """The env keys the native vector env gives its sub-envs for ``reset(seed=seed)``
    (:func:`bbgym.backends.env_keys`), as uint32: :meth:`JaxEnv.reset_from_key` with key
    ``i`` starts sub-env ``i``'s episode.

    Args:
        seed: the vector env's reset seed.
        num_envs: how many keys.

    Returns:
        A ``(num_envs,)`` uint32 array.
    """
    import jax.numpy as jnp

    return jnp.asarray(backends.env_keys(seed, num_envs, np).astype(np.uint32))


def _get(tree: Mapping[str, Any], path: str) -> Any:
    for part in path.split("."):
        tree = tree[part]
    return tree


def _nest(flat: Mapping[str, Any]) -> dict[str, Any]:
    """``{"dinghy.mass_kg": v}`` as ``{"dinghy": {"mass_kg": v}}``."""
    nested: dict[str, Any] = {}
    for path, value in flat.items():
        *groups, name = path.split(".")
        where = nested
        for group in groups:
            where = where.setdefault(group, {})
        where[name] = value
    return nested


def _merge(base: Mapping[str, Any], top: Mapping[str, Any]) -> dict[str, Any]:
    """``base`` with ``top``'s entries, mappings merged key by key."""
    out = dict(base)
    for key, value in top.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


class JaxEnv:
    """One bbgym env as gymnax's ``Environment``: see the module docstring.

    Args:
        env_id: a registered id (the ``bbgym/`` prefix optional).
        dtype: ``"float32"`` (the default) or ``"float64"`` (needs ``jax_enable_x64``).
        vary: the argument paths the params hold, among the family's ``jax_params``
            (None: all of them; ``()``: none, so every argument is a constant of the
            program, which compiles faster and may step faster).
        **kwargs: the task's arguments on top of the id's, as ``gym.make`` takes them
            (checked as there).

    Raises:
        TypeError: for an unknown or ill-typed argument, naming it.
        ValueError: for a value out of its interval, naming it, a ``dtype`` not
            ``"float32"``/``"float64"``, or a ``vary`` path the family does not vary.
    """

    def __init__(
        self,
        env_id: str,
        dtype: str = "float32",
        vary: tuple[str, ...] | list[str] | None = None,
        **kwargs: Any,
    ) -> None:
        import gymnasium as gym

        from bbgym.spec import spec_of

        if dtype not in backends.DTYPES:
            raise ValueError(f"dtype must be one of {list(backends.DTYPES)}, got {dtype!r}")
        self.dtype = dtype
        vec = gym.make_vec(env_id, num_envs=1, vectorization_mode="vector_entry_point", **kwargs)
        self.env_id = vec.unwrapped.spec.id if vec.unwrapped.spec else env_id
        self._task0 = vec.unwrapped.task
        self._max_steps = vec.unwrapped.max_episode_steps
        self._kwargs = dict(gym.spec(self.env_id).kwargs)
        self._kwargs = _merge(self._kwargs, kwargs)
        self._task_class = type(self._task0)
        vec.close()
        self.spec = spec_of(self.env_id)
        allowed = tuple(self.spec.jax_params)
        vary = allowed if vary is None else tuple(vary)
        unknown = [path for path in vary if path not in allowed]
        if unknown:
            raise ValueError(f"vary: {unknown} cannot vary in {self.env_id}; these can: {allowed}")
        self.varying = vary
        """The argument paths :attr:`default_params` holds (``vary``)."""

    # -- gymnax's API --------------------------------------------------------------------
    @property
    def name(self) -> str:
        """The Gymnasium id."""
        return self.env_id

    @property
    def num_actions(self) -> int:
        """The action's size."""
        return int(self._task0.action_space.shape[0])

    @property
    def default_params(self) -> EnvParams:
        """The id's own params: its time limit and its values of the varying arguments
        (floats, or pairs of floats for a range)."""
        arguments = {}
        for path in self.varying:
            value = self._argument_value(path)
            arguments[path] = tuple(float(v) for v in value) if isinstance(value, tuple) else value
        return EnvParams(self._max_steps, _nest(arguments))

    def observation_space(self, params: EnvParams | None = None) -> Box:
        """The observation space (one env's), in [-1, 1], float32.

        Args:
            params: unused (gymnax's signature).

        Returns:
            The space, a :class:`Box`.
        """
        import jax.numpy as jnp

        return Box(-1.0, 1.0, tuple(self._task0.observation_space.shape), jnp.float32)

    def action_space(self, params: EnvParams | None = None) -> Box:
        """The action space (one env's), in [-1, 1].

        Args:
            params: unused (gymnax's signature).

        Returns:
            The space, a :class:`Box`.
        """
        import jax.numpy as jnp

        return Box(-1.0, 1.0, tuple(self._task0.action_space.shape), jnp.float32)

    def reset(self, key: Any, params: EnvParams | None = None) -> tuple[Any, EnvState]:
        """A new episode from a ``jax.random`` key.

        Args:
            key: a ``jax.random`` key: it gives the env its 32-bit key.
            params: the params (None: :attr:`default_params`).

        Returns:
            ``(obs, state)``: the first observation, ``(obs_size,)`` float32, and the state.
        """
        import jax
        import jax.numpy as jnp

        return self.reset_from_key(jax.random.bits(key, (1,), jnp.uint32)[0], params)

    def reset_env(self, key: Any, params: EnvParams) -> tuple[Any, EnvState]:
        """:meth:`reset` (gymnax's inner name).

        Args:
            key: a ``jax.random`` key.
            params: the params.

        Returns:
            ``(obs, state)``.
        """
        return self.reset(key, params)

    def reset_from_key(self, env_key: Any, params: EnvParams | None = None) -> tuple:
        """A new episode from the env's 32-bit key itself (:func:`vector_keys` gives the
        native vector env's).

        Args:
            env_key: a uint32 scalar.
            params: the params (None: :attr:`default_params`).

        Returns:
            ``(obs, state)``.
        """
        import jax.numpy as jnp

        params = self.default_params if params is None else params
        xp, dtype = self._xp(), self._float()
        task = self._task(params)
        keys = jnp.reshape(jnp.asarray(env_key, dtype=jnp.uint32), (1,))
        counter = jnp.zeros(1, dtype=jnp.uint32)
        state = task.initial(counter_initial_noise(task, keys, counter, dtype, xp), {}, xp)
        obs = self._observe(task, state)
        return obs, EnvState(state, keys, counter + 1, jnp.zeros(1, dtype=jnp.int32))

    def step(
        self, key: Any, state: EnvState, action: Any, params: EnvParams | None = None
    ) -> tuple[Any, EnvState, Any, Any, dict[str, Any]]:
        """One step, and a new episode in place of one that ended (see the module
        docstring).

        Args:
            key: a ``jax.random`` key (not drawn from: the state holds the randomness).
            state: the state.
            action: ``(action_size,)``, clipped to [-1, 1].
            params: the params (None: :attr:`default_params`).

        Returns:
            ``(obs, state, reward, done, info)``: ``done`` is ``terminated | truncated``,
            and ``info`` holds both, ``discount`` (0 where terminated) and the task's
            infos of the step's last transition.
        """
        import jax.numpy as jnp

        params = self.default_params if params is None else params
        xp, dtype = self._xp(), self._float()
        task = self._task(params)
        step = VectorStep(task, params.max_steps_in_episode, xp, dtype)
        action = xp.clip(xp.reshape(xp.asarray(action, dtype=dtype), (1, -1)), -1.0, 1.0)
        carry = rolled_chunks(task, step.begin(state.task, action, state.key, state.counter), xp)
        no_restart = jnp.zeros(1, dtype=bool)
        moved, reward, terminated, truncated, counter, time = step.end(
            state.task, carry, state.counter, state.time, no_restart
        )
        done = terminated | truncated
        # The episode after: the draws the vector env's restart makes on its next step
        # (at this counter), and the counter that step leaves.
        fresh = task.initial(counter_initial_noise(task, state.key, counter, dtype, xp), {}, xp)
        new = EnvState(
            tree_select(done, fresh, moved, xp),
            state.key,
            xp.where(done, counter + 1, counter),
            xp.where(done, 0, time).astype(jnp.int32),
        )
        info = tree_map(lambda v: v[0], task.info(moved, task.measure(moved, xp), xp))
        info.update(
            terminated=terminated[0],
            truncated=truncated[0],
            discount=1.0 - terminated[0].astype(dtype),
        )
        return self._observe(task, new.task), new, reward[0], done[0], info

    def step_env(
        self, key: Any, state: EnvState, action: Any, params: EnvParams
    ) -> tuple[Any, EnvState, Any, Any, dict[str, Any]]:
        """:meth:`step` (gymnax's inner name; the autoreset is the task's own here).

        Args:
            key: a ``jax.random`` key.
            state: the state.
            action: the action.
            params: the params.

        Returns:
            ``(obs, state, reward, done, info)``, as :meth:`step` returns them.
        """
        return self.step(key, state, action, params)

    # -- params ---------------------------------------------------------------------------
    def check_params(self, params: EnvParams) -> EnvParams:
        """Check concrete params (a batch too) before they go into a program: every value
        of every varying argument is built into the task as ``gym.make`` would, so a bad
        one raises there, naming the argument and the batch entry.

        Args:
            params: params with concrete leaves (floats or arrays, batched or not).

        Returns:
            ``params`` unchanged.

        Raises:
            TypeError: for an argument the family does not vary (naming it).
            ValueError: for a value out of its interval, naming ``path[i]``.
        """
        flat = self._flat(params.arguments)
        unknown = [p for p in flat if p not in self.varying]
        if unknown:
            raise TypeError(f"params.arguments: {unknown} do not vary; these do: {self.varying}")
        steps = np.asarray(params.max_steps_in_episode)
        if steps.dtype.kind not in "iu" or np.any(steps < 1):
            raise ValueError(
                f"params.max_steps_in_episode must be ints >= 1, got {params.max_steps_in_episode}"
            )
        values = {path: np.asarray(value, dtype=float) for path, value in flat.items()}
        batch = max([v.shape[0] for p, v in values.items() if v.ndim > self._rank(p)] or [1])
        for i in range(batch):
            chosen = {}
            for path, v in values.items():
                one = v[i] if v.ndim > self._rank(path) else v
                chosen[path] = tuple(one.tolist()) if one.ndim else float(one)
            try:
                self._task_class(**_merge(self._base_arguments(), _nest(chosen)))
            except (TypeError, ValueError) as error:
                where = f" (batch entry {i})" if batch > 1 else ""
                raise type(error)(f"params.arguments: {error}{where}") from None
        return params

    def _rank(self, path: str) -> int:
        return 1 if isinstance(self._argument_value(path), tuple) else 0

    def _argument_value(self, path: str) -> Any:
        """The task's value of an argument path (what the id's task was built with)."""
        group, _, name = path.partition(".")
        if not name:
            return getattr(self._task0, group)
        return getattr(self._group(group), name)

    def _group(self, group: str) -> Any:
        """The task's parameter dataclass that the argument ``group`` built (the
        ``dinghy`` argument builds ``DinghyParams``, kept as the task's ``params``)."""
        cls = self.spec.param_groups[group]
        found = getattr(self._task0, group, None)
        if isinstance(found, cls):
            return found
        return next(a for a in vars(self._task0).values() if type(a) is cls)

    def _base_arguments(self) -> dict[str, Any]:
        """The id's arguments with each varying group in full (its dataclass's fields as
        the task has them): the params then replace single fields of it."""
        import dataclasses

        groups = {path.partition(".")[0] for path in self.varying if "." in path}
        full = {
            group: {f.name: getattr(self._group(group), f.name) for f in dataclasses.fields(cls)}
            for group in groups
            for cls in (self.spec.param_groups[group],)
        }
        return _merge(self._kwargs, full)

    @staticmethod
    def _flat(arguments: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
        flat: dict[str, Any] = {}
        for key, value in arguments.items():
            if isinstance(value, Mapping):
                flat.update(JaxEnv._flat(value, f"{prefix}{key}."))
            else:
                flat[f"{prefix}{key}"] = value
        return flat

    def _task(self, params: EnvParams) -> Any:
        """The task with the params' arguments (traced values pass its checks through)."""
        return self._task_class(**_merge(self._base_arguments(), params.arguments))

    # -- helpers ----------------------------------------------------------------------------
    def _xp(self) -> Any:
        import jax

        if self.dtype == "float64" and not jax.config.jax_enable_x64:
            raise ValueError(
                "dtype='float64' needs jax_enable_x64 on: jax.config.update('jax_enable_x64', "
                "True) at the start of the program, or use dtype='float32'"
            )
        return backends.jax_namespace(self.dtype == "float64")

    def _float(self) -> Any:
        return getattr(self._xp(), self.dtype)

    def _observe(self, task: Any, state: Any) -> Any:
        xp = self._xp()
        columns = task.observation(state, task.measure(state, xp), xp)
        return columns_to_observation(columns, xp)[0]

    def __repr__(self) -> str:
        return f"JaxEnv({self.env_id!r}, dtype={self.dtype!r})"


def make(
    env_id: str,
    dtype: str = "float32",
    vary: tuple[str, ...] | list[str] | None = None,
    **kwargs: Any,
) -> tuple[JaxEnv, EnvParams]:
    """A bbgym env for JAX and its default params, as ``gymnax.make`` returns them.

    Args:
        env_id: a registered id.
        dtype: ``"float32"`` or ``"float64"`` (needs ``jax_enable_x64``).
        vary: the arguments the params hold (:class:`JaxEnv`; None: the family's all).
        **kwargs: the task's arguments on top of the id's.

    Returns:
        ``(env, env.default_params)``.
    """
    env = JaxEnv(env_id, dtype, vary, **kwargs)
    return env, env.default_params


__all__ = ["Box", "EnvParams", "EnvState", "JaxEnv", "make", "vector_keys"]
