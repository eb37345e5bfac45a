"""Keyboard control of the envs for ``gymnasium.utils.play`` (``bbgym play``; needs pygame,
the ``render`` extra).

Both action spaces are continuous, so a small wrapper turns the keys held in each frame
into an action, keeping state between frames: :class:`KeyboardWrapper` here, and each
family's own, which its spec names (:attr:`bbgym.spec.EnvSpec.keyboard`): sailing's in
``bbgym.envs.sail.keys``, the ball envs' shared ``bbgym.envs.ball_keys``. The keys are listed by
``bbgym play --help`` (:mod:`bbgym.cli.play`). A finished episode starts the next one; the
seed given seeds the first episode (the next ones follow from it).
"""

from __future__ import annotations

import os

os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import itertools
import warnings
from collections.abc import Callable, Mapping
from typing import Any

import gymnasium as gym
import numpy as np
import pygame
from gymnasium import spaces

import bbgym  # noqa: F401  (registers the envs)
from bbgym.spec import spec_of


def combine_keys(effects: Mapping[int, tuple[float, ...]]) -> dict[tuple[int, ...], np.ndarray]:
    """A ``keys_to_action`` dict for ``gymnasium.utils.play``: every combination of the keys
    (sorted key codes) -> the sum of their effects, clipped to [-1, 1], as float32."""
    table = {}
    codes = sorted(effects)
    for r in range(1, len(codes) + 1):
        for combo in itertools.combinations(codes, r):
            total = np.sum([effects[k] for k in combo], axis=0)
            table[combo] = np.clip(total, -1.0, 1.0).astype(np.float32)
    return table


def show_status(text: str) -> None:
    """Show ``text`` on the console line and, when a window is open, in its title."""
    print(f"\r{text}   ", end="", flush=True)
    if pygame.display.get_init() and pygame.display.get_surface() is not None:
        pygame.display.set_caption(text)


class KeyboardWrapper(gym.Wrapper):
    """Base of the keyboard wrappers: ``get_keys_to_action()``, ``noop``, and a seed used for
    the first reset only (``gymnasium.utils.play`` resets every episode with its seed)."""

    key_effects: Mapping[int, tuple[float, ...]] = {}

    def __init__(self, env: gym.Env, seed: int | None = None) -> None:
        super().__init__(env)
        n = len(next(iter(self.key_effects.values())))
        self.action_space = spaces.Box(-1.0, 1.0, (n,), np.float32)
        self.noop = np.zeros(n, dtype=np.float32)
        self._first_seed = seed

    def get_keys_to_action(self) -> dict[tuple[int, ...], np.ndarray]:
        return combine_keys(self.key_effects)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> Any:
        if seed is None and self._first_seed is not None:
            seed = self._first_seed
        self._first_seed = None
        return self.env.reset(seed=seed, options=options)


def make_play_env(env_id: str, seed: int | None = None) -> KeyboardWrapper:
    """``env_id`` in ``rgb_array`` mode, wrapped for the keyboard by its family's
    :attr:`~bbgym.spec.EnvSpec.keyboard`."""
    spec = spec_of(env_id)
    if spec.keyboard is None:
        raise ValueError(f"no keyboard mapping for {env_id!r}")
    return spec.keyboard(gym.make(env_id, render_mode="rgb_array"), seed)


def import_gym_play() -> Any:
    """``gymnasium.utils.play``, without the side effect of its import: it switches
    matplotlib to TkAgg (for ``PlayPlot``, not used here); the backend is restored."""
    try:
        import matplotlib
    except ImportError:
        from gymnasium.utils import play as gym_play

        return gym_play
    backend = dict.__getitem__(matplotlib.rcParams, "backend")  # may be "auto", unresolved
    with warnings.catch_warnings():  # its "matplotlib is not installed" when TkAgg fails
        warnings.simplefilter("ignore")
        from gymnasium.utils import play as gym_play

    if dict.__getitem__(matplotlib.rcParams, "backend") != backend:
        matplotlib.use(backend)
    return gym_play


def play_env(
    env: KeyboardWrapper,
    fps: int = 20,
    zoom: float = 1.0,
    callback: Callable[..., Any] | None = None,
) -> None:
    """Play ``env`` (a :class:`KeyboardWrapper`) in a pygame window until ESC or close."""
    import_gym_play().play(
        env,
        fps=fps,
        zoom=zoom,
        keys_to_action=env.get_keys_to_action(),
        noop=env.noop,
        callback=callback,
    )
