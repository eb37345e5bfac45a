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
from typing import Any, NamedTuple

import numpy as np

from bbgym import backends
from bbgym.physics.namespace import floats


class InitialNoise(NamedTuple):
    """The draws :meth:`initial` turns into a fresh state: sequences of ``uniform[k]`` in
    [0, 1) and ``normal[k]`` standard normal, each of the batch's shape (or floats for one
    env; step noise too is a sequence of such arrays), drawn
    in that order from the env's generator; then ``stream[k]``, standard normals from the
    env's pair stream (2 per pair, see ``initial_stream_pairs``)."""

    uniform: Any
    normal: Any
    stream: Any = ()


class TaskCore:
    """The protocol of a task core (see the module docstring); :class:`SailTask` and the
    ball tasks implement it. Class attributes say what randomness the core needs:"""

    initial_noise_counts: tuple[int, int] = (0, 0)
    """Uniform and normal draws per env for :meth:`initial`."""
    initial_stream_pairs: int = 0
    """Pairs of normals from the env's pair stream for :meth:`initial` (after the draws)."""
    step_noise_pairs: int = 0
    """Pairs of normals a transition may use per env: 1 is drawn only for the envs of
    :meth:`step_noise_mask`; more are a window of which the transition uses the first
    ``events.noise_used[i]`` (the rest stay in the stream)."""
    stops_early: bool = False
    """Whether the chunks of a transition may all be idle before the last (then
    :meth:`all_done` is checked between chunks)."""

    def step_noise_mask(self, state: Any, xp: Any) -> Any:
        """Which envs may draw step noise (an env's stream must not depend on the others)."""
        raise NotImplementedError

    def transition(
        self, state: Any, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> tuple[Any, Any]:
        """:meth:`begin`, ``chunks`` times :meth:`chunk` (stopping early once
        :meth:`all_done` where ``stops_early``), then :meth:`end`. ``noise`` is a sequence
        of ``2 * step_noise_pairs`` arrays (or floats); ``record`` asks for the samples a
        renderer draws (in ``events``)."""
        carry = self.begin(state, action, noise, xp, record)
        for _ in range(self.chunks):
            if self.stops_early and bool(xp.all(self.all_done(carry, xp))):
                break
            carry = self.chunk(carry, xp)
        return self.end(state, carry, xp)

    chunks: int = 1

    def begin(self, state: Any, action: Any, noise: Any, xp: Any, record: bool) -> Any:
        raise NotImplementedError

    def chunk(self, carry: Any, xp: Any) -> Any:
        raise NotImplementedError

    def all_done(self, carry: Any, xp: Any) -> Any:
        raise NotImplementedError

    def end(self, state: Any, carry: Any, xp: Any) -> tuple[Any, Any]:
        raise NotImplementedError


def tree_select(mask: Any, new: Any, old: Any, xp: Any) -> Any:
    """``new`` where ``mask`` (per env) and ``old`` elsewhere, leaf by leaf through nested
    NamedTuples and dicts; a leaf with more axes than the mask broadcasts it."""
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
    """``fn`` applied to every leaf of nested NamedTuples and dicts."""
    if isinstance(tree, (tuple, list)):
        items = [tree_map(fn, t) for t in tree]
        return type(tree)(*items) if hasattr(tree, "_fields") else type(tree)(items)
    if isinstance(tree, dict):
        return {k: tree_map(fn, v) for k, v in tree.items()}
    return fn(tree)


def element(tree: Any, i: int) -> Any:
    """Env ``i`` of a batched state as Python scalars (for drawing and for tests)."""

    def pick(leaf: Any) -> Any:
        value = np.asarray(backends.to_numpy(leaf))[i]
        return value.item() if value.ndim == 0 else value

    return tree_map(pick, tree)


def columns_to_observation(columns: tuple, xp: Any) -> Any:
    """Stack observation columns into ``(batch, size)`` float32, clipped to [-1, 1]."""
    obs = xp.clip(xp.stack(columns, axis=1), -1.0, 1.0)
    return xp.astype(obs, xp.float32)


def stack_pair(x: Any, y: Any, xp: Any) -> Any:
    """An ``(x, y)`` pair per env for ``info``: a ``(2,)`` NumPy array for one env (Python
    floats), ``(batch, 2)`` for a batch."""
    if xp is floats:
        return np.array((x, y))
    return xp.stack((x, y), axis=1)


def settle(
    task: Any, moved: Any, restarting: Any, steps: Any, max_episode_steps: int, xp: Any
) -> tuple[Any, Any, Any, Any]:
    """Next-step autoreset's bookkeeping of a vector step, on any backend: the one place
    that decides what a step reports. ``moved`` is every env's state after the transition;
    the envs ``restarting`` (their episode ended on the previous step) start anew on this
    one, so they report reward 0, no termination and a step count of 0 (their transition
    is discarded: :func:`restart` replaces their state). Returns ``(reward, terminated,
    truncated, steps)``; an episode is truncated when its ``max_episode_steps``-th step did
    not terminate it."""
    reward = xp.where(restarting, 0.0, task.reward(moved, xp))
    terminated = task.terminal(moved, xp) & xp.logical_not(restarting)
    steps = xp.where(restarting, 0, steps + 1)
    truncated = (steps >= max_episode_steps) & xp.logical_not(terminated)
    return reward, terminated, truncated, steps


def restart(task: Any, state: Any, mask: Any, noise: InitialNoise, options: Any, xp: Any) -> Any:
    """Fresh episodes (from ``noise``, pinned by ``options``) for the envs in ``mask``, the
    others' state kept: a reset, an autoreset and an adapter's early restart are all this.
    ``state`` None (nothing to keep) gives every env a fresh episode."""
    fresh = task.initial(noise, options, xp)
    return fresh if state is None else tree_select(mask, fresh, state, xp)


def counter_initial_noise(task: Any, keys: Any, counter: Any, dtype: Any, xp: Any) -> InitialNoise:
    """The draws of a fresh episode from the counter-based generator of
    :mod:`bbgym.backends` (streams 1-3 of each env's key at its counter), as the torch
    backend draws them inside its compiled step."""
    n_uniform, n_normal = task.initial_noise_counts
    return InitialNoise(
        backends.uniforms(keys, counter, 1, n_uniform, dtype, xp),
        backends.normals(keys, counter, 2, n_normal, dtype, xp),
        backends.normals(keys, counter, 3, 2 * task.initial_stream_pairs, dtype, xp),
    )


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
    """

    def __init__(
        self,
        task: Any,
        max_episode_steps: int,
        xp: Any,
        dtype: Any,
        info_keys: tuple[str, ...] | None = None,
    ) -> None:
        self.task, self.max_episode_steps, self.xp, self.dtype = task, max_episode_steps, xp, dtype
        self.info_keys = info_keys

    def begin(self, state: Any, action: Any, keys: Any, counter: Any) -> Any:
        task, xp, dtype = self.task, self.xp, self.dtype
        n = 2 * task.step_noise_pairs
        noise = backends.normals(keys, counter, 0, n, dtype, xp) if n else ()
        return task.begin(state, action, noise, xp, False)

    def chunk(self, carry: Any) -> Any:
        return self.task.chunk(carry, self.xp)

    def end(self, state: Any, carry: Any, counter: Any, steps: Any, restarting: Any) -> tuple:
        """The transition's end and what the step reports (:func:`settle`)."""
        moved, _ = self.task.end(state, carry, self.xp)
        reward, terminated, truncated, steps = settle(
            self.task, moved, restarting, steps, self.max_episode_steps, self.xp
        )
        return moved, reward, terminated, truncated, counter + 1, steps

    def restart(self, moved: Any, restarting: Any, keys: Any, counter: Any) -> Any:
        """Fresh episodes where ``restarting`` (run only on steps where some env restarts,
        so the common step's graph holds no :meth:`initial`)."""
        noise = counter_initial_noise(self.task, keys, counter, self.dtype, self.xp)
        return restart(self.task, moved, restarting, noise, {}, self.xp)

    def observe(self, state: Any) -> tuple:
        """Observation and info of the new state (the infos of ``info_keys`` only: in a
        compiled step the others are never computed)."""
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
        nothing."""
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
    ) -> tuple:
        """Returns ``(state, obs, reward, terminated, truncated, info, counter, steps)``.
        ``parts`` are the compiled :meth:`begin`, :meth:`chunk`, :meth:`end`,
        :meth:`restart`, :meth:`observe` (default: these, eager); ``any_restarting``, if
        the caller knows it, saves a device sync."""
        begin, chunk, end, restart_, observe = parts or (
            self.begin,
            self.chunk,
            self.end,
            self.restart,
            self.observe,
        )
        carry = begin(state, action, keys, counter)
        task = self.task
        for _ in range(task.chunks):
            if task.stops_early and bool(self.xp.all(task.all_done(carry, self.xp))):
                break
            carry = chunk(carry)
        moved, reward, terminated, truncated, new_counter, steps = end(
            state, carry, counter, steps, restarting
        )
        if any_restarting is None:
            any_restarting = bool(self.xp.any(restarting))  # a device sync
        if any_restarting:
            moved = restart_(moved, restarting, keys, counter)
        obs, info = observe(moved)
        return moved, obs, reward, terminated, truncated, info, new_counter, steps


def select_info(info: dict[str, Any], info_keys: tuple[str, ...] | None) -> dict[str, Any]:
    """The entries of ``info`` named in ``info_keys`` (all of them where it is None)."""
    return info if info_keys is None else {k: info[k] for k in info_keys}


def task_info_names(task: Any) -> list[str]:
    """The names of a task's infos (``task.info``), read from one probe state."""
    n_uniform, n_normal = task.initial_noise_counts
    half, zero = np.full(1, 0.5), np.zeros(1)
    noise = InitialNoise(
        [half] * n_uniform, [zero] * n_normal, [zero] * (2 * task.initial_stream_pairs)
    )
    state = task.initial(noise, {}, np)
    return list(task.info(state, task.measure(state, np), np))


def tree_leaves(tree: Any) -> list:
    """The leaves of nested NamedTuples, tuples, lists and dicts, in :func:`tree_map`'s
    order."""
    leaves: list = []
    tree_map(leaves.append, tree)
    return leaves


def tree_with_leaves(tree: Any, leaves: list) -> Any:
    """``tree`` with its leaves replaced, in order, by ``leaves``."""
    it = iter(leaves)
    return tree_map(lambda _: next(it), tree)


def rolled_chunks(task: Any, carry: Any, xp: Any) -> Any:
    """``task.chunks`` chunks of a transition from ``carry`` in a ``while_loop`` (torch's
    loop primitive, which ``torch.compile`` keeps rolled: one chunk in the graph, not
    hundreds) that also stops once every env is done (``task.stops_early``). The loop
    carries only the tensors a chunk changes; the rest (the wind, the screen) it reads as
    constants."""
    if task.chunks <= 1:
        return task.chunk(carry, xp)
    import torch
    from torch._higher_order_ops import while_loop

    # Which leaves a chunk changes, from a chunk traced for that alone: its results are
    # unused, so the compiler drops its ops, and the graph holds the chunk once (in the
    # loop), not twice, which is most of what it costs to compile.
    probe = task.chunk(carry, xp)
    before = tree_leaves(carry)
    varying = [
        j
        for j, (old, new) in enumerate(zip(before, tree_leaves(probe), strict=True))
        if isinstance(new, torch.Tensor) and new is not old
    ]
    # No two of the loop's inputs may share memory (rows of one noise draw are views of
    # it, a flight's fields may be one array): each gets its own copy.
    leaves = [leaf.clone() if isinstance(leaf, torch.Tensor) else leaf for leaf in before]

    def rebuild(tensors: tuple) -> Any:
        replaced = list(leaves)
        for j, tensor in zip(varying, tensors, strict=True):
            replaced[j] = tensor
        return tree_with_leaves(carry, replaced)

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
