"""The last throw's recorded poses, padded to a fixed shape so vector envs can stack them
(``info['trajectory']``) and the renderer can replay a flight.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from bbgym.envs.common import (
    pad_rows,
)
from bbgym.envs.throw.task import ThrowEvents


class FlightRecords(NamedTuple):
    """The last throw's recorded poses, fixed-shape: ``trajectory`` ``(C, 3)`` positions and
    ``orientations`` ``(C, 4)`` quaternions (w, x, y, z), ``C`` the task's
    ``record_capacity``, of which the first ``length`` (``K``) were recorded (every
    ``RECORD_DT_S``, the launch's first); rows from ``K`` on repeat the last recorded pose,
    and all are zeros where nothing was recorded (``K == 0``: no throw since the reset;
    zeros rather than NaN, so every info float stays finite). For
    a batch each has a leading axis of the envs (``length`` ``(n,)`` int64)."""

    trajectory: np.ndarray
    orientations: np.ndarray
    length: Any

    def recorded(self) -> tuple[np.ndarray, np.ndarray]:
        """One env's recorded rows, ``(K, 3)`` and ``(K, 4)`` (what the renderer draws)."""
        k = int(self.length)
        return self.trajectory[:k], self.orientations[:k]

    def env(self, i: int) -> FlightRecords:
        """Env ``i``'s records of a batch's."""
        return FlightRecords(self.trajectory[i], self.orientations[i], int(self.length[i]))

    def info(self) -> dict[str, Any]:
        return {
            "trajectory": self.trajectory,
            "orientations": self.orientations,
            "trajectory_length": self.length,
        }


def flight_records(events: ThrowEvents | None, thrown: Any, capacity: int) -> FlightRecords:
    """The last throw's :class:`FlightRecords` (``capacity`` rows) for one env (``thrown`` a
    bool) or a batch (``thrown`` an array); nothing recorded where nothing was thrown since
    the reset, or without ``events`` (the torch backend)."""
    batch = not isinstance(thrown, (bool, np.bool_))
    thrown = np.atleast_1d(np.asarray(thrown, dtype=bool))
    n = thrown.shape[0]
    poses = events.trajectory if events is not None else []
    # (K, 7, n): a pose's fields (Python floats for one env, arrays for a batch) by sample
    rows = np.array(poses, dtype=np.float64).reshape(len(poses), 7, n).transpose(2, 0, 1)
    steps = np.atleast_1d(np.asarray(events.steps)) if poses else np.zeros(n, dtype=np.int64)
    lengths = np.where(thrown, steps, 0).astype(np.int64)
    trajectory = pad_rows(rows[:, :, :3], lengths, capacity)
    orientations = pad_rows(rows[:, :, 3:], lengths, capacity)
    if not batch:
        return FlightRecords(trajectory[0], orientations[0], int(lengths[0]))
    return FlightRecords(trajectory, orientations, lengths)
