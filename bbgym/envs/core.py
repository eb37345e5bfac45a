"""The two thin adapters every env is made of: :class:`CoreEnv`, a ``gymnasium.Env`` on
Python floats, and :class:`CoreVectorEnv`, a native ``gymnasium.vector.VectorEnv`` on NumPy
or compiled torch. Both run a task core of :mod:`bbgym.envs.functional`; the vector step's
autoreset is :func:`~bbgym.envs.functional.settle` and
:func:`~bbgym.envs.functional.restart`, the same functions on every backend.
"""

from __future__ import annotations

import inspect
from contextlib import nullcontext
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from bbgym import backends
from bbgym.envs.common import (
    LIST_MODE,
    RENDER_MODES,
    NormalStreams,
    check_render_mode,
    check_seed,
    ensure_renderer,
    vector_info,
    vector_seeds,
    without_renderer,
)
from bbgym.envs.functional import (
    InitialNoise,
    VectorStep,
    columns_to_observation,
    counter_initial_noise,
    element,
    restart,
    select_info,
    settle,
    task_info_names,
    tree_map,
)
from bbgym.physics.namespace import floats
from bbgym.spec import spec_of_class


class CoreEnv(gym.Env[np.ndarray, np.ndarray]):
    """A single env over a task core, on Python floats, seeded from ``np_random``.

    A subclass sets ``metadata`` and ``task_class`` and implements ``_make_renderer`` and
    ``_scene`` (and ``_flight_scenes`` where a step is a flight); ``_on_reset`` /
    ``_on_step`` hooks follow a reset and a step.

    Rendering: ``rgb_array`` draws the state now; ``human`` shows it in a window after every
    reset and step, a step's flight first; ``rgb_array_list`` (Gymnasium's convention, as
    :class:`gymnasium.wrappers.RenderCollection` makes it) collects the frames of the reset
    and of every step since, each step's flight (``_flight_scenes``) then its end, and
    ``render()`` returns them as a list and clears it. The frames are collected as drawing
    descriptions and drawn by ``render()``: a step costs no drawing until then.
    """

    metadata: dict[str, Any] = {"render_modes": list(RENDER_MODES)}
    task_class: type

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        check_render_mode(render_mode, self.metadata["render_modes"])
        check_single_env_arguments(type(self).__name__, kwargs)
        self.task = self.task_class(**kwargs)
        self.render_mode = render_mode
        self.action_space = self.task.action_space
        self.observation_space = self.task.observation_space
        self.state: Any = None
        self.events: Any = None
        self.streams = NormalStreams(1)
        self._measures: Any = None
        self._renderer: Any = None
        self._animate = False
        self._collected: list[Any] = []  # rgb_array_list: scenes not yet rendered
        self._init_host_state()

    def _init_host_state(self) -> None:
        """Hook: set up what the env keeps on the host beside its state (a wake to draw,
        the last records), once the task and spaces exist."""

    @property
    def started(self) -> bool:
        return self.state is not None

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=None if seed is None else check_seed(seed))
        options = self.task.check_options(options)
        self.streams.set(0, self.np_random)
        n_uniform, n_normal = self.task.initial_noise_counts
        uniform = self.np_random.random(n_uniform).tolist()
        normal = self.np_random.standard_normal(n_normal).tolist()
        self.streams.discard(np.ones(1, dtype=bool))
        stream = []
        for _ in range(self.task.initial_stream_pairs):
            stream += self.streams.one(True)
        self.state = self.task.initial(InitialNoise(uniform, normal, stream), options, floats)
        self._measures = self.task.measure(self.state, floats)
        self._on_reset()
        if self.render_mode == "human":
            self.render()
        elif self.render_mode == LIST_MODE:
            self._collected = [self._scene()]
        return self._observation(), self._info()

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if not self.started:
            raise gym.error.ResetNeeded("Call reset() before step()")
        a = self.task.check_action(action, 0)
        mask = self.task.step_noise_mask(self.state, floats)
        pairs = self.task.step_noise_pairs
        if pairs == 1:
            noise: Any = self.streams.one(mask)
        elif pairs:
            noise = self.streams.peek(np.array([mask]), pairs)[..., 0].reshape(-1).tolist()
        else:
            noise = ()
        self.state, self.events = self.task.transition(
            self.state, a, noise, floats, record=self.records
        )
        if pairs > 1:
            self.streams.advance(np.array([self.events.noise_used]))
        self._measures = self.task.measure(self.state, floats)
        self._on_step(a)
        if self.render_mode == "human":
            self._animate = True
            self.render()
        elif self.render_mode == LIST_MODE:
            scene = self._scene()
            self._collected += [*self._flight_scenes(scene), scene]
        reward = self.task.reward(self.state, floats)
        terminated = self.task.terminal(self.state, floats)
        return self._observation(), float(reward), bool(terminated), False, self._info()

    def _observation(self) -> np.ndarray:
        columns = self.task.observation(self.state, self._measures, floats)
        # clip the floats first: one small array, no temporaries
        return np.array([min(max(c, -1.0), 1.0) for c in columns], dtype=np.float32)

    records = True
    """Whether transitions keep the samples a renderer or ``info`` needs (``events``)."""

    def _info(self) -> dict[str, Any]:
        info = self.task.info(self.state, self._measures, floats)
        info.update(self._step_info())
        return info

    def _step_info(self) -> dict[str, Any]:
        """Hook: info entries from the last transition's ``events`` ({} after a reset)."""
        return {}

    def _on_reset(self) -> None:
        """Hook: the env has just been reset."""

    def _on_step(self, action: Any) -> None:
        """Hook: a step with ``action`` has just been taken."""

    def render(self) -> np.ndarray | list[np.ndarray] | None:
        """``rgb_array``: the frame of the state now, ``(H, W, 3)`` uint8. ``rgb_array_list``:
        the frames collected since the last ``render()`` or ``reset()`` (the reset's, then
        per step its flight and its end), a list, cleared. ``human``: ``None`` (the window
        shows every reset and step by itself)."""
        renderer = ensure_renderer(self)
        if renderer is None:
            return None
        if self.render_mode == LIST_MODE:
            scenes, self._collected = self._collected, []
            return [renderer.render(s) for s in scenes]
        scene = self._scene()
        if self._animate:
            # Human mode plays a new step's flight in real time, then shows where it ended.
            self._animate = False
            for flight_scene in self._flight_scenes(scene):
                renderer.render(flight_scene)
        return renderer.render(scene)

    def _scene(self) -> Any:
        """The drawing description of the state now (the renderer does no physics)."""
        raise NotImplementedError

    def _flight_scenes(self, scene: Any) -> list[Any]:
        """The frames a step plays before ``scene``, its end (a flight); none by default."""
        return []

    def _make_renderer(self) -> Any:
        raise NotImplementedError

    def __getstate__(self) -> dict[str, Any]:
        return without_renderer(self.__dict__)

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def check_single_env_arguments(env_name: str, kwargs: dict[str, Any]) -> None:
    """Refuse, naming it, an argument only the native vector env takes (``backend``, ...)
    given to ``gym.make``: the task would raise a ``TypeError`` naming itself instead.

    Args:
        env_name: the env class's name, for the message.
        kwargs: the task arguments ``gym.make`` passed.

    Raises:
        UnknownArgumentError: for the first vector-only argument.
    """
    from bbgym.spec import UnknownArgumentError

    vector_only = inspect.signature(CoreVectorEnv.__init__).parameters
    for name in kwargs:
        if name in vector_only and name not in ("self", "render_mode", "kwargs"):
            raise UnknownArgumentError(
                f"{env_name} got {name!r}, an argument of its native vector env only: "
                f"gym.make_vec(id, num_envs=N, {name}=...)"
            )


class FlightFrames:
    """For a :class:`CoreEnv` whose step is a flight (a throw, an interval): the frames of
    the last step's flight, as human mode plays them and ``rgb_array_list`` collects them."""

    def render_flight(self) -> list[np.ndarray]:
        """The frames of the last step's flight, one per recorded sample (every 0.05 s, so
        ``render_fps`` plays it in real time), without the end frame that ``render()``
        returns; ``[]`` before the first step. These are the frames human mode shows after
        a step, and those ``rgb_array_list`` collects before a step's end. In ``rgb_array``
        and ``rgb_array_list`` mode: a list of ``(H, W, 3)`` uint8 arrays
        (``rgb_array_list``'s collected frames stay as they are); in ``human`` mode the
        flight is shown again and the list is empty."""
        renderer = ensure_renderer(self)
        if renderer is None:
            return []
        frames = [renderer.render(s) for s in self._flight_scenes(self._scene())]
        return [f for f in frames if f is not None]


def check_info_keys(info_keys: Any, task: Any) -> tuple[str, ...] | None:
    """``info_keys`` as a tuple of the task's info names (None: all), or an error naming
    ``info_keys``."""
    if info_keys is None:
        return None
    if isinstance(info_keys, str) or not isinstance(info_keys, (tuple, list)):
        raise TypeError(
            f"info_keys must be a list or tuple of info names or None, got {info_keys!r}"
        )
    names = task_info_names(task)
    unknown = [k for k in info_keys if k not in names]
    if unknown:
        raise ValueError(
            f"info_keys: {unknown} are not infos of this env; its infos: {', '.join(names)}"
        )
    return tuple(info_keys)


def check_tensor_actions(actions: Any, shape: tuple[int, ...], backend: Any) -> Any:
    """A batch of actions given as a tensor, on the backend's device and float dtype and
    clipped to [-1, 1]; a complex tensor raises ``TypeError``, a wrong shape or a NaN/inf
    ``ValueError`` naming the rows, as the NumPy check does.

    Args:
        actions: a torch tensor of shape ``shape``.
        shape: the vector env's action shape ``(num_envs, size)``.
        backend: the env's :class:`bbgym.backends.Backend`.

    Returns:
        The checked, clipped tensor.
    """
    if actions.is_complex():  # a cast would drop the imaginary part with a mere warning
        raise TypeError(f"actions must be real, got a {actions.dtype} tensor")
    if tuple(actions.shape) != tuple(shape):
        raise ValueError(f"actions must have shape {tuple(shape)}, got {tuple(actions.shape)}")
    a = actions.to(device=backend.device, dtype=backend.float_dtype)
    # One reduction and a device sync a step: a NaN row would otherwise poison that env's
    # state for the rest of its episode, silently (an inf clips to a valid action, but a
    # learner that emits one is broken, and NumPy refuses it too).
    finite = a.isfinite().all(dim=-1)
    if not bool(finite.all()):
        rows = [int(i) for i in (~finite).nonzero().flatten()[:8]]
        raise ValueError(f"actions must be finite: rows {rows} hold NaN or inf")
    return a.clamp(-1.0, 1.0)


class CoreVectorEnv(VectorEnv):
    """A native vector env over a task core: ``num_envs`` envs in one batch.

    ``backend="numpy"`` (float64): the core runs op by op on NumPy, with each env's own
    random stream, so sub-env ``i`` reset with ``seed=s`` follows a single env reset with
    ``seed=s + i`` under the same actions. ``backend="torch"``: the whole step (transition,
    autoreset, observation, reward, termination, truncation, info and the random numbers)
    is compiled by ``torch.compile`` for ``device`` in ``dtype`` (as its parts or as one
    graph, ``step_graph``); observations,
    rewards and infos come back as NumPy arrays (zero-copy on the CPU) or, with
    ``output="torch"``, as tensors on the device. ``compile=False`` runs torch eagerly.
    ``step_graph`` says whether the step compiles as its parts or as one graph
    (:data:`bbgym.backends.STEP_GRAPHS`; by default one graph where that paid here).
    ``info_keys`` (a list of the task's info names) keeps only those infos, the others
    never computed (in a compiled step they drop out of the graph); None keeps all.

    Finished sub-envs reset on the next ``step`` (``AutoresetMode.NEXT_STEP``), which
    returns the new episode's first observation with reward 0 for them. The time limit
    (``max_episode_steps``) is applied here, since ``gym.make_vec`` adds no ``TimeLimit``
    wrapper to a native vector env. Infos are arrays with Gymnasium's ``_key`` masks.

    ``render()`` draws the first (up to 4) sub-envs: ``rgb_array`` a tuple of their frames,
    ``rgb_array_list`` a tuple of their lists of frames since the last ``render()`` or
    ``reset()`` (as ``SyncVectorEnv`` of such envs returns; a sub-env restarted by a step
    adds its new episode's first frame), ``human`` the first in a window. In
    ``rgb_array_list`` mode the frames wait (as drawing descriptions) for ``render()``:
    call it regularly, since autoreset never clears them.
    """

    metadata: dict[str, Any] = {
        "render_modes": list(RENDER_MODES),
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }
    task_class: type

    def __init__(
        self,
        num_envs: int = 1,
        render_mode: str | None = None,
        max_episode_steps: int | None = None,
        backend: str = "numpy",
        device: str | None = None,
        dtype: str = "float64",
        output: str = "numpy",
        compile: bool = True,
        step_graph: str = "auto",
        info_keys: tuple[str, ...] | list[str] | None = None,
        **kwargs: Any,
    ) -> None:
        if max_episode_steps is None:
            # One source for the time limit: the family's spec, as gym.make's TimeLimit.
            max_episode_steps = spec_of_class(type(self)).max_episode_steps
        if not isinstance(num_envs, (int, np.integer)) or isinstance(num_envs, (bool, np.bool_)):
            raise TypeError(f"num_envs must be an int >= 1, got {num_envs!r}")
        if num_envs < 1:
            raise ValueError(f"num_envs must be an int >= 1, got {num_envs!r}")
        if not isinstance(max_episode_steps, (int, np.integer)) or max_episode_steps < 1:
            raise ValueError(f"max_episode_steps must be an int >= 1, got {max_episode_steps!r}")
        check_render_mode(render_mode, self.metadata["render_modes"])
        self.backend = backends.resolve_backend(backend, device, dtype, output, compile, step_graph)
        self.task = self.task_class(**kwargs)
        self.info_keys = check_info_keys(info_keys, self.task)
        self.num_envs = int(num_envs)
        self.max_episode_steps = int(max_episode_steps)
        self.render_mode = render_mode
        self.single_action_space = self.task.action_space
        self.single_observation_space = self.task.observation_space
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.state: Any = None
        self.events: Any = None
        self.streams = NormalStreams(self.num_envs)
        self._steps: Any = None
        self._autoreset: Any = None
        self._keys: Any = None
        self._counter: Any = None
        self._compiled_step: Any = None
        self._any_restarting: bool | None = None
        self._renderer: Any = None
        self._collected: list[list[Any]] = []  # rgb_array_list: per drawn sub-env
        self._init_host_state()

    def _init_host_state(self) -> None:
        """Hook: set up what the env keeps on the host beside its batched state (the drawn
        sub-envs' wakes, the last records), once the task, spaces and backend exist."""

    @property
    def started(self) -> bool:
        return self.state is not None

    @property
    def xp(self) -> Any:
        return self.backend.xp

    # -- the NumPy reference path -------------------------------------------------------------
    def _initial_noise(self, mask: np.ndarray) -> InitialNoise:
        """Each env in ``mask`` draws from its own generator (zeros elsewhere)."""
        n_uniform, n_normal = self.task.initial_noise_counts
        uniform = np.zeros((n_uniform, self.num_envs))
        normal = np.zeros((n_normal, self.num_envs))
        for i in np.flatnonzero(mask):
            rng = self.streams.rngs[i]
            uniform[:, i] = rng.random(n_uniform)
            normal[:, i] = rng.standard_normal(n_normal)
        self.streams.discard(mask)
        stream = [self.streams.pairs(mask) for _ in range(self.task.initial_stream_pairs)]
        # sequences of per-env rows: what a core indexes (noise.uniform[k])
        return InitialNoise(list(uniform), list(normal), [row for pair in stream for row in pair])

    def _restart(self, mask: np.ndarray, options: dict[str, Any]) -> None:
        """Fresh episodes for the envs in ``mask`` (:func:`restart`), each from its own
        random stream: a generator per env on NumPy, the counter-based one on torch."""
        if self.backend.name == "numpy":
            self.state = restart(
                self.task, self.state, mask, self._initial_noise(mask), options, np
            )
            return
        xp, m = self.xp, self._tensor(mask)
        noise = counter_initial_noise(
            self.task, self._keys, self._counter, self.backend.float_dtype, xp
        )
        state = restart(self.task, self.state, m, noise, options, xp)
        # Distinct tensors per leaf: the compiled step's guards would otherwise see the
        # fields a fresh state shares (zeros) as aliases, and recompile once they part.
        self.state = tree_map(lambda t: t.clone(), state)
        self._counter = self._counter + xp.astype(m, xp.int64)

    # -- the torch path -----------------------------------------------------------------------
    def _tensor(self, x: Any, dtype: Any = None) -> Any:
        import torch

        return torch.as_tensor(x, dtype=dtype, device=self.backend.device)

    @property
    def step_graph(self) -> str:
        """How the torch step runs, ``"parts"`` or ``"one"``: ``step_graph="auto"``
        resolved for this task, one graph where a compiled transition runs several chunks
        (eager torch, the reference the compiled step is tested against, runs the parts)."""
        graph = self.backend.step_graph
        if graph == "auto":
            graph = "one" if self.task.chunks > 1 and self.backend.compile else "parts"
        return graph

    def _make_compiled_step(self) -> Any:
        """The torch step: the parts of :class:`VectorStep`, each compiled, called one by
        one (``step_graph="parts"``), or the whole step as one compiled call
        (``step_graph="one"``, :meth:`VectorStep.fused`); eager without ``compile``."""
        step = VectorStep(
            self.task, self.max_episode_steps, self.xp, self.backend.float_dtype, self.info_keys
        )
        if self.step_graph == "one":
            fused = backends.compiled(step.fused, self.backend)

            def run_one(*args: Any, any_restarting: bool | None = None) -> tuple:
                return fused(*args)  # the restart is in the graph: no need to know

            return run_one
        parts = tuple(
            backends.compiled(f, self.backend)
            for f in (step.begin, step.chunk, step.end, step.restart, step.observe)
        )

        def run(*args: Any, any_restarting: bool | None = None) -> tuple:
            return step(*args, parts=parts, any_restarting=any_restarting)

        return run

    # -- Gymnasium's API ----------------------------------------------------------------------
    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[Any, dict[str, Any]]:
        options = self.task.check_options(options)
        everyone = np.ones(self.num_envs, dtype=bool)
        if seed is not None or not self.started:
            seeds = vector_seeds(seed, self.num_envs)
            self.streams.seed(seeds)
            if seed is not None:
                self._np_random, self._np_random_seed = seeding.np_random(seeds[0])
            if self.backend.name == "torch":
                self._seed_torch(seeds)
        self.state = None if self.backend.name == "torch" and seed is not None else self.state
        self._restart(everyone, options)
        if self.backend.name == "numpy":
            self._steps = np.zeros(self.num_envs, dtype=np.int64)
            self._autoreset = np.zeros(self.num_envs, dtype=bool)
        else:
            self._steps = self._tensor(np.zeros(self.num_envs, dtype=np.int64))
            self._autoreset = self._tensor(np.zeros(self.num_envs, dtype=bool))
            self._any_restarting = False
        self._on_reset(everyone)
        if self.render_mode == LIST_MODE:
            self._collected = [[] for _ in range(self._drawn_envs)]
            self._collect(everyone)
        m = self.task.measure(self.state, self.xp)
        obs = columns_to_observation(self.task.observation(self.state, m, self.xp), self.xp)
        info = select_info(self.task.info(self.state, m, self.xp), self.info_keys)
        if self.backend.name == "numpy":  # the host keeps the samples a renderer draws
            info = {**info, **self._step_info()}
        return self._out(obs), self._vector_info(info)

    def _seed_torch(self, seeds: list[int | None]) -> None:
        base = seeds[0]
        if base is None:
            base = int(np.random.SeedSequence().generate_state(1)[0])
        keys = np.array(
            [
                backends.env_keys(s if s is not None else base + i, 1, np)[0]
                for i, s in enumerate(seeds)
            ]
        )
        self._keys = self._tensor(keys)
        self._counter = self._tensor(np.zeros(self.num_envs, dtype=np.int64))

    def step(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        if not self.started:
            raise gym.error.ResetNeeded("Call reset() before step()")
        if self.backend.name == "torch":
            return self._step_torch(actions)
        a = self.task.check_action(actions, self.num_envs)
        restarting = self._autoreset
        active = ~restarting
        mask = self.task.step_noise_mask(self.state, np) & active
        pairs = self.task.step_noise_pairs
        if pairs == 1:
            noise: Any = tuple(self.streams.pairs(mask))
        elif pairs:
            noise = tuple(self.streams.peek(mask, pairs).reshape(2 * pairs, self.num_envs))
        else:
            noise = ()
        self.state, self.events = self.task.transition(
            self.state, a, noise, np, record=self.records
        )
        if pairs > 1:
            self.streams.advance(np.where(active, self.events.noise_used, 0))
        reward, terminated, truncated, self._steps = settle(
            self.task, self.state, restarting, self._steps, self.max_episode_steps, np
        )
        if restarting.any():
            # Next-step autoreset: the finished envs start anew and ignore this action.
            self._restart(restarting, {})
            self._on_reset(restarting)
        self._autoreset = terminated | truncated
        self._on_step(a)
        if self.render_mode == LIST_MODE:
            self._collect(restarting)
        m = self.task.measure(self.state, np)
        obs = columns_to_observation(self.task.observation(self.state, m, np), np)
        info = select_info(self.task.info(self.state, m, np), self.info_keys)
        info = self._vector_info({**info, **self._step_info()})
        return obs, reward.astype(np.float64), terminated, truncated, info

    records = True
    """Whether NumPy transitions keep the samples a renderer or ``info`` needs (the torch
    backend never does: its step stays on the device)."""

    def _step_info(self) -> dict[str, Any]:
        """Hook: info entries from the last NumPy transition's ``self.events`` (arrays of
        the batch, or object arrays), {} after a reset."""
        return {}

    def _step_torch(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        if hasattr(actions, "detach"):  # a tensor from a GPU-resident learner
            a = check_tensor_actions(actions, self.action_space.shape, self.backend)
        else:
            a = self._tensor(
                self.task.check_action(actions, self.num_envs), self.backend.float_dtype
            )
        any_restarting = self._any_restarting
        first = self._compiled_step is None
        if first:
            self._compiled_step = self._make_compiled_step()
            # The first step runs the restart part too (where no env restarts it changes
            # nothing), so every part compiles now rather than when the first episode ends.
            any_restarting = True
        restarting = self._autoreset
        with self._compile_logged() if first and self.backend.compile else nullcontext():
            out = self._compiled_step(
                self.state,
                a,
                self._keys,
                self._counter,
                self._steps,
                restarting,
                any_restarting=any_restarting,
            )
        self.state, obs, reward, terminated, truncated, info, self._counter, self._steps = out
        self._autoreset = terminated | truncated
        self._any_restarting = None
        if self.backend.output == "numpy":  # the host has the ends: no sync next step
            terminated, truncated = backends.to_numpy(terminated), backends.to_numpy(truncated)
            self._any_restarting = bool(terminated.any() or truncated.any())
        if self._wants_reset_hook:
            self._on_reset(backends.to_numpy(restarting))
        self._on_step(a)
        if self.render_mode == LIST_MODE:
            self._collect(np.asarray(backends.to_numpy(restarting), dtype=bool))
        return (
            self._out(obs),
            self._out(reward),
            self._out(terminated),
            self._out(truncated),
            self._vector_info(info),
        )

    def _compile_logged(self) -> Any:
        """:func:`backends.compile_logged` for this env's first step (where its parts
        compile, for its task, batch size and dtype)."""
        name = self.spec.id if self.spec is not None else type(self.task).__name__
        return backends.compile_logged(
            f"the {name} step", self.backend, self.num_envs, self.step_graph
        )

    _wants_reset_hook = False
    """Subclasses that keep per-env host state (render wakes) set this."""

    def reset_envs(self, mask: np.ndarray) -> Any:
        """Restart the envs in ``mask`` now, without seeds (each continues its own random
        stream), and return every env's observation. Adapters whose API resets on the step
        that ends an episode (stable-baselines3) use this instead of waiting for the next
        ``step``."""
        mask = np.asarray(mask, dtype=bool)
        if mask.any():
            self._restart(mask, {})
            m = mask if self.backend.name == "numpy" else self._tensor(mask)
            self._steps = self.xp.where(m, 0, self._steps)
            self._autoreset = self._autoreset & self.xp.logical_not(m)
            self._any_restarting = None
            self._on_reset(mask)
            if self.render_mode == LIST_MODE and self._collected:
                for i in np.flatnonzero(mask[: self._drawn_envs]):
                    self._collected[i].append(self._scene_env(int(i)))
        m = self.task.measure(self.state, self.xp)
        return self._out(
            columns_to_observation(self.task.observation(self.state, m, self.xp), self.xp)
        )

    def _out(self, x: Any) -> Any:
        return x if self.backend.output == "torch" else backends.to_numpy(x)

    def _vector_info(self, info: dict[str, Any]) -> dict[str, Any]:
        return vector_info(tree_map(self._out, info), self.num_envs)

    def _on_reset(self, mask: np.ndarray) -> None:
        """Hook: envs in ``mask`` have just been reset."""

    def _on_step(self, actions: Any) -> None:
        """Hook: a step with ``actions`` has just been taken."""

    def element_state(self, i: int) -> Any:
        """Sub-env ``i``'s state as Python floats."""
        return element(self.state, i)

    @property
    def _drawn_envs(self) -> int:
        """How many sub-envs ``render()`` draws (the first)."""
        return 1 if self.render_mode == "human" else min(self.num_envs, 4)

    def render(self) -> tuple[np.ndarray, ...] | tuple[list[np.ndarray], ...] | None:
        """Frames of the first (up to 4) sub-envs: a tuple of frames (``rgb_array``) or of
        lists of frames since the last ``render()`` or ``reset()`` (``rgb_array_list``);
        ``human`` shows the first in a window and returns ``None``."""
        renderer = ensure_renderer(self)
        if renderer is None:
            return None
        if self.render_mode == LIST_MODE:
            collected = self._collected
            self._collected = [[] for _ in range(self._drawn_envs)]
            return tuple([renderer.render(s) for s in scenes] for scenes in collected)
        frames = tuple(renderer.render(self._scene_env(i)) for i in range(self._drawn_envs))
        return None if self.render_mode == "human" else frames

    def _collect(self, restarted: np.ndarray) -> None:
        """``rgb_array_list``: each drawn sub-env's frames of the reset or step just made: a
        restarted env's first frame, else the step's flight and its end."""
        for i in range(self._drawn_envs):
            scene = self._scene_env(i)
            if not restarted[i]:
                self._collected[i] += self._flight_scenes(scene)
            self._collected[i].append(scene)

    def _make_renderer(self) -> Any:
        raise NotImplementedError

    def _scene_env(self, i: int) -> Any:
        """The drawing description of sub-env ``i`` now."""
        raise NotImplementedError

    def _flight_scenes(self, scene: Any) -> list[Any]:
        """The frames a step plays before ``scene``, its end (a flight); none by default."""
        return []

    def __getstate__(self) -> dict[str, Any]:
        state = without_renderer(self.__dict__)
        state["_compiled_step"] = None  # a compiled function does not pickle: made on use
        return state

    def close_extras(self, **kwargs: Any) -> None:
        # (getattr: a constructor that raised, on bad arguments, made no renderer)
        if getattr(self, "_renderer", None) is not None:
            self._renderer.close()
            self._renderer = None
