"""The main job as `make run` runs it, on a small budget: the Makefile's own command line,
through the installed console script, in a separate process; its results table is what
`bbgym evaluate` gives the model it saved, and the README names that same command."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("stable_baselines3")
pytest.importorskip("matplotlib")

ROOT = Path(__file__).resolve().parents[1]
MAIN_ENV = "BeachballSail-v2"
"""The env the main job trains (the sailing baseline of the README)."""


def make_run_command() -> list[str]:
    """The `run` recipe of the Makefile, as argv after the console script's name."""
    makefile = (ROOT / "Makefile").read_text()
    recipe = re.search(r"^run:.*\n\t(.+)$", makefile, re.MULTILINE)
    assert recipe, "the Makefile has a run target with a one-line recipe"
    words = shlex.split(recipe.group(1))
    words = [w for w in words if not re.fullmatch(r"[A-Z_]+=.*", w)]  # environment settings
    assert words[0].endswith("/bbgym"), words
    return words[1:]


def test_the_readme_names_the_makefiles_main_job():
    argv = make_run_command()
    assert argv[:3] == ["baseline", "--env", MAIN_ENV]
    readme = (ROOT / "README.md").read_text()
    assert f"`bbgym {' '.join(argv)}`" in readme
    assert f"make run                     # = bbgym {' '.join(argv)}" in readme


def test_the_main_job_end_to_end_on_a_small_budget(tmp_path):
    from small_preset import write_tiny_sail_preset

    from bbgym.config import load_training, preset_path

    argv = make_run_command()
    # The job's preset (the quick one: under 10 minutes on two cores), on a tiny budget.
    name = argv[argv.index("--preset") + 1]
    assert name == "beachball_sail_v2_quick"
    _, settings = load_training(name)
    assert settings["algo"] == "sac" and settings["evaluate_model"] == "final"
    preset = write_tiny_sail_preset(tmp_path / "sail.yaml", preset_path(name).name)
    out_at = argv.index("--out")
    out = tmp_path / "main"
    argv[out_at + 1] = str(out)  # the job's own folder, under the test's
    small = ["--preset", str(preset), "--timesteps", "2048", "--episodes", "3", "--no-progress"]
    env = {**os.environ, "SDL_VIDEODRIVER": "dummy"}
    bbgym = [sys.executable, "-m", "bbgym"]
    job = subprocess.run(
        [*bbgym, *argv, *small], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600
    )
    assert job.returncode == 0, job.stderr[-3000:]

    for name in (
        "results.md",
        "results.json",
        "learning_curve.png",
        "episode.gif",
        "summary.json",
        "seed0/model.zip",
        "seed0/best_model.zip",
        "seed0/train.json",
    ):
        assert (out / name).stat().st_size > 0, name
    rows = json.loads((out / "results.json").read_text())
    assert [r["policy"] for r in rows] == ["random", "scripted", "sac, 1 seed"]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["training_seeds"] == [0] and summary["torch_threads"] == 2  # the Makefile's
    assert summary["algo"] == "sac" and "sac_mean" in summary["success_rate"]
    assert summary["evaluated_model"] == "model.zip"  # the preset's evaluate_model: final
    assert summary["command"][1:] == [*argv, *small]  # provenance: the command line itself

    # The table's SAC row is what the evaluate command gives the saved final model.
    check = subprocess.run(
        [
            *bbgym,
            "evaluate",
            "--env",
            MAIN_ENV,
            "--policies",
            "sac",
            "--model",
            str(out / "seed0" / "model.zip"),
            "--episodes",
            "3",
            "--out",
            str(tmp_path / "e"),
        ],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert check.returncode == 0, check.stderr[-3000:]
    (again,) = json.loads((tmp_path / "e" / f"{MAIN_ENV}.json").read_text())
    learnt = rows[2]
    for key in ("success_rate", "mean_return", "mean_length", "mean_time_to_mark_s"):
        assert learnt[key] == again[key], key
    table = (out / "results.md").read_text()
    assert table.count(f"| {MAIN_ENV} |") == 3
