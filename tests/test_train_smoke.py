"""End to end: train PPO and SAC a few thousand steps, save, resume, load and evaluate
(train extra)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")


def small_ppo_run(tmp_path: Path, n_epochs: int = 2) -> tuple[Path, list[str]]:
    """A run folder and the ``bbgym train`` command (less its budget) of a small PPO
    preset on Sail-v0: 4 envs, an evaluation and a checkpoint every 1,024 timesteps."""
    from small_preset import write_small_preset

    config = write_small_preset(
        tmp_path / "sail.yaml",
        ppo={"n_steps": 128, "batch_size": 128, "n_epochs": n_epochs},
        train={
            "n_envs": 4,
            "eval_every_timesteps": 1024,
            "eval_episodes": 2,
            "checkpoint_every_timesteps": 1024,
        },
    )
    out = tmp_path / "run"
    train = [
        sys.executable,
        "-m",
        "bbgym",
        "train",
        "--env",
        "BeachballSail-v0",
        "--preset",
        str(config),
        "--out",
        str(out),
        "--no-progress",
    ]
    return out, train


def test_train_save_load_evaluate(tmp_path):
    out, train = small_ppo_run(tmp_path)
    done = subprocess.run(
        [*train, "--timesteps", "2048"], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-2000:]
    summary = json.loads((out / "train.json").read_text())
    assert summary["timesteps"] >= 2048
    assert (out / "model.zip").exists() and (out / "best_model.zip").exists()
    assert list((out / "checkpoints").glob("ppo_*_steps.zip"))
    assert list((out / "tb").iterdir())  # TensorBoard logs
    # Resume continues the same model up to the new budget.
    done = subprocess.run(
        [*train, "--timesteps", "2560", "--resume"], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-2000:]
    resumed = json.loads((out / "train.json").read_text())
    assert (resumed["timesteps"], resumed["timesteps_trained"]) == (2560, 512)
    # ... and not past it: a budget the run has met is refused, naming the option.
    done = subprocess.run(
        [*train, "--timesteps", "2560", "--resume"], capture_output=True, text=True, timeout=600
    )
    assert done.returncode != 0 and "--resume" in done.stderr and "2560" in done.stderr
    evaluate = [
        sys.executable,
        "-m",
        "bbgym",
        "evaluate",
        "--env",
        "BeachballSail-v0",
        "--policies",
        "ppo",
        "--model",
        str(out / "model.zip"),
        "--episodes",
        "2",
        "--out",
        str(tmp_path / "eval"),
    ]
    done = subprocess.run(evaluate, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    results = json.loads((tmp_path / "eval" / "BeachballSail-v0.json").read_text())
    assert results[0]["policy"] == "ppo" and results[0]["episodes"] == 2


def test_normalized_rewards_train_resume_and_score_raw(tmp_path):
    """``train.normalize_reward`` (the Sail-v1 PPO preset): the rewards PPO learns from are
    scaled by running statistics that are saved and resumed, while the evaluation during
    training scores the env's own returns."""
    from small_preset import write_small_preset
    from stable_baselines3 import PPO
    from stable_baselines3.common.evaluation import evaluate_policy
    from stable_baselines3.common.vec_env import VecMonitor, VecNormalize

    from bbgym.cli.train import EVAL_SEED_OFFSET, VEC_NORMALIZE_FILE, train_sb3
    from bbgym.sb3 import make_sb3_vec_env

    config = write_small_preset(
        tmp_path / "sail_v1.yaml",
        "beachball_sail_v1_ppo.yaml",
        ppo={"n_steps": 64, "batch_size": 256},
        train={
            "n_envs": 8,
            "eval_every_timesteps": 100_000,
            "eval_episodes": 2,
            "checkpoint_every_timesteps": 100_000,
        },
    )
    out = tmp_path / "run"
    train_sb3("BeachballSail-v1", preset=config, timesteps=2048, seed=3, out=out, progress=False)
    dummy = make_sb3_vec_env("BeachballSail-v1", n_envs=1, seed=0)
    stats = VecNormalize.load(str(out / VEC_NORMALIZE_FILE), dummy)
    assert not stats.norm_obs and stats.norm_reward and stats.gamma == 0.99
    assert stats.ret_rms.count == pytest.approx(2048, abs=1e-3)  # one per env step
    assert stats.ret_rms.var > 0.0

    # The one evaluation (of the final model, at the end of training) equals SB3's
    # evaluation of model.zip in fresh envs alike, unnormalized: v1's time cost of 0.1 a
    # step, not a scaled-down reward.
    logged = np.load(out / "eval" / "evaluations.npz")
    assert list(logged["timesteps"]) == [2048]
    env_kwargs = {"time_penalty": 0.1, "capsize_penalty": 30.0}
    eval_env = VecMonitor(
        make_sb3_vec_env("BeachballSail-v1", n_envs=2, seed=3 + EVAL_SEED_OFFSET, **env_kwargs)
    )
    returns, _ = evaluate_policy(
        PPO.load(out / "model.zip", device="cpu"),
        eval_env,
        n_eval_episodes=2,
        deterministic=True,
        return_episode_rewards=True,
    )
    assert sorted(logged["results"][-1]) == pytest.approx(sorted(returns))
    assert min(returns) < -20.0  # 300 s at 0.1 a step is -120; a scaled return is O(1)

    # --resume continues the statistics with the model.
    train_sb3(
        "BeachballSail-v1",
        preset=config,
        timesteps=2048 + 512,
        seed=3,
        out=out,
        resume=True,
        progress=False,
    )
    stats = VecNormalize.load(str(out / VEC_NORMALIZE_FILE), dummy)
    assert stats.ret_rms.count == pytest.approx(2048 + 512, abs=1e-3)


def test_sac_trains_resumes_its_replay_buffer_and_evaluates(tmp_path):
    """The Sail-v1 preset trains SAC: its checkpoints, replay buffer (saved with the model,
    continued by ``--resume``) and model, which ``bbgym evaluate`` loads as ``sac`` only."""
    from small_preset import write_tiny_sail_preset

    from bbgym.cli.train import REPLAY_BUFFER_FILE, train_sb3
    from bbgym.sb3 import load_model

    config = write_tiny_sail_preset(tmp_path / "sail_v1.yaml", "beachball_sail_v1.yaml")
    out = tmp_path / "run"
    summary = train_sb3(
        "BeachballSail-v1", preset=config, timesteps=1024, seed=2, out=out, progress=False
    )
    assert summary["algo"] == "sac" and summary["timesteps"] == 1024
    # Every 100k steps, and at the end (what --resume continues; model.zip is its link).
    names = sorted(p.name for p in (out / "checkpoints").iterdir())
    assert names == [
        "sac_1024_steps.zip",
        "sac_best_model_1024_steps.zip",
        "sac_eval_1024_steps.json",
        "sac_replay_buffer_1024_steps.pkl",
    ]
    assert (out / "best_model.zip").exists()
    model = load_model(out / "model.zip", "sac")
    model.load_replay_buffer(out / REPLAY_BUFFER_FILE)
    assert model.replay_buffer.size() * model.n_envs == 1024  # every step, 8 envs a row
    # Two updates per step of the 8 envs from the 256th step on.
    assert model._n_updates == 2 * (1024 - 256) // 8
    train_sb3(
        "BeachballSail-v1",
        preset=config,
        timesteps=1024 + 512,
        seed=2,
        out=out,
        resume=True,
        progress=False,
    )
    model = load_model(out / "model.zip", "sac")
    model.load_replay_buffer(out / REPLAY_BUFFER_FILE)
    assert (model.replay_buffer.n_steps, model.replay_buffer.gamma) == (3, 0.99)  # n-step
    assert model.num_timesteps == 1024 + 512
    assert model.replay_buffer.size() * model.n_envs == 1024 + 512  # the buffer continued
    assert model._n_updates == 2 * (1024 + 512 - 256) // 8

    def evaluate(policy: str) -> subprocess.CompletedProcess:
        command = [
            sys.executable,
            "-m",
            "bbgym",
            "evaluate",
            "--env",
            "BeachballSail-v1",
            "--policies",
            policy,
            "--model",
            str(out / "model.zip"),
            "--episodes",
            "2",
            "--out",
            str(tmp_path / "eval"),
            "--overwrite",
        ]
        return subprocess.run(command, capture_output=True, text=True, timeout=600)

    done = evaluate("sac")
    assert done.returncode == 0, done.stderr[-2000:]
    results = json.loads((tmp_path / "eval" / "BeachballSail-v1.json").read_text())
    assert results[0]["policy"] == "sac" and results[0]["episodes"] == 2
    done = evaluate("ppo")
    assert done.returncode != 0
    assert "--model" in done.stderr and "is a SAC model, not PPO" in done.stderr
