"""BeachballSail-v0: sail a dinghy to a mark with rudder and sheet.

The task code (:class:`SailTask`) is batched: the single env runs a batch of one, the
native vector env a batch of ``num_envs``, through the same functions.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

import numpy as np
from gymnasium import spaces

from bbgym.envs.common import (
    NativeVectorEnv,
    SingleEnv,
    TaskSim,
    check_multiple,
    check_option_keys,
    element,
    ensure_renderer,
    option_path,
)
from bbgym.physics import backend
from bbgym.physics.backend import Array
from bbgym.physics.common import wrap_angle
from bbgym.physics.sailing import (
    DinghyParams,
    DinghyState,
    StepEvents,
    apparent_wind_body,
    dinghy_at_rest,
    sail_force,
    split_along,
    step,
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


@dataclass
class Scenario:
    """What an episode is about, per env (arrays of shape ``(batch,)``)."""

    wind_speed_mps: np.ndarray
    wind_from_rad: np.ndarray
    mark_x_m: np.ndarray
    mark_y_m: np.ndarray
    gusts: np.ndarray


class SailTask:
    """The sailing task over a batch: scenario sampling, transition, observation, reward.

    Holds the arguments shared by :class:`BeachballSailEnv` and
    :class:`BeachballSailVectorEnv`; see the env docstring for their meaning.
    """

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
        self.progress_weight = check_number("progress_weight", progress_weight, REWARD_WEIGHT)
        self.arrival_bonus = check_number("arrival_bonus", arrival_bonus, REWARD_WEIGHT)
        self.capsize_penalty = check_number("capsize_penalty", capsize_penalty, REWARD_WEIGHT)
        self.time_penalty = check_number("time_penalty", time_penalty, REWARD_WEIGHT)
        # Progress is measured against what a fast boat covers in one step, so the dense
        # term stays within [-1, 1] per step.
        self.progress_scale_m = BOAT_SPEED_SCALE_MPS * self.ctrl_dt

        self.observation_space = spaces.Box(-1.0, 1.0, (OBS_SIZE,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.reward_range = (
            -(self.progress_weight + self.time_penalty + self.capsize_penalty),
            self.progress_weight + self.arrival_bonus,
        )

    # -- scenario ---------------------------------------------------------------------------
    def sample(
        self, rngs: list[np.random.Generator], options: Mapping[str, Any] | None
    ) -> tuple[Scenario, DinghyState, GustState]:
        """Draw a scenario and the initial boat and gust state for each generator."""
        options = self.check_options(options)
        batch = len(rngs)
        draws = np.array([rng.random(6) for rng in rngs]).T  # (6, batch), one row per use
        noise = np.array([rng.standard_normal(2) for rng in rngs]).T
        lo, hi = self.wind_speed_range
        wind_speed = options.get("wind_speed", lo + (hi - lo) * draws[0])
        wind_from = options.get("wind_from", 2.0 * math.pi * draws[1])
        if "mark" in options:
            mark_x, mark_y = options["mark"]
        else:
            d_lo, d_hi = self.mark_distance_range
            distance = d_lo + (d_hi - d_lo) * draws[2]
            bearing = 2.0 * math.pi * draws[3]
            mark_x, mark_y = distance * np.cos(bearing), distance * np.sin(bearing)
        heading = options.get("heading", 2.0 * math.pi * draws[4])
        s_lo, s_hi = self.initial_speed_range
        speed = options.get("speed", s_lo + (s_hi - s_lo) * draws[5])
        gusts = np.broadcast_to(options.get("gusts", self.gusts), (batch,)).copy()

        def full(value: Any) -> np.ndarray:
            return np.broadcast_to(np.asarray(value, dtype=np.float64), (batch,)).copy()

        heading = full(heading)
        wind_from = full(wind_from)
        # Start with the boom to leeward, where the wind would put it.
        wind_side = np.sin(wind_from - heading)
        boom = -np.where(wind_side >= 0.0, 1.0, -1.0) * self.params.sheet_min_rad
        scenario = Scenario(
            wind_speed_mps=full(wind_speed),
            wind_from_rad=wind_from,
            mark_x_m=full(mark_x),
            mark_y_m=full(mark_y),
            gusts=gusts.astype(bool),
        )
        boat = dinghy_at_rest(batch, heading_rad=heading, speed_mps=full(speed), boom_rad=boom)
        return scenario, boat, gust_init(self.gust_params, noise, scenario.gusts)

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

    def transition(
        self,
        boat: DinghyState,
        gust: GustState,
        scenario: Scenario,
        rudder_action: Array,
        sheet_action: Array,
        noise: Any,
        xp: Any = np,
    ) -> tuple[DinghyState, GustState, StepEvents]:
        """Hold rudder and sheet (actions in [-1, 1]) for ``ctrl_dt``, then move the gusts."""
        rudder = rudder_action * self.params.rudder_max_rad
        sheet = 0.5 * (sheet_action + 1.0)
        wind_x, wind_y, _, _ = wind_vector(
            scenario.wind_speed_mps, scenario.wind_from_rad, gust, xp
        )
        boat, events = step(
            self.params, boat, rudder, sheet, wind_x, wind_y, self.sim_dt, self.n_substeps, xp
        )
        gust = gust_step(gust, self.gust_params, self.ctrl_dt, noise, scenario.gusts, xp)
        return boat, gust, events

    def measure(
        self, boat: DinghyState, gust: GustState, scenario: Scenario, xp: Any = np
    ) -> dict[str, Array]:
        """Physical quantities of the current state (shared by observation, reward, info)."""
        cos_h, sin_h = xp.cos(boat.heading_rad), xp.sin(boat.heading_rad)
        wind_x, wind_y, wind_speed, wind_from = wind_vector(
            scenario.wind_speed_mps, scenario.wind_from_rad, gust, xp
        )
        aw_u, aw_v = apparent_wind_body(boat, wind_x, wind_y, cos_h, sin_h)
        surge, sway = split_along(boat.vx_mps, boat.vy_mps, cos_h, sin_h)
        dx, dy = scenario.mark_x_m - boat.x_m, scenario.mark_y_m - boat.y_m
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

    def observation_columns(self, boat: DinghyState, m: dict, xp: Any = np) -> tuple:
        """The 16 observation values (unclipped), in the order of the env's table."""
        p = self.params
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

    def reward(
        self, previous_distance: Array, m: dict, arrived: Array, capsized: Array, xp: Any = np
    ) -> tuple[Array, dict[str, Array]]:
        """Dense progress toward the mark, arrival bonus, capsize penalty, time cost."""
        progress = (previous_distance - m["distance_to_mark"]) / self.progress_scale_m
        progress = self.progress_weight * xp.clip(progress, -1.0, 1.0)
        terms = {
            "progress": progress,
            "arrival": self.arrival_bonus * arrived,
            "capsize": -self.capsize_penalty * capsized,
            "time": 0.0 * progress - self.time_penalty,  # same shape as the others
        }
        return terms["progress"] + terms["arrival"] + terms["capsize"] + terms["time"], terms


class _SailSim(TaskSim):
    """Task state over a batch (NumPy arrays) or for one env (Python floats, ``scalar``),
    with per-env random streams and episode counters."""

    boat: DinghyState

    def reset(self, mask: np.ndarray, options: Mapping[str, Any] | None) -> None:
        """Start new episodes where ``mask`` is true."""
        idx = np.flatnonzero(mask)
        scenario, boat, gust = self.task.sample([self.streams.rngs[i] for i in idx], options)
        self.streams.discard(mask)
        if self.scalar:
            self.scenario, self.boat, self.gust = (element(x, 0) for x in (scenario, boat, gust))
            self.jibes = self.tacks = 0
            self.max_jibe_severity = self.elapsed = 0.0
        elif self.scenario is None or idx.size == self.batch:
            self.scenario, self.boat, self.gust = scenario, boat, gust
            self.jibes = np.zeros(self.batch, dtype=np.int64)
            self.tacks = np.zeros(self.batch, dtype=np.int64)
            self.max_jibe_severity = np.zeros(self.batch)
            self.elapsed = np.zeros(self.batch)
        else:
            for name, new in (("scenario", scenario), ("boat", boat), ("gust", gust)):
                old = getattr(self, name)
                for f in fields(old):
                    getattr(old, f.name)[idx] = getattr(new, f.name)
            for counter in (self.jibes, self.tacks, self.max_jibe_severity, self.elapsed):
                counter[idx] = 0
        self.measures = self.task.measure(self.boat, self.gust, self.scenario, self.xp)
        if self.scalar or idx.size == self.batch:
            zero = 0.0 * self.measures["distance_to_mark"]
            self.terms = {k: zero for k in ("progress", "arrival", "capsize", "time")}
            self.last_jibe_severity = zero
            self.arrived = zero > 0.0
        else:  # the other envs keep what their last step reported
            self.terms = {k: np.where(mask, 0.0, v) for k, v in self.terms.items()}
            self.last_jibe_severity = np.where(mask, 0.0, self.last_jibe_severity)
            self.arrived = self.arrived & ~mask

    def _noise(self, active: np.ndarray | None) -> Any:
        """Standard normal pairs for the gusts: only envs with gusts (and still running)
        draw, so an env's random stream does not depend on the others."""
        if self.scalar:
            return self.streams.one(self.scenario.gusts)
        gusts = self.scenario.gusts
        return self.streams.pairs(gusts if active is None else gusts & active)

    def step(self, action: Any, active: np.ndarray | None = None) -> tuple[Any, Any]:
        """Advance by one control step; returns ``(reward, terminated)``."""
        task, xp = self.task, self.xp
        if self.scalar:
            rudder, sheet = action
        else:
            rudder, sheet = action[:, 0], action[:, 1]
        previous_distance = self.measures["distance_to_mark"]
        self.boat, self.gust, events = task.transition(
            self.boat, self.gust, self.scenario, rudder, sheet, self._noise(active), xp
        )
        self.jibes = self.jibes + events.jibes
        self.tacks = self.tacks + events.tacks
        self.last_jibe_severity = events.jibe_severity_rps
        self.max_jibe_severity = xp.maximum(self.max_jibe_severity, events.jibe_severity_rps)
        self.elapsed = self.elapsed + task.ctrl_dt
        self.measures = task.measure(self.boat, self.gust, self.scenario, xp)
        capsized = self.boat.capsized
        arrived = (self.measures["distance_to_mark"] <= task.mark_radius) & xp.logical_not(capsized)
        reward, self.terms = task.reward(previous_distance, self.measures, arrived, capsized, xp)
        self.arrived = arrived
        return reward, arrived | capsized

    def observation(self) -> np.ndarray:
        """Observation(s), float32, clipped to the space's bounds."""
        columns = self.task.observation_columns(self.boat, self.measures, self.xp)
        if self.scalar:  # clip the floats first: one small array, no temporaries
            return np.array([min(max(c, -1.0), 1.0) for c in columns], dtype=np.float32)
        return np.clip(np.stack(columns, axis=1), -1.0, 1.0).astype(np.float32)

    def info(self) -> dict[str, Any]:
        """Physical quantities: Python scalars for one env, arrays ``(batch,)`` for a batch."""
        m, boat, xp = self.measures, self.boat, self.xp
        pair = np.array if self.scalar else (lambda xy: np.stack(xy, axis=1))
        info = {
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
            "mark": pair((self.scenario.mark_x_m, self.scenario.mark_y_m)),
            "jibes": self.jibes,
            "jibe_severity": self.last_jibe_severity,
            "max_jibe_severity": self.max_jibe_severity,
            "tacks": self.tacks,
            "capsized": boat.capsized,
            "elapsed_time": self.elapsed,
            "is_success": self.arrived,
            "reward_terms": dict(self.terms),
        }
        if not self.scalar:
            # Counters are updated in place by resets: hand out copies.
            for key in ("jibes", "tacks", "max_jibe_severity", "capsized", "elapsed_time"):
                info[key] = info[key].copy()
        return info


_DOC_ARGS = """
    ## Arguments

    All are keyword arguments of ``gym.make("BeachballSail-v0", ...)`` (and of
    ``gym.make_vec``); the defaults are the preset in ``configs/beachball_sail.yaml``.

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"` (headless frames) or `"human"` (window) |
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


class BeachballSailEnv(SingleEnv):
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

    Per step, bounded in [-11.01, 11]:

    * `progress`: metres gained toward the mark over 1.5 m (6 m/s for 0.25 s), clipped to
      [-1, 1], times `progress_weight`;
    * `arrival`: `+arrival_bonus` (10) on reaching the mark;
    * `capsize`: `-capsize_penalty` (10) on capsizing;
    * `time`: `-time_penalty` (0.01) every step.

    Each term is in `info["reward_terms"]`.

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

    ## Version History

    * v0: Initial version.
    * v0, bbgym 0.2.0 (before any release; trajectories differ from 0.1.0 within the
      integration error): the stiff terms are integrated implicitly, so every accepted
      boat is stable; by the lee only the boom is blown across (the old push against the air
      created energy), so a crash jibe with the sheet fully eased capsizes the default boat
      from about 13.5 m/s of wind instead of 12; arguments and options are validated with
      accepted intervals (``TypeError``/``ValueError`` naming them). The polar is unchanged.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 4}
    task_class = SailTask
    sim_class = _SailSim

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
            self._wake.append((self._sim.boat.x_m, self._sim.boat.y_m))

    def _make_renderer(self) -> Any:
        return _make_renderer(self)

    def render(self) -> np.ndarray | None:
        renderer = ensure_renderer(self)
        if renderer is None:
            return None
        return renderer.render(_scene(self._sim, 0, tuple(self._wake), self._last_action))


def _make_renderer(env: Any) -> Any:
    from bbgym.render.sail_view import SailRenderer

    return SailRenderer(
        env.render_mode,
        pixels_per_meter=RENDER_PIXELS_PER_M,
        render_fps=env.metadata["render_fps"],  # real time: one frame per env step
    )


def _scene(sim: _SailSim, i: int, wake: tuple, action: np.ndarray) -> Any:
    """Drawing description of env ``i`` (the renderer itself does no physics)."""
    from bbgym.render.sail_view import SailScene

    xp = backend.scalar
    if sim.scalar:
        boat, gust, scenario = sim.boat, sim.gust, sim.scenario
        jibes, tacks, elapsed = sim.jibes, sim.tacks, sim.elapsed
    else:
        boat, gust, scenario = (element(x, i) for x in (sim.boat, sim.gust, sim.scenario))
        jibes, tacks, elapsed = int(sim.jibes[i]), int(sim.tacks[i]), float(sim.elapsed[i])
    p = sim.task.params
    m = sim.task.measure(boat, gust, scenario, xp)
    wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed_mps, scenario.wind_from_rad, gust, xp)
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
        mark_radius_m=sim.task.mark_radius,
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


class BeachballSailVectorEnv(NativeVectorEnv):
    """Native vector version of :class:`BeachballSailEnv`: one batched simulation.

    Same task, spaces, arguments and info keys as the single env; see
    :class:`bbgym.envs.common.NativeVectorEnv` for seeding, autoreset and infos.
    """

    metadata = {**NativeVectorEnv.metadata, "render_fps": 4}
    task_class = SailTask
    sim_class = _SailSim

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

    def _on_reset(self, mask: np.ndarray) -> None:
        for i in np.flatnonzero(mask):
            self._wakes[i].clear()
        self._last_action[mask] = 0.0

    def _on_step(self, actions: np.ndarray) -> None:
        self._last_action = actions
        if self.render_mode is not None:
            for i in range(min(self.num_envs, 4)):
                self._wakes[i].append((float(self._sim.boat.x_m[i]), float(self._sim.boat.y_m[i])))

    def _make_renderer(self) -> Any:
        return _make_renderer(self)

    def _render_env(self, renderer: Any, i: int) -> np.ndarray | None:
        return renderer.render(_scene(self._sim, i, tuple(self._wakes[i]), self._last_action[i]))


BeachballSailEnv.__doc__ = BeachballSailEnv.__doc__.replace("{args}", _DOC_ARGS)
