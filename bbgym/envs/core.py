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
    TaskCore,
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

    Args:
        render_mode: one of ``metadata["render_modes"]`` (``"human"``, ``"rgb_array"``,
            ``"rgb_array_list"``), or None for no rendering.
        **kwargs: the task's arguments (the fields of its ``params_class``), checked by the
            task; an argument of the native vector env only is refused, naming it.
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
        # The one step order (functional.VectorStep) on Python floats; the draws from the
        # counter-based keys, or, for a "generator" task, from np_random (GeneratorDraws).
        self._stepper: VectorStep | None = None  # made on use (it holds no state to pickle)
        generator = self.task.randomness == "generator"
        self._draws = GeneratorDraws(self.streams, 1, one_env=True) if generator else None
        self._key: int | None = None
        self._counter = 0
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
        """Whether the env has been reset (it holds a state)."""
        return self.state is not None

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start a new episode (Gymnasium's ``Env.reset``).

        Args:
            seed: an int >= 0 that seeds the env (``np_random`` and the counter-based key,
                that of sub-env ``i`` of a vector env seeded ``seed - i``), or None to go on
                with the env's random stream (fresh entropy on the first reset).
            options: the task's reset options (:meth:`TaskCore.check_options`), or None.

        Returns:
            ``(observation, info)``: the ``(size,)`` float32 observation in [-1, 1] and the
            task's infos (Python floats and bools, small NumPy arrays).

        Raises:
            TypeError: for a seed that is not an int, or an unknown option, naming it.
            ValueError: for a negative seed or an option out of its interval.
        """
        super().reset(seed=None if seed is None else check_seed(seed))
        options = self.task.check_options(options)
        if self._draws is not None:
            self.streams.set(0, self.np_random)
            noise = self._draws.initial(self.task, True)
        else:
            if seed is not None or self._key is None:
                # The key of sub-env i of a vector env seeded seed - i (backends.env_keys).
                base = seed if seed is not None else int(self.np_random.integers(2**32))
                self._key, self._counter = int(backends.env_keys(base, 1, np)[0]), 0
            noise = counter_initial_noise(self.task, self._key, self._counter, float, floats)
            self._counter += 1
        self.state = restart(self.task, None, True, noise, options, floats)
        self._measures = self.task.measure(self.state, floats)
        self._on_reset()
        if self.render_mode == "human":
            self.render()
        elif self.render_mode == LIST_MODE:
            self._collected = [self._scene()]
        return self._observation(), self._info()

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """Take one step (Gymnasium's ``Env.step``).

        Args:
            action: an array-like of the action space's shape, checked by the task
                (:meth:`TaskCore.check_action`: a Box action is clipped to [-1, 1]).

        Returns:
            ``(observation, reward, terminated, truncated, info)``; ``truncated`` is always
            False here (``gym.make``'s ``TimeLimit`` truncates).

        Raises:
            gymnasium.error.ResetNeeded: before the first ``reset()``.
            ValueError: for an action of the wrong shape, or a NaN or inf.
        """
        if not self.started:
            raise gym.error.ResetNeeded("Call reset() before step()")
        a = self.task.check_action(action, 0)
        if self._stepper is None:
            self._stepper = VectorStep(self.task, None, floats, float)
        self._stepper.record = self.records
        self.state, self.events = self._stepper.transition(
            self.state, a, self._key, self._counter, True, self._draws
        )
        self._counter += 1
        self._measures = self.task.measure(self.state, floats)
        self._on_step(a)
        if self.render_mode == "human":
            self._animate = True
            self.render()
        elif self.render_mode == LIST_MODE:
            scene = self._scene()
            self._collected += [*self._flight_scenes(scene), scene]
        reward, terminated, _, _ = settle(self.task, self.state, False, 0, None, floats)
        return self._observation(), float(reward), bool(terminated), False, self._info()

    def _observation(self) -> np.ndarray:
        columns = self.task.observation(self.state, self._measures, floats)
        return columns_to_observation(columns, floats)

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
        shows every reset and step by itself).

        Returns:
            A frame, a list of frames, or None (``human``, or no ``render_mode``), by render
            mode as above.
        """
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
        return {**without_renderer(self.__dict__), "_stepper": None}

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


class GeneratorDraws:
    """The host draws of a task of ``randomness = "generator"`` (the versions made before
    the counter-based keys): each env's own ``numpy.random.Generator`` and its stream of
    normal pairs (:class:`~bbgym.envs.common.NormalStreams`), so sub-env ``i`` equals the
    single env seeded ``seed + i`` on NumPy. Their golden replays pin these bits; this is
    the one place they are drawn (torch draws those tasks' declared counts from the keys,
    :func:`~bbgym.envs.functional.counter_initial_noise`).

    Args:
        streams: every env's generator and pair stream.
        num_envs: how many envs draw.
        one_env: a single env on Python floats (its masks are Python bools).
    """

    def __init__(self, streams: NormalStreams, num_envs: int, one_env: bool = False) -> None:
        self.streams, self.num_envs, self.one_env = streams, num_envs, one_env

    def initial(self, task: TaskCore, mask: Any) -> InitialNoise:
        """A fresh episode's draws for the envs in ``mask`` (zeros elsewhere).

        Args:
            task: the task core (its declared counts).
            mask: which envs restart (``True`` for a single env).

        Returns:
            The draws, as floats for a single env or rows of the batch.
        """
        n_uniform, n_normal = task.initial_noise_counts
        if self.one_env:
            rng = self.streams.rngs[0]
            uniform = rng.random(n_uniform).tolist()
            normal = rng.standard_normal(n_normal).tolist()
            self.streams.discard(np.ones(1, dtype=bool))
            stream: list = []
            for _ in range(task.initial_stream_pairs):
                stream += self.streams.one(True)
            return InitialNoise(uniform, normal, stream)
        uniform_rows = np.zeros((n_uniform, self.num_envs))
        normal_rows = np.zeros((n_normal, self.num_envs))
        for i in np.flatnonzero(mask):
            rng = self.streams.rngs[i]
            uniform_rows[:, i] = rng.random(n_uniform)
            normal_rows[:, i] = rng.standard_normal(n_normal)
        self.streams.discard(mask)
        pairs = [self.streams.pairs(mask) for _ in range(task.initial_stream_pairs)]
        # sequences of per-env rows: what a core indexes (noise.uniform[k])
        rows = [row for pair in pairs for row in pair]
        return InitialNoise(list(uniform_rows), list(normal_rows), rows)

    def step_noise(self, task: TaskCore, state: Any, active: Any) -> Any:
        """A step's pairs of normals (``task.step_noise_pairs``) for the active envs of
        ``task.step_noise_mask``.

        Args:
            task: the task core.
            state: the state before the step.
            active: which envs step (``True`` for a single env).

        Returns:
            A sequence of ``2 * step_noise_pairs`` rows (floats for a single env).
        """
        pairs = task.step_noise_pairs
        if self.one_env:
            mask = task.step_noise_mask(state, floats)
            if pairs == 1:
                return self.streams.one(mask)
            if pairs:
                return self.streams.peek(np.array([mask]), pairs)[..., 0].reshape(-1).tolist()
            return ()
        mask = task.step_noise_mask(state, np) & active
        if pairs == 1:
            return tuple(self.streams.pairs(mask))
        if pairs:
            return tuple(self.streams.peek(mask, pairs).reshape(2 * pairs, self.num_envs))
        return ()

    def stepped(self, task: TaskCore, events: Any, active: Any) -> None:
        """Use up the pairs a window transition used (``events.noise_used``).

        Args:
            task: the task core.
            events: the transition's events.
            active: which envs stepped.
        """
        if task.step_noise_pairs > 1:
            if self.one_env:
                self.streams.advance(np.array([events.noise_used]))
            else:
                self.streams.advance(np.where(active, events.noise_used, 0))


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
        flight is shown again and the list is empty.

        Returns:
            The flight's ``(H, W, 3)`` uint8 frames (none in ``human`` mode, before the
            first step, or without a ``render_mode``).
        """
        renderer = ensure_renderer(self)
        if renderer is None:
            return []
        frames = [renderer.render(s) for s in self._flight_scenes(self._scene())]
        return [f for f in frames if f is not None]


def check_info_keys(info_keys: Any, task: Any) -> tuple[str, ...] | None:
    """``info_keys`` as a tuple of the task's info names (None: all), or an error naming
    ``info_keys``.

    Args:
        info_keys: a list or tuple of the task's info names, or None.
        task: the task core whose infos they name.

    Returns:
        The names as a tuple, or None (every info).

    Raises:
        TypeError: for an ``info_keys`` that is not a list, a tuple or None (a string too).
        ValueError: for a name that is not one of the task's infos.
    """
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
    if backends.is_jax_array(actions):
        return _check_jax_actions(actions, shape, backend)
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


def _check_jax_actions(actions: Any, shape: tuple[int, ...], backend: Any) -> Any:
    """:func:`check_tensor_actions` for a JAX array (on the backend's device, one
    reduction and a sync a step, as for torch)."""
    import jax

    xp = backend.xp
    if xp.iscomplexobj(actions):
        raise TypeError(f"actions must be real, got a {actions.dtype} array")
    if tuple(actions.shape) != tuple(shape):
        raise ValueError(f"actions must have shape {tuple(shape)}, got {tuple(actions.shape)}")
    a = jax.device_put(xp.astype(actions, backend.float_dtype), backend.jax_device)
    finite = xp.all(xp.isfinite(a), axis=-1)
    if not bool(xp.all(finite)):
        rows = [int(i) for i in np.flatnonzero(~np.asarray(finite))[:8]]
        raise ValueError(f"actions must be finite: rows {rows} hold NaN or inf")
    return xp.clip(a, -1.0, 1.0)


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

    Args:
        num_envs: how many envs the batch holds (an int >= 1).
        render_mode: ``"human"``, ``"rgb_array"``, ``"rgb_array_list"``, or None for no
            rendering.
        max_episode_steps: the time limit in steps (an int >= 1); None: the family's
            registered one (its spec's ``max_episode_steps``).
        backend: ``"numpy"`` (float64, the reference) or ``"torch"``.
        device: ``"cpu"``, ``"cuda"`` or ``"cuda:N"`` (torch only); None: ``"cpu"``.
        dtype: ``"float64"``, or ``"float32"`` (torch only).
        output: ``"numpy"``, or ``"torch"`` for tensors on ``device`` (torch only).
        compile: whether torch compiles the step (False: it runs eagerly).
        step_graph: ``"auto"``, ``"parts"`` or ``"one"`` (torch only;
            :data:`bbgym.backends.STEP_GRAPHS`).
        info_keys: the task's info names to keep (a list or tuple), or None for all.
        **kwargs: the task's arguments (the fields of its ``params_class``), checked by the
            task.

    Raises:
        TypeError: for a ``num_envs`` that is not an int, or a wrong argument type.
        ValueError: for a value out of its accepted ones, naming the argument.
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
        self._reset_program: Any = None
        self._any_restarting: bool | None = None
        self._renderer: Any = None
        self._collected: list[list[Any]] = []  # rgb_array_list: per drawn sub-env
        # A "generator" task on NumPy draws from each env's generator (the one adapter
        # that keeps those versions' bits); everything else from the counter-based keys.
        self._draws = None if self.keyed else GeneratorDraws(self.streams, self.num_envs)
        self._init_host_state()

    def _init_host_state(self) -> None:
        """Hook: set up what the env keeps on the host beside its batched state (the drawn
        sub-envs' wakes, the last records), once the task, spaces and backend exist."""

    @property
    def started(self) -> bool:
        """Whether the env has been reset (it holds a batched state)."""
        return self.state is not None

    @property
    def xp(self) -> Any:
        """The backend's array namespace (``numpy``, or torch's through array-api-compat)."""
        return self.backend.xp

    @property
    def keyed(self) -> bool:
        """Whether the draws come from the counter-based keys (every backend for a
        ``"keys"`` task, torch and JAX for every task), not from each env's generator."""
        return self.backend.name != "numpy" or self.task.randomness == "keys"

    def _restart(self, mask: np.ndarray, options: dict[str, Any]) -> None:
        """Fresh episodes for the envs in ``mask`` (:func:`restart`), each from its own
        random stream: the counter-based keys, or a "generator" task's generators."""
        if self._draws is not None:
            noise = self._draws.initial(self.task, mask)
            self.state = restart(self.task, self.state, mask, noise, options, np)
            return
        xp, m = self.xp, self._tensor(mask)
        noise = counter_initial_noise(
            self.task, self._keys, self._counter, self.backend.float_dtype, xp
        )
        state = restart(self.task, self.state, m, noise, options, xp)
        if self.backend.name == "torch":
            # Distinct tensors per leaf: the compiled step's guards would otherwise see the
            # fields a fresh state shares (zeros) as aliases, and recompile once they part.
            state = tree_map(lambda t: t.clone(), state)
        self.state = state
        self._counter = self._counter + xp.astype(m, self._counter.dtype)

    def _tensor(self, x: Any, dtype: Any = None) -> Any:
        """``x`` as an array of the backend (on its device)."""
        if self.backend.name == "jax":
            import jax

            x = np.asarray(x, dtype=dtype)
            if x.dtype == np.int64 and self.backend.dtype == "float32":
                x = x.astype(np.int32)  # JAX's int without 64-bit types (the counts fit)
            return jax.device_put(x, self.backend.jax_device)
        if self.backend.name != "torch":
            return np.asarray(x, dtype=dtype)
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
        if self.backend.name == "numpy":  # a "keys" task on NumPy: the host step

            def run_host(*args: Any, any_restarting: bool | None = None) -> tuple:
                step.record = self.records
                out = step(*args, any_restarting=any_restarting)
                self.events = step.events
                return out

            return run_host
        if self.step_graph == "one" or (self.backend.name == "jax" and self.backend.compile):
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
        """Reset every sub-env (Gymnasium's ``VectorEnv.reset``).

        Args:
            seed: an int >= 0 (sub-env ``i`` gets ``seed + i``), a list of ``num_envs``
                seeds (ints >= 0 or None), or None to go on with each sub-env's random
                stream (fresh entropy on the first reset).
            options: the task's reset options (:meth:`TaskCore.check_options`) for every
                sub-env, or None.

        Returns:
            ``(observations, infos)``: the ``(num_envs, size)`` float32 observations in
            [-1, 1] and the infos, arrays with Gymnasium's ``_key`` masks (NumPy, or
            tensors with ``output="torch"``).

        Raises:
            TypeError: for a seed or option of the wrong kind, naming it.
            ValueError: for a negative seed, a list of the wrong length or an option out
                of its interval.
        """
        with self.backend.context():
            return self._reset(seed, options)

    def _reset(self, seed: Any, options: dict[str, Any] | None) -> tuple[Any, dict[str, Any]]:
        options = self.task.check_options(options)
        everyone = np.ones(self.num_envs, dtype=bool)
        if seed is not None or not self.started:
            seeds = vector_seeds(seed, self.num_envs)
            self.streams.seed(seeds)
            if seed is not None:
                self._np_random, self._np_random_seed = seeding.np_random(seeds[0])
            if self.keyed:
                self._seed_keys(seeds)
        self.state = None if self.keyed and seed is not None else self.state
        fresh = None
        if self.backend.name == "jax" and self.backend.compile and self.keyed and not options:
            # One program (compiled once a process, cached by JAX), not a compile of each
            # of the restart's many small ops, which JAX runs one by one outside jit.
            if self._reset_program is None:
                self._reset_program = backends.compiled(self._fresh_episodes, self.backend)
            fresh = self._reset_program(self._keys, self._counter)
            self.state = fresh[0]
            self._counter = self._counter + 1
        else:
            self._restart(everyone, options)
        self._steps = self._tensor(np.zeros(self.num_envs, dtype=np.int64))
        self._autoreset = self._tensor(np.zeros(self.num_envs, dtype=bool))
        self._any_restarting = False
        self._on_reset(everyone)
        if self.render_mode == LIST_MODE:
            self._collected = [[] for _ in range(self._drawn_envs)]
            self._collect(everyone)
        if fresh is not None:
            obs, info = fresh[1:]
        else:
            m = self.task.measure(self.state, self.xp)
            obs = columns_to_observation(self.task.observation(self.state, m, self.xp), self.xp)
            info = select_info(self.task.info(self.state, m, self.xp), self.info_keys)
        if self.backend.name == "numpy":  # the host keeps the samples a renderer draws
            info = {**info, **self._step_info()}
        return self._out(obs), self._vector_info(info)

    def _fresh_episodes(self, keys: Any, counter: Any) -> tuple[Any, Any, dict[str, Any]]:
        """Every env's fresh episode at its key and counter, without reset options: the
        state, the observations and the infos (what a reset computes, as one function)."""
        xp = self.xp
        noise = counter_initial_noise(self.task, keys, counter, self.backend.float_dtype, xp)
        state = restart(self.task, None, None, noise, {}, xp)
        m = self.task.measure(state, xp)
        obs = columns_to_observation(self.task.observation(state, m, xp), xp)
        return state, obs, select_info(self.task.info(state, m, xp), self.info_keys)

    def _seed_keys(self, seeds: list[int | None]) -> None:
        base = seeds[0]
        if base is None:
            base = int(np.random.SeedSequence().generate_state(1)[0])
        keys = np.array(
            [
                backends.env_keys(s if s is not None else base + i, 1, np)[0]
                for i, s in enumerate(seeds)
            ]
        )
        # JAX holds the 32-bit keys as uint32, whose arithmetic wraps as the hash needs
        # without 64-bit types (backends.hash32); NumPy and torch as int64.
        word = np.uint32 if self.backend.name == "jax" else np.int64
        self._keys = self._tensor(keys.astype(word))
        self._counter = self._tensor(np.zeros(self.num_envs, dtype=word))

    def step(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        """Step every sub-env (Gymnasium's ``VectorEnv.step``), with next-step autoreset:
        a sub-env whose episode ended on the previous step starts anew, ignores its action
        and reports reward 0.

        Args:
            actions: a ``(num_envs, size)`` array-like, checked by the task (a Box action is
                clipped to [-1, 1]), or on the torch backend a tensor of that shape (moved
                to its device and dtype).

        Returns:
            ``(observations, rewards, terminated, truncated, infos)``, each of ``num_envs``
            entries: NumPy arrays, or tensors on the device with ``output="torch"``.

        Raises:
            gymnasium.error.ResetNeeded: before the first ``reset()``.
            ValueError: for actions of the wrong shape, or a NaN or inf.
        """
        if not self.started:
            raise gym.error.ResetNeeded("Call reset() before step()")
        if self.keyed:
            with self.backend.context():
                return self._step_keyed(actions)
        # A "generator" task on NumPy: the same step, its draws from GeneratorDraws.
        a = self.task.check_action(actions, self.num_envs)
        restarting = self._autoreset
        any_restarting = bool(restarting.any())
        self._host_step.record = self.records
        out = self._host_step(
            self.state, a, None, None, self._steps, restarting, None, any_restarting, self._draws
        )
        self.state, obs, reward, terminated, truncated, info, _, self._steps = out
        self.events = self._host_step.events
        if any_restarting:
            # Next-step autoreset: the finished envs started anew and ignored this action.
            self._on_reset(restarting)
        self._autoreset = terminated | truncated
        self._on_step(a)
        if self.render_mode == LIST_MODE:
            self._collect(restarting)
        info = self._vector_info({**info, **self._step_info()})
        return obs, reward.astype(np.float64), terminated, truncated, info

    @property
    def _host_step(self) -> VectorStep:
        """The step of a "generator" task on NumPy (made on first use)."""
        if self._compiled_step is None:
            self._compiled_step = VectorStep(
                self.task, self.max_episode_steps, np, np.float64, self.info_keys
            )
        return self._compiled_step

    records = True
    """Whether NumPy transitions keep the samples a renderer or ``info`` needs (the torch
    backend never does: its step stays on the device)."""

    def _step_info(self) -> dict[str, Any]:
        """Hook: info entries from the last NumPy transition's ``self.events`` (arrays of
        the batch, or object arrays), {} after a reset."""
        return {}

    def _step_keyed(self, actions: Any) -> tuple[Any, Any, Any, Any, dict[str, Any]]:
        if hasattr(actions, "detach") or backends.is_jax_array(actions):
            # a tensor or JAX array from a device-resident learner
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
        compiling = first and self.backend.name != "numpy" and self.backend.compile
        with self._compile_logged() if compiling else nullcontext():
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
        if self._wants_reset_hook or self.backend.name == "numpy":
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
        ``step``.

        Args:
            mask: a ``(num_envs,)`` bool array-like: the envs to restart.

        Returns:
            Every env's observation, ``(num_envs, size)`` float32 (NumPy, or a tensor with
            ``output="torch"``).
        """
        with self.backend.context():
            return self._reset_envs(np.asarray(mask, dtype=bool))

    def _reset_envs(self, mask: np.ndarray) -> Any:
        if mask.any():
            self._restart(mask, {})
            m = self._tensor(mask)
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
        return x if self.backend.output != "numpy" else backends.to_numpy(x)

    def _vector_info(self, info: dict[str, Any]) -> dict[str, Any]:
        return vector_info(tree_map(self._out, info), self.num_envs)

    def _on_reset(self, mask: np.ndarray) -> None:
        """Hook: envs in ``mask`` have just been reset."""

    def _on_step(self, actions: Any) -> None:
        """Hook: a step with ``actions`` has just been taken."""

    def element_state(self, i: int) -> Any:
        """Sub-env ``i``'s state as Python floats.

        Args:
            i: the sub-env's index, in ``[0, num_envs)``.

        Returns:
            The state's tree with Python scalars (NumPy arrays for leaves with more axes).
        """
        return element(self.state, i)

    @property
    def _drawn_envs(self) -> int:
        """How many sub-envs ``render()`` draws (the first)."""
        return 1 if self.render_mode == "human" else min(self.num_envs, 4)

    def render(self) -> tuple[np.ndarray, ...] | tuple[list[np.ndarray], ...] | None:
        """Frames of the first (up to 4) sub-envs: a tuple of frames (``rgb_array``) or of
        lists of frames since the last ``render()`` or ``reset()`` (``rgb_array_list``);
        ``human`` shows the first in a window and returns ``None``.

        Returns:
            A tuple with one entry per drawn sub-env (a ``(H, W, 3)`` uint8 frame or a list
            of them, by render mode), or None (``human``, or no ``render_mode``).
        """
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
