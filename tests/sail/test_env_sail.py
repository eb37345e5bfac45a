"""BeachballSail-v0 and -v1: Gymnasium contract, determinism, vector env, options, rewards."""

from __future__ import annotations

import math
import os

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs.sail import BeachballSailEnv, BeachballSailVectorEnv

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

INFO_KEYS = {
    "position",
    "velocity",
    "boat_speed",
    "heading",
    "true_wind_angle",
    "apparent_wind_angle",
    "apparent_wind_speed",
    "heel",
    "leeway",
    "boom_angle",
    "vmg_to_mark",
    "distance_to_mark",
    "jibes",
    "tacks",
    "capsized",
    "is_success",
    "reward_terms",
}


def rollout(env, seed, actions):
    obs, _ = env.reset(seed=seed)
    out = [obs]
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a)
        out.append(obs)
        if terminated or truncated:
            break
    return np.array(out)


def test_registered_with_entry_points_and_time_limit():
    spec = gym.spec("BeachballSail-v0")
    assert spec.entry_point == "bbgym.envs.sail:BeachballSailEnv"
    assert spec.vector_entry_point == "bbgym.envs.sail:BeachballSailVectorEnv"
    assert spec.max_episode_steps == 1200
    env = gym.make("bbgym:BeachballSail-v0")
    assert isinstance(env.unwrapped, BeachballSailEnv)
    vec = gym.make_vec("BeachballSail-v0", num_envs=3)
    assert isinstance(vec, BeachballSailVectorEnv) and vec.max_episode_steps == 1200


def test_check_env_passes_without_gusts_on_the_seed_sail():
    # The registered ids pass it in the kit (tests/test_conformance.py); this is a variant.
    check_env(BeachballSailEnv(gusts=False, sail_model="seed"), skip_render_check=True)


def test_vector_env_matches_single_envs():
    n, steps = 4, 120
    actions = np.random.default_rng(1).uniform(-1, 1, (steps, n, 2)).astype(np.float32)
    vec = gym.make_vec("BeachballSail-v0", num_envs=n)
    obs, _ = vec.reset(seed=100)
    vec_obs, vec_rew, vec_done = [obs], [], []
    for t in range(steps):
        obs, rew, term, trunc, info = vec.step(actions[t])
        # Every env's reward is the sum of its reported terms, also on steps where another
        # env restarts (a partial reset must not wipe the others' infos).
        terms = info["reward_terms"]
        np.testing.assert_allclose(sum(terms[k] for k in terms if not k.startswith("_")), rew)
        vec_obs.append(obs)
        vec_rew.append(rew)
        vec_done.append(term | trunc)
    vec_obs, vec_rew, vec_done = np.array(vec_obs), np.array(vec_rew), np.array(vec_done)
    for i in range(n):
        env = gym.make("BeachballSail-v0")
        obs, _ = env.reset(seed=100 + i)
        np.testing.assert_allclose(obs, vec_obs[0, i], atol=1e-6)
        for t in range(steps):
            obs, rew, term, trunc, _ = env.step(actions[t, i])
            np.testing.assert_allclose(obs, vec_obs[t + 1, i], atol=1e-5)
            assert rew == pytest.approx(vec_rew[t, i], abs=1e-6)
            assert (term or trunc) == vec_done[t, i]
            if term or trunc:
                obs, _ = env.reset()  # the vector env restarts on its next step
                np.testing.assert_allclose(obs, vec_obs[t + 2, i], atol=1e-6)
                break


def test_vector_env_autoresets_on_next_step():
    vec = BeachballSailVectorEnv(num_envs=2, max_episode_steps=5)
    vec.reset(seed=0)
    for _ in range(5):
        _, _, term, trunc, _ = vec.step(np.zeros((2, 2), np.float32))
    assert trunc.all() and not term.any()
    obs, reward, term, trunc, info = vec.step(np.zeros((2, 2), np.float32))
    np.testing.assert_array_equal(reward, 0.0)
    assert not (term | trunc).any()
    np.testing.assert_allclose(info["elapsed_time"], 0.0)
    np.testing.assert_allclose(info["position"], 0.0)
    assert INFO_KEYS <= set(info) and info["_boat_speed"].all()


def test_reset_options_pin_the_scenario():
    env = gym.make("BeachballSail-v0")
    options = dict(
        wind_speed=6.0,
        wind_from=math.pi / 2,
        mark=(30.0, -20.0),
        heading=math.pi,
        speed=1.0,
        gusts=False,
    )
    obs, info = env.reset(seed=0, options=options)
    assert info["true_wind_speed"] == pytest.approx(6.0)
    # Heading west, wind from the north: from the boat's right (starboard), TWA = -90 deg.
    assert info["true_wind_angle"] == pytest.approx(-math.pi / 2)
    assert info["boat_speed"] == pytest.approx(1.0)
    np.testing.assert_allclose(info["mark"], [30.0, -20.0])
    assert info["distance_to_mark"] == pytest.approx(math.hypot(30.0, 20.0))
    # Egocentric observation: true wind from the right => sin(TWA) = -1.
    assert obs[4] == pytest.approx(-1.0, abs=1e-6)
    for _ in range(20):
        *_, info = env.step(np.zeros(2, np.float32))
    assert info["true_wind_speed"] == pytest.approx(6.0)  # no gusts


@pytest.mark.parametrize(
    "options, name",
    [
        ({"wind_speed": -1.0}, "wind_speed"),
        ({"wind_from": float("nan")}, "wind_from"),
        ({"mark": (1.0, 0.0)}, "mark"),
        ({"mark": (1.0,)}, "mark"),
    ],
)
def test_bad_reset_options_raise(options, name):
    # Unknown keys and wrong types raise TypeError: tests/test_validation.py.
    env = gym.make("BeachballSail-v0")
    with pytest.raises(ValueError, match=name):
        env.reset(seed=0, options=options)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"mark_radius": -1.0}, "mark_radius"),
        ({"wind_speed_range": (5.0, 2.0)}, "wind_speed_range"),
        ({"ctrl_dt": 0.0}, "ctrl_dt"),
        ({"ctrl_dt": 0.23}, "ctrl_dt"),
        ({"dinghy": {"mass_kg": 0.0}}, "mass_kg"),
        ({"sail_model": "wing"}, "sail_model"),
        ({"gust_params": {"speed_std": -1}}, "speed_std"),
        ({"render_mode": "ascii"}, "render_mode"),
    ],
)
def test_bad_constructor_arguments_raise(kwargs, name):
    with pytest.raises(ValueError, match=name):
        BeachballSailEnv(**kwargs)


def test_bad_actions_raise():
    env = gym.make("BeachballSail-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([np.nan, 0.0], np.float32))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(3, np.float32))
    vec = gym.make_vec("BeachballSail-v0", num_envs=2)
    vec.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        vec.step(np.array([[0.0, 0.0], [np.inf, 0.0]], np.float32))


def test_rewards_bounded_and_terms_add_up():
    env = gym.make("BeachballSail-v0")
    low, high = env.unwrapped.task.reward_range
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    for _ in range(600):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2))
        assert low <= reward <= high
        assert reward == pytest.approx(sum(info["reward_terms"].values()))
        assert env.observation_space.contains(obs)
        if terminated or truncated:
            env.reset()


def test_arrival_terminates_with_success_and_bonus():
    env = gym.make("BeachballSail-v0")
    env.reset(
        seed=0,
        options=dict(
            wind_speed=5.0,
            wind_from=math.pi / 2,
            mark=(12.0, 0.0),
            heading=0.0,
            speed=2.5,
            gusts=False,
        ),
    )
    for _ in range(100):
        _, reward, terminated, truncated, info = env.step(np.array([0.0, 0.0], np.float32))
        if terminated:
            break
    assert terminated and info["is_success"] and not info["capsized"]
    assert info["reward_terms"]["arrival"] == 10.0 and reward > 9.0
    assert info["distance_to_mark"] <= 5.0


def test_capsize_terminates_with_penalty():
    env = gym.make("BeachballSail-v0")
    env.reset(
        seed=0,
        options=dict(
            wind_speed=9.5,
            wind_from=math.pi / 2,
            mark=(-90.0, 0.0),
            heading=0.0,
            speed=2.0,
            gusts=False,
        ),
    )
    for _ in range(100):
        _, reward, terminated, _, info = env.step(np.array([0.0, -1.0], np.float32))
        if terminated:
            break
    assert terminated and info["capsized"] and not info["is_success"]
    assert info["reward_terms"]["capsize"] == -10.0 and reward < -9.0


def test_info_carries_physical_quantities():
    env = gym.make("BeachballSail-v0")
    _, info = env.reset(seed=0)
    assert INFO_KEYS <= set(info)
    _, _, _, _, info = env.step(np.zeros(2, np.float32))
    assert info["boat_speed"] == pytest.approx(float(np.hypot(*info["velocity"])))
    assert isinstance(info["jibes"], int) and isinstance(info["is_success"], bool)


def test_render_rgb_array_single_and_vector():
    pytest.importorskip("pygame")
    env = gym.make("BeachballSail-v0", render_mode="rgb_array")
    env.reset(seed=0)
    env.step(np.zeros(2, np.float32))
    frame = env.render()
    assert frame.shape == (480, 640, 3) and frame.dtype == np.uint8 and frame.std() > 5
    env.close()
    vec = gym.make_vec("BeachballSail-v0", num_envs=2, render_mode="rgb_array")
    vec.reset(seed=0)
    frames = vec.render()
    assert len(frames) == 2 and frames[0].shape == (480, 640, 3)
    assert not np.array_equal(frames[0], frames[1])
    vec.close()


def test_v1_is_v0_with_time_and_capsizes_costing_more():
    """BeachballSail-v1 sails exactly as v0 (observations, ends, progress, arrivals); only
    its time term (-0.1 a step, v0 -0.01) and capsize term (-30, v0 -10) differ."""
    check_env(gym.make("BeachballSail-v1").unwrapped, skip_render_check=True)
    strong = {"wind_speed_range": (9.0, 14.0)}  # random play capsizes in this
    v0 = gym.make_vec("BeachballSail-v0", num_envs=64, **strong)
    v1 = gym.make_vec("BeachballSail-v1", num_envs=64, **strong)
    np.testing.assert_array_equal(v0.reset(seed=5)[0], v1.reset(seed=5)[0])
    rng = np.random.default_rng(1)
    capsizes = 0
    for _ in range(300):
        action = rng.uniform(-1.0, 1.0, (64, 2)).astype(np.float32)
        (o0, r0, term0, trunc0, i0), (o1, r1, term1, trunc1, i1) = v0.step(action), v1.step(action)
        for a, b in ((o0, o1), (term0, term1), (trunc0, trunc1)):
            np.testing.assert_array_equal(a, b)
        t0, t1 = i0["reward_terms"], i1["reward_terms"]
        for term in ("progress", "arrival"):
            np.testing.assert_array_equal(t0[term], t1[term])
        stepped = t0["time"] != 0.0  # not the step that restarts a finished env
        capsized = t0["capsize"] != 0.0
        np.testing.assert_array_equal(stepped, t1["time"] != 0.0)
        np.testing.assert_array_equal(capsized, t1["capsize"] != 0.0)
        np.testing.assert_allclose(t0["time"][stepped], -0.01)
        np.testing.assert_allclose(t1["time"][stepped], -0.1)
        np.testing.assert_allclose(t0["capsize"][capsized], -10.0)
        np.testing.assert_allclose(t1["capsize"][capsized], -30.0)
        extra = np.where(stepped, -0.09, 0.0) + np.where(capsized, -20.0, 0.0)
        np.testing.assert_allclose(r1 - r0, extra, atol=1e-9)
        capsizes += int(capsized.sum())
    assert capsizes > 0
