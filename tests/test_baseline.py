"""The main job end to end on a tiny budget: train, evaluate three policies, plot, record."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("matplotlib")
yaml = pytest.importorskip("yaml")

ROOT = Path(__file__).resolve().parents[1]


def test_main_job_writes_the_run_folder(tmp_path):
    from PIL import Image

    from bbgym import cli

    preset = yaml.safe_load((ROOT / "configs" / "beachball_sail.yaml").read_text())
    preset["ppo"].update(n_steps=64, batch_size=256)
    preset["train"].update(n_envs=8, eval_every_timesteps=1024, eval_episodes=2,
                           checkpoint_every_timesteps=100_000)  # fmt: skip
    config = tmp_path / "sail.yaml"
    config.write_text(yaml.safe_dump(preset))
    out = tmp_path / "run"
    argv = ["--env", "BeachballSail-v0", "--preset", str(config), "--timesteps", "2048",
            "--episodes", "3", "--out", str(out), "--no-progress"]  # fmt: skip
    assert cli.main(["baseline", *argv]) == 0

    for name in ("model.zip", "best_model.zip", "results.md", "results.json",
                 "learning_curve.png", "episode.gif", "summary.json", "train.json"):  # fmt: skip
        assert (out / name).stat().st_size > 0, name
    results = json.loads((out / "results.json").read_text())
    assert [r["policy"] for r in results] == ["random", "scripted", "ppo"]
    assert all(r["episodes"] == 3 and r["seeds"] == [0, 2] for r in results)
    # The autopilot is the oracle: its own time ratio is exactly 1 where it arrived.
    scripted = results[1]
    assert scripted["success_rate"] == 1.0
    assert scripted["time_vs_oracle"] == pytest.approx(1.0)
    table = (out / "results.md").read_text()
    assert table.count("| BeachballSail-v0 |") == 3
    summary = json.loads((out / "summary.json").read_text())
    assert summary["timesteps"] == 2048 and summary["train_wall_time_s"] > 0
    with Image.open(out / "learning_curve.png") as png:
        assert png.size[0] > 600
    with Image.open(out / "episode.gif") as gif:
        assert gif.n_frames > 1


def test_main_job_rejects_bad_arguments(capsys):
    from bbgym import cli

    with pytest.raises(SystemExit):
        cli.main(["baseline", "--env", "BeachballSail-v0", "--episodes", "0"])
    assert "--episodes: must be >= 1" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        cli.main(["baseline", "--env", "NoSuchEnv-v0"])
