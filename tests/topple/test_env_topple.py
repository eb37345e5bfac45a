"""BeachballTopple-v0: contract, determinism, vector env, scenarios, errors."""

from __future__ import annotations

import math
import os
from dataclasses import fields

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs.topple import BeachballToppleEnv, BeachballToppleVectorEnv

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

INFO_KEYS = {
    "wall_angle",
    "wall_angular_velocity",
    "wall_state",
    "hits",
    "throws",
    "is_success",
    "reward_terms",
    "windsock",
    "ball_trajectory",
    "wall_angle_samples",
}
WAIT = np.zeros(6, np.float32)


def throw(speed: float, elevation_deg: float) -> np.ndarray:
    el = math.radians(elevation_deg)
    v = speed * np.array([math.cos(el), 0.0, math.sin(el)]) / 18.0
    return np.concatenate([v, np.zeros(3)]).astype(np.float32)


def test_registered_with_entry_points():
    spec = gym.spec("BeachballTopple-v0")
    assert spec.entry_point == "bbgym.envs.topple:BeachballToppleEnv"
    assert spec.vector_entry_point == "bbgym.envs.topple:BeachballToppleVectorEnv"
    assert spec.max_episode_steps == 100
    assert isinstance(gym.make("bbgym:BeachballTopple-v0").unwrapped, BeachballToppleEnv)
    assert isinstance(gym.make_vec("BeachballTopple-v0", num_envs=2), BeachballToppleVectorEnv)


def test_v2_is_v1_in_rk4_steps():
    """v2's registered kwargs: v1's walls and winds, the interval in RK4 steps of 0.05 s;
    a pinned reset gives v1's observation (the scenario's draws are the same)."""
    assert gym.spec("BeachballTopple-v2").kwargs == {
        **gym.spec("BeachballTopple-v1").kwargs,
        "interval_integrator": "rk4_events",
        "sim_dt": 0.05,
    }
    v1, v2 = gym.make("BeachballTopple-v1"), gym.make("BeachballTopple-v2")
    pinned = {"wind": (-1.0, 0.5), "wall_distance": 4.0}
    np.testing.assert_array_equal(
        v1.reset(seed=3, options=pinned)[0], v2.reset(seed=3, options=pinned)[0]
    )
    throw = np.array([0.6, 0.0, 0.15, 0.0, 0.0, 0.0], np.float32)
    info1, info2 = v1.step(throw)[4], v2.step(throw)[4]
    assert info1["hits"] == info2["hits"] == 1
    assert abs(info1["wall_angle"] - info2["wall_angle"]) < 0.02


def test_v1_puts_the_wall_near_in_an_onshore_breeze():
    """v1's registered kwargs: walls 3-5 m away, the mean wind never against the throw
    (from the half-turn behind the thrower), its speed and the physics as in v0."""
    assert gym.spec("BeachballTopple-v1").kwargs == {
        "wall_distance_range": (3.0, 5.0),
        "wind_from_range": (0.5 * math.pi, 1.5 * math.pi),
    }
    vec = gym.make_vec("BeachballTopple-v1", num_envs=400)
    vec.reset(seed=0)
    scenario = vec.unwrapped.state.scenario
    distance, speed, wind_from = (np.asarray(x) for x in scenario[:3])
    assert 3.0 <= distance.min() < 3.1 and 4.9 < distance.max() <= 5.0
    along_throw = -speed * np.cos(wind_from)  # the mean air velocity's x (toward the wall)
    assert along_throw.min() >= 0.0 and along_throw.max() > 2.5
    assert np.abs(speed * np.sin(wind_from)).max() > 2.5  # strong crosswinds remain
    assert 0.0 <= speed.min() and speed.max() <= 3.0
    v0, v1 = gym.make("BeachballTopple-v0"), gym.make("BeachballTopple-v1")
    pinned = {"wind": (1.0, -0.5), "wall_distance": 4.0}
    np.testing.assert_array_equal(
        v0.reset(seed=2, options=pinned)[0], v1.reset(seed=2, options=pinned)[0]
    )
    throw = np.array([0.7, 0.0, 0.4, 0.0, 0.0, 0.0], np.float32)
    assert v0.step(throw)[4]["wall_angle"] == v1.step(throw)[4]["wall_angle"]


def test_vector_env_matches_single_envs():
    n, steps = 3, 6
    rng = np.random.default_rng(5)
    actions = rng.uniform(-1, 1, (steps, n, 6)).astype(np.float32)
    vec = gym.make_vec("BeachballTopple-v0", num_envs=n)
    first, _ = vec.reset(seed=20)
    rows = [vec.step(actions[t]) for t in range(steps)]
    for i in range(n):
        env = gym.make("BeachballTopple-v0")
        obs, _ = env.reset(seed=20 + i)
        np.testing.assert_allclose(obs, first[i], atol=1e-6)
        done = False
        for t in range(steps):
            vec_obs, vec_rew, vec_term, _, vec_info = rows[t]
            if done:
                obs, _ = env.reset()
                np.testing.assert_allclose(obs, vec_obs[i], atol=1e-5)
                assert vec_rew[i] == 0.0
                done = False
                continue
            obs, rew, term, trunc, info = env.step(actions[t, i])
            np.testing.assert_allclose(obs, vec_obs[i], atol=1e-5)
            assert rew == pytest.approx(vec_rew[i], abs=1e-6)
            assert term == vec_term[i] and info["wall_state"] == vec_info["wall_state"][i]
            terms = vec_info["reward_terms"]
            assert sum(terms[k][i] for k in info["reward_terms"]) == pytest.approx(rew)
            done = term or trunc


def test_calm_air_without_throws_the_wall_stands_all_episode():
    env = gym.make("BeachballTopple-v0")
    env.reset(seed=0, options=dict(wind=(0.0, 0.0), gusts=False))
    for k in range(8):
        _, reward, terminated, truncated, info = env.step(WAIT)
        assert terminated == (k == 7) and not truncated
        assert info["wall_state"] == "standing" and info["wall_angle"] == 0.0
        assert info["throws"] == 0 and reward == 0.0
    assert not info["is_success"]


def test_a_storm_brings_it_down_by_itself():
    env = gym.make("BeachballTopple-v0")
    env.reset(seed=0, options=dict(wind=(12.0, 0.0), gusts=False))
    _, reward, terminated, _, info = env.step(WAIT)
    assert terminated and info["is_success"] and info["wall_state"] in ("fallen_away", "loose")
    assert info["reward_terms"]["success"] == 10.0
    env.reset(seed=0, options=dict(wind=(-6.0, 0.0), gusts=False))
    _, reward, terminated, _, info = env.step(WAIT)
    assert terminated and not info["is_success"] and info["wall_state"] == "fallen_toward"
    assert info["reward_terms"]["failure"] == -5.0 and reward < -4.0


def test_a_good_high_hit_topples_the_near_wall_in_calm_air():
    env = gym.make("BeachballTopple-v0")
    obs, _ = env.reset(seed=0, options=dict(wind=(0.0, 0.0), wall_distance=4.0, gusts=False))
    assert obs[2] == pytest.approx(0.4)
    obs, reward, terminated, _, info = env.step(throw(16.0, 15.0))
    assert info["hits"] == 1 and info["throws"] == 1 and obs[8] == 1.0
    assert terminated and info["is_success"] and info["wall_state"] == "fallen_away"
    assert info["wall_angle"] == pytest.approx(math.pi / 2)
    assert reward == pytest.approx(10.0 - 0.2 + 1.0)  # bonus, throw cost, full lean
    # A low hit only rocks it: it settles back on its foot.
    env.reset(seed=0, options=dict(wind=(0.0, 0.0), wall_distance=4.0, gusts=False))
    obs, _, terminated, _, info = env.step(throw(10.0, 15.0))
    assert info["hits"] == 1 and not terminated and info["wall_state"] == "standing"
    assert 0.0 < obs[9] < 0.7 and max(info["wall_angle_samples"]) > 0.0
    # A miss is seen as a miss.
    env.reset(seed=0, options=dict(wind=(0.0, 0.0), wall_distance=8.0, gusts=False))
    obs, _, _, _, info = env.step(throw(6.0, 30.0))
    assert info["hits"] == 0 and obs[8] == -1.0


def test_vector_env_autoresets_after_the_episode():
    vec = BeachballToppleVectorEnv(num_envs=2, throws_per_episode=1)
    vec.reset(seed=0)
    _, _, term, _, _ = vec.step(np.zeros((2, 6), np.float32))
    assert term.all()
    obs, reward, term, trunc, info = vec.step(np.zeros((2, 6), np.float32))
    np.testing.assert_array_equal(reward, 0.0)
    assert not (term | trunc).any() and (obs[:, 7] == 1.0).all()
    assert INFO_KEYS <= set(info) and info["_wall_state"].all()


def test_a_wall_falling_mid_interval_stops_only_its_env_in_a_batch():
    """Env 0's wall is toppled by a high hit and falls within the interval while env 1
    waits under a standing wall: env 0 stops at its fall, as the single env does (same
    samples, observation), and env 1 runs the whole interval (60 samples of 0.05 s)."""
    options = dict(wind=(1.0, 0.0), wall_distance=4.0, gusts=True)
    single = gym.make("BeachballTopple-v0")
    single.reset(seed=7, options=options)
    obs, reward, terminated, _, info = single.step(throw(16.0, 15.0))
    k = info["samples_length"]
    assert terminated and info["wall_state"] == "fallen_away" and k < 60
    assert info["wall_angle_samples"].shape == (60,) and info["ball_trajectory_length"] == k
    # The rows past the interval's stop repeat its last sample (the wall where it lies).
    np.testing.assert_array_equal(info["wall_angle_samples"][k:], info["wall_angle_samples"][k - 1])
    vec = BeachballToppleVectorEnv(num_envs=2)
    vec.reset(seed=7, options=options)
    vec_obs, vec_reward, vec_term, _, vec_info = vec.step(np.stack([throw(16.0, 15.0), WAIT]))
    assert vec_info["samples_length"].tolist() == [k, 60]
    assert vec_info["wall_angle_samples"].shape == (2, 60)
    assert vec_term.tolist() == [True, False] and vec_reward[0] == pytest.approx(reward)
    for key in ("wall_angle_samples", "ball_trajectory", "loose_samples"):
        np.testing.assert_allclose(vec_info[key][0], info[key], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(vec_obs[0], obs, rtol=1e-6)
    # A wait throws no ball: no rows of its trajectory (all zeros, length 0).
    assert vec_info["ball_trajectory_length"][1] == 0
    assert not np.any(vec_info["ball_trajectory"][1])


def _names(state):
    """Field names of a state: a NamedTuple's or a dataclass's."""
    return state._fields if isinstance(state, tuple) else [f.name for f in fields(state)]


@pytest.mark.parametrize("num_envs", [0, 3])  # 0: the single env
def test_steps_and_resets_make_new_states_and_never_change_old_ones(num_envs):
    """A state object, once made, keeps its values: a step or a (partial) reset replaces
    the env's wall, gust and scenario states instead of writing into them."""
    if num_envs:
        env = BeachballToppleVectorEnv(num_envs=num_envs, throws_per_episode=2)
        actions = [np.stack([throw(14.0, 15.0), WAIT, throw(9.0, 25.0)])] * 5
    else:
        env = BeachballToppleEnv(throws_per_episode=2)
        actions = [throw(14.0, 15.0), WAIT, throw(9.0, 25.0), WAIT, WAIT]
    env.reset(seed=1, options=dict(wind=(2.0, 0.0), wall_distance=6.0))
    stressed = 0
    for action in actions:  # the third step restarts the vector env's sub-envs
        kept = (env.state.wall, env.state.gust, env.state.scenario)
        values = [{n: np.copy(getattr(s, n)) for n in _names(s)} for s in kept]
        stressed += np.any(np.asarray(env.state.wall.stress) > 0.0)
        _, _, terminated, _, _ = env.step(action)
        for state, before in zip(kept, values, strict=True):
            for name, value in before.items():
                np.testing.assert_array_equal(getattr(state, name), value, err_msg=name)
        assert env.state.wall is not kept[0]
        if not num_envs and terminated:
            env.reset()
    assert stressed >= 2  # the interval's stress reset had something to clear


@pytest.mark.parametrize(
    "options, name",
    [
        ({"wind": (1.0, float("nan"))}, "wind"),
        ({"wall_distance": 0.5}, "wall_distance"),
    ],
)
def test_bad_reset_options_raise(options, name):
    # Unknown keys and wrong types raise TypeError: tests/test_validation.py.
    with pytest.raises(ValueError, match=name):
        gym.make("BeachballTopple-v0").reset(seed=0, options=options)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"wall": {"mass_kg": -1.0}}, "mass_kg"),
        ({"interval": 0.0}, "interval"),
        ({"interval": 1.005}, "interval"),
        ({"wall_distance_range": (8.0, 4.0)}, "wall_distance_range"),
        ({"wind_from_range": (0.0, 7.0)}, "wind_from_range"),
        ({"wind_from_range": (-3.0, 3.5)}, "wind_from_range"),
        ({"throws_per_episode": 0}, "throws_per_episode"),
        ({"render_mode": "text"}, "render_mode"),
    ],
)
def test_bad_constructor_arguments_raise(kwargs, name):
    with pytest.raises(ValueError, match=name):
        BeachballToppleEnv(**kwargs)


def test_bad_actions_raise():
    env = gym.make("BeachballTopple-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([np.inf, 0, 0, 0, 0, 0], np.float32))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(5, np.float32))


def test_rewards_bounded_and_terms_add_up():
    env = gym.make("BeachballTopple-v0")
    low, high = env.unwrapped.task.reward_range
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    for _ in range(30):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 6))
        assert low <= reward <= high
        assert reward == pytest.approx(sum(info["reward_terms"].values()))
        assert env.observation_space.contains(obs) and INFO_KEYS <= set(info)
        if terminated or truncated:
            env.reset()


def test_render_rgb_array_and_human():
    pytest.importorskip("pygame")
    env = gym.make("BeachballTopple-v0", render_mode="rgb_array")
    env.reset(seed=0, options=dict(wind=(0.0, 0.0), wall_distance=4.0, gusts=False))
    before = env.render()
    env.step(throw(16.0, 15.0))
    after = env.render()
    assert after.shape == (480, 640, 3) and not np.array_equal(before, after)
    human = gym.make("BeachballTopple-v0", render_mode="human", interval=0.5)
    human.reset(seed=0)
    human.step(WAIT)
    human.close()
