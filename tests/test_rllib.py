"""Ray RLlib (new API stack) on bbgym's native vector envs (the ``rllib`` extra).

One local Ray cluster of 2 CPUs serves the module (no external service): starting Ray
and its worker processes is most of the cost, so it starts once.
"""

from __future__ import annotations

import json
import math

import gymnasium as gym
import numpy as np
import pytest

ray = pytest.importorskip("ray")
pytest.importorskip("ray.rllib")

import bbgym  # noqa: E402,F401
from bbgym import rllib  # noqa: E402
from bbgym.config import preset_files  # noqa: E402
from bbgym.envs.core import CoreVectorEnv  # noqa: E402
from bbgym.envs.sail import BeachballSailVectorEnv  # noqa: E402

ENV = "BeachballSail-v0"
SMALL = {"train_batch_size": 256, "minibatch_size": 128, "num_epochs": 1}
"""A batch the 2-core machine samples and learns in about a second."""
SHORT = {"max_episode_steps": 40}
"""Episodes that end within an iteration, so the return metric has values."""


@pytest.fixture(scope="module")
def cluster():
    if ray.is_initialized():  # someone else's: leave it as it is
        yield
        return
    # "local": a new cluster, even where a `ray start` elsewhere left its address behind.
    ray.init(address="local", num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def test_train_two_runners_checkpoint_restores(cluster, tmp_path):
    rows = []
    summary = rllib.train(
        ENV,
        iterations=2,
        num_env_runners=2,
        num_envs_per_env_runner=4,
        seed=0,
        out=tmp_path,
        env_kwargs=SHORT,
        callback=rows.append,
        **SMALL,
    )
    assert rows == summary["history"]
    assert ray.is_initialized()  # the fixture's cluster: train() did not start it
    assert summary == json.loads((tmp_path / "rllib.json").read_text())
    assert summary["env"] == ENV and summary["iterations"] == 2
    assert summary["num_env_runners"] == 2 and summary["num_envs_per_env_runner"] == 4
    batch = SMALL["train_batch_size"]
    # Each iteration samples the batch (a fragment of 256 / (2 * 4) = 32 steps per env);
    # episodes that end mid-fragment may add a few steps.
    assert 2 * batch <= summary["env_steps_sampled"] <= 2 * batch + 2 * 4 * 8
    assert [row["iteration"] for row in summary["history"]] == [1, 2]
    assert summary["history"][0]["env_steps_sampled"] >= batch
    assert summary["episodes"] >= 2 * 4  # 64 steps per env, episodes of 40
    for key in ("episode_return_mean", "wall_time_s", "env_steps_per_s", "build_time_s"):
        assert math.isfinite(summary[key]), key
    assert summary["env_steps_per_s"] > 0
    assert summary["ray_version"] == ray.__version__

    checkpoint = tmp_path / "checkpoint"
    assert checkpoint.is_dir() and summary["checkpoint"] == str(checkpoint.resolve())
    env = gym.make(ENV)
    obs, _ = env.reset(seed=1)

    from ray.rllib.algorithms.algorithm import Algorithm

    restored = Algorithm.from_checkpoint(str(checkpoint))
    try:
        # The remote env runners (other processes) built bbgym's native vector env.
        kinds = restored.env_runner_group.foreach_env_runner(
            lambda runner: type(runner.env.unwrapped).__name__, local_env_runner=False
        )
        assert kinds == ["BeachballSailVectorEnv"] * 2
        action = rllib.compute_action(restored.get_module(), obs, env.action_space)
        assert action.shape == env.action_space.shape and env.action_space.contains(action)
    finally:
        restored.stop()

    # The policy alone, for evaluation: no algorithm, same action.
    module = rllib.load_rl_module(checkpoint)
    again = rllib.compute_action(module, obs, env.action_space)
    np.testing.assert_allclose(again, action, rtol=1e-5, atol=1e-6)
    batch_actions = rllib.compute_action(module, np.stack([obs, obs]), env.action_space, True)
    assert batch_actions.shape == (2, *env.action_space.shape)
    assert all(env.action_space.contains(a) for a in batch_actions)


@pytest.mark.parametrize("plain_id", [False, True], ids=["bbgym:id", "registered"])
def test_env_runner_steps_the_native_vector_env(cluster, plain_id):
    config = rllib.ppo_config(
        ENV, num_env_runners=0, num_envs_per_env_runner=3, env_kwargs={"mark_radius": 6.0}, **SMALL
    )
    assert config.gym_env_vectorize_mode == gym.VectorizeMode.VECTOR_ENTRY_POINT
    if plain_id:  # a hand-written config naming the plain id, through Tune's registry
        assert rllib.register_envs() == list(preset_files())
        config.environment(env=ENV)
    algo = config.build_algo()
    try:
        venv = algo.env_runner.env.unwrapped
        assert isinstance(venv, BeachballSailVectorEnv) and isinstance(venv, CoreVectorEnv)
        assert venv.num_envs == 3 and venv.max_episode_steps == gym.spec(ENV).max_episode_steps
        assert venv.task.mark_radius == 6.0  # the env kwargs reached the env
        # Through Tune's registry RLlib wraps the creator in an id of its own.
        expected = "rllib-single-agent-env-v0" if plain_id else ENV
        assert venv.spec.id == expected
    finally:
        algo.stop()


def test_config_follows_the_preset():
    throw = rllib.ppo_config("BeachballThrow-v0", num_env_runners=2)
    assert throw.env == "bbgym:BeachballThrow-v0"
    assert throw.num_env_runners == 2 and throw.num_envs_per_env_runner == 256
    assert throw.train_batch_size_per_learner == 16 * 256
    assert (throw.minibatch_size, throw.num_epochs, throw.gamma) == (1024, 8, 0.95)
    assert (throw.lr, throw.lambda_, throw.clip_param) == (0.001, 0.95, 0.2)
    assert throw.num_gpus_per_learner == 0 and throw.num_learners == 0
    assert throw.model_config["fcnet_hiddens"] == [128, 128]
    assert throw.model_config["vf_share_layers"] is False
    assert "max_episode_steps" not in throw.env_config
    assert throw.env_config["screen"] is False
    curve = rllib.ppo_config("BeachballCurve-v0", lr=3e-4, env_kwargs={"gusts": False})
    assert curve.env_config["screen"] is True
    assert curve.env_config["target_distance_range"] == (7.0, 10.0)
    assert curve.env_config["gusts"] is False and curve.lr == 3e-4
    topple = preset_files()["BeachballTopple-v0"]
    with pytest.raises(ValueError, match="is a preset of BeachballTopple-v0"):
        rllib.ppo_config("BeachballCurve-v0", preset=topple)
    # BeachballSail-v1's own preset trains SAC; its PPO preset is there by name.
    with pytest.raises(ValueError, match="RLlib trains PPO presets; this one trains sac"):
        rllib.ppo_config("BeachballSail-v1")
    assert rllib.ppo_config("BeachballSail-v1", preset="beachball_sail_v1_ppo") is not None


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"env_id": "Nope-v0"}, "env_id"),
        ({"iterations": 0}, "iterations"),
        ({"num_env_runners": -1}, "num_env_runners"),
        ({"num_envs_per_env_runner": 0}, "num_envs_per_env_runner"),
        ({"num_env_runners": 3, "num_cpus": 2}, "num_cpus"),
        ({"address": "auto", "num_cpus": 2}, "num_cpus"),
        ({"train_batch_size": 64, "minibatch_size": 128}, "minibatch_size"),
    ],
)
def test_bad_arguments_are_named(tmp_path, kwargs, name):
    args = {"env_id": ENV, "iterations": 1, "out": tmp_path, **kwargs}
    with pytest.raises(ValueError, match=name):
        rllib.train(args.pop("env_id"), **args)


def test_the_train_command_on_rllib(tmp_path):
    """``bbgym train --engine rllib``: its own local Ray (two CPUs), two iterations of the
    Sail preset's batch with two env runners, a checkpoint and the summary."""
    import subprocess
    import sys

    out = tmp_path / "run"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "bbgym",
            "train",
            "--env",
            "BeachballSail-v0",
            "--engine",
            "rllib",
            "--num-env-runners",
            "2",
            "--num-envs-per-env-runner",
            "8",
            "--iterations",
            "2",
            "--num-cpus",
            "2",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    summary = json.loads((out / "rllib.json").read_text())
    assert summary["iterations"] == 2 and summary["num_env_runners"] == 2
    assert summary["torch_threads"] == 1 and summary["versions"]["ray"] == summary["ray_version"]
    batch = summary["train_batch_size"]
    assert 2 * batch <= summary["env_steps_sampled"] < 2 * batch + 2 * 8 * 2
    assert (out / "checkpoint").is_dir() and any((out / "checkpoint").iterdir())
