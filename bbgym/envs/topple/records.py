"""The samples of a step's interval (ball, wall, loose panel), padded to a fixed shape so
vector envs can stack them and the renderer can replay the interval.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bbgym.envs.common import (
    pad_rows,
)
from bbgym.envs.topple.task import ToppleEvents
from bbgym.physics.wall import (
    LOOSE,
)

SAMPLE_KEYS = (
    "ball_trajectory",
    "ball_orientations",
    "wall_angle_samples",
    "loose_samples",
    "loose_mask",
)
"""The info entries of a step's samples, ``(C, ...)`` each (see :func:`step_records`)."""
LENGTH_KEYS = ("samples_length", "ball_trajectory_length")


def step_records(
    events: ToppleEvents | None,
    every: int,
    fresh: np.ndarray,
    capacity: int,
    only: int | None = None,
) -> dict[str, np.ndarray]:
    """The envs' samples of the last transition (for info and rendering; env ``only`` alone
    if given), fixed-shape: of the substeps' samples every ``every``-th, the first
    ``samples[i]`` of them (those taken while env ``i`` ran; none for the envs reset since,
    ``fresh``, or without ``events``). Each of :data:`SAMPLE_KEYS` is ``(n, capacity, ...)``
    (``n`` envs, or 1 with ``only``), padded by :func:`~bbgym.envs.common.pad_rows` (rows
    past an env's last repeat it; zeros, ``False`` for ``loose_mask``, where it has none);
    ``samples_length`` ``(n,)`` counts the rows of the wall's and loose panel's samples,
    ``ball_trajectory_length`` the ball's (the same, or 0 where no ball was thrown)."""
    n = len(fresh) if only is None else 1
    envs = slice(None) if only is None else slice(only, only + 1)
    if events is None or events.taken is None:
        rows = np.zeros((n, 0, 12))
        samples = thrown = np.zeros(n, dtype=np.int64)
    else:
        taken = events.taken[::every]
        # (K, 12) or (K, 12, n): SAMPLE_FIELDS by sample, as (n, K, 12)
        rows = np.array(taken, dtype=np.float64).reshape(len(taken), 12, -1)[:, :, envs]
        rows = rows.transpose(2, 0, 1)
        samples = np.atleast_1d(events.samples)[envs]
        thrown = np.atleast_1d(events.thrown)[envs]
        samples = np.where(np.asarray(fresh)[envs], 0, samples).astype(np.int64)
    ball = np.where(thrown, samples, 0).astype(np.int64)
    return {
        "ball_trajectory": pad_rows(rows[:, :, :3], ball, capacity),
        "ball_orientations": pad_rows(rows[:, :, 3:7], ball, capacity),
        "wall_angle_samples": pad_rows(rows[:, :, 7], samples, capacity),
        "loose_samples": pad_rows(rows[:, :, 8:11], samples, capacity),
        "loose_mask": pad_rows(rows[:, :, 11] == LOOSE, samples, capacity, fill=False),
        "samples_length": samples,
        "ball_trajectory_length": ball,
    }


def env_record(records: dict[str, np.ndarray], i: int = 0) -> dict[str, Any]:
    """Env ``i``'s entries of :func:`step_records` (lengths as ints)."""
    return {k: int(v[i]) if k in LENGTH_KEYS else v[i] for k, v in records.items()}


def recorded_rows(record: dict[str, Any]) -> dict[str, np.ndarray]:
    """One env's samples cut to the rows recorded (what the renderer draws)."""
    k, ball = record["samples_length"], record["ball_trajectory_length"]
    cut = {key: record[key][:k] for key in SAMPLE_KEYS}
    cut["ball_trajectory"] = record["ball_trajectory"][:ball]
    cut["ball_orientations"] = record["ball_orientations"][:ball]
    return cut
