"""``bbgym train``'s report: the budget's rounding said, a short summary on stdout (the whole
one in ``train.json``), a training rate without the evaluations, and a run shorter than the
evaluation period not spending the preset's whole evaluation on its one model."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")


def test_a_short_run_says_what_it_rounded_and_reports_training_apart(tmp_path, capsys):
    from small_preset import write_small_preset

    from bbgym import cli

    config = write_small_preset(
        tmp_path / "sail.yaml",
        ppo={"n_steps": 16, "batch_size": 64, "n_epochs": 1},
        train={
            "n_envs": 4,
            "eval_every_timesteps": 1_000_000,
            "eval_episodes": 10,
            "checkpoint_every_timesteps": 1_000_000,
        },
    )
    out = tmp_path / "run"
    argv = [
        "train",
        "--env",
        "BeachballSail-v0",
        "--preset",
        str(config),
        "--timesteps",
        "100",
        "--out",
        str(out),
        "--no-progress",
    ]
    assert cli.main(argv) == 0
    stdout = capsys.readouterr().out
    assert "100 timesteps round up to 128" in stdout
    assert "whole rollouts of n_envs 4 x n_steps 16" in stdout
    assert '"versions"' not in stdout and len(stdout.strip().splitlines()) <= 10
    assert "PPO trained 128 timesteps (asked 100)" in stdout and str(out) in stdout

    log = json.loads((out / "train.json").read_text())
    assert log["timesteps_requested"] == 100 and log["timesteps_trained"] == 128
    assert log["eval_time_s"] > 0
    assert log["train_time_s"] + log["eval_time_s"] == pytest.approx(log["wall_time_s"])
    assert log["timesteps_per_s"] == pytest.approx(128 / log["train_time_s"])
    # No scheduled evaluation came: the final one (for best_model.zip) is one episode per
    # evaluation env, min(n_envs, eval_episodes) = 4, not the preset's 10.
    assert log["evaluations"] == 1 and log["last_eval_episodes"] == 4
    assert np.load(out / "eval" / "evaluations.npz")["results"].shape == (1, 4)
    assert (out / "best_model.zip").is_file()


def test_an_off_policy_budget_rounds_to_the_envs_stepped_together(capsys):
    from bbgym.cli.train import budget_granule, round_budget

    assert budget_granule({"algo": "sac", "train_freq": 1}, 8)[0] == 8
    assert budget_granule({"algo": "sac", "train_freq": [2, "step"]}, 8)[0] == 16
    assert budget_granule({"algo": "sac", "train_freq": [1, "episode"]}, 8)[0] is None
    assert budget_granule({"algo": "ppo"}, 2)[0] == 2 * 2048  # PPO's default n_steps
    assert round_budget("sac", {"train_freq": 1}, 8, 10) == 16
    assert "10 timesteps round up to 16" in capsys.readouterr().out
    assert round_budget("sac", {"train_freq": 1}, 8, 16) == 16
    assert capsys.readouterr().out == ""


def test_the_evaluation_env_steps_the_presets_eval_envs_at_once(tmp_path):
    from small_preset import write_small_preset

    from bbgym.cli.train import _training_envs, resolve_preset
    from bbgym.config import load_training

    for extra, expected in (({}, 4), ({"eval_envs": 10}, 10)):
        config = write_small_preset(
            tmp_path / "sail.yaml",
            ppo={"n_steps": 16, "batch_size": 64, "n_epochs": 1},
            train={"n_envs": 4, "eval_episodes": 10, **extra},
        )
        _, env_kwargs = resolve_preset("BeachballSail-v0", config)
        settings = load_training(config)[1]
        vec_env, eval_env = _training_envs("BeachballSail-v0", env_kwargs, settings, 0, 0.99)
        try:
            assert (vec_env.num_envs, eval_env.num_envs) == (4, expected)
        finally:
            vec_env.close()
            eval_env.close()
