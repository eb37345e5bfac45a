"""A training's checkpoints, and where ``bbgym train --resume`` continues from.

A checkpoint at ``T`` timesteps is a set of files in ``<out>/checkpoints``, named as
stable-baselines3's ``CheckpointCallback`` names them (so RL Zoo's and SB3's loaders
know them), each written whole (:mod:`bbgym._files`):

    <algo>_replay_buffer_<T>_steps.pkl   an off-policy algorithm's (SAC's) replay buffer
    <algo>_vecnormalize_<T>_steps.pkl    the reward normalizer's statistics (normalize_reward)
    <algo>_eval_<T>_steps.json           the evaluation's state: best mean return, when, time
    <algo>_best_model_<T>_steps.zip      the best model so far (a hard link, no copy)
    <algo>_<T>_steps.zip                 the model, written last: the checkpoint is complete

A training saves one every ``checkpoint_every_timesteps`` and one when it ends (the run's
``model.zip``, ``replay_buffer.pkl`` and ``vecnormalize.pkl`` are links to that last one),
so a run killed at any instant resumes from its newest complete checkpoint. Only the
newest replay buffer is kept: one is 30-60 MB at Sail-v1's budget.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bbgym._files import link_or_copy, write_atomic, write_text_atomic

CHECKPOINTS = "checkpoints"


@dataclass(frozen=True)
class Checkpoint:
    """The files of one complete checkpoint (those its run had)."""

    timesteps: int
    model: Path
    replay_buffer: Path | None
    vecnormalize: Path | None
    eval_state: dict[str, Any]
    best_model: Path | None


def _file(out: Path, algo: str, kind: str, timesteps: int, suffix: str) -> Path:
    infix = f"{kind}_" if kind else ""
    return out / CHECKPOINTS / f"{algo}_{infix}{timesteps}_steps.{suffix}"


def save_checkpoint(model: Any, out: Path, algo: str, evaluation: Any) -> Checkpoint:
    """Write the checkpoint of ``model`` at its timestep count (the model last), then
    drop older replay buffers; return it."""
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm

    steps = int(model.num_timesteps)
    buffer = vecnormalize = best = None
    if isinstance(model, OffPolicyAlgorithm):
        buffer = write_atomic(
            _file(out, algo, "replay_buffer", steps, "pkl"), model.save_replay_buffer
        )
    normalizer = model.get_vec_normalize_env()
    if normalizer is not None:
        vecnormalize = write_atomic(
            _file(out, algo, "vecnormalize", steps, "pkl"), lambda p: normalizer.save(str(p))
        )
    state = evaluation.state()
    write_text_atomic(_file(out, algo, "eval", steps, "json"), json.dumps(state) + "\n")
    if (out / "best_model.zip").exists():
        best = link_or_copy(out / "best_model.zip", _file(out, algo, "best_model", steps, "zip"))
    path = write_atomic(_file(out, algo, "", steps, "zip"), model.save)
    for old in (out / CHECKPOINTS).glob(f"{algo}_replay_buffer_*_steps.pkl"):
        if old != buffer:
            old.unlink(missing_ok=True)
    return Checkpoint(steps, path, buffer, vecnormalize, state, best)


def latest_checkpoint(out: Path, algo: str) -> Checkpoint | None:
    """The newest complete checkpoint in ``<out>/checkpoints`` (its model written), or
    None. A file still being written when the run was killed is never one of them."""
    pattern = re.compile(rf"{re.escape(algo)}_(\d+)_steps\.zip")
    found = sorted(
        (int(m.group(1)), p)
        for p in (out / CHECKPOINTS).glob(f"{algo}_*_steps.zip")
        if (m := pattern.fullmatch(p.name))
    )
    if not found:
        return None
    steps, model = found[-1]

    def optional(kind: str, suffix: str) -> Path | None:
        path = _file(out, algo, kind, steps, suffix)
        return path if path.exists() else None

    state_file = optional("eval", "json")
    state = json.loads(state_file.read_text()) if state_file else {}
    return Checkpoint(
        steps,
        model,
        optional("replay_buffer", "pkl"),
        optional("vecnormalize", "pkl"),
        state,
        optional("best_model", "zip"),
    )


def finished_run(out: Path) -> Checkpoint | None:
    """A finished run's end as a checkpoint: its ``model.zip`` at ``train.json``'s
    timesteps, with the replay buffer and reward statistics beside it. What ``--resume``
    continues in a run folder written before checkpoints held a run's end (bbgym 0.8.0
    and earlier); None where the run has no ``train.json`` or model."""
    summary, model = out / "train.json", out / "model.zip"
    if not (summary.exists() and model.exists()):
        return None
    steps = int(json.loads(summary.read_text())["timesteps"])

    def beside(name: str) -> Path | None:
        return out / name if (out / name).exists() else None

    return Checkpoint(
        steps, model, beside("replay_buffer.pkl"), beside("vecnormalize.pkl"), {}, None
    )


def checkpoint_callback(out: Path, algo: str, every_timesteps: int, evaluation: Any) -> Any:
    """An SB3 callback that saves a checkpoint (:func:`save_checkpoint`) each time the
    model's timestep count passes a multiple of ``every_timesteps``: the same timesteps
    in a run and in its resumption, which an SB3 ``CheckpointCallback`` (counting its own
    calls) would not keep."""
    from stable_baselines3.common.callbacks import BaseCallback

    class RunCheckpoints(BaseCallback):
        def _on_training_start(self) -> None:
            self.saved = int(self.model.num_timesteps) // every_timesteps

        def _on_step(self) -> bool:
            if int(self.model.num_timesteps) // every_timesteps > self.saved:
                self.saved = int(self.model.num_timesteps) // every_timesteps
                save_checkpoint(self.model, out, algo, evaluation)
            return True

    return RunCheckpoints()
