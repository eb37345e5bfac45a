"""The ``bbgym`` command: its parser, its errors, presets by id, and a budget shorter than
the evaluation period (which once crashed with "best_model.zip.zip not found")."""

from __future__ import annotations

import json
import logging
import subprocess
import sys

import pytest

from bbgym import cli
from bbgym.config import CONFIG_DIR, env_preset, load_preset, preset_files, preset_path


def test_python_m_bbgym_lists_every_command():
    done = subprocess.run(
        [sys.executable, "-m", "bbgym", "--help"], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0
    for command in cli.COMMANDS:
        assert command in done.stdout


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["evaluate", "--env", "NoSuchEnv-v0"], "unknown env id 'NoSuchEnv-v0'"),
        (
            ["evaluate", "--env", "BeachballSail-v0", "--policies", "ppo,bogus"],
            "unknown policies ['bogus']",
        ),
        (["evaluate", "--env", "BeachballSail-v0", "--episodes", "0"], "--episodes: must be >= 1"),
        (["evaluate", "--env", "BeachballSail-v0", "--policies", "ppo"], "needs --model"),
        (
            ["evaluate", "--env", "BeachballSail-v1", "--policies", "random,sac"],
            "--policies sac needs --model",
        ),
        (
            ["train", "--env", "BeachballSail-v1", "--engine", "rllib"],
            "--engine rllib trains PPO presets; beachball_sail_v1.yaml trains sac",
        ),
        (
            ["train", "--env", "BeachballSail-v0", "--preset", "no_such_preset"],
            "preset 'no_such_preset' is neither",
        ),
        (
            ["train", "--env", "BeachballSail-v0", "--preset", "BeachballTopple-v0"],
            "is a preset of BeachballTopple-v0, not BeachballSail-v0",
        ),
        (["train", "--env", "BeachballSail-v0", "--engine", "tf"], "invalid choice: 'tf'"),
        (["polar", "--wind-speed", "-1"], "--wind-speed: must be finite and > 0"),
        (["polar", "--step-deg", "120"], "--step-deg must be in (0, 90]"),
        (
            ["record", "--env", "BeachballSail-v0", "--policy", "random", "--fps", "nan"],
            "--fps: must be finite and > 0",
        ),
        (["fuzz", "--num-envs", "2.5"], "--num-envs: expected an integer, got '2.5'"),
    ],
)
def test_bad_arguments_say_what_is_wrong(capsys, argv, message):
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv",
    [
        ["train", "--env", "CartPole-v1"],
        ["evaluate", "--env", "CartPole-v1"],
        ["baseline", "--env", "CartPole-v1"],
        ["record", "--env", "CartPole-v1", "--policy", "random"],
        ["play", "--env", "CartPole-v1"],
        ["demo", "--env", "CartPole-v1"],
        ["bench", "--envs", "BeachballSail-v0", "CartPole-v1"],
        ["bench", "--env", "CartPole-v1"],
    ],
)
def test_a_registered_env_that_is_not_bbgyms_is_refused_by_every_command(capsys, argv):
    """CartPole-v1 is registered (by Gymnasium), but no bbgym family declares it: every
    command taking an env id says so, naming the argument and bbgym's ids (evaluate once
    crashed with a bare KeyError: 'is_success')."""
    with pytest.raises(SystemExit) as exit_info:
        cli.main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    option = argv[1]  # as typed: bench takes --envs and --env alike
    assert f"argument {option}: 'CartPole-v1' is a registered Gymnasium env but not" in err
    assert "BeachballSail-v1" in err


def test_evaluating_an_id_of_no_bbgym_family_from_python_says_so():
    from bbgym.cli.evaluate import evaluate

    with pytest.raises(ValueError, match="unknown env id 'CartPole-v1'; known: BeachballSail"):
        evaluate("CartPole-v1", "random", 1, 0, None)


def test_the_command_shows_bbgym_info_lines_and_leaves_no_handler(capsys):
    """``bbgym`` prints the library's INFO lines (the torch backend's compile notice) on
    stderr while it runs; the library itself configures no logging."""
    logger = logging.getLogger("bbgym.backends")
    handlers = list(logging.getLogger("bbgym").handlers)
    with cli.show_bbgym_logs():
        logger.info("compiling the step")
        logger.debug("not shown")
    logger.info("after the command")
    err = capsys.readouterr().err
    assert err == "bbgym: compiling the step\n"
    assert logging.getLogger("bbgym").handlers == handlers


def test_a_missing_extra_names_it(capsys, monkeypatch):
    import importlib.util

    find_spec = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "stable_baselines3" else find_spec(name, *a),
    )
    assert cli.main(["train", "--env", "BeachballSail-v0"]) == 3
    err = capsys.readouterr().err
    from bbgym._extras import install_hint

    assert "'stable_baselines3'" in err and install_hint("train") in err


@pytest.mark.parametrize("env_id", sorted(preset_files()))
def test_presets_load_by_id_name_and_path(env_id):
    import gymnasium as gym

    by_id = load_preset(env_id)
    assert by_id[0] == env_id
    name = preset_files()[env_id].stem
    assert preset_path(name) == preset_path(env_id) == CONFIG_DIR / f"{name}.yaml"
    assert load_preset(name) == load_preset(CONFIG_DIR / f"{name}.yaml")
    # An id's kwargs are that id's: Curve is the throw preset with its registered kwargs.
    assert {k: by_id[1][k] for k in gym.spec(env_id).kwargs} == gym.spec(env_id).kwargs
    path, kwargs = env_preset(env_id)
    assert path == preset_path(env_id) and "max_episode_steps" not in kwargs
    env = gym.make(env_id, **kwargs)
    env.reset(seed=0)
    env.close()


def test_a_budget_shorter_than_the_evaluation_period_still_keeps_a_best_model(tmp_path):
    """The end of training is always evaluated: the best model and the evaluation log
    exist after 256 steps of a preset that evaluates every 10^6."""
    pytest.importorskip("stable_baselines3")
    from small_preset import write_small_preset

    from bbgym.cli.train import train_sb3

    config = write_small_preset(
        tmp_path / "sail.yaml",
        ppo={"n_steps": 64, "batch_size": 64, "n_epochs": 1},
        train={
            "n_envs": 4,
            "eval_every_timesteps": 1_000_000,
            "eval_episodes": 2,
            "checkpoint_every_timesteps": 1_000_000,
        },
    )
    out = tmp_path / "run"
    summary = train_sb3("BeachballSail-v0", preset=config, timesteps=256, out=out, progress=False)
    assert summary["timesteps"] == 256 and (out / "best_model.zip").is_file()
    assert summary["best_model_timesteps"] == 256
    import numpy as np

    log = np.load(out / "eval" / "evaluations.npz")
    assert list(log["timesteps"]) == [256] and log["results"].shape == (1, 2)
    assert json.loads((out / "train.json").read_text())["best_model"].endswith("best_model.zip")


@pytest.mark.parametrize(
    ("velocity", "kind"),
    [
        ((4.0, 0.0, 4.0), "missed short"),  # a lob that lands a few metres out
        ((12.0, 0.0, 8.0), "missed long"),  # far past the 6 m target
        ((4.2, 3.5, 5.0), "missed left"),  # 40 deg to the left of the line
        ((4.2, -3.5, 5.0), "missed right"),
    ],
)
def test_the_failure_breakdown_names_where_a_throw_missed(velocity, kind):
    """The target straight ahead at 6 m, no wind: the breakdown of an episode of one throw
    says which way it missed, from the landing point against the line to the target."""
    import gymnasium as gym
    import numpy as np

    from bbgym.cli.evaluate import outcome_kind

    env = gym.make("BeachballThrow-v0", throws_per_episode=1)
    env.reset(seed=0, options={"wind": (0.0, 0.0), "gusts": False, "target": (6.0, 0.0)})
    speed = env.unwrapped.task.max_speed
    action = np.array([*(np.array(velocity) / speed), 0.0, 0.0, 0.0], np.float32)
    _, _, terminated, truncated, info = env.step(action)
    assert terminated and not info["is_success"]
    assert outcome_kind(env, info, terminated, truncated) == kind
    env.close()


def test_the_interval_over_seeds():
    from bbgym.cli.evaluate import mean_interval

    low, high = mean_interval([0.9, 0.92, 0.94, 0.96, 0.98])
    # mean 0.94, sd 0.0316, t(4) 2.776: half width 0.0393
    assert low == pytest.approx(0.94 - 0.03925, abs=1e-4)
    assert high == pytest.approx(0.94 + 0.03925, abs=1e-4)
    assert mean_interval([0.5]) == (0.0, 1.0)
    assert mean_interval([1.0, 1.0, 1.0]) == (1.0, 1.0)


def test_one_seed_keeps_its_own_interval():
    from bbgym.cli.evaluate import format_over_seeds, over_seeds

    seed = {
        "env": "E",
        "episodes": 100,
        "seeds": [0, 99],
        "success_rate": 0.98,
        "success_ci95": [0.93, 0.99],
        "mean_return": 1.0,
        "mean_length": 2.0,
        "mean_time_to_mark_s": None,
        "outcomes": {"success": 98, "timed out": 2},
        "wall_time_s": 1.0,
        "training_seed": 0,
    }
    one = over_seeds([seed])
    assert one["policy"] == "ppo, 1 seed" and one["success_ci95"] == [0.93, 0.99]
    assert "95% Wilson interval 93-99%" in format_over_seeds(one)
    two = over_seeds([seed, {**seed, "success_rate": 0.90, "training_seed": 1}])
    assert two["policy"] == "ppo, 2 seeds" and two["worst_seed"] == 1
    assert two["outcomes"] == {"success": 196, "timed out": 4}


def test_evaluate_refuses_to_replace_its_results_without_overwrite(tmp_path, capsys):
    argv = [
        "evaluate",
        "--env",
        "BeachballThrow-v0",
        "--policies",
        "random",
        "--episodes",
        "1",
        "--out",
        str(tmp_path),
    ]
    assert cli.main(argv) == 0
    first = (tmp_path / "BeachballThrow-v0.json").read_text()
    with pytest.raises(SystemExit) as exit_info:
        cli.main([*argv, "--seed", "5"])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert f"--out {tmp_path}:" in err and "--overwrite" in err
    assert (tmp_path / "BeachballThrow-v0.json").read_text() == first
    assert cli.main([*argv, "--seed", "5", "--overwrite"]) == 0
    assert json.loads((tmp_path / "BeachballThrow-v0.json").read_text())[0]["seeds"] == [5, 5]


def _row(env: str, policy: str, **fields) -> dict:
    return {
        "env": env,
        "policy": policy,
        "episodes": 100,
        "success_rate": 0.5,
        "success_ci95": [0.4, 0.6],
        "mean_return": 1.0,
        "mean_length": 2.0,
        "mean_time_to_mark_s": None,
        "outcomes": {"success": 50, "missed long": 50},
        "wall_time_s": 3.0,
        **fields,
    }


def test_a_throw_table_has_no_time_columns():
    from bbgym.cli.evaluate import format_table

    table = format_table(
        [_row("BeachballThrow-v0", "random"), _row("BeachballThrow-v0", "scripted")]
    )
    header = table.splitlines()[0]
    assert "time to mark" not in header and "time / oracle" not in header
    assert all(line.count("|") == header.count("|") for line in table.splitlines())
    assert "missed long 50" in table


def test_a_mean_over_few_finished_episodes_shows_their_count():
    from bbgym.cli.evaluate import add_time_vs_oracle, format_table

    oracle = _row(
        "BeachballSail-v1",
        "scripted",
        mean_time_to_mark_s=40.0,
        time_to_mark_episodes=100,
        episode_time_to_mark_s=[40.0] * 100,
    )
    lucky = [None] * 100
    lucky[3], lucky[7] = 80.0, 64.0
    random = _row(
        "BeachballSail-v1",
        "random",
        mean_time_to_mark_s=72.0,
        time_to_mark_episodes=2,
        episode_time_to_mark_s=lucky,
    )
    for row in (oracle, random):
        add_time_vs_oracle(row, oracle)
    assert random["time_vs_oracle"] == pytest.approx(1.8)
    assert random["time_vs_oracle_episodes"] == 2
    table = format_table([random, oracle])
    random_line, oracle_line = table.splitlines()[2:]
    assert "| 72.0 s (2 ep.) | 1.80 (2 ep.) |" in random_line
    assert "| 40.0 s | 1.00 |" in oracle_line
