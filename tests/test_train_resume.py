"""A training killed mid-run (``kill -9``) resumes from its last checkpoint with
``--resume`` and ends as a whole run: its budget, its evaluation log, its best model, no
half-written file (train extra)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")


def test_a_killed_training_resumes_from_its_last_checkpoint(tmp_path):
    from test_train_smoke import small_ppo_run

    from bbgym.cli.checkpoints import latest_checkpoint
    from bbgym.sb3 import load_model

    out, train = small_ppo_run(tmp_path, n_epochs=1)
    # A budget it cannot finish before the kill: killed once its second checkpoint is there.
    errors = tmp_path / "stderr.txt"
    with (
        errors.open("w") as stderr,
        subprocess.Popen(
            [*train, "--timesteps", "1000000"], stdout=subprocess.DEVNULL, stderr=stderr
        ) as run,
    ):
        try:
            deadline = time.monotonic() + 300
            while not (out / "checkpoints" / "ppo_2048_steps.zip").exists():
                assert run.poll() is None, errors.read_text()[-2000:]
                assert time.monotonic() < deadline, "no second checkpoint in 300 s"
                time.sleep(0.05)
        finally:
            os.kill(run.pid, signal.SIGKILL)
            run.wait()
    assert run.returncode == -signal.SIGKILL
    assert not (out / "train.json").exists()  # it did not finish
    point = latest_checkpoint(out, "ppo")
    assert point is not None and point.timesteps >= 2048
    # A file being written when the run died is never read: a partial model past the
    # last checkpoint, and a sidecar without its model.
    later = point.timesteps + 1024
    (out / "checkpoints" / f".ppo_{later}_steps.partial.zip").write_bytes(b"half a zip")
    (out / "checkpoints" / f"ppo_eval_{later}_steps.json").write_text("{")
    assert latest_checkpoint(out, "ppo").timesteps == point.timesteps

    budget = point.timesteps + 2048
    done = subprocess.run(
        [*train, "--timesteps", str(budget), "--resume"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert f"resuming from {point.model} at {point.timesteps} of {budget}" in done.stdout
    summary = json.loads((out / "train.json").read_text())
    assert summary["timesteps"] == budget and summary["timesteps_trained"] == 2048
    model = load_model(out / "model.zip", "ppo")
    assert model.num_timesteps == budget
    # The evaluation log runs on from before the kill, at the same period, without a gap
    # or a repeat; the best model is one the log holds.
    with np.load(out / "eval" / "evaluations.npz") as log:
        steps = list(log["timesteps"])
        means = log["results"].mean(axis=1)
    assert steps == list(range(1024, budget + 1, 1024))
    assert summary["best_model_timesteps"] in steps
    assert summary["best_mean_return"] == pytest.approx(means.max())
    assert load_model(out / "best_model.zip", "ppo").num_timesteps in steps
    # Nothing half written is left (the planted one was replaced when that checkpoint was
    # written), nor the evaluation's scratch folder.
    assert [p.name for p in out.rglob("*") if ".partial" in p.name] == []
    assert not (out / ".eval-scratch").exists()


def test_resume_continues_a_run_that_ended_before_checkpoints_held_its_end(tmp_path):
    """A run folder of bbgym 0.8.0 has periodic checkpoints but its end only in model.zip
    and train.json: --resume continues from the end, not from an older checkpoint."""
    from test_train_smoke import small_ppo_run

    out, train = small_ppo_run(tmp_path, n_epochs=1)
    done = subprocess.run(
        [*train, "--timesteps", "2048"], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-2000:]
    for path in (out / "checkpoints").iterdir():
        if path.name != "ppo_1024_steps.zip":  # what 0.8.0 left: the periodic model alone
            path.unlink()
    done = subprocess.run(
        [*train, "--timesteps", "3072", "--resume"], capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert f"resuming from {out / 'model.zip'} at 2048 of 3072" in done.stdout
    summary = json.loads((out / "train.json").read_text())
    assert (summary["timesteps"], summary["timesteps_trained"]) == (3072, 1024)
    with np.load(out / "eval" / "evaluations.npz") as log:
        assert list(log["timesteps"]) == [1024, 2048, 3072]
        assert summary["best_mean_return"] == pytest.approx(log["results"].mean(axis=1).max())
