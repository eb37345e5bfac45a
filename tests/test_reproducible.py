"""Training is reproducible: the same command and seed on the same machine give the same
model, bit for bit, and the run folder records what the result depends on."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("stable_baselines3")
torch = pytest.importorskip("torch")

from small_preset import write_small_preset  # noqa: E402

import bbgym  # noqa: E402
from bbgym.cli.train import train_sb3  # noqa: E402


def small_preset(tmp_path):
    return write_small_preset(
        tmp_path / "sail.yaml",
        ppo={"n_steps": 64, "batch_size": 128, "n_epochs": 2},
        train={"n_envs": 8, "eval_every_timesteps": 1024, "eval_episodes": 2,
               "checkpoint_every_timesteps": 1_000_000},
    )  # fmt: skip


def parameters(run):
    from stable_baselines3 import PPO

    return PPO.load(run / "model.zip", device="cpu").policy.state_dict()


def test_the_same_seed_trains_the_same_model_and_another_seed_does_not(tmp_path):
    preset = small_preset(tmp_path)
    threads = torch.get_num_threads()
    runs = {}
    for name, seed in (("a", 3), ("b", 3), ("c", 4)):
        runs[name] = tmp_path / name
        train_sb3("BeachballSail-v0", preset=preset, timesteps=2048, seed=seed, out=runs[name],
                  progress=False, torch_threads=1)  # fmt: skip
    assert torch.get_num_threads() == 1  # pinned by the run
    torch.set_num_threads(threads)
    a, b, c = (parameters(runs[k]) for k in "abc")
    assert a.keys() == b.keys()
    assert all(torch.equal(a[k], b[k]) for k in a)  # exactly, every tensor
    assert not all(torch.equal(a[k], c[k]) for k in a if a[k].is_floating_point())
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
