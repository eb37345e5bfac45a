"""The default preset in configs/ equals the code's defaults."""

from __future__ import annotations

import inspect

import gymnasium as gym
import pytest

from bbgym.config import CONFIG_DIR, load_preset
from bbgym.envs.sail import SailTask
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.water import WaterParams
from bbgym.physics.wind import GustParams


def test_sail_preset_matches_code_defaults():
    env_id, kwargs = load_preset(CONFIG_DIR / "beachball_sail.yaml")
    assert env_id == "BeachballSail-v0"
    assert kwargs.pop("max_episode_steps") == gym.spec(env_id).max_episode_steps
    assert DinghyParams(**kwargs.pop("dinghy")) == DinghyParams()
    assert GustParams(**kwargs.pop("gust_params")) == GustParams()
    assert WaterParams(**kwargs.pop("water")) == WaterParams()
    defaults = {
        k: p.default
        for k, p in inspect.signature(SailTask.__init__).parameters.items()
        # sail_model (default None: the dinghy's) is given as dinghy.sail_model
        if k not in ("self", "dinghy", "gust_params", "water", "sail_model")
    }
    assert kwargs == defaults


def test_preset_builds_the_env():
    env_id, kwargs = load_preset(CONFIG_DIR / "beachball_sail.yaml")
    env = gym.make(env_id, **kwargs)
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    env.close()


def test_throw_preset_matches_code_defaults():
    from bbgym.envs.ball import BALL_GUSTS
    from bbgym.envs.throw.task import ThrowTask
    from bbgym.physics.ball import BallParams

    env_id, kwargs = load_preset(CONFIG_DIR / "beachball_throw.yaml")
    assert env_id == "BeachballThrow-v0"
    assert kwargs.pop("max_episode_steps") == gym.spec(env_id).max_episode_steps
    assert BallParams(**kwargs.pop("ball")) == BallParams()
    assert GustParams(**kwargs.pop("gust_params")) == BALL_GUSTS
    defaults = {
        k: p.default
        for k, p in inspect.signature(ThrowTask.__init__).parameters.items()
        if k not in ("self", "ball", "gust_params")
    }
    assert kwargs == defaults


def test_topple_preset_matches_code_defaults():
    from bbgym.envs.ball import BALL_GUSTS
    from bbgym.envs.topple import ToppleTask
    from bbgym.physics.ball import BallParams
    from bbgym.physics.wall import WallParams

    env_id, kwargs = load_preset(CONFIG_DIR / "beachball_topple.yaml")
    assert env_id == "BeachballTopple-v0"
    assert kwargs.pop("max_episode_steps") == gym.spec(env_id).max_episode_steps
    assert WallParams(**kwargs.pop("wall")) == WallParams()
    assert BallParams(**kwargs.pop("ball")) == BallParams()
    assert GustParams(**kwargs.pop("gust_params")) == BALL_GUSTS
    defaults = {
        k: p.default
        for k, p in inspect.signature(ToppleTask.__init__).parameters.items()
        if k not in ("self", "wall", "ball", "gust_params")
    }
    assert kwargs == defaults


def test_linear_schedules_in_the_ppo_section(tmp_path):
    from bbgym.config import LinearSchedule, load_training

    config = tmp_path / "p.yaml"
    config.write_text("env_id: X\nenv: {}\nppo:\n  learning_rate: lin_0.001\n  clip_range: 0.2\n")
    ppo, _ = load_training(config)
    schedule = ppo["learning_rate"]
    assert isinstance(schedule, LinearSchedule)
    # SB3 passes the fraction of the budget still to go: 1 at the start, 0 at the end.
    assert schedule(1.0) == pytest.approx(1e-3)
    assert schedule(0.25) == pytest.approx(2.5e-4)
    assert schedule(0.0) == 0.0
    assert ppo["clip_range"] == 0.2
    for bad in ("exp_0.001", "lin_abc", "lin_-1", "lin_nan"):
        config.write_text(f"env_id: X\nenv: {{}}\nppo:\n  learning_rate: {bad}\n")
        with pytest.raises(ValueError, match="ppo.learning_rate"):
            load_training(config)


def test_curve_preset_is_the_registered_v1():
    from bbgym.config import env_preset, load_training

    env_id, kwargs = load_preset("BeachballCurve-v1")
    assert env_id == "BeachballCurve-v1"
    assert kwargs.pop("max_episode_steps") == gym.spec(env_id).max_episode_steps
    assert kwargs == gym.spec(env_id).kwargs
    assert env_preset(env_id)[0] == CONFIG_DIR / "beachball_curve.yaml"
    ppo, train = load_training(env_id)
    assert ppo["learning_rate"](1.0) == pytest.approx(1e-3) and ppo["learning_rate"](0.0) == 0.0
    # 5.5M throws in batched flights of 1024, 4 epochs an update (docs/pages/baselines.md).
    assert (train["total_timesteps"], train["n_envs"], ppo["n_epochs"]) == (5_500_000, 1024, 4)
    # Its SAC preset (chosen by name): the same env, the whole budget in the replay buffer,
    # a sharper policy than SB3's default entropy target (-6 for the 6 action dimensions).
    assert load_preset("beachball_curve_sac") == load_preset(env_id)
    sac, train = load_training("beachball_curve_sac")
    assert train["algo"] == "sac" and train["evaluate_model"] == "final"
    assert sac["buffer_size"] >= train["total_timesteps"] == 400_000
    from stable_baselines3 import SAC

    env = gym.make(env_id)
    try:
        model = SAC(env=env, **sac)  # SB3 takes every key of the section
        assert model.target_entropy == -12.0 and model.gamma == 0.95
        assert model.gradient_steps == 32 and model.batch_size == 256
    finally:
        env.close()


def test_sail_v1_presets_are_the_registered_v1():
    from bbgym.config import env_preset, load_training

    ppo_v0, train_v0 = load_training("BeachballSail-v0")
    for name in ("BeachballSail-v1", "beachball_sail_v1_ppo"):
        env_id, kwargs = load_preset(name)
        assert env_id == "BeachballSail-v1"
        assert kwargs.pop("max_episode_steps") == gym.spec(env_id).max_episode_steps
        assert kwargs == gym.spec(env_id).kwargs == {"time_penalty": 0.1, "capsize_penalty": 30.0}
    # The env id's preset trains SAC, its whole budget in the replay buffer.
    assert env_preset("BeachballSail-v1")[0] == CONFIG_DIR / "beachball_sail_v1.yaml"
    sac, train = load_training("BeachballSail-v1")
    assert train["algo"] == "sac" and not train["normalize_reward"]
    assert train["evaluate_model"] == "final"  # PPO's presets: "best"
    assert load_training("BeachballSail-v0")[1]["evaluate_model"] == "best"
    assert sac["buffer_size"] >= train["total_timesteps"]
    # The PPO preset: PPO as for v0, with the rewards normalized in training.
    ppo, train = load_training("beachball_sail_v1_ppo")
    assert ppo == ppo_v0
    assert train == {**train_v0, "normalize_reward": True}
    task = gym.make("BeachballSail-v1").unwrapped.task
    assert (task.time_penalty, task.capsize_penalty) == (0.1, 30.0)
    assert task.reward_range == (-31.1, 11.0)


def test_algo_names_the_section_of_its_arguments(tmp_path):
    from bbgym.config import load_training

    config = tmp_path / "p.yaml"
    config.write_text("env_id: X\nenv: {}\nalgo: sac\nsac:\n  learning_rate: lin_0.001\n")
    sac, train = load_training(config)
    assert train["algo"] == "sac" and sac["policy"] == "MlpPolicy"
    assert sac["learning_rate"](0.5) == pytest.approx(5e-4)
    assert load_training(CONFIG_DIR / "beachball_sail.yaml")[1]["algo"] == "ppo"  # default
    for text, error in (
        ("algo: dqn\n", "algo must be one of"),
        ("algo: sac\nppo: {}\n", "trains sac .algo. but has a ppo section"),
        ("ppo: {}\nsac: {}\n", "trains ppo .algo. but has a sac section"),
        ("algo: sac\nsac:\n  learning_rate: lin_x\n", "sac.learning_rate"),
        ("train:\n  evaluate_model: last\n", "train.evaluate_model must be one of"),
        ("train:\n  eval_envs: 0\n", "train.eval_envs must be a whole number from 1"),
        ("train:\n  eval_envs: 21\n", r"train.eval_envs .* to eval_episodes \(20\), got 21"),
        ("train:\n  eval_envs: 2.5\n", "train.eval_envs"),
        ("train:\n  eval_envs: true\n", "train.eval_envs"),
    ):
        config.write_text("env_id: X\nenv: {}\n" + text)
        with pytest.raises(ValueError, match=error):
            load_training(config)


def test_the_evaluation_during_training_steps_its_envs_at_once(tmp_path):
    from bbgym.config import eval_env_count, load_training

    # By default min(n_envs, eval_episodes): Sail-v0's 32 envs evaluate 32 of 50 episodes at
    # once, Curve-v1's 1024 its 100; a preset may give one env per episode (eval_envs).
    assert eval_env_count(load_training("BeachballSail-v0")[1]) == 32
    assert eval_env_count(load_training("BeachballCurve-v1")[1]) == 100
    config = tmp_path / "p.yaml"
    config.write_text("env_id: X\nenv: {}\ntrain:\n  n_envs: 8\n  eval_episodes: 50\n")
    assert eval_env_count(load_training(config)[1]) == 8
    config.write_text(config.read_text() + "  eval_envs: 50\n")
    assert eval_env_count(load_training(config)[1]) == 50


@pytest.mark.parametrize("version", ["v1", "v2"])
def test_the_quick_sail_presets_are_the_shipped_ones_with_a_quarter_of_their_update_work(
    version,
):
    from bbgym.config import load_training

    env_id = f"BeachballSail-{version}"
    assert load_preset(f"beachball_sail_{version}_quick") == load_preset(env_id)
    sac, train = load_training(env_id)
    quick_sac, quick_train = load_training(f"beachball_sail_{version}_quick")
    # Half the updates (one per step of the 8 envs) on networks of half the width: the
    # main job's (make run) quarter of the shipped preset's update work, nothing else.
    assert quick_sac == {**sac, "gradient_steps": 1, "policy_kwargs": {"net_arch": [128, 128]}}
    assert sac["gradient_steps"] == 2 and sac["policy_kwargs"] == {"net_arch": [256, 256]}
    assert quick_train == {**train, "eval_envs": 50} and train["eval_episodes"] == 50
