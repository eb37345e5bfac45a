"""BeachballThrow-v0 / BeachballCurve-v0: contract, determinism, vector env, options, errors."""

from __future__ import annotations

import math
import os

import gymnasium as gym
import numpy as np
import pytest
from bbgym.agents.throw_solver import solve_throw

import bbgym  # noqa: F401  (registers the ids)
from bbgym.envs.throw import BeachballThrowEnv, BeachballThrowVectorEnv

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

INFO_KEYS = {
    "landing_point",
    "miss_distance",
    "flight_time",
    "apex_height",
    "spin_parameter",
    "trajectory",
    "is_success",
    "reward_terms",
    "wind",
    "windsock",
    "throws_left",
}
CALM = dict(wind=(0.0, 0.0), gusts=False)


def throw_action(speed, elevation_deg, azimuth_deg, spin=(0.0, 0.0, 0.0), env=None):
    task = (env or gym.make("BeachballThrow-v0")).unwrapped.task
    el, az = math.radians(elevation_deg), math.radians(azimuth_deg)
    v = speed * np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])
    return np.concatenate([v / task.max_speed, np.array(spin) / task.max_spin]).astype(np.float32)


def test_registered_with_entry_points():
    for env_id in ("BeachballThrow-v0", "BeachballCurve-v0"):
        spec = gym.spec(env_id)
        assert spec.entry_point == "bbgym.envs.throw:BeachballThrowEnv"
        assert spec.vector_entry_point == "bbgym.envs.throw:BeachballThrowVectorEnv"
        assert spec.max_episode_steps == 100
    assert gym.spec("BeachballCurve-v0").kwargs["screen"] is True
    assert isinstance(gym.make("bbgym:BeachballCurve-v0").unwrapped, BeachballThrowEnv)
    assert isinstance(gym.make_vec("BeachballThrow-v0", num_envs=2), BeachballThrowVectorEnv)


@pytest.mark.parametrize("env_id", ["BeachballThrow-v0", "BeachballCurve-v0"])
def test_vector_env_matches_single_envs(env_id):
    n, steps = 3, 7
    actions = np.random.default_rng(2).uniform(-1, 1, (steps, n, 6)).astype(np.float32)
    vec = gym.make_vec(env_id, num_envs=n)
    first, _ = vec.reset(seed=40)
    rows = [vec.step(actions[t]) for t in range(steps)]
    for i in range(n):
        env = gym.make(env_id)
        obs, _ = env.reset(seed=40 + i)
        np.testing.assert_allclose(obs, first[i], atol=1e-6)
        done = False
        for t in range(steps):
            vec_obs, vec_rew, vec_term, vec_trunc, vec_info = rows[t]
            if done:  # the vector env restarts this sub-env on this step
                obs, _ = env.reset()
                np.testing.assert_allclose(obs, vec_obs[i], atol=1e-5)
                assert vec_rew[i] == 0.0
                done = False
                continue
            obs, rew, term, trunc, info = env.step(actions[t, i])
            np.testing.assert_allclose(obs, vec_obs[i], atol=1e-5)
            assert rew == pytest.approx(vec_rew[i], abs=1e-6)
            assert term == vec_term[i]
            assert info["miss_distance"] == pytest.approx(vec_info["miss_distance"][i], abs=1e-6)
            assert info["is_success"] == vec_info["is_success"][i]
            vec_terms = vec_info["reward_terms"]
            assert sum(vec_terms[k][i] for k in info["reward_terms"]) == pytest.approx(rew)
            np.testing.assert_allclose(info["trajectory"], vec_info["trajectory"][i], atol=1e-6)
            done = term or trunc


def test_episode_is_a_few_throws_and_observation_shows_landing():
    env = gym.make("BeachballThrow-v0")
    obs, info = env.reset(seed=0, options=dict(target=(6.0, 1.0), **CALM))
    assert obs[6] == 1.0 and obs[7] == 0.0 and info["throws_left"] == 3
    np.testing.assert_allclose(obs[:2], [0.6, 0.1], atol=1e-6)
    short = throw_action(6.0, 30.0, 0.0)
    for k in range(3):
        obs, reward, terminated, truncated, info = env.step(short)
        assert terminated == (k == 2) and not truncated
        assert not info["is_success"]
        # The landing relative to the target is in the observation.
        rel = (info["landing_point"] - np.array([6.0, 1.0])) / 10.0
        np.testing.assert_allclose(obs[4:6], rel, atol=1e-6)
        assert obs[7] == 1.0 and obs[6] == pytest.approx((2 - k) / 3)
        np.testing.assert_allclose(obs[8:14], short, atol=1e-6)
        assert info["miss_distance"] == pytest.approx(float(np.hypot(*(rel * 10.0))))
        assert reward == pytest.approx(math.exp(-info["miss_distance"] / 2.0))


def test_hit_terminates_with_success_and_bonus():
    env = gym.make("BeachballThrow-v0")
    env.reset(seed=0, options=dict(target=(7.0, 0.0), **CALM))
    solution = solve_throw(env.unwrapped.task, (7.0, 0.0))
    _, reward, terminated, _, info = env.step(solution.action)
    assert terminated and info["is_success"] and info["miss_distance"] <= 0.75
    assert info["miss_distance"] == pytest.approx(solution.predicted_miss_m, abs=1e-6)
    assert info["reward_terms"]["hit"] == 5.0 and reward > 5.5


def test_throw_solved_for_the_wind_hits_where_no_spin_cannot_pass_the_screen():
    env = gym.make("BeachballCurve-v0")
    target, wind = (8.5, -1.5), (-1.2, 0.0)  # a headwind: it cannot blow a ball round
    env.reset(seed=0, options=dict(target=target, wind=wind, gusts=False))
    task = env.unwrapped.task
    curved = solve_throw(task, target, wind, screen=True)
    straight = solve_throw(task, target, wind, screen=True, use_spin=False)
    assert straight.predicted_miss_m > 1.5 * task.target_radius
    _, _, terminated, _, info = env.step(curved.action)
    assert info["is_success"] and terminated and not info["hit_screen"]
    assert abs(info["spin_parameter"]) > 0.2
    # The same throw ignoring the wind misses: the wind matters.
    calm = solve_throw(task, target, (0.0, 0.0), screen=True)
    env.reset(seed=0, options=dict(target=target, wind=wind, gusts=False))
    assert not env.step(calm.action)[4]["is_success"]


def test_side_spin_curves_the_throw_in_the_env():
    env = gym.make("BeachballThrow-v0")
    landings = {}
    for name, spin in (("none", 0.0), ("left", 40.0), ("right", -40.0)):
        env.reset(seed=0, options=dict(target=(8.0, 0.0), **CALM))
        info = env.step(throw_action(12.0, 30.0, 0.0, (0.0, 0.0, spin)))[4]
        landings[name] = info["landing_point"][1]
    assert landings["none"] == pytest.approx(0.0, abs=1e-9)
    assert landings["left"] > 0.5 and landings["right"] == pytest.approx(-landings["left"])


def test_launch_speed_and_spin_are_norm_clipped():
    task = gym.make("BeachballThrow-v0").unwrapped.task
    v, w = task.launch(np.ones(6))
    assert np.linalg.norm(v) == pytest.approx(task.max_speed)
    assert np.linalg.norm(w) == pytest.approx(task.max_spin)
    v, _ = task.launch(np.array([0.5, 0.0, 0.0, 0.0, 0.0, 0.0]))
    assert v[0] == pytest.approx(0.5 * task.max_speed)


def test_gusts_change_the_wind_between_throws_and_windsock_is_noisy():
    env = gym.make("BeachballThrow-v0")
    env.reset(seed=1, options=dict(wind=(2.0, 0.0), gusts=True))
    winds = [env.step(np.zeros(6, np.float32))[4]["wind"] for _ in range(3)]
    assert not np.allclose(winds[0], winds[1])
    env.reset(seed=1, options=dict(wind=(2.0, 0.0), gusts=False))
    infos = [env.step(np.zeros(6, np.float32))[4] for _ in range(3)]
    np.testing.assert_allclose(infos[0]["wind"], [2.0, 0.0], atol=1e-12)
    assert not np.allclose(infos[0]["windsock"], [2.0, 0.0])


def test_vector_env_autoresets_after_the_last_throw():
    vec = BeachballThrowVectorEnv(num_envs=2, throws_per_episode=1)
    vec.reset(seed=0)
    _, _, term, _, _ = vec.step(np.zeros((2, 6), np.float32))
    assert term.all()
    obs, reward, term, trunc, info = vec.step(np.zeros((2, 6), np.float32))
    np.testing.assert_array_equal(reward, 0.0)
    assert not (term | trunc).any() and (obs[:, 7] == 0.0).all()
    assert INFO_KEYS <= set(info) and info["_miss_distance"].all()


@pytest.mark.parametrize(
    "options, name",
    [
        ({"wind": (1.0,)}, "wind"),
        ({"target": (0.1, 0.0)}, "target"),
        ({"target": (float("inf"), 0.0)}, "target"),
    ],
)
def test_bad_reset_options_raise(options, name):
    # Unknown keys and wrong types raise TypeError: tests/test_validation.py.
    with pytest.raises(ValueError, match=name):
        gym.make("BeachballThrow-v0").reset(seed=0, options=options)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"max_speed": 0.0}, "max_speed"),
        ({"throws_per_episode": 0}, "throws_per_episode"),
        ({"target_distance_range": (5.0, 2.0)}, "target_distance_range"),
        ({"ball": {"radius_m": -0.1}}, "radius_m"),
        ({"screen_position": 1.5}, "screen_position"),
        ({"field_radius": 5.0}, "field_radius"),
        ({"render_mode": "text"}, "render_mode"),
    ],
)
def test_bad_constructor_arguments_raise(kwargs, name):
    with pytest.raises(ValueError, match=name):
        BeachballThrowEnv(**kwargs)


def test_bad_actions_raise():
    env = gym.make("BeachballThrow-v0")
    env.reset(seed=0)
    with pytest.raises(ValueError, match="finite"):
        env.step(np.array([np.nan, 0, 0, 0, 0, 0], np.float32))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(2, np.float32))


def test_rewards_bounded_and_terms_add_up():
    env = gym.make("BeachballCurve-v0")
    low, high = env.unwrapped.task.reward_range
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    for _ in range(30):
        obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 6))
        assert low <= reward <= high
        assert reward == pytest.approx(sum(info["reward_terms"].values()))
        assert env.observation_space.contains(obs)
        assert INFO_KEYS <= set(info) and info["trajectory"].shape[1] == 3
        if terminated or truncated:
            env.reset()


def test_render_rgb_array_single_and_vector():
    pytest.importorskip("pygame")
    env = gym.make("BeachballCurve-v0", render_mode="rgb_array")
    env.reset(seed=0)
    before = env.render()
    env.step(throw_action(12.0, 30.0, -20.0, (0.0, 0.0, 40.0)))
    after = env.render()
    assert after.shape == (480, 640, 3) and after.dtype == np.uint8
    assert not np.array_equal(before, after)  # the flight is drawn
    vec = gym.make_vec("BeachballThrow-v0", num_envs=2, render_mode="rgb_array")
    vec.reset(seed=0)
    assert len(vec.render()) == 2


@pytest.mark.parametrize("target", [(10.0, 0.0), (7.07, 7.07), (7.07, -7.07)])
def test_farthest_targets_are_reachable_in_calm_air(target):
    task = gym.make("BeachballThrow-v0").unwrapped.task
    assert solve_throw(task, target).predicted_miss_m < 0.5 * task.target_radius


def test_human_render_plays_the_flight():
    pytest.importorskip("pygame")
    env = gym.make("BeachballThrow-v0", render_mode="human")
    env.reset(seed=0, options=dict(target=(6.0, 0.0), **CALM))
    renderer = env.unwrapped._renderer
    frames = []
    draw = renderer.render
    renderer.render = lambda scene: frames.append(scene.frame_index) or draw(scene)
    _, _, _, _, info = env.step(throw_action(10.0, 35.0, 0.0))
    k = info["trajectory_length"]
    # One frame per recorded point of the flight, then the landing.
    assert k > 10 and frames == [*range(k - 1), None]
    env.close()
