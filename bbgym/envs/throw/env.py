"""BeachballThrow-v0 and BeachballCurve-v0/-v1: the Gymnasium adapters (single and native
vector env) over :class:`~bbgym.envs.throw.task.ThrowTask`, with the docstring tables.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bbgym import backends
from bbgym.envs.core import CoreEnv, CoreVectorEnv, FlightFrames
from bbgym.envs.throw.records import FlightRecords, flight_records
from bbgym.envs.throw.scene import describe_scene, flight_scenes, make_renderer
from bbgym.envs.throw.task import ThrowTask

_DOC_ARGS = """
    ## Arguments

    Keyword arguments of ``gym.make("BeachballThrow-v0", ...)`` and ``gym.make_vec``; the
    defaults are the preset in ``configs/beachball_throw.yaml`` (``BeachballCurve-v0``:
    ``screen=True``, ``target_distance_range=(7.0, 10.0)``; ``BeachballCurve-v1`` also
    ``wind_speed_range=(0.0, 2.0)``; ``BeachballThrow-v1`` and ``BeachballCurve-v2``:
    those of Throw-v0 and Curve-v1 with ``flight_integrator="rk4_events"``,
    ``sim_dt=0.05``).

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"`, `"rgb_array_list"` or `"human"` (see Rendering) |
    | `ball` | `None` | mapping of `BallParams` fields (radius, shell density, C_d, ...) |
    | `throws_per_episode` | `3` | throws at the same target in the same wind |
    | `target_distance_range` | `(3.0, 10.0)` | m from the thrower |
    | `target_bearing_range` | `(-pi/4, pi/4)` | rad, counterclockwise from +x |
    | `target_radius` | `0.75` | ring radius, m |
    | `wind_speed_range` | `(0.0, 3.0)` | mean wind speed, m/s, from any direction |
    | `gusts`, `gust_params` | `True`, `None` | gusts and shifts (`GustParams` fields) |
    | `throw_interval` | `5.0` | s of gusts between two throws |
    | `windsock_noise` | `0.3` | std of the windsock reading per component, m/s |
    | `max_speed` | `18.0` | launch speed at full impulse, m/s (norm clipped) |
    | `max_spin` | `60.0` | spin at full action, rad/s (norm clipped) |
    | `launch_height` | `1.5` | m |
    | `screen` | `False` | a screen between thrower and target |
    | `screen_height`, `screen_half_width` | `8.0`, `1.0` | m |
    | `screen_position` | `0.5` | fraction of the target distance |
    | `flight_integrator` | `"semi_implicit_euler"` | substeps to rest, or `"rk4_events"` |
    | `sim_dt`, `max_flight_time` | `0.01`, `6.0` | s: the substep (RK4: step), longest flight |
    | `max_roll_time` | `2.0` | s a ball may roll after landing before the throw ends |
    | `field_radius` | `30.0` | m; a ball beyond it is out |
    | `miss_scale`, `hit_bonus` | `2.0`, `5.0` | reward shape |

    A value of the wrong type raises ``TypeError``, a non-finite or out-of-interval value
    ``ValueError``, each naming the argument (``dinghy.mass_kg``); an unknown argument or
    field raises ``TypeError``. The accepted intervals are on the documentation's
    "Validation and errors" page, from ``ARGUMENT_TABLE`` and the parameter dataclasses.
"""


class BeachballThrowEnv(FlightFrames, CoreEnv):
    """Throw a beach ball through a gusty wind into a ring on the ground.

    ## Description

    A thrower stands at the origin; a target ring lies on the ground 3-10 m away within
    45 deg of +x. A wind blows from any direction at up to 3 m/s with gusts and shifts. An
    episode is a few throws (3) at the same target; each step is one throw of a 40 cm,
    250 g beach ball, simulated (drag, Magnus force from the spin, bounces, rolling) until
    it rests, leaves the field, has rolled 2 s after landing (a beach ball blown along the
    ground may never stop) or 6 s pass. The agent sees where each throw landed before
    the next, so it can correct for a wind it only senses through a noisy windsock. A
    spinning ball curves: backspin carries it, topspin drops it, side spin bends it.

    With `screen=True` a screen 8 m high and 2 m wide stands across the line halfway to the
    target: too tall to lob over, so only a ball curved around it with side spin can reach
    the ring. `BeachballCurve-v0` is this with targets 7-10 m away (nearer ones leave too
    little room to curve round the screen); `BeachballCurve-v1` also caps the mean wind at
    2 m/s (see Version History).

    `BeachballThrow-v1` and `BeachballCurve-v2` are Throw-v0 and Curve-v1 flown another
    way (`flight_integrator="rk4_events"`): RK4 steps of 0.05 s, the touchdown and the
    screen hits located inside a step as roots of its dense output, and the flight over at
    the first touchdown, which is all a throw is scored on. Their landings are within
    0.001 m (95%) of a 10x finer step where v0's substeps of 0.01 s are within 0.15 m,
    and a throw costs several times less. The bounces and the roll after the touchdown are
    flown for display only (`trajectory`, rendering), and `apex_height` and `hit_screen`
    are those of the flight to the touchdown.

    World frame: x east, y north, z up, metres.

    ## Action Space

    `Box(-1, 1, (6,), float32)`; NaN/inf raise, values beyond [-1, 1] are clipped.

    | Num | Action | Physical |
    |-----|--------|----------|
    | 0-2 | launch impulse x, y, z | x `max_speed` (18 m/s) as launch velocity; norm clipped to it |
    | 3-5 | spin x, y, z | x `max_spin` (60 rad/s), world frame; norm clipped to it |

    Spin about +y on a throw toward +x is topspin; about -y backspin; about +z it curves
    the ball to the left (+y).

    ## Observation Space

    `Box(-1, 1, (19,), float32)`; each value is clipped to [-1, 1].

    | Num | Observation | Scale |
    |-----|-------------|-------|
    | 0-1 | target position x, y | / 10 m |
    | 2-3 | windsock reading x, y (where the air moves, noisy) | / 5 m/s |
    | 4-5 | last landing point relative to the target (0 before the first throw) | / 10 m |
    | 6 | throws left | / throws per episode |
    | 7 | 1 after the first throw, else 0 | - |
    | 8-13 | last action | - |
    | 14 | 1 if a screen stands, else 0 | - |
    | 15-16 | screen centre x, y (0 without screen) | / 10 m |
    | 17 | screen height (0 without screen) | / 10 m |
    | 18 | screen half width (0 without screen) | / 10 m |

    ## Rewards

    Per throw, in [0, 6]: `closeness` = `exp(-miss / 2 m)` for the first touchdown's
    distance from the ring's centre, plus `hit` = 5 when it lands inside the ring (radius
    0.75 m). Terms in `info["reward_terms"]`.

    ## Starting State

    Target distance uniform in 3-10 m, bearing uniform in +-45 deg; mean wind uniform in
    0-3 m/s (Curve-v1: 0-2 m/s) from a uniform direction; gusts start from their
    stationary distribution.
    `reset(options=...)` pins `wind` ((x, y) mean wind vector, m/s, where the air moves),
    `target` ((x, y) m), `gusts` (bool), `screen` (bool). Unknown keys raise `TypeError`.

    ## Episode End

    Terminated after a hit (`info["is_success"]`) or the last throw. Registered with
    `max_episode_steps=100`, which the default 3 throws never reach.
    {args}
    ## Info

    `thrown` (a throw has been made this episode), `landing_point` (first touchdown x, y),
    `miss_distance`, `flight_time` (to the first touchdown), `apex_height`,
    `spin_parameter` (`S = r omega / v` at launch), `hit_screen`, `wind` (the wind during
    the throw), `windsock`, `target`, `throws_left`, `is_success`, `reward_terms`, and the
    last throw's recorded poses, every 0.05 s from the launch: `trajectory` (`(C, 3)`
    positions, m), `orientations` (`(C, 4)` quaternions w, x, y, z) and
    `trajectory_length` (`K`, an int: the rows recorded). Their shape is fixed, so
    vector envs stack them: `C` is the task's `record_capacity`, the most poses a flight
    records (`1 + max_flight_time / 0.05`: 121 by default); rows `K:` repeat the last
    recorded pose (the ball where it stopped), and after a reset (`K = 0`) all rows are zeros.
    With `rk4_events` the poses are one per RK4 step to the touchdown (0.05 s apart but
    for a step cut at a screen hit), then every 0.05 s of the bounces and roll (`C` is
    `1 + max_flight_time / sim_dt + 8 + max_roll_time / 0.05`: 169 by default).
    `info["trajectory"][:info["trajectory_length"]]` is the flight. The same keys and
    types follow a reset and a step.

    ## Rendering

    `render_mode="rgb_array"`: `render()` returns the frame of the state now (the last
    throw's landing), `(480, 640, 3)` uint8, headless; `render_flight()` the frames of the
    last throw's flight. `"rgb_array_list"` (Gymnasium's convention): `render()` returns
    the frames since the last `render()` or `reset()`, a list: the reset's, then per throw
    its flight (one frame per recorded pose but the last, at `render_fps` = 20 real time)
    and its landing; `render()` clears it. `"human"`: a window plays each throw's flight
    in real time, then shows its landing.

    ## Version History

    * v0: Initial version.
    * v0, bbgym 0.2.0 (before any release): ground contact by friction impulses (a ball no
      longer gains energy when it starts to roll), drag and Magnus force integrated
      implicitly (first touchdowns moved by a median 0.12 m, toward the converged answer);
      arguments and options validated with accepted intervals; target ranges must lie
      outside the ring.
    * v0, bbgym 0.3.0: the same dynamics (episodes replay bit for bit,
      ``tests/test_golden_v0.py``) on a functional core; the vector env takes
      ``backend``, ``device``, ``dtype``, ``output``, ``compile`` (torch, compiled).
    * v0, bbgym 0.4.0 (the same dynamics): `trajectory` and `orientations` are
      fixed-shape, padded, with `trajectory_length` (Gymnasium's vector envs stack them);
      `render_mode="rgb_array_list"`.
    * BeachballCurve-v1, bbgym 0.5.0: the same physics and spaces, a winnable task
      distribution. The privileged planner (`bbgym.agents.planner`: each throw solved in
      the true wind, verified on a copy of the env) wins 95 of Curve-v0's first 100
      episodes; the 5 it loses are all far targets (8-10 m) against a headwind of 2.1-2.8
      m/s, where no ball bent round the screen reaches the ring. v1 caps the mean wind at
      2 m/s (`wind_speed_range=(0, 2)`, gusts as before): the planner wins 100 of its
      first 100 episodes, random play none.
    * BeachballThrow-v1 and BeachballCurve-v2 (unreleased, after bbgym 0.8.0): Throw-v0
      and Curve-v1 flown in RK4 steps with event location to the first touchdown
      (Description), with their own golden replays (``tests/throw/test_golden_throw_v1.py``);
      the same spaces, rewards and draws. They refuse a ball too light for the RK4 step
      (before the check, a 0.02 kg/m^2 shell thrown forward landed behind the thrower):
      the error names the ball's mass field and `sim_dt` and quotes the bounds
      (`bbgym.envs.ball.check_rk4_ball`); every ball they take keeps its bits.
    """

    metadata = {"render_modes": ["human", "rgb_array", "rgb_array_list"], "render_fps": 20}
    task_class = ThrowTask

    def _init_host_state(self) -> None:
        self._landings: list[tuple[float, float]] = []
        self._records = flight_records(None, False, self.task.record_capacity)

    def _on_reset(self) -> None:
        self._landings = []
        self._records = flight_records(None, False, self.task.record_capacity)

    def _on_step(self, action: Any) -> None:
        self._landings.append((self.state.landing_x, self.state.landing_y))
        self._records = flight_records(self.events, self.state.thrown, self.task.record_capacity)

    def _step_info(self) -> dict[str, Any]:
        return self._records.info()

    def _make_renderer(self) -> Any:
        return make_renderer(self)

    def _scene(self) -> Any:
        return describe_scene(self.task, self.state, self._records, tuple(self._landings[:-1]))

    def _flight_scenes(self, scene: Any) -> list[Any]:
        # One recorded point per frame at render_fps = 1 / 0.05 s: real time.
        return flight_scenes(scene)


class BeachballThrowVectorEnv(CoreVectorEnv):
    """Native vector version of :class:`BeachballThrowEnv`: all throws fly in one batch.

    Same task, spaces, arguments, render modes and info keys as the single env, plus the
    backend keywords ``backend``, ``device``, ``dtype``, ``output``, ``compile``,
    ``step_graph``, ``info_keys``; see
    :class:`bbgym.envs.core.CoreVectorEnv` for backends, seeding, autoreset, rendering and
    infos. On NumPy, `trajectory` ``(n, C, 3)``, `orientations` ``(n, C, 4)`` and
    `trajectory_length` ``(n,)`` stack the single env's (sub-env ``i``'s equal its): the
    same padding, zeros for a sub-env reset since its last throw. The torch backend does not
    record them (its step stays on the device).
    """

    metadata = {**CoreVectorEnv.metadata, "render_fps": 20}
    task_class = ThrowTask

    def _init_host_state(self) -> None:
        self._records: FlightRecords | None = None

    def _on_reset(self, mask: np.ndarray) -> None:
        self._records = None

    def _on_step(self, actions: Any) -> None:
        self._records = None

    def _flight_records(self) -> FlightRecords:
        """The last throw's records per env (none where reset since, nor on torch), made
        when first asked for after a step."""
        if self._records is None:
            events = self.events if self.backend.name == "numpy" else None
            thrown = np.asarray(backends.to_numpy(self.state.thrown), dtype=bool)
            self._records = flight_records(events, thrown, self.task.record_capacity)
        return self._records

    def _step_info(self) -> dict[str, Any]:
        return self._flight_records().info()

    def _make_renderer(self) -> Any:
        return make_renderer(self)

    def _scene_env(self, i: int) -> Any:
        state = self.element_state(i)
        return describe_scene(self.task, state, self._flight_records().env(i), ())

    def _flight_scenes(self, scene: Any) -> list[Any]:
        return flight_scenes(scene)


BeachballThrowEnv.__doc__ = BeachballThrowEnv.__doc__.replace("{args}", _DOC_ARGS)
