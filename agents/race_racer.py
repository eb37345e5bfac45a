"""A scripted racer for BeachballRace: the sail env's VMG autopilot steering for the point
the race names, with a start routine, the penalty turns it owes and right-of-way
avoidance. It reads the race's observation by column name
(:data:`bbgym.envs.race.task.RACE_COLUMNS`, :data:`~bbgym.envs.race.task.NEIGHBOUR_COLUMNS`).

- **Start**: before the gun it sails for the point the race names (above the line within
  its ends: :func:`bbgym.envs.race.course.steer_target`) like the autopilot, but while
  more time is left than it needs to get there (its distance at :data:`APPROACH_SPEED_MPS`,
  plus ``start_margin_s``) it eases both sheets and luffs: it waits near the line and goes
  for it in time, which keeps it from being over early.
- **Penalty turns** (``penalty="turn"``, the default): while it owes one (fouls before
  the start too), it turns hard to port, rudder full over and its sheets as the autopilot
  trims them (eased, a boat stalls head to wind and never completes the circle), until
  the circle is done.
- **Keeping clear**: a neighbour it must keep clear of (``right_of_way`` -1) within
  ``avoid_m`` and not behind it: it turns away from that boat's side and, within half that
  distance, eases its sheets to slow down and pass astern.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .sail_autopilot import VMGAutopilot

APPROACH_SPEED_MPS = 4.0
"""The speed the racer counts on to reach the line: a dinghy's fast reach. Counting on it,
the racer waits long enough to be over early rarely (4 boats of 40 in ten seeded 4-boat
races, where the autopilot alone was over with 18: ``scripts/race_eval.py``)."""
WAYPOINT_DISTANCE_SCALE_M = 200.0
"""The sail env's mark-distance column is the distance over this (its mark range's 2x)."""
SAIL_DISTANCE_COLUMN = 14


class RaceRacer:
    """Scripted actions for a batch of race observations ``(n, size)``, one row per boat
    in a fixed order (the autopilot remembers each row's tack): :meth:`actions` takes a
    PettingZoo step's observation dict and keeps that order itself. Call :meth:`reset` at
    each new race."""

    def __init__(
        self,
        pilot: VMGAutopilot,
        sail_size: int,
        neighbours: int,
        countdown_s: float,
        start_margin_s: float = 4.0,
        avoid_m: float = 10.0,
        penalty_turns: bool = True,
    ) -> None:
        from bbgym.envs.race.task import NEIGHBOUR_COLUMNS, RACE_COLUMNS

        self.pilot, self.sail_size, self.neighbours = pilot, sail_size, neighbours
        self.countdown_s, self.start_margin_s, self.avoid_m = countdown_s, start_margin_s, avoid_m
        self.penalty_turns = penalty_turns
        self.race = {name: sail_size + i for i, name in enumerate(RACE_COLUMNS)}
        first = sail_size + len(RACE_COLUMNS)
        width = len(NEIGHBOUR_COLUMNS)
        self.neighbour = {
            name: [first + width * k + i for k in range(neighbours)]
            for i, name in enumerate(NEIGHBOUR_COLUMNS)
        }

    @classmethod
    def for_env(cls, env: Any, tack_cone_deg: float | None = None, **kwargs: Any) -> RaceRacer:
        """A racer for the boats of a :class:`~bbgym.envs.race.parallel.BeachballRaceEnv` (or of
        a fleet, whose rows are its boats in order); ``tack_cone_deg`` is its autopilot's
        (:class:`~bbgym.agents.VMGAutopilot`: play the shifts on a beat).

        The first racer of a boat in a process computes its autopilot's polar (about 16 s on
        the 2-core machine); a wait over 2 s is said on stderr
        (:func:`bbgym.backends.announced`, silenced by ``BBGYM_QUIET=1``).

        Args:
            env: the race env or fleet.
            tack_cone_deg: the autopilot's tack cone, or None (tack at the layline).
            **kwargs: the racer's other arguments (:class:`RaceRacer`).

        Returns:
            The racer, its :attr:`boats` the env's possible agents.
        """
        from bbgym.backends import announced

        task = env.unwrapped.task if hasattr(env, "unwrapped") else env.task
        with announced("RaceRacer: computing the boats' polar for their autopilot"):
            pilot = VMGAutopilot(task.sail.params, tack_cone_deg=tack_cone_deg)
        kwargs.setdefault("penalty_turns", task.penalty == "turn")
        racer = cls(pilot, task.race_column, task.neighbours, task.countdown_s, **kwargs)
        racer.boats = list(getattr(env, "possible_agents", []))
        return racer

    boats: list[str] = []
    """The agents in row order (:meth:`for_env` sets them to the env's possible agents)."""

    def reset(self) -> None:
        """Forget every boat's remembered tack (a new race)."""
        self.pilot.reset()

    def actions(
        self, observations: dict[str, np.ndarray], agents: list[str]
    ) -> dict[str, np.ndarray]:
        """Actions for ``agents`` (the env's ``agents``: the boats still racing) from a
        PettingZoo step's ``observations``, each boat in its own row of :attr:`boats`
        whoever has left the race."""
        size = len(next(iter(observations.values())))
        rows = np.stack([observations.get(b, np.zeros(size, np.float32)) for b in self.boats])
        out = self(rows)
        return {b: out[i] for i, b in enumerate(self.boats) if b in agents}

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        o = np.asarray(obs, dtype=np.float64)
        single = o.ndim == 1
        o = o[None] if single else o
        action = np.array(self.pilot(o[:, : self.sail_size]), dtype=np.float64)
        rudder, sheets = action[:, 0], action[:, 1:]
        # start: wait near the line while there is time to spare
        to_gun_s = o[:, self.race["time_to_gun"]] * max(self.countdown_s, 1.0)
        distance = o[:, SAIL_DISTANCE_COLUMN] * WAYPOINT_DISTANCE_SCALE_M
        early = (to_gun_s > 0.0) & (to_gun_s > distance / APPROACH_SPEED_MPS + self.start_margin_s)
        sheets = np.where(early[:, None], 1.0, sheets)
        # keep clear of the boats it must
        if self.neighbours:
            here = o[:, self.neighbour["present"]] > 0.5
            ahead = o[:, self.neighbour["ahead"]] * 50.0
            port = o[:, self.neighbour["port"]] * 50.0
            gap = np.hypot(ahead, port)
            give_way = here & (o[:, self.neighbour["right_of_way"]] < -0.5)
            threat = give_way & (gap < self.avoid_m) & (ahead > -2.0)
            nearest = np.where(threat, gap, np.inf)
            k = np.argmin(nearest, axis=1)
            rows = np.arange(len(o))
            avoiding = np.isfinite(nearest[rows, k])
            away = -np.sign(port[rows, k])  # it is to port: turn to starboard
            rudder = np.where(avoiding, np.where(away == 0.0, -1.0, away), rudder)
            slow = avoiding & (nearest[rows, k] < 0.5 * self.avoid_m)
            sheets = np.where(slow[:, None], 1.0, sheets)
        # a penalty turn owed: round to port, hard
        if self.penalty_turns:
            owed = o[:, self.race["penalty_owed"]] > 0.0
            rudder = np.where(owed, 1.0, rudder)
        out = np.concatenate([rudder[:, None], sheets], axis=1).astype(np.float32)
        return out[0] if single else out
