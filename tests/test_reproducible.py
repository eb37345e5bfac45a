"""Training is reproducible: the same command and seed on the same machine give the same
model, bit for bit, and the run folder records what the result depends on."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")

from small_preset import write_small_preset, write_tiny_sail_preset  # noqa: E402

import bbgym  # noqa: E402
from bbgym.cli.train import train_sb3  # noqa: E402


def small_preset(tmp_path):
    return write_small_preset(
        tmp_path / "sail.yaml",
        ppo={"n_steps": 64, "batch_size": 128, "n_epochs": 2},
        train={
            "n_envs": 8,
            "eval_every_timesteps": 1024,
            "eval_episodes": 2,
            "checkpoint_every_timesteps": 1_000_000,
        },
    )


def parameters(run, algo="ppo"):
    from bbgym.sb3 import load_model

    return load_model(run / "model.zip", algo).policy.state_dict()


def train_twice_and_once_more(tmp_path, env_id, preset, seed, timesteps, algo="ppo"):
    """Train runs ``a`` and ``b`` on ``seed`` and ``c`` on ``seed + 1`` at one torch thread;
    assert that a and b have the same networks exactly and c does not; return the runs."""
    threads = torch.get_num_threads()
    runs = {}
    for name, run_seed in (("a", seed), ("b", seed), ("c", seed + 1)):
        runs[name] = tmp_path / name
        train_sb3(
            env_id,
            preset=preset,
            timesteps=timesteps,
            seed=run_seed,
            out=runs[name],
            progress=False,
            torch_threads=1,
        )
    assert torch.get_num_threads() == 1  # pinned by the run
    torch.set_num_threads(threads)
    a, b, c = (parameters(runs[k], algo) for k in "abc")
    assert a.keys() == b.keys()
    assert all(torch.equal(a[k], b[k]) for k in a)  # exactly, every tensor
    assert not all(torch.equal(a[k], c[k]) for k in a if a[k].is_floating_point())
    return runs, a


def test_the_same_seed_trains_the_same_model_and_another_seed_does_not(tmp_path):
    runs, _ = train_twice_and_once_more(
        tmp_path, "BeachballSail-v0", small_preset(tmp_path), seed=3, timesteps=2048
    )
    # The evaluations during training are the same numbers too.
    import numpy as np

    logs = [np.load(runs[k] / "eval" / "evaluations.npz") for k in "ab"]
    np.testing.assert_array_equal(logs[0]["results"], logs[1]["results"])

    summary = json.loads((runs["a"] / "train.json").read_text())
    assert summary["seed"] == 3 and summary["torch_threads"] == 1
    versions = summary["versions"]
    assert versions["torch"] == torch.__version__
    assert versions["bbgym"] == bbgym.__version__
    assert {"bbgym", "stable-baselines3", "gymnasium", "numpy", "python"} <= set(versions)
    assert summary["command"] and summary["machine"]["cpus"] >= 1


def test_sac_is_reproducible_too(tmp_path):
    """SAC (the Sail-v1 preset): replay sampling, updates and the entropy coefficient are
    seeded alike, so two runs of one seed give the same networks, bit for bit."""
    preset = write_tiny_sail_preset(tmp_path / "sail_v1.yaml", "beachball_sail_v1.yaml")
    _, networks = train_twice_and_once_more(
        tmp_path, "BeachballSail-v1", preset, seed=5, timesteps=1024, algo="sac"
    )
    assert any("critic_target" in k for k in networks)  # the target critic too


def test_the_model_does_not_depend_on_how_many_envs_evaluate_it(tmp_path):
    """``train.eval_envs`` changes the episodes the evaluations during training draw, not
    the training: evaluating acts deterministically and draws nothing from the training's
    generators, so the final model (which SAC's presets evaluate) is the same, bit for bit."""
    import numpy as np

    nets, logs = [], []
    for eval_envs in (1, 2):
        preset = write_small_preset(
            tmp_path / f"quick{eval_envs}.yaml",
            "beachball_sail_v1_quick.yaml",
            sac={"learning_starts": 256, "buffer_size": 4096},
            train={
                "n_envs": 8,
                "eval_every_timesteps": 512,
                "eval_episodes": 2,
                "eval_envs": eval_envs,
                "checkpoint_every_timesteps": 1_000_000,
            },
        )
        out = tmp_path / f"run{eval_envs}"
        train_sb3(
            "BeachballSail-v1",
            preset=preset,
            timesteps=1536,
            seed=2,
            out=out,
            progress=False,
            torch_threads=1,
        )
        nets.append(parameters(out, "sac"))
        logs.append(np.load(out / "eval" / "evaluations.npz")["ep_lengths"])
    assert all(torch.equal(nets[0][k], nets[1][k]) for k in nets[0])
    assert logs[0].shape == logs[1].shape == (3, 2)  # evaluated at 512, 1024 and 1536 steps
