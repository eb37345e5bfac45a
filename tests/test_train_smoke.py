"""End to end: train PPO a few thousand steps, save, load and evaluate (train extra)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

pytest.importorskip("stable_baselines3")


def test_train_save_load_evaluate(tmp_path):
    from small_preset import write_small_preset

    config = write_small_preset(
        tmp_path / "sail.yaml",
        ppo={"n_steps": 128, "batch_size": 128, "n_epochs": 2},
        train={"n_envs": 4, "eval_every_timesteps": 1024, "eval_episodes": 2,
               "checkpoint_every_timesteps": 1024},
    )  # fmt: skip
    out = tmp_path / "run"
    train = [sys.executable, "-m", "bbgym", "train", "--env", "BeachballSail-v0",
             "--preset", str(config), "--out", str(out), "--no-progress"]  # fmt: skip
    done = subprocess.run([*train, "--timesteps", "2048"], capture_output=True, text=True,
                          timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    summary = json.loads((out / "train.json").read_text())
    assert summary["timesteps"] >= 2048
    assert (out / "model.zip").exists() and (out / "best_model.zip").exists()
    assert list((out / "checkpoints").glob("ppo_*_steps.zip"))
    assert list((out / "tb").iterdir())  # TensorBoard logs
    # Resume continues the same model.
    done = subprocess.run([*train, "--timesteps", "512", "--resume"], capture_output=True,
                          text=True, timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    assert json.loads((out / "train.json").read_text())["timesteps"] >= 2048 + 512
    evaluate = [sys.executable, "-m", "bbgym", "evaluate", "--env",
                "BeachballSail-v0", "--policies", "ppo", "--model", str(out / "model.zip"),
                "--episodes", "2", "--out", str(tmp_path / "eval")]  # fmt: skip
    done = subprocess.run(evaluate, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    results = json.loads((tmp_path / "eval" / "BeachballSail-v0.json").read_text())
    assert results[0]["policy"] == "ppo" and results[0]["episodes"] == 2
