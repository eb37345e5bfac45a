"""A boat at rest in a calm on the float32 torch backend (issue 51's fuzz found it): the
apparent wind's direction divided 0 by ``0 + 1e-300``, and 1e-300 is 0 in float32, so the
first step was NaN everywhere. The floor of a norm is now one float32 represents
(:data:`bbgym.physics.common.NORM_FLOOR`), and a real motion's float64 bits are unchanged
(the golden replays)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401  (registers the ids)
from bbgym.physics.common import NORM_FLOOR


def test_the_norm_floor_and_its_inverse_are_float32_numbers() -> None:
    assert np.float32(NORM_FLOOR) > 0.0
    assert np.isfinite(np.float32(1.0) / np.float32(NORM_FLOOR))


@pytest.mark.parametrize("env_id", ["BeachballSail-v1", "BeachballSail-v2"])
def test_a_boat_at_rest_in_a_calm_stays_finite_in_float32(env_id: str) -> None:
    pytest.importorskip("torch")
    pytest.importorskip("array_api_compat")
    calm = {"wind_speed_range": (0.0, 0.0), "initial_speed_range": (0.0, 0.0), "gusts": False}
    env = gym.make_vec(env_id, num_envs=2, backend="torch", dtype="float32", compile=False, **calm)
    obs, _ = env.reset(seed=0)
    for _ in range(3):
        obs, reward, *_ = env.step(np.zeros(env.action_space.shape, np.float32))
        assert np.isfinite(np.asarray(obs)).all() and np.isfinite(np.asarray(reward)).all()
    # Nothing drives it: it stays where it started, as in float64 (the same draws).
    reference = gym.make_vec(
        env_id, num_envs=2, backend="torch", dtype="float64", compile=False, **calm
    )
    expected, _ = reference.reset(seed=0)
    for _ in range(3):
        expected = reference.step(np.zeros(env.action_space.shape, np.float32))[0]
    np.testing.assert_allclose(np.asarray(obs), np.asarray(expected), atol=1e-5)
