"""The stable-baselines3 adapter gives the transitions of SB3's own DummyVecEnv."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from stable_baselines3.common.vec_env import DummyVecEnv  # noqa: E402

import bbgym  # noqa: E402, F401
from bbgym.sb3 import NativeVecEnvAdapter, make_sb3_vec_env  # noqa: E402


@pytest.mark.parametrize(
    "env_id, kwargs, steps",
    [
        # A short time limit makes truncations; random sailing also capsizes (terminations).
        ("BeachballSail-v0", {"max_episode_steps": 40}, 120),
        ("BeachballThrow-v0", {}, 8),
        ("BeachballTopple-v0", {"throws_per_episode": 2}, 6),
    ],
)
def test_adapter_matches_dummy_vec_env(env_id, kwargs, steps):
    n, seed = 4, 7
    adapter = make_sb3_vec_env(env_id, n_envs=n, seed=seed, **kwargs)
    dummy = DummyVecEnv([lambda: gym.make(env_id, **kwargs) for _ in range(n)])
    dummy.seed(seed)
    np.testing.assert_allclose(adapter.reset(), dummy.reset(), atol=1e-5)
    rng = np.random.default_rng(0)
    shape = adapter.action_space.shape
    done_count = truncation_count = 0
    for _ in range(steps):
        actions = rng.uniform(-1, 1, (n, *shape)).astype(np.float32)
        a_obs, a_rew, a_done, a_info = adapter.step(actions)
        d_obs, d_rew, d_done, d_info = dummy.step(actions)
        np.testing.assert_allclose(a_obs, d_obs, atol=1e-5)
        np.testing.assert_allclose(a_rew, d_rew, atol=1e-5)
        np.testing.assert_array_equal(a_done, d_done)
        for i in np.flatnonzero(d_done):
            done_count += 1
            truncation_count += d_info[i]["TimeLimit.truncated"]
            np.testing.assert_allclose(
                a_info[i]["terminal_observation"], d_info[i]["terminal_observation"], atol=1e-5
            )
            assert a_info[i]["TimeLimit.truncated"] == d_info[i]["TimeLimit.truncated"]
            assert a_info[i]["is_success"] == d_info[i]["is_success"]
    assert done_count >= n  # the comparison went through episode ends
    if env_id == "BeachballSail-v0":
        assert truncation_count > 0


def test_ppo_trains_on_the_adapter():
    from stable_baselines3 import PPO

    env = make_sb3_vec_env("BeachballSail-v0", n_envs=4, seed=0)
    model = PPO("MlpPolicy", env, n_steps=64, batch_size=64, n_epochs=1, seed=0, device="cpu")
    model.learn(total_timesteps=512)
    assert model.num_timesteps >= 512
    action, _ = model.predict(env.reset(), deterministic=True)
    assert action.shape == (4, 2)


def test_adapter_rejects_other_vector_envs():
    with pytest.raises(ValueError, match="venv"):
        NativeVecEnvAdapter(gym.make_vec("CartPole-v1", num_envs=2, vectorization_mode="sync"))
