"""The functional core of a task, and the vector step with its autoreset, as pure functions.

A task core is a set of pure functions over a batch of immutable states (NamedTuples of
arrays, nested), in the shape of Gymnasium's ``FuncEnv`` and gymnax:

=====================================  ==================================================
``initial(noise, options, xp)``        a fresh state per env from its random draws
``transition(state, action, noise,     the state one env step later, and what happened
xp) -> (state, events)``               (the physics; the step's reward terms are part of
                                       the new state)
``measure(state, xp)``                 the physical quantities observation and info share
``observation(state, m, xp)``          the observation's columns (unclipped)
``reward(state, xp)``                  the last transition's reward
``terminal(state, xp)``                whether the episode has ended
``info(state, m, xp)``                 what a researcher plots, as arrays
=====================================  ==================================================

Every function takes the array namespace ``xp`` and keeps the contract of
:mod:`bbgym.physics.namespace`, so the same source runs one env on Python floats
(:class:`CoreEnv`), a batch on NumPy, and a batch on torch compiled for the CPU or a GPU
(:class:`CoreVectorEnv`). A partial reset is one :func:`tree_select`. The randomness is
passed in: the NumPy adapters draw it from each env's ``numpy.random.Generator`` (so
sub-env ``i`` equals the single env seeded ``seed + i``), the torch backend from the
counter-based generator of :mod:`bbgym.backends` inside the compiled step.
"""

from __future__ import annotations

import contextlib
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from typing import Any, ClassVar, Generic, NamedTuple, TypeVar

import numpy as np
from gymnasium import spaces

from bbgym import backends
from bbgym.envs.common import check_box_action, check_option_keys
from bbgym.physics.namespace import floats

StateT = TypeVar("StateT")
"""A task's state: an immutable NamedTuple of arrays (or of Python floats for one env)."""
CarryT = TypeVar("CarryT")
"""What a transition carries between its chunks (a task's own NamedTuple)."""

RANDOMNESS = ("keys", "generator")
"""Where a task's draws come from: ``"keys"``, the counter-based generator of
:mod:`bbgym.backends` on every backend (sub-env ``i`` equals the single env seeded
``seed + i`` on every backend, and the backends agree through autoresets); ``"generator"``,
the versions made before it: each env's ``numpy.random.Generator`` on the host (their
golden replays pin those bits) and the counter-based generator on torch."""


class InitialNoise(NamedTuple):
    """The draws :meth:`TaskCore.initial` turns into a fresh state, for a task of
    ``randomness = "generator"``: sequences of ``uniform[k]`` in [0, 1) and ``normal[k]``
    standard normal, each of the batch's shape (or floats for one env; step noise too is a
    sequence of such arrays), drawn in that order from the env's generator; then
    ``stream[k]``, standard normals from the env's pair stream (2 per pair, see
    ``initial_stream_pairs``). A task of ``randomness = "keys"`` gets :class:`Draws`."""

    uniform: Any
    normal: Any
    stream: Any = ()


class Draws:
    """Random draws for one reset or one step of a task of ``randomness = "keys"``, handed
    out in the order the task asks: ``uniform()`` in (0, 1), ``normal()`` standard normal,
    each of the batch's shape (a Python float for one env). Nothing is counted by hand: a
    draw is a pure function of the env's key, its counter (one per reset or step), the
    stream and the draw's place in it (:func:`bbgym.backends.draw_at`), so every
    backend gives the same numbers whichever envs draw.

    Args:
        keys: each env's 32-bit key (``(batch,)`` int64; a Python int for one env).
        counter: each env's counter (same shape as ``keys``).
        streams: the streams of ``uniform()`` and of ``normal()``.
        dtype: the float dtype of the draws (``float`` for one env).
        xp: the array namespace (:data:`bbgym.physics.namespace.floats` for one env).
    """

    def __init__(
        self, keys: Any, counter: Any, streams: tuple[int, int], dtype: Any, xp: Any
    ) -> None:
        self.keys, self.counter, self.streams, self.dtype, self.xp = (
            keys,
            counter,
            streams,
            dtype,
            xp,
        )
        self.uniforms_drawn = 0
        self.normals_drawn = 0

    def uniform(self) -> Any:
        """The next uniform draw in (0, 1).

        Returns:
            An array of the batch's shape (a float for one env).
        """
        k, self.uniforms_drawn = self.uniforms_drawn, self.uniforms_drawn + 1
        return self._draw(self.streams[0], k, False)

    def normal(self) -> Any:
        """The next standard normal draw.

        Returns:
            An array of the batch's shape (a float for one env).
        """
        k, self.normals_drawn = self.normals_drawn, self.normals_drawn + 1
        return self._draw(self.streams[1], k, True)

    def _draw(self, stream: int, k: int, normal: bool) -> Any:
        if self.xp is floats:  # one env: the same hash on a NumPy scalar
            key, counter = np.int64(self.keys), np.int64(self.counter)
            return float(backends.draw_at(key, counter, stream, k, np.float64, np, normal))
        return backends.draw_at(self.keys, self.counter, stream, k, self.dtype, self.xp, normal)


INITIAL_STREAMS = (1, 2)
"""The counter-based streams of a fresh episode's uniform and normal draws (a step's are
:data:`STEP_STREAMS`; stream 3 holds the pair stream of ``"generator"`` tasks on torch)."""
STEP_STREAMS = (4, 0)
"""The counter-based streams of a step's uniform and normal draws."""


class TaskCore(ABC, Generic[StateT, CarryT]):
    """The contract of a task core: pure functions over an immutable batch of states, on
    any array namespace ``xp`` (see the module docstring). A task implements
    :meth:`initial`, a transition (:meth:`advance` for a one-piece step, or :meth:`begin`,
    :meth:`chunk` and :meth:`end` for one taken in chunks), :meth:`observation`,
    :meth:`reward` and :meth:`terminal`; the rest have defaults for what most tasks do
    not need (no reset options, a Box action, no measures or infos, one chunk, no early
    stop). Its randomness comes in as :class:`Draws` (``randomness = "keys"``, every new
    task) and is never drawn inside.

    Attributes:
        action_space: the single env's action space (a ``gymnasium.spaces.Box``).
        observation_space: the single env's observation space (a Box in [-1, 1]).
    """

    action_space: spaces.Box
    observation_space: spaces.Box

    params_class: ClassVar[type | None] = None
    """A frozen dataclass whose fields are all the task's arguments, each with its
    accepted interval (:func:`bbgym.physics.validation.param`): the default constructor
    makes :attr:`params` of them, and the argument checks, the fuzzer and the docs'
    tables read them. None: the task writes its own constructor."""
    params: Any = None

    def __init__(self, **kwargs: Any) -> None:
        """The task with its arguments, checked (a task with :attr:`params_class`).

        Args:
            **kwargs: the fields of :attr:`params_class` the user gives.

        Raises:
            TypeError: for an argument of the wrong type, naming it.
            ValueError: for a value outside its interval, naming it.
        """
        if self.params_class is None:
            if kwargs:
                raise TypeError(f"{type(self).__name__} takes no arguments, got {list(kwargs)}")
            return
        try:
            self.params = self.params_class(**kwargs)
        except (TypeError, ValueError) as error:  # name the argument as the user gave it
            raise type(error)(str(error).replace(f"{self.params_class.__name__}.", "")) from None

    randomness: ClassVar[str] = "keys"
    """Where the draws come from (:data:`RANDOMNESS`)."""
    chunks: int = 1
    """How many times :meth:`chunk` runs in a transition (a fixed number of substeps
    each)."""
    stops_early: bool = False
    """Whether the chunks may all be idle before the last (then :meth:`all_done` is
    checked between chunks)."""
    initial_noise_counts: tuple[int, int] = (0, 0)
    """``"generator"`` tasks: uniform and normal draws per env for :meth:`initial`."""
    initial_stream_pairs: int = 0
    """``"generator"`` tasks: pairs of normals from the env's pair stream for
    :meth:`initial` (after the draws)."""
    step_noise_pairs: int = 0
    """``"generator"`` tasks: pairs of normals a transition may use per env: 1 is drawn
    only for the envs of :meth:`step_noise_mask`; more are a window of which the
    transition uses the first ``events.noise_used[i]`` (the rest stay in the stream)."""

    # -- what every task writes ----------------------------------------------------------
    @abstractmethod
    def initial(self, noise: Any, options: Mapping[str, Any], xp: Any) -> StateT:
        """A fresh state per env.

        Args:
            noise: the episode's draws: :class:`Draws` (``"keys"``) or
                :class:`InitialNoise` (``"generator"``).
            options: the checked reset options (:meth:`check_options`).
            xp: the array namespace.

        Returns:
            The state of every env of the batch.
        """

    @abstractmethod
    def observation(self, state: StateT, m: Mapping[str, Any], xp: Any) -> tuple:
        """The observation's columns, each in about [-1, 1] (the adapters clip them and
        stack them as float32).

        Args:
            state: the state now.
            m: :meth:`measure` of it.
            xp: the array namespace.

        Returns:
            One array (or float) per observation entry.
        """

    @abstractmethod
    def reward(self, state: StateT, xp: Any) -> Any:
        """The reward of the transition that made ``state``.

        Args:
            state: the state after the transition.
            xp: the array namespace.

        Returns:
            A float per env.
        """

    @abstractmethod
    def terminal(self, state: StateT, xp: Any) -> Any:
        """Whether the episode has ended in ``state`` (its goal reached or lost).

        Args:
            state: the state now.
            xp: the array namespace.

        Returns:
            A bool per env.
        """

    # -- the transition: advance, or begin / chunk / end ----------------------------------
    def advance(self, state: StateT, action: Any, noise: Any, xp: Any) -> StateT:
        """The state one env step later, for a task whose step is one piece (the default
        :meth:`begin` calls it); a task taken in chunks implements :meth:`begin`,
        :meth:`chunk` and :meth:`end` instead.

        Args:
            state: the state now.
            action: the checked action: a tuple of floats for one env, ``(batch, size)``
                otherwise.
            noise: the step's :class:`Draws` (``"keys"``).
            xp: the array namespace.

        Returns:
            The next state (its reward terms included).
        """
        raise NotImplementedError(
            f"{type(self).__name__} implements neither advance() nor begin/chunk/end()"
        )

    def transition(
        self, state: StateT, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> tuple[StateT, Any]:
        """:meth:`begin`, ``chunks`` times :meth:`chunk` (:func:`run_chunks`), then
        :meth:`end`.

        Args:
            state: the state now.
            action: the checked action.
            noise: :class:`Draws` (``"keys"``), or a sequence of ``2 * step_noise_pairs``
                arrays (``"generator"``).
            xp: the array namespace.
            record: whether to keep the samples a renderer draws (in the events).

        Returns:
            ``(state, events)``: the next state and what happened (None by default).
        """
        carry = run_chunks(self, self.begin(state, action, noise, xp, record), xp)
        return self.end(state, carry, xp)

    def begin(self, state: StateT, action: Any, noise: Any, xp: Any, record: bool) -> CarryT:
        """What the chunks of a transition start from. Default: the whole one-piece step,
        :meth:`advance` (its draws taken here, where they are made), so the carry is the
        next state and :meth:`end` returns it.

        Args:
            state: the state now.
            action: the checked action.
            noise: the step's draws.
            xp: the array namespace.
            record: whether to keep the samples a renderer draws.

        Returns:
            The carry the chunks update.
        """
        return self.advance(state, action, noise, xp)  # type: ignore[return-value]

    def chunk(self, carry: CarryT, xp: Any) -> CarryT:
        """One chunk of a transition's substeps (default: nothing, one-piece steps).

        Args:
            carry: what :meth:`begin` or the last chunk made.
            xp: the array namespace.

        Returns:
            The carry after the chunk; an env that is done must pass through unchanged.
        """
        return carry

    def all_done(self, carry: CarryT, xp: Any) -> Any:
        """Which envs' chunks are idle now (checked between chunks where
        ``stops_early``).

        Args:
            carry: the carry between chunks.
            xp: the array namespace.

        Returns:
            A bool per env.
        """
        raise NotImplementedError(f"{type(self).__name__} stops early but has no all_done()")

    def end(self, state: StateT, carry: CarryT, xp: Any) -> tuple[StateT, Any]:
        """The transition's end (default: :meth:`begin`'s carry is the next state).

        Args:
            state: the state before the transition.
            carry: the last chunk's carry.
            xp: the array namespace.

        Returns:
            ``(state, events)``: the next state and what happened (None by default).
        """
        return carry, None  # type: ignore[return-value]

    def step_noise_mask(self, state: StateT, xp: Any) -> Any:
        """``"generator"`` tasks with step noise: which envs may draw it (an env's stream
        must not depend on the others). Default: none.

        Args:
            state: the state now.
            xp: the array namespace.

        Returns:
            A bool per env.
        """
        return xp.zeros_like(self.terminal(state, xp), dtype=xp.bool) if xp is not floats else False

    # -- what most tasks leave as it is ---------------------------------------------------
    def measure(self, state: StateT, xp: Any) -> dict[str, Any]:
        """The physical quantities :meth:`observation` and :meth:`info` share (default:
        none).

        Args:
            state: the state now.
            xp: the array namespace.

        Returns:
            A dict of arrays (floats for one env).
        """
        return {}

    def info(self, state: StateT, m: Mapping[str, Any], xp: Any) -> dict[str, Any]:
        """What a researcher plots, as arrays; ``is_success`` where the task has a goal
        (default: none).

        Args:
            state: the state now.
            m: :meth:`measure` of it.
            xp: the array namespace.

        Returns:
            A dict of arrays (floats or bools for one env).
        """
        return {}

    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        """``reset``'s options, checked (default: none accepted).

        Args:
            options: what the user passed to ``reset`` (None: none).

        Returns:
            The options as a dict.

        Raises:
            TypeError: for an unknown key, naming it.
            ValueError: for a value out of its interval, naming ``options['key']``.
        """
        return check_option_keys(options, ())

    def check_action(self, action: Any, batch: int) -> Any:
        """An action (``batch == 0``: one env) or a batch of actions, checked and clipped
        to [-1, 1] (default: the ``Box`` of :attr:`action_space`).

        Args:
            action: what the user passed to ``step``.
            batch: the number of envs, 0 for one env.

        Returns:
            A tuple of floats for one env, a float64 ``(batch, size)`` array otherwise.

        Raises:
            ValueError: for a wrong shape or a NaN or inf.
        """
        a = check_box_action(action, self.action_space.shape[0], batch)
        return tuple(a.tolist()) if batch == 0 else a


def run_chunks(
    task: TaskCore, carry: Any, xp: Any, chunk: Callable[[Any], Any] | None = None
) -> Any:
    """``task.chunks`` chunks of a transition from ``carry``, stopping once every env is
    done (``task.stops_early``): the one chunk loop of the host and eager steps (a
    compiled one-graph step rolls it, :func:`rolled_chunks`).

    Args:
        task: the task core.
        carry: what :meth:`TaskCore.begin` made.
        xp: the array namespace.
        chunk: the chunk to run (a compiled :meth:`TaskCore.chunk`; default the task's).

    Returns:
        The carry after the last chunk.
    """
    chunk = chunk or (lambda c: task.chunk(c, xp))
    for _ in range(task.chunks):
        if task.stops_early and bool(xp.all(task.all_done(carry, xp))):
            break
        carry = chunk(carry)
    return carry


def tree_select(mask: Any, new: Any, old: Any, xp: Any) -> Any:
    """``new`` where ``mask`` (per env) and ``old`` elsewhere, leaf by leaf through nested
    NamedTuples and dicts; a leaf with more axes than the mask broadcasts it.

    Args:
        mask: which envs take ``new``: a ``(batch,)`` bool array (a Python bool for one env
            on Python floats).
        new: the tree to take where ``mask``, of ``old``'s structure.
        old: the tree to keep elsewhere: nested NamedTuples, tuples, lists and dicts of
            arrays (or of Python floats for one env).
        xp: the array namespace.

    Returns:
        A tree of ``old``'s structure and types.
    """
    if isinstance(old, (tuple, list)):
        items = [tree_select(mask, a, b, xp) for a, b in zip(new, old, strict=True)]
        return type(old)(*items) if hasattr(old, "_fields") else type(old)(items)
    if isinstance(old, dict):
        return {k: tree_select(mask, new[k], old[k], xp) for k in old}
    if xp is floats:
        return new if mask else old
    if new is old:
        return old
    m = mask
    for _ in range(len(old.shape) - len(mask.shape)):
        m = m[..., None]
    return xp.where(m, new, old)


def tree_map(fn: Any, tree: Any) -> Any:
    """``fn`` applied to every leaf of nested NamedTuples and dicts.

    Args:
        fn: a function of one leaf.
        tree: nested NamedTuples, tuples, lists and dicts (anything else is a leaf).

    Returns:
        A tree of ``tree``'s structure with ``fn(leaf)`` at each leaf.
    """
    if isinstance(tree, (tuple, list)):
        items = [tree_map(fn, t) for t in tree]
        return type(tree)(*items) if hasattr(tree, "_fields") else type(tree)(items)
    if isinstance(tree, dict):
        return {k: tree_map(fn, v) for k, v in tree.items()}
    return fn(tree)


def element(tree: Any, i: int) -> Any:
    """Env ``i`` of a batched state as Python scalars (for drawing and for tests).

    Args:
        tree: a batched state: leaves with the batch as their first axis (NumPy arrays or
            tensors, on any device).
        i: the env's index in the batch.

    Returns:
        The state's tree with each leaf's row ``i``: a Python scalar for a per-env value, a
        NumPy array for a leaf with more axes.
    """

    def pick(leaf: Any) -> Any:
        value = np.asarray(backends.to_numpy(leaf))[i]
        return value.item() if value.ndim == 0 else value

    return tree_map(pick, tree)


def columns_to_observation(columns: tuple, xp: Any) -> Any:
    """Stack observation columns into ``(batch, size)`` float32 (``(size,)`` for one env
    on Python floats), clipped to [-1, 1].

    Args:
        columns: the observation's columns (:meth:`TaskCore.observation`): ``(batch,)``
            arrays, or Python floats for one env.
        xp: the array namespace.

    Returns:
        A ``(batch, size)`` float32 array of ``xp`` (a ``(size,)`` NumPy array for one env).
    """
    if xp is floats:  # clip the floats first: one small array, no temporaries
        return np.array([min(max(c, -1.0), 1.0) for c in columns], dtype=np.float32)
    obs = xp.clip(xp.stack(columns, axis=1), -1.0, 1.0)
    return xp.astype(obs, xp.float32)


def stack_pair(x: Any, y: Any, xp: Any) -> Any:
    """An ``(x, y)`` pair per env for ``info``: a ``(2,)`` NumPy array for one env (Python
    floats), ``(batch, 2)`` for a batch.

    Args:
        x: the first value: a ``(batch,)`` array, or a Python float for one env.
        y: the second value, of ``x``'s shape.
        xp: the array namespace.

    Returns:
        A ``(2,)`` NumPy array for one env, a ``(batch, 2)`` array of ``xp`` otherwise.
    """
    if xp is floats:
        return np.array((x, y))
    return xp.stack((x, y), axis=1)


def settle(
    task: Any, moved: Any, restarting: Any, steps: Any, max_episode_steps: int | None, xp: Any
) -> tuple[Any, Any, Any, Any]:
    """Next-step autoreset's bookkeeping of a vector step, on any backend: the one place
    that decides what a step reports. ``moved`` is every env's state after the transition;
    the envs ``restarting`` (their episode ended on the previous step) start anew on this
    one, so they report reward 0, no termination and a step count of 0 (their transition
    is discarded: :func:`restart` replaces their state). Returns ``(reward, terminated,
    truncated, steps)``; an episode is truncated when its ``max_episode_steps``-th step did
    not terminate it (never where ``max_episode_steps`` is None).

    Args:
        task: the task core (its :meth:`~TaskCore.reward` and :meth:`~TaskCore.terminal`).
        moved: every env's state after the transition.
        restarting: which envs restart on this step: a ``(batch,)`` bool array (a Python
            bool for one env).
        steps: each env's steps in its episode before this step: a ``(batch,)`` int64
            array (an int for one env).
        max_episode_steps: the time limit in steps, or None (a single env: ``gym.make``'s
            ``TimeLimit`` truncates).
        xp: the array namespace.

    Returns:
        ``(reward, terminated, truncated, steps)``, each per env: the reward (0 where
        restarting), whether the episode ended, whether the time limit cut it, and the
        steps in the episode after this one (0 where restarting).
    """
    reward = xp.where(restarting, 0.0, task.reward(moved, xp))
    terminated = task.terminal(moved, xp) & xp.logical_not(restarting)
    steps = xp.where(restarting, 0, steps + 1)
    if max_episode_steps is None:  # a single env: gym.make's TimeLimit truncates
        return reward, terminated, terminated & False, steps
    truncated = (steps >= max_episode_steps) & xp.logical_not(terminated)
    return reward, terminated, truncated, steps


def restart(task: Any, state: Any, mask: Any, noise: InitialNoise, options: Any, xp: Any) -> Any:
    """Fresh episodes (from ``noise``, pinned by ``options``) for the envs in ``mask``, the
    others' state kept: a reset, an autoreset and an adapter's early restart are all this.
    ``state`` None (nothing to keep) gives every env a fresh episode.

    Args:
        task: the task core.
        state: every env's state, or None.
        mask: which envs start anew: a ``(batch,)`` bool array (a Python bool for one env).
        noise: the fresh episodes' draws, what :meth:`TaskCore.initial` takes:
            :class:`Draws` (``"keys"``) or :class:`InitialNoise` (``"generator"``).
        options: the checked reset options (:meth:`TaskCore.check_options`).
        xp: the array namespace.

    Returns:
        The state of every env: fresh where ``mask``, ``state``'s elsewhere.
    """
    fresh = task.initial(noise, options, xp)
    return fresh if state is None else tree_select(mask, fresh, state, xp)


def counter_initial_noise(task: TaskCore, keys: Any, counter: Any, dtype: Any, xp: Any) -> Any:
    """The draws of a fresh episode from the counter-based generator of
    :mod:`bbgym.backends` at each env's counter: :class:`Draws` for a ``"keys"`` task;
    for a ``"generator"`` task on torch, its declared counts from streams 1-3.

    Args:
        task: the task core.
        keys: each env's key.
        counter: each env's counter.
        dtype: the float dtype of the draws.
        xp: the array namespace.

    Returns:
        The ``noise`` that :meth:`TaskCore.initial` takes: :class:`Draws`, or an
        :class:`InitialNoise` of ``(batch,)`` arrays.
    """
    if task.randomness == "keys":
        return Draws(keys, counter, INITIAL_STREAMS, dtype, xp)
    n_uniform, n_normal = task.initial_noise_counts
    return InitialNoise(
        backends.uniforms(keys, counter, 1, n_uniform, dtype, xp),
        backends.normals(keys, counter, 2, n_normal, dtype, xp),
        backends.normals(keys, counter, 3, 2 * task.initial_stream_pairs, dtype, xp),
    )


def _counter_step_noise(task: TaskCore, keys: Any, counter: Any, dtype: Any, xp: Any) -> Any:
    """:func:`counter_initial_noise` for a step: :class:`Draws` for a ``"keys"`` task; for
    a ``"generator"`` task on torch, its ``2 * step_noise_pairs`` normals of stream 0 (``()``
    where it has no step noise)."""
    if task.randomness == "keys":
        return Draws(keys, counter, STEP_STREAMS, dtype, xp)
    n = 2 * task.step_noise_pairs
    return backends.normals(keys, counter, 0, n, dtype, xp) if n else ()


class VectorStep:
    """One vector step with next-step autoreset as pure functions of arrays, in parts: what
    the torch backend compiles and what the backend equivalence tests replay on NumPy. A
    task's transition is :meth:`begin`, ``chunks`` times :meth:`chunk` (a fixed number of
    physics substeps) and :meth:`end` (the transition's end and :func:`settle`); then
    :meth:`restart` (only where some env restarts) and :meth:`observe`. By default each
    part is compiled separately (:meth:`__call__` with ``parts``): a graph holds one chunk
    rather than the unrolled loop, and no graph is large (inductor's code generation grows
    faster than the graph: an unrolled sailing step with its autoreset took over 200 s to
    compile, these parts take well under 60). A task whose chunks may all be idle early
    (``stops_early``: every ball landed) is checked between chunks (one device sync each).
    :meth:`fused` is the whole step as one function for one graph instead
    (``step_graph="one"``), its chunks rolled into a loop inside it. The random numbers
    come from the counter-based generator (stream 0: the step's noise, 1-3: a fresh
    episode's draws, :func:`counter_initial_noise`), so the same functions run, with the
    same results, on NumPy or any array-API namespace.

    Args:
        task: the task core (a :class:`TaskCore`).
        max_episode_steps: the time limit in steps (:func:`settle`), or None for a single
            env (``gym.make``'s ``TimeLimit`` truncates).
        xp: the array namespace: :data:`bbgym.physics.namespace.floats` for one env,
            ``numpy``, or the torch namespace of :mod:`bbgym.backends`.
        dtype: the float dtype of the draws (``float`` for one env, else the backend's
            ``float64`` or ``float32``).
        info_keys: the infos :meth:`observe` computes (checked names), or None for all.
        record: whether transitions keep the samples a renderer draws (host steps only).
    """

    def __init__(
        self,
        task: Any,
        max_episode_steps: int,
        xp: Any,
        dtype: Any,
        info_keys: tuple[str, ...] | None = None,
        record: bool = False,
    ) -> None:
        self.task, self.max_episode_steps, self.xp, self.dtype = task, max_episode_steps, xp, dtype
        self.info_keys = info_keys
        self.record = record
        """Whether transitions keep the samples a renderer draws (a host step's; a
        compiled step never does), as :attr:`events` after each step."""
        self.events: Any = None

    @property
    def host(self) -> bool:
        """Whether the step runs on the host (Python floats, NumPy), where the task's own
        :meth:`TaskCore.transition` runs (a task may fly its host transitions faster)."""
        return self.xp is floats or self.xp is np

    def transition(
        self, state: Any, action: Any, keys: Any, counter: Any, active: Any, draws: Any = None
    ) -> tuple[Any, Any]:
        """A host transition: the step's draws (from ``draws``, the host adapter of a
        ``"generator"`` task, :class:`bbgym.envs.core.GeneratorDraws`; else from the
        counters), then :meth:`TaskCore.transition`.

        Args:
            state: every env's state.
            action: the checked actions.
            keys: each env's key (None with ``draws``).
            counter: each env's counter (None with ``draws``).
            active: which envs step (the others restart: they draw nothing).
            draws: a ``"generator"`` task's host draws, or None.

        Returns:
            ``(state, events)`` after the transition.
        """
        task, xp = self.task, self.xp
        if draws is None:
            noise = _counter_step_noise(task, keys, counter, self.dtype, xp)
        else:
            noise = draws.step_noise(task, state, active)
        moved, events = task.transition(state, action, noise, xp, self.record)
        if draws is not None:
            draws.stepped(task, events, active)
        if self.record:
            self.events = events
        return moved, events

    def begin(self, state: Any, action: Any, keys: Any, counter: Any) -> Any:
        """The step's draws from the counters (the counter-based generator) and the start of
        the transition (:meth:`TaskCore.begin`): the step's first part.

        Args:
            state: every env's state.
            action: the checked actions, ``(batch, size)``.
            keys: each env's key (``(batch,)`` int64).
            counter: each env's counter (``(batch,)`` int64).

        Returns:
            The carry the chunks update.
        """
        noise = _counter_step_noise(self.task, keys, counter, self.dtype, self.xp)
        return self.task.begin(state, action, noise, self.xp, self.record)

    def chunk(self, carry: Any) -> Any:
        """One chunk of the transition (:meth:`TaskCore.chunk`), the part that runs
        ``task.chunks`` times.

        Args:
            carry: what :meth:`begin` or the last chunk made.

        Returns:
            The carry after the chunk.
        """
        return self.task.chunk(carry, self.xp)

    def end(self, state: Any, carry: Any, counter: Any, steps: Any, restarting: Any) -> tuple:
        """The transition's end and what the step reports (:func:`settle`).

        Args:
            state: every env's state before the transition.
            carry: the last chunk's carry.
            counter: each env's counter (``(batch,)`` int64).
            steps: each env's steps in its episode before this step.
            restarting: which envs restart on this step (``(batch,)`` bool).

        Returns:
            ``(state, reward, terminated, truncated, counter, steps)``: the state after the
            transition, what :func:`settle` reports, and the counters one further.
        """
        moved, events = self.task.end(state, carry, self.xp)
        if self.record:  # a host step's (a compiled one never records: no side effect)
            self.events = events
        reward, terminated, truncated, steps = settle(
            self.task, moved, restarting, steps, self.max_episode_steps, self.xp
        )
        return moved, reward, terminated, truncated, counter + 1, steps

    def restart(self, moved: Any, restarting: Any, keys: Any, counter: Any) -> Any:
        """Fresh episodes where ``restarting`` (run only on steps where some env restarts,
        so the common step's graph holds no :meth:`initial`).

        Args:
            moved: every env's state after the transition.
            restarting: which envs start anew (``(batch,)`` bool).
            keys: each env's key (``(batch,)`` int64).
            counter: each env's counter, the step's (a fresh episode draws from other
                streams, :func:`counter_initial_noise`).

        Returns:
            The state of every env: fresh where ``restarting``, ``moved`` elsewhere.
        """
        noise = counter_initial_noise(self.task, keys, counter, self.dtype, self.xp)
        return restart(self.task, moved, restarting, noise, {}, self.xp)

    def observe(self, state: Any) -> tuple:
        """Observation and info of the new state (the infos of ``info_keys`` only: in a
        compiled step the others are never computed).

        Args:
            state: every env's state.

        Returns:
            ``(obs, info)``: the ``(batch, size)`` float32 observation in [-1, 1] and the
            dict of infos.
        """
        task, xp = self.task, self.xp
        m = task.measure(state, xp)
        info = select_info(task.info(state, m, xp), self.info_keys)
        return columns_to_observation(task.observation(state, m, xp), xp), info

    def fused(
        self, state: Any, action: Any, keys: Any, counter: Any, steps: Any, restarting: Any
    ) -> tuple:
        """The whole step as one function of tensors, for one ``torch.compile`` graph: what
        :meth:`__call__` does, with the chunks after the first rolled into one
        ``torch._higher_order_ops.while_loop`` (so the graph holds one chunk however many
        a transition takes, and a flight stops inside the graph once every env is done)
        and the restart computed for every env and kept where ``restarting`` (at a batch
        of thousands some env restarts on nearly every step, and a branch would need the
        host to know which). Same results as :meth:`__call__`: a chunk leaves a finished
        env as it is, so the one chunk it may run past :meth:`__call__`'s stop changes
        nothing.

        Args:
            state: every env's state.
            action: the checked actions, ``(batch, size)``.
            keys: each env's key (``(batch,)`` int64).
            counter: each env's counter (``(batch,)`` int64).
            steps: each env's steps in its episode.
            restarting: which envs restart on this step (``(batch,)`` bool).

        Returns:
            ``(state, obs, reward, terminated, truncated, info, counter, steps)``, as
            :meth:`__call__` returns them.
        """
        carry = rolled_chunks(self.task, self.begin(state, action, keys, counter), self.xp)
        moved, reward, terminated, truncated, new_counter, steps = self.end(
            state, carry, counter, steps, restarting
        )
        moved = self.restart(moved, restarting, keys, counter)
        obs, info = self.observe(moved)
        return moved, obs, reward, terminated, truncated, info, new_counter, steps

    def __call__(
        self,
        state: Any,
        action: Any,
        keys: Any,
        counter: Any,
        steps: Any,
        restarting: Any,
        parts: tuple | None = None,
        any_restarting: bool | None = None,
        draws: Any = None,
    ) -> tuple:
        """The step, in the one order every backend keeps: the draws, the transition,
        what it reports (:func:`settle`), the restart of the envs whose episode ended on
        the previous step, the observation and infos.

        Args:
            state: every env's state.
            action: the checked actions.
            keys: each env's key (None with ``draws``).
            counter: each env's counter (None with ``draws``).
            steps: each env's steps in its episode.
            restarting: which envs restart on this step.
            parts: the compiled :meth:`begin`, :meth:`chunk`, :meth:`end`,
                :meth:`restart`, :meth:`observe` (default: on the host the task's own
                transition, else these, eager).
            any_restarting: whether any env restarts, if the caller knows (saves a
                device sync).
            draws: a ``"generator"`` task's host draws
                (:class:`bbgym.envs.core.GeneratorDraws`), or None.

        Returns:
            ``(state, obs, reward, terminated, truncated, info, counter, steps)``.
        """
        xp = self.xp
        begin, chunk, end, restart_, observe = parts or (
            self.begin,
            self.chunk,
            self.end,
            self.restart,
            self.observe,
        )
        if parts is None and self.host:
            active = xp.logical_not(restarting)
            moved, _ = self.transition(state, action, keys, counter, active, draws)
            reward, terminated, truncated, steps = settle(
                self.task, moved, restarting, steps, self.max_episode_steps, xp
            )
            new_counter = None if counter is None else counter + 1
        else:
            carry = run_chunks(self.task, begin(state, action, keys, counter), xp, chunk)
            moved, reward, terminated, truncated, new_counter, steps = end(
                state, carry, counter, steps, restarting
            )
        if any_restarting is None:
            any_restarting = bool(xp.any(restarting))  # a device sync
        if any_restarting and draws is not None:
            noise = draws.initial(self.task, restarting)
            moved = restart(self.task, moved, restarting, noise, {}, xp)
        elif any_restarting:
            moved = restart_(moved, restarting, keys, counter)
        obs, info = observe(moved)
        return moved, obs, reward, terminated, truncated, info, new_counter, steps


def select_info(info: dict[str, Any], info_keys: tuple[str, ...] | None) -> dict[str, Any]:
    """The entries of ``info`` named in ``info_keys`` (all of them where it is None).

    Args:
        info: the task's infos (:meth:`TaskCore.info`), by name.
        info_keys: the names to keep (checked: :func:`bbgym.envs.core.check_info_keys`),
            or None.

    Returns:
        The entries kept (``info`` itself where ``info_keys`` is None).
    """
    return info if info_keys is None else {k: info[k] for k in info_keys}


def task_info_names(task: Any) -> list[str]:
    """The names of a task's infos (``task.info``), read from one probe state.

    Args:
        task: the task core.

    Returns:
        The info names, in the order ``task.info`` gives them.
    """
    zero = np.zeros(1, dtype=np.int64)
    state = task.initial(counter_initial_noise(task, zero, zero, np.float64, np), {}, np)
    return list(task.info(state, task.measure(state, np), np))


def tree_leaves(tree: Any) -> list:
    """The leaves of nested NamedTuples, tuples, lists and dicts, in :func:`tree_map`'s
    order.

    Args:
        tree: nested NamedTuples, tuples, lists and dicts.

    Returns:
        The leaves, in order.
    """
    leaves: list = []
    tree_map(leaves.append, tree)
    return leaves


def tree_with_leaves(tree: Any, leaves: list) -> Any:
    """``tree`` with its leaves replaced, in order, by ``leaves``.

    Args:
        tree: nested NamedTuples, tuples, lists and dicts.
        leaves: one new leaf per leaf of ``tree``, in :func:`tree_leaves`' order.

    Returns:
        A tree of ``tree``'s structure holding ``leaves``.
    """
    it = iter(leaves)
    return tree_map(lambda _: next(it), tree)


def _varying_leaves(task: Any, carry: Any, xp: Any, array_type: type) -> tuple[list, list, list]:
    """The carry's leaves, one chunk's leaves, and the places of those a chunk changes,
    found by a chunk
    traced for that alone: its results are unused, so the compiler drops its ops, and the
    program holds the chunk once (in the loop), not twice, which is most of what it costs
    to compile."""
    probe = task.chunk(carry, xp)
    before, after = tree_leaves(carry), tree_leaves(probe)
    varying = [
        j
        for j, (old, new) in enumerate(zip(before, after, strict=True))
        if isinstance(new, array_type) and new is not old
    ]
    return before, after, varying


def _with_varying(carry: Any, leaves: list, varying: list, arrays: tuple) -> Any:
    """``carry`` with its leaves ``leaves``, those at ``varying`` replaced by ``arrays``."""
    replaced = list(leaves)
    for j, array in zip(varying, arrays, strict=True):
        replaced[j] = array
    return tree_with_leaves(carry, replaced)


def rolled_chunks(task: Any, carry: Any, xp: Any) -> Any:
    """``task.chunks`` chunks of a transition from ``carry`` in a while loop (torch's
    ``while_loop``, which ``torch.compile`` keeps rolled, or ``jax.lax.while_loop``: one
    chunk in the program, not hundreds) that also stops once every env is done
    (``task.stops_early``). The loop carries only the arrays a chunk changes; the rest
    (the wind, the screen) it reads as constants.

    Args:
        task: the task core (its ``chunks``, ``stops_early``, :meth:`~TaskCore.chunk` and
            :meth:`~TaskCore.all_done`); a task of one chunk runs it once, with no loop.
        carry: what :meth:`TaskCore.begin` made (of torch tensors or JAX arrays where it
            has chunks).
        xp: the array namespace (torch's or JAX's where the task has chunks).

    Returns:
        The carry after the last chunk.
    """
    if task.chunks <= 1:
        return task.chunk(carry, xp)
    if backends.is_jax(xp):
        return _jax_rolled_chunks(task, carry, xp)
    import torch
    from torch._higher_order_ops import while_loop

    before, _, varying = _varying_leaves(task, carry, xp, torch.Tensor)
    # No two of the loop's inputs may share memory (rows of one noise draw are views of
    # it, a flight's fields may be one array): each gets its own copy.
    leaves = [leaf.clone() if isinstance(leaf, torch.Tensor) else leaf for leaf in before]

    def rebuild(tensors: tuple) -> Any:
        return _with_varying(carry, leaves, varying, tensors)

    def more(done_chunks: Any, *tensors: Any) -> Any:
        go = done_chunks < task.chunks
        if task.stops_early:
            go = go & xp.logical_not(xp.all(task.all_done(rebuild(tensors), xp)))
        return go

    def chunk(done_chunks: Any, *tensors: Any) -> tuple:
        out = tree_leaves(task.chunk(rebuild(tensors), xp))
        # The loop's outputs may not alias its inputs: a leaf a chunk passed through
        # unchanged (a finished flight's flag) is copied.
        new = [out[j].clone() if any(out[j] is t for t in tensors) else out[j] for j in varying]
        return (done_chunks + 1, *new)

    zero = torch.zeros((), dtype=torch.int64, device=leaves[varying[0]].device)
    carried = (zero, *[leaves[j] for j in varying])
    # In the compiled step (dynamic=False) every int is a constant. Run eagerly,
    # while_loop traces its functions itself, and Dynamo would make an int it saw change
    # between two tasks (their chunks, a gust period) symbolic, which the loop cannot
    # carry: every int stays a constant there too.
    constant_ints = (
        contextlib.nullcontext()
        if torch.compiler.is_compiling()
        else torch._dynamo.config.patch(automatic_dynamic_shapes=False)
    )
    with constant_ints:
        out = while_loop(more, chunk, carried)
    return rebuild(tuple(out[1:]))


def _jax_rolled_chunks(task: Any, carry: Any, xp: Any) -> Any:
    """:func:`rolled_chunks` in ``jax.lax.while_loop``: the loop carries the leaves a chunk
    changes, each with the dtype and shape a chunk gives it (a Python number in the first
    carry becomes an array of the chunk's type, as the loop needs)."""
    import jax

    before, after, varying = _varying_leaves(task, carry, xp, jax.Array)

    def rebuild(arrays: tuple) -> Any:
        return _with_varying(carry, before, varying, arrays)

    def more(carried: tuple) -> Any:
        go = carried[0] < task.chunks
        if task.stops_early:
            go = go & xp.logical_not(xp.all(task.all_done(rebuild(carried[1:]), xp)))
        return go

    def chunk(carried: tuple) -> tuple:
        out = tree_leaves(task.chunk(rebuild(carried[1:]), xp))
        return (carried[0] + 1, *[out[j] for j in varying])

    first = [
        xp.broadcast_to(xp.asarray(before[j], dtype=after[j].dtype), after[j].shape)
        for j in varying
    ]
    out = jax.lax.while_loop(more, chunk, (xp.asarray(0, dtype=xp.int32), *first))
    return rebuild(tuple(out[1:]))
