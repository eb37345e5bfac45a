"""BeachballTopple-v0, -v1 and -v2: the Gymnasium adapters (single and native vector env) over
:class:`~bbgym.envs.topple.task.ToppleTask`, with the docstring tables.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bbgym import backends
from bbgym.envs.core import CoreEnv, CoreVectorEnv, FlightFrames
from bbgym.envs.topple.records import env_record, step_records
from bbgym.envs.topple.scene import describe_scene, flight_scenes, make_renderer
from bbgym.envs.topple.task import ToppleTask
from bbgym.physics.wall import (
    STATE_NAMES,
)

_DOC_ARGS = """
    ## Arguments

    Keyword arguments of ``gym.make("BeachballTopple-v0", ...)`` and ``gym.make_vec``; the
    defaults are the preset in ``configs/beachball_topple.yaml``. ``BeachballTopple-v1``
    is registered with ``wall_distance_range=(3.0, 5.0)`` and
    ``wind_from_range=(pi / 2, 3 pi / 2)``, ``BeachballTopple-v2`` with those and
    ``interval_integrator="rk4_events"``, ``sim_dt=0.05`` (see Version History).

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"`, `"rgb_array_list"` or `"human"` (see Rendering) |
    | `wall` | `None` | mapping of `WallParams` fields (height, width, foot, mass, hold, ...) |
    | `ball` | `None` | mapping of `BallParams` fields |
    | `throws_per_episode` | `8` | steps (throws or waits) per episode |
    | `wall_distance_range` | `(4.0, 8.0)` | m along +x |
    | `wind_speed_range` | `(0.0, 3.0)` | mean wind, m/s |
    | `wind_from_range` | `(0.0, 2 pi)` | rad, where the mean wind blows from (pi: behind you) |
    | `gusts`, `gust_params`, `gust_dt` | `True`, `None`, `0.25` | gust renewal period, s |
    | `windsock_noise` | `0.3` | m/s per component |
    | `max_speed`, `max_spin` | `18.0`, `60.0` | launch speed (m/s), spin (rad/s) at full action |
    | `launch_height` | `1.5` | m |
    | `wait_speed` | `0.5` | a launch slower than this (m/s) is a wait: no ball is thrown |
    | `interval` | `3.0` | s simulated per step |
    | `sim_dt` | `0.01` | s |
    | `interval_integrator` | `"semi_implicit_euler"` | substeps, or `"rk4_events"` (v2) |
    | `success_bonus`, `failure_penalty` | `10.0`, `5.0` | |
    | `throw_cost`, `lean_weight` | `0.2`, `1.0` | |

    A value of the wrong type raises ``TypeError``, a non-finite or out-of-interval value
    ``ValueError``, each naming the argument (``dinghy.mass_kg``); an unknown argument or
    field raises ``TypeError``. The accepted intervals are on the documentation's
    "Validation and errors" page, from ``ARGUMENT_TABLE`` and the parameter dataclasses.
"""


class BeachballToppleEnv(FlightFrames, CoreEnv):
    """Bring down a wall standing in gusty wind by throwing beach balls at it.

    ## Description

    A light stage-set panel (2.4 m high, 0.7 m wide, 8 kg, on a foot 0.4 m deep) stands
    4-8 m in front of the thrower along +x (v1: 3-5 m), its face toward the thrower, in a
    gusty wind from any direction (v1: an onshore breeze, from behind the thrower's
    shoulders). The wind on its face and the beach balls that hit it rock it about
    the edge of its foot (seed §8, "Buster Keaton"); once its centre of mass passes over the
    edge it falls. A strong enough push along the ground tears the foot loose, and the
    panel flies off in the wind. Each step the agent throws a ball (impulse and spin, as in
    `BeachballThrow-v0`; a launch slower than 0.5 m/s means "wait"), then 3 s pass in which
    the ball flies and wind and hits act on the wall.

    Success: the wall falls away from the thrower or breaks loose, in as few throws as
    possible. Failure: it falls toward the thrower, or the 8 steps run out. In calm air one
    good hit high on the face topples the wall from 4 m; from farther the draggy ball
    arrives too slow, and a tailwind or a gust timed right must help. The wind alone tips
    the wall when its component against the face exceeds 3.3 m/s and tears it loose above
    11 m/s.

    World frame: x east, y north, z up, metres.

    ## Action Space

    `Box(-1, 1, (6,), float32)`: launch velocity x, y, z (x 18 m/s) and spin x, y, z
    (x 60 rad/s), norms clipped, as in `BeachballThrow-v0`.

    ## Observation Space

    `Box(-1, 1, (19,), float32)`; each value is clipped to [-1, 1].

    | Num | Observation | Scale |
    |-----|-------------|-------|
    | 0 | wall lean, + away from the thrower | / (pi/2) |
    | 1 | wall lean rate | / 2 rad/s |
    | 2 | wall distance | / 10 m |
    | 3-4 | wall height, width | / 5 m |
    | 5-6 | windsock reading x, y (noisy) | / 10 m/s |
    | 7 | throws left | / throws per episode |
    | 8 | last step: 1 hit the wall, -1 threw and missed, 0 waited | - |
    | 9 | height of the last hit on the face (0 if none) | / wall height |
    | 10 | sideways position of the last hit | / (width / 2) |
    | 11 | largest force on the foot's edge last step, as a fraction of what holds it | - |
    | 12 | pivot edge: +1 far, -1 near, 0 resting on the foot | - |
    | 13-18 | last action | - |

    ## Rewards

    Per step, bounded in [-6.2, 11]: `success` +10 when the wall falls away or breaks loose,
    `failure` -5 when it falls toward the thrower, `throw` -0.2 per ball thrown, and `lean`
    = change of `sin(lean)` over the step (so leaning it away pays as it goes). Terms in
    `info["reward_terms"]`.

    ## Starting State

    The wall stands upright at a uniform distance of 4-8 m (v1: 3-5 m); the mean wind is
    uniform in 0-3 m/s from a direction uniform in `wind_from_range` (v0: any; v1: the
    half-turn behind the thrower, so the mean wind never blows against the throw).
    `reset(options=...)` pins `wind` ((x, y) m/s, where the air moves), `wall_distance`
    (m), `gusts` (bool). Unknown keys raise `TypeError`.

    ## Episode End

    Terminated when the wall is down (either way) or loose, or after the 8th step.
    Registered with `max_episode_steps=100`, which the default 8 steps never reach.
    {args}
    ## Info

    `wall_angle` (rad, + away from the thrower), `wall_angular_velocity`, `wall_state`
    (`"standing"`, `"fallen_away"`, `"fallen_toward"`, `"loose"`), `wall_stress`, `hits`,
    `throws` (balls thrown, not waits), `throws_left`, `is_success`, `reward_terms`,
    `windsock`, and the last step's samples every 0.05 s of its interval: `ball_trajectory`
    (`(C, 3)`, m), `ball_orientations` (`(C, 4)` quaternions w, x, y, z),
    `wall_angle_samples` (`(C,)`, rad), `loose_samples` (`(C, 3)`: loose panel x, z,
    angle) with `loose_mask` (`(C,)`, true once loose), and their lengths:
    `samples_length` (`K`, an int: the rows recorded of the wall's and panel's samples;
    fewer than `C` where the interval stopped early, the wall down and the ball at rest)
    and `ball_trajectory_length` (the ball's rows: `K`, or 0 for a wait). Their shape is
    fixed, so vector envs stack them: `C` is the task's `record_capacity`
    (`interval / 0.05`: 60 by default); rows past a length repeat the last recorded
    sample, and where none was recorded (after a reset; the ball's after a wait) they are
    zeros (`loose_mask` false): the length says so, and every info float stays finite.
    `info["wall_angle_samples"][:info["samples_length"]]` is
    the interval. The same keys and types follow a reset and a step.

    ## Rendering

    `render_mode="rgb_array"`: `render()` returns the frame of the state now (the end of
    the last step's interval), `(480, 640, 3)` uint8, headless; `render_flight()` the
    frames of the last interval. `"rgb_array_list"` (Gymnasium's convention): `render()`
    returns the frames since the last `render()` or `reset()`, a list: the reset's, then
    per step its interval (one frame per sample, at `render_fps` = 20 real time) and its
    end; `render()` clears it. `"human"`: a window plays each step's interval in real time.

    ## Version History

    * v0: Initial version.
    * v0, bbgym 0.2.0 (before any release): the ball physics of BeachballThrow-v0 0.2.0;
      loose-panel drag and tumbling implicit; ball hits on the wall as an impulse; a vector
      sub-env stops its interval where the single env does (sub-env ``i`` equals the single
      env seeded ``seed + i`` again); arguments validated with accepted intervals.
    * v0, bbgym 0.3.0: the same dynamics (episodes replay bit for bit,
      ``tests/test_golden_v0.py``) on a functional core; the vector env takes
      ``backend``, ``device``, ``dtype``, ``output``, ``compile`` (torch, compiled).
    * v0, bbgym 0.4.0 (the same dynamics): the samples are fixed-shape, padded, with
      `samples_length` and `ball_trajectory_length` (Gymnasium's vector envs stack them);
      `render_mode="rgb_array_list"`.
    * v1, bbgym 0.5.0: the same physics and spaces, a winnable task distribution. A
      privileged planner (`bbgym.agents.planner.plan_topple`: a beam search through the
      core in the true gusts) wins only 46 of v0's first 100 episodes: in a steady
      headwind of 2 m/s no throw topples the wall even 4 m away (the draggy ball arrives
      slow, and the wind's torque on the face holds the wall back; a lighter wall on a
      deeper foot, as stable in the wind, is no easier), in gusts only a lull lets it
      fall, and walls beyond 6 m fall only to a tailwind.
      v1 puts the wall 3-5 m away (`wall_distance_range=(3, 5)`) in an onshore breeze
      (`wind_from_range=(pi / 2, 3 pi / 2)`, crosswinds included): the planner wins 100 of
      its first 100 episodes, random play 1.
    * v2 (unreleased, after bbgym 0.8.0): v1's scenarios, spaces and rewards, the interval
      stepped another way (`interval_integrator="rk4_events"`, `sim_dt=0.05`): the ball
      and the wall in classical RK4 steps of 0.05 s, the ball's bouncing touchdowns and
      its hit on the wall located inside a step on the step's dense output, the hit's
      impulse given to the wall at its moment (`bbgym.physics.toppling.event_bodies`):
      60 steps an interval instead of 300, and closer to a fine integration than v1's
      substeps (`scripts/topple_accuracy.py`). The planner wins 40 of its first 40
      episodes, the scripted agent 39, random play none (`bbgym evaluate --env
      BeachballTopple-v2 --policies random,scripted,planner --episodes 40`; on v1 40, 40
      and none). It refuses a ball too light for its RK4 step (before the check, it
      ran to NaN: a 0.02 kg/m^2 shell): the error names the ball's mass field and
      `sim_dt` and quotes the bounds; such a ball runs on v2 with a shorter `sim_dt`, or
      on v1 (`bbgym.envs.ball.check_rk4_ball`). Every ball it takes keeps its bits.
    """

    metadata = {"render_modes": ["human", "rgb_array", "rgb_array_list"], "render_fps": 20}
    task_class = ToppleTask

    def _init_host_state(self) -> None:
        self._record_cache: tuple[Any, dict[str, Any]] | None = None

    def _on_reset(self) -> None:
        self.events = None  # a new episode has no samples yet

    def _step_info(self) -> dict[str, Any]:
        """The wall's state by name and the last step's samples."""
        info: dict[str, Any] = {"wall_state": STATE_NAMES[int(self.state.wall.status)]}
        info.update(self._record())
        return info

    def _record(self) -> dict[str, Any]:
        """The last step's samples (made once per step)."""
        if self._record_cache is None or self._record_cache[0] is not self.events:
            task = self.task
            fresh = np.zeros(1, dtype=bool)
            records = step_records(self.events, task.record_every, fresh, task.record_capacity)
            self._record_cache = (self.events, env_record(records))
        return self._record_cache[1]

    def _make_renderer(self) -> Any:
        return make_renderer(self)

    def _scene(self) -> Any:
        return describe_scene(self.task, self.state, self._record())

    def _flight_scenes(self, scene: Any) -> list[Any]:
        # One sample per frame at render_fps = 1 / 0.05 s: real time.
        return flight_scenes(scene)


class BeachballToppleVectorEnv(CoreVectorEnv):
    """Native vector version of :class:`BeachballToppleEnv`: all walls and balls in one
    batch.

    Same task, spaces, arguments, render modes and info keys as the single env (the
    per-step samples, on the NumPy backend only, stack the single env's: ``(n, C, ...)``
    with lengths ``(n,)``, sub-env ``i``'s equal to its), plus the backend keywords
    ``backend``, ``device``, ``dtype``, ``output``, ``compile``,
    ``step_graph``, ``info_keys``; see
    :class:`bbgym.envs.core.CoreVectorEnv` for backends, seeding, autoreset, rendering and
    infos.
    """

    metadata = {**CoreVectorEnv.metadata, "render_fps": 20}
    task_class = ToppleTask

    def _init_host_state(self) -> None:
        self._fresh = np.ones(self.num_envs, dtype=bool)
        self._fresh_events: Any = None

    def _on_reset(self, mask: np.ndarray) -> None:
        # The envs reset since the last transition have no samples of it.
        if self._fresh_events is not self.events:
            self._fresh_events = self.events
            self._fresh = np.zeros(self.num_envs, dtype=bool)
        self._fresh = self._fresh | np.asarray(mask, dtype=bool)

    def _fresh_mask(self) -> np.ndarray:
        if self._fresh_events is self.events:
            return self._fresh
        return np.zeros(self.num_envs, dtype=bool)

    def _step_info(self) -> dict[str, Any]:
        """The walls' states by name and (NumPy) the last step's samples, object arrays."""
        status = np.asarray(backends.to_numpy(self.state.wall.status)).astype(int)
        info: dict[str, Any] = {"wall_state": np.asarray(STATE_NAMES, dtype=object)[status]}
        if self.backend.name == "numpy":
            task = self.task
            info.update(
                step_records(
                    self.events, task.record_every, self._fresh_mask(), task.record_capacity
                )
            )
        return info

    def _vector_info(self, info: dict[str, Any]) -> dict[str, Any]:
        # A reset's info (and the torch step's) has no host entries yet: added here.
        if "wall_state" not in info:
            info = {**info, **self._step_info()}
        return super()._vector_info(info)

    def _make_renderer(self) -> Any:
        return make_renderer(self)

    def _scene_env(self, i: int) -> Any:
        fresh = self._fresh_mask() if self.backend.name == "numpy" else np.ones(self.num_envs, bool)
        task = self.task
        records = step_records(self.events, task.record_every, fresh, task.record_capacity, only=i)
        return describe_scene(task, self.element_state(i), env_record(records))

    def _flight_scenes(self, scene: Any) -> list[Any]:
        return flight_scenes(scene)


BeachballToppleEnv.__doc__ = BeachballToppleEnv.__doc__.replace("{args}", _DOC_ARGS)
