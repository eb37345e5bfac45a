"""What the envs share: argument validation, batch/element conversion, rendering set-up
and the native vector env machinery."""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding


def check_option_keys(options: Mapping[str, Any] | None, known: tuple[str, ...]) -> dict:
    """``reset`` options as a dict; ``None`` is empty. A non-mapping or an unknown key
    raises ``TypeError`` naming it (as an unknown keyword argument does).

    Args:
        options: The ``options`` a user passed to ``reset``: a mapping or ``None``.
        known: The option keys the env accepts.

    Returns:
        A new dict of the options (empty for ``None``).

    Raises:
        TypeError: If ``options`` is not a mapping, or has a key not in ``known``.
    """
    if options is None:
        return {}
    if not isinstance(options, Mapping):
        raise TypeError(f"options must be a dict, got {options!r}")
    for key in options:
        if key not in known:
            raise TypeError(f"options got an unexpected key {key!r}; known keys: {list(known)}")
    return dict(options)


def option_path(key: str) -> str:
    """How errors name a reset option: ``options['speed']``.

    Args:
        key: The option's key, e.g. ``"speed"``.

    Returns:
        ``"options['<key>']"``.
    """
    return f"options[{key!r}]"


def check_multiple(name: str, value: float, base_name: str, base: float) -> int:
    """How many ``base`` steps make ``value``; ``value`` must be a whole multiple.

    Args:
        name: ``value``'s argument name, for the error (``"ctrl_dt"``).
        value: The longer duration, in the same unit as ``base`` (s).
        base_name: ``base``'s argument name, for the error (``"sim_dt"``).
        base: The step it must be a multiple of (> 0, s).

    Returns:
        ``round(value / base)``, at least 1.

    Raises:
        ValueError: If ``value`` is not a whole multiple (>= 1) of ``base`` to within a
            relative ``1e-9``.
    """
    count = round(value / base)
    if count < 1 or abs(count * base - value) > 1e-9 * max(1.0, value):
        raise ValueError(f"{name} ({value!r}) must be a whole multiple of {base_name} ({base!r})")
    return count


FULL_CIRCLE_RAD = (0.0, 2.0 * math.pi)


def mean_wind(
    options: Mapping[str, Any],
    speed_range: tuple[float, float],
    speed_draw: Any,
    from_draw: Any,
    from_range: tuple[float, float] = FULL_CIRCLE_RAD,
) -> tuple[Any, Any]:
    """Mean wind ``(speed, from)``: the ``wind`` option (a vector, where the air moves) if
    given, else a speed uniform in ``speed_range`` from a direction uniform in
    ``from_range`` (draws in [0, 1); the default, any direction, is ``2 pi * from_draw`` to
    the bit).

    Args:
        options: The checked ``reset`` options; its ``wind`` entry, if any, is ``(x, y)``
            in m/s, the direction the air moves.
        speed_range: ``(low, high)`` of the drawn wind speed, m/s.
        speed_draw: A uniform draw in [0, 1) (a float, or an array for a batch).
        from_draw: A uniform draw in [0, 1) for the direction (same shape as
            ``speed_draw``).
        from_range: ``(low, high)`` of the direction the wind blows from, rad
            (default: the full circle).

    Returns:
        ``(speed, from)``: the speed in m/s and the direction the wind blows from in rad
        (floats, or arrays shaped like the draws).
    """
    if "wind" in options:
        wx, wy = options["wind"]
        return math.hypot(wx, wy), math.atan2(-wy, -wx)
    lo, hi = speed_range
    from_lo, from_hi = from_range
    return lo + (hi - lo) * speed_draw, from_lo + (from_hi - from_lo) * from_draw


def check_box_action(action: Any, size: int, batch: int) -> np.ndarray:
    """Actions as float64 ``(size,)`` (``batch == 0``: one env) or ``(batch, size)``,
    clipped to [-1, 1]; a wrong shape or a NaN/inf raises ``ValueError``, a complex
    number ``TypeError``.

    Args:
        action: What the user passed to ``step``: array-like of real numbers.
        size: The action's length (the action space's last dimension).
        batch: The number of envs of a vector env; 0 for a single env.

    Returns:
        A float64 array of shape ``(size,)`` or ``(batch, size)``, clipped to [-1, 1].

    Raises:
        ValueError: If ``action`` is not numeric, has the wrong shape or holds a NaN or
            an infinity.
        TypeError: If ``action`` is complex.
    """
    try:
        raw = np.asarray(action)
        is_complex = raw.dtype.kind == "c"  # a cast would drop the imaginary part, warning
        a = raw if is_complex else raw.astype(np.float64)
    except (TypeError, ValueError):  # a string, a ragged nest of lists
        raise ValueError(f"action must be numeric, got {action!r}") from None
    if is_complex:
        raise TypeError(f"action must be real, got {action!r}")
    expected = (size,) if batch == 0 else (batch, size)
    if a.shape != expected:
        raise ValueError(f"action must have shape {expected}, got {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"action must be finite, got {action!r}")
    return np.clip(a, -1.0, 1.0)


def vector_seeds(seed: int | list[int | None] | None, num_envs: int) -> list[int | None]:
    """Per-sub-env seeds: ``seed + i`` for an int (Gymnasium's convention), a list as given,
    or fresh entropy for ``None``.

    Args:
        seed: An int >= 0 (sub-env ``i`` gets ``seed + i``), a list of ``num_envs`` ints
            >= 0 or ``None`` (one per sub-env), or ``None``.
        num_envs: The number of sub-envs.

    Returns:
        One seed (a Python int or ``None``) per sub-env.

    Raises:
        TypeError: If ``seed`` (or an entry) is not an int, a list or ``None``.
        ValueError: If a seed is negative or a list has not ``num_envs`` entries.
    """
    if seed is None:
        return [None] * num_envs
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, (bool, np.bool_)):
        return [check_seed(seed) + i for i in range(num_envs)]
    if not isinstance(seed, (list, tuple, np.ndarray)):
        raise TypeError(f"seed must be an int >= 0, a list of {num_envs} or None, got {seed!r}")
    seeds = list(seed)
    if len(seeds) != num_envs:
        raise ValueError(f"seed must have {num_envs} entries, got {len(seeds)}")
    return [None if s is None else check_seed(s, f"seed[{i}]") for i, s in enumerate(seeds)]


def check_seed(seed: Any, path: str = "seed") -> int:
    """A seed as a Python int: an int (not a bool) >= 0, as Gymnasium's seeding needs.

    Args:
        seed: What the user passed: a Python or NumPy int >= 0.
        path: Its name in errors (``"seed"``, ``"seed[3]"``).

    Returns:
        ``int(seed)``.

    Raises:
        TypeError: If ``seed`` is not an int (a bool is refused).
        ValueError: If ``seed`` is negative.
    """
    if not isinstance(seed, (int, np.integer)) or isinstance(seed, (bool, np.bool_)):
        raise TypeError(f"{path} must be an int >= 0 or None, got {seed!r}")
    if seed < 0:
        raise ValueError(f"{path} must be an int >= 0 or None, got {seed!r}")
    return int(seed)


def vector_info(info: dict[str, Any], num_envs: int) -> dict[str, Any]:
    """Gymnasium's vector info layout: every key with a ``_key`` mask (all envs report).

    Args:
        info: The batched info: each value an array of ``num_envs`` entries, or a nested
            dict of such.
        num_envs: The number of sub-envs.

    Returns:
        A new dict with each key (nested dicts laid out the same way) and its all-True
        ``_key`` mask.
    """
    mask = np.ones(num_envs, dtype=bool)
    out: dict[str, Any] = {}
    for key, value in info.items():
        out[key] = vector_info(value, num_envs) if isinstance(value, dict) else value
        out[f"_{key}"] = mask
    return out


LIST_MODE = "rgb_array_list"
"""Gymnasium's render mode in which ``render()`` returns the frames collected since the last
``render()`` or ``reset()`` (what :class:`gymnasium.wrappers.RenderCollection` makes of
``rgb_array``)."""
RENDER_MODES = ["human", "rgb_array", LIST_MODE]
"""The render modes of every env (single and native vector)."""


def renderer_mode(render_mode: str) -> str:
    """The renderer's mode for an env's ``render_mode``: a list of frames is drawn off-screen
    frame by frame, as ``rgb_array`` draws one.

    Args:
        render_mode: One of :data:`RENDER_MODES`.

    Returns:
        ``"rgb_array"`` for :data:`LIST_MODE`, else ``render_mode``.
    """
    return "rgb_array" if render_mode == LIST_MODE else render_mode


def pad_rows(rows: np.ndarray, lengths: np.ndarray, capacity: int, fill: Any = 0.0) -> np.ndarray:
    """Fixed-shape records: ``rows`` ``(n, K, ...)`` of which env ``i`` recorded the first
    ``lengths[i]``, as ``(n, capacity, ...)``. Rows from ``lengths[i]`` on repeat the last
    recorded one (a ball at rest stays where it stopped, so maxima, minima and the last row
    keep their meaning); an env that recorded nothing is ``fill`` (zeros, ``False`` for
    masks) throughout.

    Args:
        rows: The records, ``(n, K, ...)``.
        lengths: How many rows each env recorded, ``(n,)`` ints in ``[0, min(K,
            capacity)]``.
        capacity: The number of rows of the result.
        fill: The value of an env that recorded nothing.

    Returns:
        An ``(n, capacity, ...)`` array of ``rows``' dtype.

    Raises:
        ValueError: If an env recorded more than ``min(K, capacity)`` rows.
    """
    n, k = rows.shape[:2]
    lengths = np.asarray(lengths, dtype=np.int64).reshape(n)
    if int(lengths.max(initial=0)) > min(k, capacity):
        raise ValueError(f"records of {lengths.max()} rows exceed {min(k, capacity)}")
    tail = rows.shape[2:]
    if k == 0:
        return np.full((n, capacity, *tail), fill, dtype=rows.dtype)
    index = np.clip(np.minimum(np.arange(capacity), lengths[:, None] - 1), 0, k - 1)
    padded = np.take_along_axis(rows, index.reshape(n, capacity, *(1,) * len(tail)), axis=1)
    recorded = (lengths > 0).reshape(n, 1, *(1,) * len(tail))
    return np.where(recorded, padded, np.asarray(fill, dtype=rows.dtype))


def check_render_mode(render_mode: str | None, modes: list[str]) -> None:
    """``None`` or one of ``modes``, else ``ValueError`` naming ``render_mode``.

    Args:
        render_mode: The ``render_mode`` a user passed.
        modes: The env's render modes (:data:`RENDER_MODES`).

    Raises:
        ValueError: If ``render_mode`` is neither ``None`` nor in ``modes``.
    """
    if render_mode is not None and render_mode not in modes:
        raise ValueError(f"render_mode must be one of {modes}, got {render_mode!r}")


def ensure_renderer(env: Any) -> Any:
    """The env's renderer, made on first use by ``env._make_renderer()`` (so pygame is
    imported only then); ``None``, with a warning, for an env without a ``render_mode``.

    Args:
        env: A bbgym env (single or native vector) with ``render_mode``, ``_renderer``
            and ``_make_renderer()``.

    Returns:
        The env's renderer, or ``None`` where ``env.render_mode`` is ``None``.

    Raises:
        gymnasium.error.ResetNeeded: If the env has not been reset yet.
    """
    if env.render_mode is None:
        gym.logger.warn(
            "render() called without a render_mode; pass render_mode='rgb_array', "
            "'rgb_array_list' or 'human'."
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
    copy, so the renderer is left out and made again on the next ``render()``.

    Args:
        attributes: The env's ``__dict__``.

    Returns:
        A shallow copy with ``_renderer`` set to ``None``.
    """
    state = dict(attributes)
    state["_renderer"] = None
    return state


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

    Args:
        batch: The number of envs (1 for a single env).
        block: Pairs each env draws from its generator at a time.
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
        """Give every env a fresh generator seeded from ``seeds`` (its unused pairs go).

        Args:
            seeds: One seed per env: an int >= 0, or ``None`` for fresh entropy.
        """
        for i, s in enumerate(seeds):
            self.set(i, seeding.np_random(s)[0])

    def set(self, i: int, rng: np.random.Generator) -> None:
        """Give env ``i`` the generator ``rng`` (a single env's ``np_random``).

        Args:
            i: The env's index in ``[0, batch)``.
            rng: Its new generator; its unused pairs are discarded.
        """
        self.rngs[i] = rng
        self.discard(self._rows == i)

    def discard(self, mask: np.ndarray) -> None:
        """Throw away the unused pairs of the envs in ``mask`` (a reset): their next pair
        starts a new block, drawn from the generator after whatever the reset drew.

        Args:
            mask: ``(batch,)`` bools: the envs that reset.
        """
        self._end = np.where(mask, self._drawn, self._end)
        self._next = np.where(mask, self._end, self._next)
        for i in np.flatnonzero(mask):
            self._ahead.pop(int(i), None)

    def one(self, draw: bool) -> tuple[float, float]:
        """The single env's next pair as Python floats (zeros if not ``draw``), from the
        same stream as :meth:`pairs`.

        Args:
            draw: Whether to draw a pair (``False``: nothing is used up).

        Returns:
            ``(first, second)``, two standard normals, or ``(0.0, 0.0)``.
        """
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

        Envs outside ``mask`` draw nothing, so no env's numbers depend on another's.

        Args:
            mask: ``(batch,)`` bools: the envs that draw.

        Returns:
            A ``(2, batch)`` float64 array.
        """
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
        only once they are used: a reset in between leaves the stream as if never peeked.

        Args:
            mask: ``(batch,)`` bools: the envs whose pairs are shown.
            count: Pairs shown per env (>= 0).

        Returns:
            A ``(count, 2, batch)`` float64 array.
        """
        mask = np.asarray(mask, dtype=bool)
        for i in np.flatnonzero(mask & (self._end - self._next < count)):
            self._refill(i, count)
        take = self._next[:, None] + np.arange(count)
        picked = self._buffer[self._rows[:, None], np.minimum(take, self._buffer.shape[1] - 1)]
        return np.where(mask[:, None, None], picked, 0.0).transpose(1, 2, 0)

    def advance(self, used: np.ndarray) -> None:
        """Use up ``used[i]`` pairs of env ``i`` (at most what :meth:`peek` showed).

        Args:
            used: ``(batch,)`` ints (or bools, one pair each) >= 0: pairs each env used.
        """
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
