"""The sail task with a jib and water that moves (what BeachballSail-v2 is made of): its
spaces, options and errors, determinism, single == vector, NumPy == torch, and the sea as
the boat senses it. Still water with a cat rig is v0's and v1's task (their golden replays
guard it); these tests use the v1 id with the sea's arguments."""

from __future__ import annotations

import math

import backend_replica
import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import bbgym  # noqa: F401
from bbgym.envs.sail import BeachballSailEnv, BeachballSailVectorEnv
from bbgym.envs.sail.task import OBS_SIZE, SEA_OBS_SIZE
from bbgym.physics.calibration import calibrated_sloop
from bbgym.physics.water import WaterParams

WATER = {
    "wave_amplitude_m": 0.12,
    "wavelength_m": 10.0,
    "wave_components": 3,
    "wave_spread_rad": 0.5,
}
SEA = {
    "sail_model": "cambered",
    "dinghy": calibrated_sloop(),
    "water": WATER,
    "current_speed_range": (0.0, 0.4),
}


def sea_env(**changes) -> BeachballSailEnv:
    return BeachballSailEnv(**{**SEA, **changes})


def test_spaces_grow_with_the_jib_and_the_sea() -> None:
    assert BeachballSailEnv().observation_space.shape == (OBS_SIZE,)
    assert BeachballSailEnv().action_space.shape == (2,)
    sloop = sea_env()
    assert sloop.observation_space.shape == (OBS_SIZE + SEA_OBS_SIZE,)
    assert sloop.action_space.shape == (3,)
    cat_at_sea = BeachballSailEnv(water=WATER)
    assert cat_at_sea.observation_space.shape == (OBS_SIZE + SEA_OBS_SIZE,)
    assert cat_at_sea.action_space.shape == (2,)
    still_sloop = sea_env(water=None, current_speed_range=(0.0, 0.0))
    assert not still_sloop.task.moving_water
    assert still_sloop.action_space.shape == (3,)


@pytest.mark.parametrize(
    "changes", [{}, {"dinghy": None, "sail_model": "lift"}, {"water": None}], ids=str
)
def test_check_env(changes) -> None:
    check_env(sea_env(**changes), skip_render_check=True)


def rollout(env: gym.Env, seed: int, steps: int = 60) -> np.ndarray:
    rng = np.random.default_rng(seed)
    obs, _ = env.reset(seed=seed)
    rows = [obs]
    for _ in range(steps):
        obs, reward, term, trunc, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        rows.append(np.append(obs, reward))
        if term or trunc:
            obs, _ = env.reset()
    return np.concatenate(rows)


def test_deterministic_under_a_seed() -> None:
    a, b = rollout(sea_env(), 4), rollout(sea_env(), 4)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, rollout(sea_env(), 5))


def test_vector_env_equals_single_envs() -> None:
    """Sub-env i is the single env seeded seed + i, through its first episode's end and
    the restart on the next step."""
    n, steps = 3, 80
    actions = np.random.default_rng(1).uniform(-1, 1, (steps, n, 3)).astype(np.float32)
    venv = BeachballSailVectorEnv(num_envs=n, max_episode_steps=50, **SEA)
    rows = [venv.reset(seed=11)[0]]
    rewards, done = [], []
    for a in actions:
        obs, reward, term, trunc, _ = venv.step(a)
        rows.append(obs)
        rewards.append(reward)
        done.append(term | trunc)
    restarted = 0
    for i in range(n):
        env = gym.wrappers.TimeLimit(sea_env(), 50)
        np.testing.assert_allclose(env.reset(seed=11 + i)[0], rows[0][i], rtol=0, atol=1e-6)
        for t in range(steps):
            obs, reward, term, trunc, _ = env.step(actions[t, i])
            np.testing.assert_allclose(obs, rows[t + 1][i], rtol=0, atol=1e-6)
            assert reward == pytest.approx(rewards[t][i], abs=1e-9)
            assert (term or trunc) == done[t][i]
            if term or trunc:
                np.testing.assert_allclose(env.reset()[0], rows[t + 2][i], rtol=0, atol=1e-6)
                restarted += 1
                break
    assert restarted == n


def test_torch_float64_equals_numpy_replica() -> None:
    """The torch backend steps the same sea and jib as NumPy (float64, eager), through
    autoresets."""
    pytest.importorskip("torch")
    pytest.importorskip("array_api_compat")
    n, env_id = 6, "BeachballSail-v1"
    kwargs = {**SEA, "max_episode_steps": 25}
    actions = np.random.default_rng(3).uniform(-1, 1, (60, n, 3)).astype(np.float32)
    expected = backend_replica.replica_run(env_id, n, 7, actions, **kwargs)
    venv = backend_replica.make_torch(env_id, n, **kwargs)
    venv.reset(seed=7)
    for a, (obs, reward, term, trunc) in zip(actions, expected, strict=True):
        got = venv.step(a)
        np.testing.assert_allclose(got[0], obs, rtol=0, atol=1e-6)
        np.testing.assert_allclose(got[1], reward, rtol=0, atol=1e-9)
        np.testing.assert_array_equal(got[2] | got[3], term | trunc)
    assert np.abs(np.asarray(got[0])[:, OBS_SIZE + 3]).max() > 0.05  # the waves are there


def test_a_pinned_current_is_what_the_boat_senses_and_drifts_with() -> None:
    """No wind, no waves, 0.6 m/s toward north-east: the water columns read the current
    in the boat's frame, and a boat at rest is carried off with it. (Across a hull the
    centreboard grips the water, along it the hull slips: a boat not aligned with the
    current is carried a few degrees off the set, so this one points along it.)"""
    env = sea_env(water=None, current_speed_range=(0.0, 1.0), gusts=False)
    set_rad = math.pi / 4
    options = {
        "wind_speed": 0.0,
        "speed": 0.0,
        "heading": 0.3,
        "current_speed": 0.6,
        "current_set": set_rad,
    }
    obs, info = env.reset(seed=0, options=options)
    np.testing.assert_allclose(info["water_velocity"], 0.6 * np.array([1, 1]) / math.sqrt(2))
    # body frame, heading 0.3 rad: along the hull and to port, over 6 m/s
    along, across = math.cos(set_rad - 0.3), math.sin(set_rad - 0.3)
    water_columns = obs[OBS_SIZE + 1 : OBS_SIZE + 3]
    np.testing.assert_allclose(water_columns, [0.1 * along, 0.1 * across], atol=1e-7)
    obs, info = env.reset(seed=0, options={**options, "heading": set_rad})
    for _ in range(120):  # 30 s
        _, _, _, _, info = env.step(np.zeros(3))
    # The still air holds the hull back a little (windage against the hull's drag in the
    # water: 0.89 of a 1 m/s current, tests/sail/test_sailing_water.py), along the set.
    speed = np.hypot(*info["velocity"])
    assert 0.8 * 0.6 < speed < 0.6
    assert math.atan2(info["velocity"][1], info["velocity"][0]) == pytest.approx(set_rad, abs=2e-3)


def test_pinned_waves_set_the_height_at_the_boat() -> None:
    """One wave of 0.2 m travelling east with phase 0 at the origin: the surface at the
    boat is a crest (z = +A); turned by pi, a trough; the waves' direction is in the
    observation relative to the bow."""
    water = {"wave_amplitude_m": 0.2, "wavelength_m": 12.0, "wave_components": 1}
    env = sea_env(water=water, current_speed_range=(0.0, 0.0))
    options = {"wave_direction": 0.0, "wave_phase": 0.0, "heading": math.pi / 2}
    obs, info = env.reset(seed=1, options=options)
    assert info["wave_height"] == pytest.approx(0.2, abs=1e-9)
    assert obs[OBS_SIZE + 3] == pytest.approx(1.0, abs=1e-6)  # height over the amplitude
    # heading north, waves from the west: from port, 90 deg off the bow
    assert obs[OBS_SIZE + 5] == pytest.approx(0.0, abs=1e-6)
    assert obs[OBS_SIZE + 6] == pytest.approx(1.0, abs=1e-6)
    _, info = env.reset(seed=1, options={**options, "wave_phase": math.pi})
    assert info["wave_height"] == pytest.approx(-0.2, abs=1e-9)


def test_the_jib_column_says_which_side_the_jib_is_on() -> None:
    """Wind from starboard (from the south while heading east): the port sheet pulled
    hard trims the jib to port (leeward), the starboard sheet backs it to starboard."""
    p = calibrated_sloop()
    env = sea_env(water=None, current_speed_range=(0.0, 0.0), gusts=False)
    options = {"wind_speed": 5.0, "wind_from": -math.pi / 2, "heading": 0.0, "speed": 2.0}
    for sheet, expected in ((1.0, p.jib_sheet_min_rad), (-1.0, -p.jib_sheet_min_rad)):
        env.reset(seed=0, options=options)
        obs, _, _, _, info = env.step(np.array([0.0, -1.0, sheet]))
        assert info["jib_angle"] == pytest.approx(expected, abs=1e-9)
        assert obs[OBS_SIZE] == pytest.approx(expected / p.jib_sheet_max_rad, abs=1e-6)


def test_the_sea_options_and_arguments_are_checked() -> None:
    still = BeachballSailEnv()
    with pytest.raises(ValueError, match=r"options\['current_speed'\] needs water that moves"):
        still.reset(options={"current_speed": 0.5})
    current_only = BeachballSailEnv(current_speed_range=(0.0, 1.0))
    with pytest.raises(ValueError, match=r"options\['wave_phase'\] needs waves"):
        current_only.reset(options={"wave_phase": 0.5})
    with pytest.raises(ValueError, match=r"options\['current_speed'\]"):
        sea_env().reset(options={"current_speed": 4.0})
    with pytest.raises(ValueError, match=r"options\['current_set'\]"):
        sea_env().reset(options={"current_set": math.inf})
    with pytest.raises(ValueError, match="current_speed_range"):
        BeachballSailEnv(current_speed_range=(0.0, 3.5))
    with pytest.raises(ValueError, match=r"^water\.wave_amplitude_m must be at most 0.4775 m"):
        BeachballSailEnv(water={"wave_amplitude_m": 2.0, "wavelength_m": 5.0})
    with pytest.raises(TypeError, match=r"water"):
        BeachballSailEnv(water={"wave_height": 1.0})
    assert sea_env().task.water == WaterParams(**WATER)
