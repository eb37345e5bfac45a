"""BeachballSail-v0, -v1 and -v2: the Gymnasium adapters (single and native vector env) over
:class:`~bbgym.envs.sail.task.SailTask`, with the docstring tables of the spaces.
"""

from __future__ import annotations

from collections import deque
from typing import Any

import numpy as np

from bbgym import backends
from bbgym.envs.core import CoreEnv, CoreVectorEnv
from bbgym.envs.sail.scene import describe_scene, make_renderer
from bbgym.envs.sail.task import SailTask
from bbgym.physics.dinghy import SAIL_MODELS, DinghyParams
from bbgym.physics.validation import choices_text

_DOC_ARGS = """
    ## Arguments

    All are keyword arguments of ``gym.make("BeachballSail-v0", ...)`` (and of
    ``gym.make_vec``); the defaults are the preset in ``configs/beachball_sail.yaml``.
    ``BeachballSail-v1`` is registered with ``time_penalty=0.1, capsize_penalty=30.0``
    (its preset, ``configs/beachball_sail_v1.yaml``, trains SAC); ``BeachballSail-v2`` with
    v1's reward, ``sail_model="cambered"``, the calibrated sloop as ``dinghy``
    (``bbgym.physics.calibration.CALIBRATED_SLOOP``), small waves as ``water`` (0.1 m, 10
    m long, 3 components over 0.5 rad), ``current_speed_range=(0.0, 0.3)`` and
    ``initial_sheet=1.0`` (its preset, ``configs/beachball_sail_v2.yaml``). Any argument
    overrides them; a mapping given as ``dinghy``, ``water`` or ``gust_params`` changes
    only the fields it names (v2 with ``dinghy={"mass_kg": 150}`` is the calibrated sloop,
    150 kg), a dataclass replaces the whole group. ``sail_model`` is a shorthand for
    ``dinghy.sail_model``: given both, they must agree (``ValueError``).

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"`, `"rgb_array_list"` or `"human"` (see Rendering) |
    | `sail_model` | `None` (the dinghy's: `"lift"`) | sail coefficient model, {sail_models} |
    | `dinghy` | `None` | mapping of `DinghyParams` fields (mass, sail area, drags, ...) |
    | `wind_speed_range` | `(3.0, 7.0)` | true wind speed drawn per episode, m/s |
    | `gusts` | `True` | gusts and shifts on by default |
    | `gust_params` | `None` | `GustParams` fields (speed std, shift std, time constant) |
    | `mark_distance_range` | `(40.0, 100.0)` | distance of the mark from the start, m |
    | `mark_radius` | `5.0` | arrival radius, m |
    | `initial_speed_range` | `(0.5, 2.0)` | initial speed ahead, m/s |
    | `initial_sheet` | `0.0` | how far the sheets start eased, 0 (in) .. 1 (out) |
    | `water` | `None` | mapping of `WaterParams` fields (current's variation, waves) |
    | `current_speed_range` | `(0.0, 0.0)` | current's speed drawn per episode, m/s |
    | `ctrl_dt` | `0.25` | seconds per env step |
    | `sim_dt` | `0.05` | physics substep, s (`ctrl_dt` must be a multiple) |
    | `progress_weight` | `1.0` | weight of the dense progress term |
    | `arrival_bonus` | `10.0` | reward on arrival |
    | `capsize_penalty` | `10.0` | penalty on capsize |
    | `time_penalty` | `0.01` | cost per step |

    A value of the wrong type raises ``TypeError``, a non-finite or out-of-interval value
    ``ValueError``, each naming the argument (``dinghy.mass_kg``); an unknown argument or
    field raises ``TypeError``. The accepted intervals are on the documentation's
    "Validation and errors" page, from ``ARGUMENT_TABLE`` and the parameter dataclasses.
""".replace("{sail_models}", choices_text(SAIL_MODELS))


class BeachballSailEnv(CoreEnv):
    """Sail a dinghy from the start to a mark, in any direction from the wind, upright.

    ## Description

    A Laser-like single-handed dinghy (seed §9) floats on still water in a true wind with
    gusts and shifts (v2: a sloop calibrated to a Laser's polar, in a light current and
    small Gerstner waves, seed §10). The helmsman steers with the rudder and trims the sail
    with the sheet (v2: and the jib with its two sheets); the crew hikes automatically. The
    wind drives the boat through the apparent wind on a flat sail; the centreboard resists
    sideways drift; the side force heels the boat, and too much heel capsizes it. A mark
    lies 40-100 m away in any direction, upwind included, so the boat must beat and tack to
    reach some marks; downwind it may have to jibe.

    Conventions: world frame x east, y north, angles counterclockwise from +x in radians;
    `wind_from` is the direction the true wind blows from; body frame x forward, y to port.

    ## Action Space

    `Box(-1, 1, (2,), float32)`, v2 (a sloop) `Box(-1, 1, (3,), float32)`; values beyond
    [-1, 1] are clipped, NaN/inf raise.

    | Num | Action | Min | Max | Physical |
    |-----|--------|-----|-----|----------|
    | 0 | rudder | -1 | 1 | x 30 deg; + turns the bow counterclockwise (to port) going ahead |
    | 1 | sheet | -1 | 1 | -1 fully in (boom out 4 deg at most), +1 out (boom free to 85 deg) |
    | 2 | jib sheets (v2) | -1 | 1 | + pulls the port sheet, - the starboard one, 0 both free |

    The jib has a sheet on each side. Pulled hard (`|a| = 1`) the sheet holds the clew 10
    deg off the centreline on its side, released (`a = 0`) the jib swings free to 60 deg.
    The leeward sheet trims the jib; the windward one backs it, and the wind then pushes
    the bow away from the wind (seed §9: how a sloop stopped head to wind gets going).

    ## Observation Space

    `Box(-1, 1, (16,), float32)`, v2 `Box(-1, 1, (23,), float32)` (columns 16-22 exist when
    the boat is a sloop or the water moves); egocentric; angles relative to the bow,
    counterclockwise positive (toward port); each value is clipped to [-1, 1].

    | Num | Observation | Scale | Range of the physical value |
    |-----|-------------|-------|-----------------------------|
    | 0 | cos of apparent wind angle (where it comes from) | 1 | [-1, 1] |
    | 1 | sin of apparent wind angle | 1 | [-1, 1] |
    | 2 | apparent wind speed | / 15 m/s | [0, 15] m/s |
    | 3 | cos of true wind angle | 1 | [-1, 1] |
    | 4 | sin of true wind angle | 1 | [-1, 1] |
    | 5 | true wind speed | / 15 m/s | [0, 15] m/s |
    | 6 | velocity along the hull (surge) | / 6 m/s | [-6, 6] m/s |
    | 7 | velocity across the hull, to port (sway) | / 6 m/s | [-6, 6] m/s |
    | 8 | yaw rate | / 1.5 rad/s | [-1.5, 1.5] rad/s |
    | 9 | heel, + port side down | / capsize heel (60 deg) | [-60, 60] deg |
    | 10 | heel rate | / 2 rad/s | [-2, 2] rad/s |
    | 11 | boom angle, + swung out to port | / 85 deg | [-85, 85] deg |
    | 12 | cos of bearing to the mark | 1 | [-1, 1] |
    | 13 | sin of bearing to the mark | 1 | [-1, 1] |
    | 14 | distance to the mark | / (2 x largest mark distance) | [0, 200] m |
    | 15 | velocity made good toward the mark | / 6 m/s | [-6, 6] m/s |
    | 16 | jib angle, + clew to port (0 for a cat rig) | / 60 deg | [-60, 60] deg |
    | 17 | water's velocity along the hull (current + waves' orbit) | / 6 m/s | [-6, 6] m/s |
    | 18 | water's velocity across the hull, to port | / 6 m/s | [-6, 6] m/s |
    | 19 | sea's height at the boat | / sum of amplitudes (0.1 m) | [-1, 1] |
    | 20 | sea's rate of rise at the boat (heave) | / sum of A omega | [-1, 1] |
    | 21 | cos of the angle the main wave comes from | 1 | [-1, 1] |
    | 22 | sin of that angle | 1 | [-1, 1] |

    Columns 6-7 are the boat's velocity over the ground; minus 17-18 they give its velocity
    through the water, what the hull, centreboard and rudder feel. 19 and 20 together are
    the phase of the waves under the boat; a flat sea reads 0 in 19-22.

    ## Rewards

    Per step, bounded in [-11.01, 11] (v1: [-31.1, 11]):

    * `progress`: metres gained toward the mark over 1.5 m (6 m/s for 0.25 s), clipped to
      [-1, 1], times `progress_weight`;
    * `arrival`: `+arrival_bonus` (10) on reaching the mark;
    * `capsize`: `-capsize_penalty` (10; v1: 30) on capsizing;
    * `time`: `-time_penalty` (0.01; v1: 0.1) every step.

    Each term is in `info["reward_terms"]`. The progress terms of an episode sum to the
    distance made good whatever the speed, so in v0 only the 0.01 a step and the discount
    pay for sailing fast. In v1 time costs 0.1 a step: a boat making good 1.5 m/s earns
    0.25 a step, so a slow course runs at a loss. A capsize costs 30, more than the time
    left in any episode is worth at a discount of 0.99 (0.1 / (1 - 0.99) = 10).

    ## Starting State

    The boat starts at the origin, upright, heading uniformly random, moving ahead at
    0.5-2 m/s with the sheet in on the leeward side. The true wind blows from a uniformly
    random direction at 3-7 m/s; the mark lies 40-100 m from the start at a uniformly
    random bearing. `reset(options=...)` pins any of: `wind_speed` (m/s), `wind_from`
    (rad), `mark` ((x, y) m relative to the start), `heading` (rad), `speed` (m/s ahead),
    `gusts` (bool). Unknown keys raise `TypeError`.

    In moving water (v2) each episode also draws a current of 0-0.3 m/s toward a uniformly
    random set, waves travelling within 30 deg of the wind's direction and each wave
    component's phase; the options `current_speed` (m/s), `current_set` (rad, where it
    flows to), `wave_direction` (rad, where the main wave travels to) and `wave_phase`
    (rad, every component's) pin them. On still water these options raise `ValueError`.
    v2's boat starts with the sheets eased (`initial_sheet=1.0`): sheeted in on a reach in
    a gust, the boat would capsize before any policy could act.

    ## Episode End

    * Termination: the boat is within `mark_radius` (5 m) of the mark (success,
      `info["is_success"]`), or it capsizes (heel beyond 60 deg).
    * Truncation: 1200 steps (300 s), enough to beat 100 m upwind in light air.
    {args}
    ## Info

    `position`, `velocity` (over ground, m/s), `boat_speed`, `heading`,
    `true_wind_angle`, `true_wind_speed`, `apparent_wind_angle`, `apparent_wind_speed`,
    `heel`, `leeway`, `boom_angle` (rad), `vmg_to_mark`, `distance_to_mark`, `mark`,
    `jibes`, `tacks` (counts this episode), `jibe_severity` (boom angular speed at a jibe
    this step, rad/s), `max_jibe_severity`, `capsized`, `elapsed_time`, `is_success`,
    `reward_terms`; v2 (a sloop or moving water) also `jib_angle` (rad), `water_velocity`
    (the water's velocity at the boat, world frame, m/s) and `wave_height` (m).

    ## Rendering

    `render_mode="rgb_array"`: `render()` returns the frame of the state now, `(480, 640, 3)`
    uint8, headless. `"rgb_array_list"` (Gymnasium's convention): the frames since the last
    `render()` or `reset()`, a list (the reset's and one per step), cleared by `render()`;
    `gymnasium.wrappers.RecordVideo` accepts it. `"human"`: a window shows every reset and
    step at `render_fps` (4, real time). v2 draws the jib, the current as arrows fixed to the
    water's frame and the sea's height (crests light, troughs dark), so the crests travel.

    ## Version History

    * v0: Initial version.
    * v0, bbgym 0.2.0 (before any release; trajectories differ from 0.1.0 within the
      integration error): the stiff terms are integrated implicitly, so every accepted
      boat is stable; by the lee only the boom is blown across (the old push against the air
      created energy), so a crash jibe with the sheet fully eased capsizes the default boat
      from about 13.5 m/s of wind instead of 12; arguments and options are validated with
      accepted intervals (``TypeError``/``ValueError`` naming them). The polar is unchanged.
    * v0, bbgym 0.3.0: the same dynamics (episodes replay bit for bit,
      ``tests/test_golden_v0.py``) on a functional core; the vector env takes
      ``backend``, ``device``, ``dtype``, ``output``, ``compile`` (torch, compiled).
    * v0, bbgym 0.4.0 (the same dynamics): `render_mode="rgb_array_list"`.
    * v1, bbgym 0.6.0: the same boat, wind, marks, spaces and dynamics; the reward charges
      time: `time_penalty=0.1` (v0: 0.01) and `capsize_penalty=30` (v0: 10), the kwargs it
      is registered with. Success and time to the mark mean what they mean in v0.
    * v2 (unreleased, after bbgym 0.8.0): a sloop calibrated to a Laser's polar (cambered
      sails, a planing hull, a jib whose sheets are a third action, sails that steer), a
      light current and small Gerstner waves the hull, centreboard and rudder meet, 7 more
      observations, the sheets eased at the start; v1's reward. v0 and v1 replay as before.
    """

    metadata = {"render_modes": ["human", "rgb_array", "rgb_array_list"], "render_fps": 4}
    task_class = SailTask

    def _init_host_state(self) -> None:
        self._wake: deque[tuple[float, float]] = deque(maxlen=120)
        self._last_action = np.zeros(2)

    @property
    def params(self) -> DinghyParams:
        return self.task.params

    def _on_reset(self) -> None:
        self._wake.clear()
        self._last_action = np.zeros(2)

    def _on_step(self, action: Any) -> None:
        self._last_action = action
        if self.render_mode is not None:
            self._wake.append((self.state.boat.x_m, self.state.boat.y_m))

    def _make_renderer(self) -> Any:
        return make_renderer(self)

    def _scene(self) -> Any:
        return describe_scene(self.task, self.state, tuple(self._wake), self._last_action)


class BeachballSailVectorEnv(CoreVectorEnv):
    """Native vector version of :class:`BeachballSailEnv`: one batched simulation.

    Same task, spaces, arguments and info keys as the single env, plus the backend
    keywords ``backend``, ``device``, ``dtype``, ``output``, ``compile``,
    ``step_graph``, ``info_keys``; see
    :class:`bbgym.envs.core.CoreVectorEnv` for backends, seeding, autoreset and infos.
    """

    metadata = {**CoreVectorEnv.metadata, "render_fps": 4}
    task_class = SailTask

    def _init_host_state(self) -> None:
        self._wakes = [deque(maxlen=120) for _ in range(self.num_envs)]
        self._last_action = np.zeros((self.num_envs, 2))
        self._wants_reset_hook = self.render_mode is not None

    def _on_reset(self, mask: np.ndarray) -> None:
        for i in np.flatnonzero(mask)[:4]:
            self._wakes[i].clear()
        self._last_action[mask] = 0.0

    def _on_step(self, actions: Any) -> None:
        if self.render_mode is not None:
            self._last_action = np.array(backends.to_numpy(actions), dtype=np.float64)
            x = backends.to_numpy(self.state.boat.x_m)
            y = backends.to_numpy(self.state.boat.y_m)
            for i in range(min(self.num_envs, 4)):
                self._wakes[i].append((float(x[i]), float(y[i])))

    def _make_renderer(self) -> Any:
        return make_renderer(self)

    def _scene_env(self, i: int) -> Any:
        state = self.element_state(i)
        return describe_scene(self.task, state, tuple(self._wakes[i]), self._last_action[i].copy())


BeachballSailEnv.__doc__ = BeachballSailEnv.__doc__.replace("{args}", _DOC_ARGS)
