"""A scenario pinned by reset options is the same episode on every backend.

The NumPy backend draws from NumPy's generators (sub-env ``i`` is the single env seeded
``seed + i``); the torch backend from its counter-based generator (``bbgym.backends``). So
an episode drawn at random differs between them, but an episode whose every random input is
pinned (the reset options, gusts off, no windsock noise) is the same to float64 rounding,
up to the first autoreset: options pin the episode of the ``reset`` call they are passed
to (Gymnasium's contract), and the episodes after an autoreset are drawn again, by each
backend's own generator."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401

pytest.importorskip("torch")
pytest.importorskip("array_api_compat")

N = 4
PINNED = {
    "BeachballThrow-v0": (
        {"windsock_noise": 0.0},
        {"wind": (1.0, -0.5), "target": (7.0, 1.0), "gusts": False},
    ),
    "BeachballCurve-v1": (
        {"windsock_noise": 0.0},
        {"wind": (1.0, -0.5), "target": (7.0, 1.0), "gusts": False, "screen": True},
    ),
    "BeachballCurve-v2": (
        {"windsock_noise": 0.0},
        {"wind": (1.0, -0.5), "target": (7.0, 1.0), "gusts": False, "screen": True},
    ),
    "BeachballTopple-v1": (
        {"windsock_noise": 0.0},
        {"wind": (1.5, 0.5), "wall_distance": 6.0, "gusts": False},
    ),
    "BeachballTopple-v2": (
        {"windsock_noise": 0.0},
        {"wind": (1.5, 0.5), "wall_distance": 4.0, "gusts": False},
    ),
    "BeachballSail-v1": (
        {"max_episode_steps": 40},
        {
            "wind_speed": 5.0,
            "wind_from": 1.0,
            "speed": 1.0,
            "heading": 0.3,
            "mark": (30.0, 10.0),
            "gusts": False,
        },
    ),
}


def make(env_id: str, backend: str, **kwargs) -> gym.vector.VectorEnv:
    extra = {"dtype": "float64", "compile": False} if backend == "torch" else {}
    return gym.make_vec(
        env_id,
        num_envs=N,
        vectorization_mode="vector_entry_point",
        backend=backend,
        **extra,
        **kwargs,
    )


@pytest.mark.parametrize("env_id", sorted(PINNED))
def test_a_pinned_episode_is_the_same_on_numpy_and_torch(env_id: str) -> None:
    kwargs, options = PINNED[env_id]
    envs = {b: make(env_id, b, **kwargs) for b in ("numpy", "torch")}
    first = {b: e.reset(seed=5, options=options)[0] for b, e in envs.items()}
    np.testing.assert_allclose(first["torch"], first["numpy"], rtol=0, atol=1e-6)
    actions = (
        np.random.default_rng(3)
        .uniform(-1, 1, (200, *envs["numpy"].action_space.shape))
        .astype(np.float32)
    )
    steps = 0
    for a in actions:
        got = {b: e.step(a) for b, e in envs.items()}
        np.testing.assert_allclose(got["torch"][0], got["numpy"][0], rtol=0, atol=1e-6)
        np.testing.assert_allclose(got["torch"][1], got["numpy"][1], rtol=0, atol=1e-9)
        for i in (2, 3):  # terminated, truncated
            np.testing.assert_array_equal(got["torch"][i], got["numpy"][i])
        steps += 1
        if np.any(got["numpy"][2] | got["numpy"][3]):
            break  # the next step starts episodes drawn by each backend's own generator
    assert steps >= 2, "the pinned episode ended before it could be compared"
    assert np.all(got["numpy"][2] | got["numpy"][3]), "the envs' episodes ended apart"
