"""BeachballSail-v0 and -v1: sail a dinghy to a mark with rudder and sheet.

The task's functional core (:class:`SailTask`) is pure functions over a batch of
immutable :class:`SailState`: the single env runs it on Python floats, the native vector
env on NumPy or compiled torch (:mod:`bbgym.envs.core`).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces

from bbgym import backends
from bbgym.envs.common import (
    check_multiple,
    check_option_keys,
    option_path,
    renderer_mode,
)
from bbgym.envs.core import CoreEnv, CoreVectorEnv, InitialNoise, TaskCore
from bbgym.physics.backend import Array, floats
from bbgym.physics.common import wrap_angle
from bbgym.physics.sailing import (
    DinghyParams,
    DinghyState,
    StepEvents,
    apparent_wind_body,
    crew_step,
    dinghy_moving,
    sail_force,
    split_along,
    step_begin,
    step_end,
    step_substep,
)
from bbgym.physics.validation import (
    ANGLE_RAD,
    build_params,
    check_bool,
    check_norm,
    check_number,
    check_pair,
    check_range,
    interval,
)
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector

RESET_OPTIONS = ("wind_speed", "wind_from", "mark", "heading", "speed", "gusts")
OBS_SIZE = 16
# Scales that bring each observation into roughly [-1, 1]; values beyond are clipped.
WIND_SCALE_MPS = 15.0
BOAT_SPEED_SCALE_MPS = 6.0
YAW_RATE_SCALE_RPS = 1.5
HEEL_RATE_SCALE_RPS = 2.0
# Accepted intervals of the task's arguments and reset options (README, "Validation and
# errors"). The physics is stable for any boat at any of these (tests/test_sailing_stability.py).
WIND_SPEED_MPS = interval(0.0, 25.0)
"""True wind, mean of an episode: calm to a full gale (50 knots); gusts add to it."""
INITIAL_SPEED_MPS = interval(0.0, 15.0)
"""Boat speed ahead at the start: at rest to a planing skiff's top speed."""
MARK_RADIUS_M = interval(0.0, 100.0, low_open=True)
MARK_DISTANCE_MAX_M = 5000.0
CTRL_DT_S = interval(0.0, 5.0, low_open=True)
SIM_DT_S = interval(1e-3, 0.25)
REWARD_WEIGHT = interval(0.0, 1000.0)
ARGUMENT_TABLE = (
    ("`sail_model`", '`"lift"` or `"seed"`'),
    ("`dinghy`, `gust_params`", "mappings of their fields (tables below), or the dataclass"),
    ("`wind_speed_range`, `options['wind_speed']`", f"{WIND_SPEED_MPS} m/s"),
    ("`initial_speed_range`, `options['speed']`", f"{INITIAL_SPEED_MPS} m/s"),
    ("`mark_radius`", f"{MARK_RADIUS_M} m"),
    (
        "`mark_distance_range`, length of `options['mark']`",
        f"(mark_radius, {MARK_DISTANCE_MAX_M:g}] m",
    ),
    ("`options['wind_from']`, `options['heading']`", f"{ANGLE_RAD} rad"),
    ("`sim_dt`", f"{SIM_DT_S} s"),
    ("`ctrl_dt`", f"{CTRL_DT_S} s, a whole multiple of `sim_dt`"),
    ("`progress_weight`, `arrival_bonus`, `capsize_penalty`, `time_penalty`", f"{REWARD_WEIGHT}"),
    ("`gusts`, `options['gusts']`", "bool"),
)
"""The README's table of this env's arguments and options (a test keeps them equal)."""
# Zoom of the top view: the 4.2 m hull is about 70 px long.
RENDER_PIXELS_PER_M = 16.0


class Scenario(NamedTuple):
    """What an episode is about, per env."""

    wind_speed_mps: Array
    wind_from_rad: Array
    mark_x_m: Array
    mark_y_m: Array
    gusts: Array


class SailState(NamedTuple):
    """Everything an env is, immutable: the boat, the gusts, the scenario, this episode's
    counters and what the last step reported (its reward terms)."""

    boat: DinghyState
    gust: GustState
    scenario: Scenario
    jibes: Array
    tacks: Array
    max_jibe_severity: Array
    last_jibe_severity: Array
    elapsed_s: Array
    arrived: Array
    progress: Array
    arrival: Array
    capsize: Array
    time: Array


REWARD_TERMS = ("progress", "arrival", "capsize", "time")


class SailTask(TaskCore):
    """The sailing task's functional core (see :mod:`bbgym.envs.core`): pure functions
    over a batch of :class:`SailState`, for floats, NumPy and torch alike.

    Holds the validated arguments shared by :class:`BeachballSailEnv` and
    :class:`BeachballSailVectorEnv`; see the env docstring for their meaning.
    """

    initial_noise_counts = (6, 2)
    """Uniform and normal draws per env for :meth:`initial`."""
    step_noise_pairs = 1
    """Pairs of standard normals a transition may use per env (the gusts)."""

    def __init__(
        self,
        sail_model: str = "lift",
        dinghy: Mapping[str, Any] | DinghyParams | None = None,
        wind_speed_range: tuple[float, float] = (3.0, 7.0),
        gusts: bool = True,
        gust_params: Mapping[str, float] | GustParams | None = None,
        mark_distance_range: tuple[float, float] = (40.0, 100.0),
        mark_radius: float = 5.0,
        initial_speed_range: tuple[float, float] = (0.5, 2.0),
        ctrl_dt: float = 0.25,
        sim_dt: float = 0.05,
        progress_weight: float = 1.0,
        arrival_bonus: float = 10.0,
        capsize_penalty: float = 10.0,
        time_penalty: float = 0.01,
    ) -> None:
        self.params = build_params(DinghyParams, "dinghy", dinghy, sail_model=sail_model)
        self.gust_params = build_params(GustParams, "gust_params", gust_params)
        self.wind_speed_range = check_range("wind_speed_range", wind_speed_range, WIND_SPEED_MPS)
        self.gusts = check_bool("gusts", gusts)
        self.mark_radius = check_number("mark_radius", mark_radius, MARK_RADIUS_M)
        # Marks lie outside the arrival circle of the start: the same interval serves the
        # constructor's range and the reset option, so the two always agree.
        self.mark_distance = interval(self.mark_radius, MARK_DISTANCE_MAX_M, low_open=True)
        self.mark_distance_range = check_range(
            "mark_distance_range", mark_distance_range, self.mark_distance,
            why="a mark lies beyond mark_radius",
        )  # fmt: skip
        self.initial_speed_range = check_range(
            "initial_speed_range", initial_speed_range, INITIAL_SPEED_MPS
        )
        self.ctrl_dt = check_number("ctrl_dt", ctrl_dt, CTRL_DT_S)
        self.sim_dt = check_number("sim_dt", sim_dt, SIM_DT_S)
        self.n_substeps = check_multiple("ctrl_dt", self.ctrl_dt, "sim_dt", self.sim_dt)
        # A compiled backend compiles one chunk of substeps: up to 5 (the default step) in a
        # graph, so a step is few calls yet the graph stays small to compile.
        self.substeps_per_chunk = max(k for k in range(1, 6) if self.n_substeps % k == 0)
        self.progress_weight = check_number("progress_weight", progress_weight, REWARD_WEIGHT)
        self.arrival_bonus = check_number("arrival_bonus", arrival_bonus, REWARD_WEIGHT)
        self.capsize_penalty = check_number("capsize_penalty", capsize_penalty, REWARD_WEIGHT)
        self.time_penalty = check_number("time_penalty", time_penalty, REWARD_WEIGHT)
        # Progress is measured against what a fast boat covers in one step, so the dense
        # term stays within [-1, 1] per step.
        self.progress_scale_m = BOAT_SPEED_SCALE_MPS * self.ctrl_dt
        # Fill the physics' per-step-size caches now, not while torch.compile traces a step
        # (a cache filled during tracing changes the guards and forces a recompile).
        crew_step(self.params, 0.0, 0.0, 0.0, self.sim_dt, floats)

        self.observation_space = spaces.Box(-1.0, 1.0, (OBS_SIZE,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.reward_range = (
            -(self.progress_weight + self.time_penalty + self.capsize_penalty),
            self.progress_weight + self.arrival_bonus,
        )

    # -- scenario ---------------------------------------------------------------------------
    def initial(self, noise: InitialNoise, options: Mapping[str, Any], xp: Any) -> SailState:
        """A fresh episode per env from its draws (``noise.uniform[0..5]``,
        ``noise.normal[0..1]``); checked ``options`` pin any of the draws' results."""
        draws = noise.uniform
        zero = 0.0 * draws[0]

        def pinned(key: str, drawn: Any) -> Any:
            return zero + options[key] if key in options else drawn

        lo, hi = self.wind_speed_range
        wind_speed = pinned("wind_speed", lo + (hi - lo) * draws[0])
        wind_from = pinned("wind_from", 2.0 * math.pi * draws[1])
        if "mark" in options:
            mark_x, mark_y = zero + options["mark"][0], zero + options["mark"][1]
        else:
            d_lo, d_hi = self.mark_distance_range
            distance = d_lo + (d_hi - d_lo) * draws[2]
            bearing = 2.0 * math.pi * draws[3]
            mark_x, mark_y = distance * xp.cos(bearing), distance * xp.sin(bearing)
        heading = pinned("heading", 2.0 * math.pi * draws[4])
        s_lo, s_hi = self.initial_speed_range
        speed = pinned("speed", s_lo + (s_hi - s_lo) * draws[5])
        gusts = xp.full_like(zero, options.get("gusts", self.gusts), dtype=xp.bool)
        # Start with the boom to leeward, where the wind would put it.
        wind_side = xp.sin(wind_from - heading)
        boom = xp.where(
            wind_side >= 0.0, zero - self.params.sheet_min_rad, self.params.sheet_min_rad
        )
        scenario = Scenario(wind_speed, wind_from, mark_x, mark_y, gusts)
        count = xp.zeros_like(zero, dtype=xp.int64)
        return SailState(
            boat=dinghy_moving(heading, speed, boom, xp),
            gust=gust_init(self.gust_params, noise.normal, gusts, xp),
            scenario=scenario,
            jibes=count,
            tacks=count,
            max_jibe_severity=zero,
            last_jibe_severity=zero,
            elapsed_s=zero,
            arrived=zero > 0.0,
            progress=zero,
            arrival=zero,
            capsize=zero,
            time=zero,
        )

    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        """Validate ``reset`` options against the same intervals as the constructor's
        ranges; unknown keys raise ``TypeError``, bad values name ``options[key]``."""
        checked = check_option_keys(options, RESET_OPTIONS)
        accepted = {
            "wind_speed": WIND_SPEED_MPS,
            "speed": INITIAL_SPEED_MPS,
            "wind_from": ANGLE_RAD,
            "heading": ANGLE_RAD,
        }
        for key, value in checked.items():
            path = option_path(key)
            if key == "gusts":
                checked[key] = check_bool(path, value)
            elif key == "mark":
                checked[key] = check_norm(path, check_pair(path, value), self.mark_distance)
            else:
                checked[key] = check_number(path, value, accepted[key])
        return checked

    # -- dynamics ---------------------------------------------------------------------------
    def check_action(self, action: Any, batch: int) -> Any:
        """Validate and clip actions to [-1, 1]: a ``(rudder, sheet)`` tuple of floats for one
        env (``batch == 0``), a float64 ``(batch, 2)`` array for a batch. NaN/inf or a wrong
        shape raise ``ValueError``."""
        try:
            a = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"action must be numeric, got {action!r}") from None
        expected = (2,) if batch == 0 else (batch, 2)
        if a.shape != expected:
            raise ValueError(f"action must have shape {expected}, got {a.shape}")
        if batch == 0:
            rudder, sheet = float(a[0]), float(a[1])
            if not (math.isfinite(rudder) and math.isfinite(sheet)):
                raise ValueError(f"action must be finite, got {action!r}")
            return (min(max(rudder, -1.0), 1.0), min(max(sheet, -1.0), 1.0))
        if not np.isfinite(a).all():
            raise ValueError(f"action must be finite, got {action!r}")
        return np.clip(a, -1.0, 1.0)

    def step_noise_mask(self, state: SailState, xp: Any) -> Any:
        """Which envs draw a pair of normals this step: those with gusts (so an env's
        random stream does not depend on the others)."""
        return state.scenario.gusts

    def wind(self, state: SailState, xp: Any) -> tuple[Array, Array, Array, Array]:
        """True wind now: ``(vx, vy, speed, from)``."""
        sc = state.scenario
        return wind_vector(sc.wind_speed_mps, sc.wind_from_rad, state.gust, xp)

    def begin(
        self, state: SailState, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> tuple:
        """Start a transition: hold rudder and sheet (actions in [-1, 1]: a ``(rudder,
        sheet)`` pair of floats or a ``(batch, 2)`` array) and the wind for ``ctrl_dt``;
        ``noise`` (a pair of standard normals per env) moves the gusts at the end."""
        if xp is floats:
            rudder_action, sheet_action = action
        else:
            rudder_action, sheet_action = action[:, 0], action[:, 1]
        rudder = rudder_action * self.params.rudder_max_rad
        sheet = 0.5 * (sheet_action + 1.0)
        wind_x, wind_y, _, _ = self.wind(state, xp)
        carry = step_begin(self.params, state.boat, rudder, sheet, wind_x, wind_y, xp)
        return (carry, noise[0], noise[1])

    @property
    def chunks(self) -> int:
        """Chunks (:meth:`chunk`) per transition."""
        return self.n_substeps // self.substeps_per_chunk

    stops_early = False

    def chunk(self, carry: tuple, xp: Any) -> tuple:
        """``substeps_per_chunk`` physics substeps."""
        boat = carry[0]
        for _ in range(self.substeps_per_chunk):
            boat = step_substep(self.params, boat, self.sim_dt, xp)
        return (boat, carry[1], carry[2])

    def end(self, state: SailState, carry: tuple, xp: Any) -> tuple[SailState, StepEvents]:
        """Finish a transition: count the tack, move the gusts, score the step."""
        sc = state.scenario
        boat, events = step_end(self.params, state.boat, carry[0], xp)
        noise = (carry[1], carry[2])
        gust = gust_step(state.gust, self.gust_params, self.ctrl_dt, noise, sc.gusts, xp)
        distance_before = xp.hypot(sc.mark_x_m - state.boat.x_m, sc.mark_y_m - state.boat.y_m)
        distance = xp.hypot(sc.mark_x_m - boat.x_m, sc.mark_y_m - boat.y_m)
        capsized = boat.capsized
        arrived = (distance <= self.mark_radius) & xp.logical_not(capsized)
        progress = (distance_before - distance) / self.progress_scale_m
        progress = self.progress_weight * xp.clip(progress, -1.0, 1.0)
        new = SailState(
            boat=boat,
            gust=gust,
            scenario=sc,
            jibes=state.jibes + events.jibes,
            tacks=state.tacks + events.tacks,
            max_jibe_severity=xp.maximum(state.max_jibe_severity, events.jibe_severity_rps),
            last_jibe_severity=events.jibe_severity_rps,
            elapsed_s=state.elapsed_s + self.ctrl_dt,
            arrived=arrived,
            progress=progress,
            arrival=xp.where(arrived, self.arrival_bonus + 0.0 * progress, 0.0),
            capsize=xp.where(capsized, -self.capsize_penalty + 0.0 * progress, 0.0),
            time=0.0 * progress - self.time_penalty,  # same shape as the others
        )
        return new, events

    def reward(self, state: SailState, xp: Any) -> Array:
        """Dense progress toward the mark, arrival bonus, capsize penalty, time cost."""
        return state.progress + state.arrival + state.capsize + state.time

    def terminal(self, state: SailState, xp: Any) -> Array:
        """Arrived at the mark, or capsized."""
        return state.arrived | state.boat.capsized

    def measure(self, state: SailState, xp: Any) -> dict[str, Array]:
        """Physical quantities of the current state (shared by observation and info)."""
        boat, sc = state.boat, state.scenario
        cos_h, sin_h = xp.cos(boat.heading_rad), xp.sin(boat.heading_rad)
        wind_x, wind_y, wind_speed, wind_from = self.wind(state, xp)
        aw_u, aw_v = apparent_wind_body(boat, wind_x, wind_y, cos_h, sin_h)
        surge, sway = split_along(boat.vx_mps, boat.vy_mps, cos_h, sin_h)
        dx, dy = sc.mark_x_m - boat.x_m, sc.mark_y_m - boat.y_m
        distance = xp.hypot(dx, dy)
        return {
            "surge": surge,
            "sway": sway,
            "boat_speed": xp.hypot(boat.vx_mps, boat.vy_mps),
            # Where the wind comes FROM, relative to the bow, counterclockwise (+ = from port).
            "apparent_wind_angle": xp.atan2(-aw_v, -aw_u),
            "apparent_wind_speed": xp.hypot(aw_u, aw_v),
            "true_wind_angle": wrap_angle(wind_from - boat.heading_rad, xp),
            "true_wind_speed": wind_speed,
            "bearing_to_mark": wrap_angle(xp.atan2(dy, dx) - boat.heading_rad, xp),
            "distance_to_mark": distance,
            "vmg_to_mark": (boat.vx_mps * dx + boat.vy_mps * dy) / xp.maximum(distance, 1e-9),
            # Drift angle: positive to port of the course steered.
            "leeway": xp.atan2(sway, xp.maximum(xp.abs(surge), 1e-9)) * xp.sign(surge),
        }

    def observation(self, state: SailState, m: dict, xp: Any) -> tuple:
        """The 16 observation values (unclipped), in the order of the env's table."""
        p, boat = self.params, state.boat
        return (
            xp.cos(m["apparent_wind_angle"]),
            xp.sin(m["apparent_wind_angle"]),
            m["apparent_wind_speed"] / WIND_SCALE_MPS,
            xp.cos(m["true_wind_angle"]),
            xp.sin(m["true_wind_angle"]),
            m["true_wind_speed"] / WIND_SCALE_MPS,
            m["surge"] / BOAT_SPEED_SCALE_MPS,
            m["sway"] / BOAT_SPEED_SCALE_MPS,
            boat.yaw_rate_rps / YAW_RATE_SCALE_RPS,
            boat.heel_rad / p.capsize_heel_rad,
            boat.heel_rate_rps / HEEL_RATE_SCALE_RPS,
            boat.boom_rad / p.sheet_max_rad,
            xp.cos(m["bearing_to_mark"]),
            xp.sin(m["bearing_to_mark"]),
            m["distance_to_mark"] / (2.0 * self.mark_distance_range[1]),
            m["vmg_to_mark"] / BOAT_SPEED_SCALE_MPS,
        )

    def info(self, state: SailState, m: dict, xp: Any) -> dict[str, Any]:
        """Physical quantities: Python scalars for one env, arrays ``(batch,)`` for a batch."""
        boat, sc = state.boat, state.scenario
        if xp is floats:
            pair: Any = np.array
        else:

            def pair(xy: tuple) -> Any:
                return xp.stack(xy, axis=1)

        return {
            "position": pair((boat.x_m, boat.y_m)),
            "velocity": pair((boat.vx_mps, boat.vy_mps)),
            "boat_speed": m["boat_speed"],
            "heading": wrap_angle(boat.heading_rad, xp),
            "true_wind_angle": m["true_wind_angle"],
            "true_wind_speed": m["true_wind_speed"],
            "apparent_wind_angle": m["apparent_wind_angle"],
            "apparent_wind_speed": m["apparent_wind_speed"],
            "heel": boat.heel_rad,
            "leeway": m["leeway"],
            "boom_angle": boat.boom_rad,
            "vmg_to_mark": m["vmg_to_mark"],
            "distance_to_mark": m["distance_to_mark"],
            "mark": pair((sc.mark_x_m, sc.mark_y_m)),
            "jibes": state.jibes,
            "jibe_severity": state.last_jibe_severity,
            "max_jibe_severity": state.max_jibe_severity,
            "tacks": state.tacks,
            "capsized": boat.capsized,
            "elapsed_time": state.elapsed_s,
            "is_success": state.arrived,
            "reward_terms": {k: getattr(state, k) for k in REWARD_TERMS},
        }


_DOC_ARGS = """
    ## Arguments

    All are keyword arguments of ``gym.make("BeachballSail-v0", ...)`` (and of
    ``gym.make_vec``); the defaults are the preset in ``configs/beachball_sail.yaml``.
    ``BeachballSail-v1`` is registered with ``time_penalty=0.1, capsize_penalty=30.0``
    (its preset, ``configs/beachball_sail_v1.yaml``, trains SAC); any argument overrides them.

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"`, `"rgb_array_list"` or `"human"` (see Rendering) |
    | `sail_model` | `"lift"` | sail coefficient model, `"lift"` or `"seed"` (§9 drag formula) |
    | `dinghy` | `None` | mapping of `DinghyParams` fields (mass, sail area, drags, ...) |
    | `wind_speed_range` | `(3.0, 7.0)` | true wind speed drawn per episode, m/s |
    | `gusts` | `True` | gusts and shifts on by default |
    | `gust_params` | `None` | `GustParams` fields (speed std, shift std, time constant) |
    | `mark_distance_range` | `(40.0, 100.0)` | distance of the mark from the start, m |
    | `mark_radius` | `5.0` | arrival radius, m |
    | `initial_speed_range` | `(0.5, 2.0)` | initial speed ahead, m/s |
    | `ctrl_dt` | `0.25` | seconds per env step |
    | `sim_dt` | `0.05` | physics substep, s (`ctrl_dt` must be a multiple) |
    | `progress_weight` | `1.0` | weight of the dense progress term |
    | `arrival_bonus` | `10.0` | reward on arrival |
    | `capsize_penalty` | `10.0` | penalty on capsize |
    | `time_penalty` | `0.01` | cost per step |

    A value of the wrong type raises ``TypeError``, a non-finite or out-of-interval value
    ``ValueError``, each naming the argument (``dinghy.mass_kg``); an unknown argument or
    field raises ``TypeError``. The accepted intervals are in the README ("Validation and
    errors") and in ``ARGUMENT_TABLE`` and the parameter dataclasses.
"""


class BeachballSailEnv(CoreEnv):
    """Sail a dinghy from the start to a mark, in any direction from the wind, upright.

    ## Description

    A Laser-like single-handed dinghy (seed §9) floats on still water in a true wind with
    gusts and shifts. The helmsman steers with the rudder and trims the sail with the
    sheet; the crew hikes automatically. The wind drives the boat through the apparent
    wind on a flat sail; the centreboard resists sideways drift; the side force heels the
    boat, and too much heel capsizes it. A mark lies 40-100 m away in any direction,
    upwind included, so the boat must beat and tack to reach some marks; downwind it may
    have to jibe.

    Conventions: world frame x east, y north, angles counterclockwise from +x in radians;
    `wind_from` is the direction the true wind blows from; body frame x forward, y to port.

    ## Action Space

    `Box(-1, 1, (2,), float32)`; values beyond [-1, 1] are clipped, NaN/inf raise.

    | Num | Action | Min | Max | Physical |
    |-----|--------|-----|-----|----------|
    | 0 | rudder | -1 | 1 | x 30 deg; + turns the bow counterclockwise (to port) going ahead |
    | 1 | sheet | -1 | 1 | -1 fully in (boom out 4 deg at most), +1 out (boom free to 85 deg) |

    ## Observation Space

    `Box(-1, 1, (16,), float32)`, egocentric; angles relative to the bow, counterclockwise
    positive (toward port); each value is clipped to [-1, 1].

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
    `reward_terms`.

    ## Rendering

    `render_mode="rgb_array"`: `render()` returns the frame of the state now, `(480, 640, 3)`
    uint8, headless. `"rgb_array_list"` (Gymnasium's convention): the frames since the last
    `render()` or `reset()`, a list (the reset's and one per step), cleared by `render()`;
    `gymnasium.wrappers.RecordVideo` accepts it. `"human"`: a window shows every reset and
    step at `render_fps` (4, real time).

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
    """

    metadata = {"render_modes": ["human", "rgb_array", "rgb_array_list"], "render_fps": 4}
    task_class = SailTask

    def __init__(self, render_mode: str | None = None, **kwargs: Any) -> None:
        super().__init__(render_mode, **kwargs)
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
        return _make_renderer(self)

    def _scene(self) -> Any:
        return _scene(self.task, self.state, tuple(self._wake), self._last_action)


def _make_renderer(env: Any) -> Any:
    from bbgym.render.sail_view import SailRenderer

    return SailRenderer(
        renderer_mode(env.render_mode),
        pixels_per_meter=RENDER_PIXELS_PER_M,
        render_fps=env.metadata["render_fps"],  # real time: one frame per env step
    )


def _scene(task: SailTask, state: SailState, wake: tuple, action: np.ndarray) -> Any:
    """Drawing description of one env's state, as floats (the renderer does no physics)."""
    from bbgym.render.sail_view import SailScene

    xp = floats
    boat, scenario = state.boat, state.scenario
    jibes, tacks, elapsed = int(state.jibes), int(state.tacks), float(state.elapsed_s)
    p = task.params
    m = task.measure(state, xp)
    wind_x, wind_y, _, _ = task.wind(state, xp)
    cos_h, sin_h = xp.cos(boat.heading_rad), xp.sin(boat.heading_rad)
    aw_u, aw_v = apparent_wind_body(boat, wind_x, wind_y, cos_h, sin_h)
    sail_normal_n = abs(sail_force(p, boat, aw_u, aw_v, xp)[2])
    return SailScene(
        time_s=elapsed,
        position_m=(boat.x_m, boat.y_m),
        heading_rad=boat.heading_rad,
        heel_rad=boat.heel_rad,
        boom_angle_rad=boat.boom_rad,
        rudder_angle_rad=float(action[0]) * p.rudder_max_rad,
        sail_force_n=sail_normal_n,
        sail_luffing=sail_normal_n < 5.0,
        mark_m=(scenario.mark_x_m, scenario.mark_y_m),
        mark_radius_m=task.mark_radius,
        true_wind_mps=(wind_x, wind_y),
        apparent_wind_speed_mps=m["apparent_wind_speed"],
        apparent_wind_angle_rad=m["apparent_wind_angle"],
        boat_speed_mps=m["boat_speed"],
        wake_m=wake,
        capsized=boat.capsized,
        hull_length_m=p.hull_length_m,
        hull_beam_m=p.hull_beam_m,
        boom_length_m=p.boom_length_m,
        jibes=jibes,
        tacks=tacks,
    )


class BeachballSailVectorEnv(CoreVectorEnv):
    """Native vector version of :class:`BeachballSailEnv`: one batched simulation.

    Same task, spaces, arguments and info keys as the single env, plus the backend
    keywords ``backend``, ``device``, ``dtype``, ``output``, ``compile``; see
    :class:`bbgym.envs.core.CoreVectorEnv` for backends, seeding, autoreset and infos.
    """

    metadata = {**CoreVectorEnv.metadata, "render_fps": 4}
    task_class = SailTask
    default_max_episode_steps = 1200

    def __init__(
        self,
        num_envs: int = 1,
        render_mode: str | None = None,
        max_episode_steps: int | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(num_envs, render_mode, max_episode_steps, **kwargs)
        self._wakes = [deque(maxlen=120) for _ in range(self.num_envs)]
        self._last_action = np.zeros((self.num_envs, 2))
        self._wants_reset_hook = render_mode is not None

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
        return _make_renderer(self)

    def _scene_env(self, i: int) -> Any:
        state = self.element_state(i)
        return _scene(self.task, state, tuple(self._wakes[i]), self._last_action[i].copy())


BeachballSailEnv.__doc__ = BeachballSailEnv.__doc__.replace("{args}", _DOC_ARGS)
