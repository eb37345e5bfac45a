"""The main job end to end on a tiny budget: train, evaluate three policies, plot, record."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("matplotlib")


def test_main_job_writes_the_run_folder(tmp_path):
    from PIL import Image
    from small_preset import write_tiny_sail_preset

    from bbgym import cli

    config = write_tiny_sail_preset(tmp_path / "sail.yaml")
    out = tmp_path / "run"
    argv = [
        "--env",
        "BeachballSail-v0",
        "--preset",
        str(config),
        "--timesteps",
        "2048",
        "--episodes",
        "3",
        "--seeds",
        "2",
        "--jobs",
        "2",
        "--out",
        str(out),
    ]
    assert cli.main(["baseline", *argv]) == 0

    for name in ("results.md", "results.json", "learning_curve.png", "episode.gif", "summary.json"):
        assert (out / name).stat().st_size > 0, name
    for seed in (0, 1):
        for name in ("model.zip", "best_model.zip", "train.json", "learning_curve.png"):
            assert (out / f"seed{seed}" / name).stat().st_size > 0, (seed, name)
    results = json.loads((out / "results.json").read_text())
    policies = [r["policy"] for r in results]
    assert policies == ["random", "scripted", "ppo, 2 seeds", "ppo seed 0", "ppo seed 1"]
    assert all(r["episodes"] == 3 and r["seeds"] == [0, 2] for r in results)
    # The autopilot is the oracle: its own time ratio is exactly 1 where it arrived.
    scripted = results[1]
    assert scripted["success_rate"] == 1.0 and scripted["outcomes"] == {"success": 3}
    assert scripted["time_vs_oracle"] == pytest.approx(1.0)
    # PPO over seeds: the mean and the worst of the per-seed rates, outcomes summed.
    ppo, by_seed = results[2], results[3:]
    rates = [r["success_rate"] for r in by_seed]
    assert ppo["success_rate"] == pytest.approx(sum(rates) / 2)
    assert ppo["worst_seed_success_rate"] == min(rates)
    assert sum(ppo["outcomes"].values()) == 6
    low, high = ppo["success_ci95"]
    assert 0.0 <= low <= ppo["success_rate"] <= high <= 1.0
    table = (out / "results.md").read_text()
    assert table.count("| BeachballSail-v0 |") == 5 and "worst seed" in table
    summary = json.loads((out / "summary.json").read_text())
    assert summary["timesteps"] == 2048 and summary["train_wall_time_s"] > 0
    assert summary["training_seeds"] == [0, 1] and summary["torch_threads"] == 1
    # Trained in two processes at once, a seed's model is the one a lone training gives.
    import torch
    from stable_baselines3 import PPO

    from bbgym.cli.train import train_sb3

    alone = tmp_path / "alone"
    train_sb3(
        "BeachballSail-v0",
        preset=config,
        timesteps=2048,
        seed=1,
        out=alone,
        progress=False,
        torch_threads=1,
    )
    a, b = (
        PPO.load(f / "model.zip", device="cpu").policy.state_dict() for f in (alone, out / "seed1")
    )
    assert all(torch.equal(a[k], b[k]) for k in a)
    with Image.open(out / "learning_curve.png") as png:
        assert png.size[0] > 600
    with Image.open(out / "episode.gif") as gif:
        assert gif.n_frames > 1

    # --no-train evaluates the models already there: the same rows (evaluation is seeded),
    # each seed's training time kept from its train.json, no rate for training it did not do.
    assert cli.main(["baseline", *argv, "--no-train"]) == 0
    again = json.loads((out / "results.json").read_text())
    drop = ("wall_time_s",)
    assert [{k: v for k, v in r.items() if k not in drop} for r in again] == [
        {k: v for k, v in r.items() if k not in drop} for r in results
    ]
    resummed = json.loads((out / "summary.json").read_text())
    assert resummed["train_wall_time_s"] is None and resummed["train_timesteps_per_s"] is None
    assert resummed["train_wall_time_s_per_seed"] == summary["train_wall_time_s_per_seed"]

    # The docs' results file of this run folder gives the baselines table its row.
    from test_docs import tables

    (tmp_path / "results" / "baselines").mkdir(parents=True)
    command = "bbgym baseline --env BeachballSail-v0 --seeds 2 --jobs 2"
    path = tables.record_baseline(out, command, note="tiny", results=tmp_path / "results")
    assert path.name == "BeachballSail-v0-ppo.json"
    recorded = json.loads(path.read_text())
    assert not any(k.startswith("episode_") for r in recorded["results"] for k in r)
    row, source = tables.baseline_row(path)
    cells = row.split(" | ")
    assert cells[0] == "| BeachballSail-v0, PPO" and cells[2].startswith("100% (")
    mean = 100 * ppo["success_rate"]
    assert cells[4].startswith(f"{mean:.1f}% (") and cells[-1] == f"`{command}` |"
    assert "record-baseline" in source


def test_main_job_rejects_bad_arguments(capsys):
    from bbgym import cli

    with pytest.raises(SystemExit):
        cli.main(["baseline", "--env", "BeachballSail-v0", "--episodes", "0"])
    assert "--episodes: must be >= 1" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        cli.main(["baseline", "--env", "NoSuchEnv-v0"])
