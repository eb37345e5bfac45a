"""BeachballThrow-v0 and BeachballCurve-v0: throw a beach ball through wind into a ring.

Each env step is one throw, simulated until the ball rests, leaves the field or time runs
out. The task code (:class:`ThrowTask`) is batched; the single env runs it on Python
floats, the native vector env on NumPy arrays.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np
from gymnasium import spaces

from bbgym.envs.common import (
    NativeVectorEnv,
    SingleEnv,
    TaskSim,
    check_box_action,
    check_option_keys,
    element,
    ensure_renderer,
    mean_wind,
    option_path,
)
from bbgym.physics import backend
from bbgym.physics.ball import BallParams, Screen, ball_at, simulate_throw
from bbgym.physics.validation import (
    build_params,
    check_bool,
    check_integer,
    check_norm,
    check_number,
    check_pair,
    check_range,
    interval,
)
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector

RESET_OPTIONS = ("wind", "target", "gusts", "screen")
OBS_SIZE = 19
DISTANCE_SCALE_M = 10.0
WIND_SCALE_MPS = 5.0
BALL_GUSTS = GustParams(speed_std=0.25, shift_std_rad=math.radians(15.0), time_constant_s=10.0,
                        smoothing_s=2.0)  # fmt: skip
"""Gusts near the ground: stronger and quicker than on open water."""

# Accepted intervals of the ball tasks' arguments and reset options (README, "Validation
# and errors"); BeachballTopple-v0 uses them too.
THROWS_PER_EPISODE = interval(1, 100)
WIND_SPEED_MPS = interval(0.0, 20.0)
"""Mean wind near the ground: calm to a gale (beyond it nobody throws beach balls)."""
TARGET_RADIUS_M = interval(0.0, 10.0, low_open=True)
FIELD_RADIUS_M = interval(0.0, 1000.0, low_open=True)
BEARING_RAD = interval(-math.pi, math.pi)
THROW_INTERVAL_S = interval(0.0, 3600.0, low_open=True)
WINDSOCK_NOISE_MPS = interval(0.0, 10.0)
LAUNCH_SPEED_MPS = interval(0.0, 60.0, low_open=True)
"""Up to a hard-hit football; a beach ball's drag takes most of it within metres."""
LAUNCH_SPIN_RPS = interval(0.0, 500.0, low_open=True)
LAUNCH_HEIGHT_MAX_M = 20.0
SCREEN_SIZE_M = interval(0.0, 100.0, low_open=True)
BALL_SIM_DT_S = interval(1e-4, 0.05)
FLIGHT_TIME_MAX_S = 600.0
MISS_SCALE_M = interval(0.0, 100.0, low_open=True)
REWARD_WEIGHT = interval(0.0, 1000.0)
ARGUMENT_TABLE = (
    ("`ball`, `gust_params`", "mappings of their fields (tables below), or the dataclass"),
    ("`throws_per_episode`", f"int in {THROWS_PER_EPISODE}"),
    ("`target_radius`", f"{TARGET_RADIUS_M} m"),
    ("`field_radius`", f"{FIELD_RADIUS_M} m"),
    (
        "`target_distance_range`, length of `options['target']`",
        "(target_radius, field_radius - target_radius) m",
    ),
    ("`target_bearing_range`", f"{BEARING_RAD} rad"),
    ("`wind_speed_range`, length of `options['wind']`", f"{WIND_SPEED_MPS} m/s"),
    ("`throw_interval`", f"{THROW_INTERVAL_S} s"),
    ("`windsock_noise`", f"{WINDSOCK_NOISE_MPS} m/s"),
    ("`max_speed`", f"{LAUNCH_SPEED_MPS} m/s"),
    ("`max_spin`", f"{LAUNCH_SPIN_RPS} rad/s"),
    ("`launch_height`", f"[ball.radius_m, {LAUNCH_HEIGHT_MAX_M:g}] m"),
    ("`screen_height`, `screen_half_width`", f"{SCREEN_SIZE_M} m"),
    ("`screen_position`", "(0, 1)"),
    ("`sim_dt`", f"{BALL_SIM_DT_S} s"),
    ("`max_flight_time`", f"[10 sim_dt, {FLIGHT_TIME_MAX_S:g}] s"),
    ("`max_roll_time`", f"(0, {FLIGHT_TIME_MAX_S:g}] s"),
    ("`miss_scale`", f"{MISS_SCALE_M} m"),
    ("`hit_bonus`", f"{REWARD_WEIGHT}"),
    ("`gusts`, `screen`, `options['gusts']`, `options['screen']`", "bool"),
)
"""The README's table of the throw envs' arguments and options (a test keeps them equal)."""


@dataclass
class ThrowScenario:
    """Per env (arrays ``(batch,)`` or floats): target, mean wind, screen, gusts."""

    target_x: Any
    target_y: Any
    wind_speed: Any
    wind_from: Any
    gusts: Any
    screen: Any


def launch_from_action(
    action: np.ndarray, max_speed: float, max_spin: float
) -> tuple[np.ndarray, np.ndarray]:
    """Launch velocity and spin ``(..., 3)`` from ``(..., 6)`` actions in [-1, 1]: scaled
    by ``max_speed`` and ``max_spin``, each vector's norm clipped to its limit."""

    def scaled(a: np.ndarray, limit: float) -> np.ndarray:
        v = a * limit
        norm = np.sqrt((v * v).sum(axis=-1, keepdims=True))
        return v * np.minimum(1.0, limit / np.maximum(norm, 1e-12))

    return scaled(action[..., :3], max_speed), scaled(action[..., 3:], max_spin)


class ThrowTask:
    """The throwing task over a batch; see :class:`BeachballThrowEnv` for the arguments."""

    def __init__(
        self,
        ball: Mapping[str, Any] | BallParams | None = None,
        throws_per_episode: int = 3,
        target_distance_range: tuple[float, float] = (3.0, 10.0),
        target_bearing_range: tuple[float, float] = (-math.pi / 4, math.pi / 4),
        target_radius: float = 0.75,
        wind_speed_range: tuple[float, float] = (0.0, 3.0),
        gusts: bool = True,
        gust_params: Mapping[str, float] | GustParams | None = None,
        throw_interval: float = 5.0,
        windsock_noise: float = 0.3,
        max_speed: float = 18.0,
        max_spin: float = 60.0,
        launch_height: float = 1.5,
        screen: bool = False,
        screen_height: float = 8.0,
        screen_half_width: float = 1.0,
        screen_position: float = 0.5,
        sim_dt: float = 0.01,
        max_flight_time: float = 6.0,
        max_roll_time: float = 2.0,
        field_radius: float = 30.0,
        miss_scale: float = 2.0,
        hit_bonus: float = 5.0,
    ) -> None:
        self.ball = build_params(BallParams, "ball", ball)
        self.throws_per_episode = check_integer(
            "throws_per_episode", throws_per_episode, THROWS_PER_EPISODE
        )
        self.target_radius = check_number("target_radius", target_radius, TARGET_RADIUS_M)
        self.field_radius = check_number("field_radius", field_radius, FIELD_RADIUS_M)
        # A target lies outside its own ring around the thrower and with its ring inside the
        # field: one interval for the constructor's range and the reset option alike.
        self.target_distance = interval(
            self.target_radius, self.field_radius - self.target_radius, low_open=True,
            high_open=True,
        )  # fmt: skip
        self.target_distance_range = check_range(
            "target_distance_range", target_distance_range, self.target_distance,
            why="a target lies beyond target_radius, its ring within field_radius",
        )  # fmt: skip
        self.target_bearing_range = check_range(
            "target_bearing_range", target_bearing_range, BEARING_RAD
        )
        self.wind_speed_range = check_range("wind_speed_range", wind_speed_range, WIND_SPEED_MPS)
        self.gusts = check_bool("gusts", gusts)
        self.screen = check_bool("screen", screen)
        self.gust_params = (
            BALL_GUSTS
            if gust_params is None
            else build_params(GustParams, "gust_params", gust_params)
        )
        self.throw_interval = check_number("throw_interval", throw_interval, THROW_INTERVAL_S)
        self.windsock_noise = check_number("windsock_noise", windsock_noise, WINDSOCK_NOISE_MPS)
        self.max_speed = check_number("max_speed", max_speed, LAUNCH_SPEED_MPS)
        self.max_spin = check_number("max_spin", max_spin, LAUNCH_SPIN_RPS)
        self.launch_height = check_number(
            "launch_height", launch_height, interval(self.ball.radius_m, LAUNCH_HEIGHT_MAX_M)
        )
        self.screen_height = check_number("screen_height", screen_height, SCREEN_SIZE_M)
        self.screen_half_width = check_number("screen_half_width", screen_half_width, SCREEN_SIZE_M)
        self.screen_position = check_number(
            "screen_position", screen_position, interval(0.0, 1.0, low_open=True, high_open=True)
        )
        self.sim_dt = check_number("sim_dt", sim_dt, BALL_SIM_DT_S)
        self.max_flight_time = check_number(
            "max_flight_time", max_flight_time, interval(10 * self.sim_dt, FLIGHT_TIME_MAX_S)
        )
        self.max_roll_time = check_number(
            "max_roll_time", max_roll_time, interval(0.0, FLIGHT_TIME_MAX_S, low_open=True)
        )
        self.miss_scale = check_number("miss_scale", miss_scale, MISS_SCALE_M)
        self.hit_bonus = check_number("hit_bonus", hit_bonus, REWARD_WEIGHT)

        self.observation_space = spaces.Box(-1.0, 1.0, (OBS_SIZE,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (6,), np.float32)
        self.reward_range = (0.0, 1.0 + self.hit_bonus)

    # -- scenario ---------------------------------------------------------------------------
    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        """Validate ``reset`` options against the same intervals as the constructor's
        ranges; unknown keys raise ``TypeError``, bad values name ``options[key]``."""
        checked = check_option_keys(options, RESET_OPTIONS)
        for key, value in checked.items():
            path = option_path(key)
            if key in ("gusts", "screen"):
                checked[key] = check_bool(path, value)
            elif key == "wind":
                checked[key] = check_norm(path, check_pair(path, value), WIND_SPEED_MPS)
            else:
                checked[key] = check_norm(path, check_pair(path, value), self.target_distance)
        return checked

    def sample(
        self, rngs: list[np.random.Generator], options: Mapping[str, Any] | None
    ) -> tuple[ThrowScenario, GustState]:
        """Draw target, wind and gust state for each generator."""
        options = self.check_options(options)
        batch = len(rngs)
        draws = np.array([rng.random(4) for rng in rngs]).T
        noise = np.array([rng.standard_normal(2) for rng in rngs]).T
        if "target" in options:
            target_x, target_y = options["target"]
        else:
            d_lo, d_hi = self.target_distance_range
            b_lo, b_hi = self.target_bearing_range
            distance = d_lo + (d_hi - d_lo) * draws[0]
            bearing = b_lo + (b_hi - b_lo) * draws[1]
            target_x, target_y = distance * np.cos(bearing), distance * np.sin(bearing)
        wind_speed, wind_from = mean_wind(options, self.wind_speed_range, draws[2], draws[3])

        def full(value: Any, dtype: Any = np.float64) -> np.ndarray:
            return np.broadcast_to(np.asarray(value, dtype=dtype), (batch,)).copy()

        scenario = ThrowScenario(
            target_x=full(target_x),
            target_y=full(target_y),
            wind_speed=full(wind_speed),
            wind_from=full(wind_from),
            gusts=full(options.get("gusts", self.gusts), bool),
            screen=full(options.get("screen", self.screen), bool),
        )
        return scenario, gust_init(self.gust_params, noise, scenario.gusts)

    def screen_geometry(self, scenario: ThrowScenario, xp: Any = np) -> Screen:
        """The screen stands across the line to the target at ``screen_position`` of it."""
        distance = xp.sqrt(scenario.target_x**2 + scenario.target_y**2)
        ux, uy = scenario.target_x / distance, scenario.target_y / distance
        return Screen(
            center_x=self.screen_position * scenario.target_x,
            center_y=self.screen_position * scenario.target_y,
            along_x=-uy,
            along_y=ux,
            half_width_m=self.screen_half_width,
            height_m=self.screen_height,
            enabled=scenario.screen,
        )

    # -- dynamics ---------------------------------------------------------------------------
    def check_action(self, action: Any, batch: int) -> np.ndarray:
        """Actions as float64 ``(6,)`` or ``(batch, 6)``, clipped to [-1, 1]."""
        return check_box_action(action, 6, batch)

    def launch(self, action: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Launch velocity and spin ``(..., 3)`` from actions: scaled, norms clipped."""
        return launch_from_action(action, self.max_speed, self.max_spin)

    def throw(
        self,
        velocity: np.ndarray,
        spin: np.ndarray,
        scenario: ThrowScenario,
        gust: GustState,
        xp: Any = np,
    ) -> tuple[Any, Any, Any]:
        """Simulate one throw per env; returns ``(result, wind_x, wind_y)``."""
        wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed, scenario.wind_from, gust, xp)
        if xp is np:
            v, w = velocity.T, spin.T
            zero = np.zeros(velocity.shape[0])
        else:
            v, w = (float(c) for c in velocity), (float(c) for c in spin)
            zero = 0.0
        start = ball_at(zero, zero, zero + self.launch_height, *v, *w)
        screen = self.screen_geometry(scenario, xp) if xp.any(scenario.screen) else None
        result = simulate_throw(
            self.ball, start, wind_x, wind_y, screen, self.sim_dt, self.max_flight_time,
            self.max_roll_time, self.field_radius, xp=xp,
        )  # fmt: skip
        return result, wind_x, wind_y

    def score(self, result: Any, scenario: ThrowScenario, xp: Any = np) -> tuple[Any, Any, dict]:
        """Miss distance, hit (first touchdown inside the ring), and reward terms."""
        dx = result.landing_x - scenario.target_x
        dy = result.landing_y - scenario.target_y
        miss = xp.sqrt(dx * dx + dy * dy)
        hit = miss <= self.target_radius
        terms = {"closeness": xp.exp(-miss / self.miss_scale), "hit": self.hit_bonus * hit}
        return miss, hit, terms

    def windsock(self, scenario: ThrowScenario, gust: GustState, noise: Any, xp: Any = np) -> Any:
        """What the windsock shows: the wind now plus reading noise."""
        wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed, scenario.wind_from, gust, xp)
        return wind_x + self.windsock_noise * noise[0], wind_y + self.windsock_noise * noise[1]


class _ThrowSim(TaskSim):
    """Task state over a batch (NumPy) or for one env (Python floats), with per-env random
    streams, the last throw's results and episode counters."""

    def _normals(self, mask: np.ndarray) -> np.ndarray:
        """Two standard normals per env where ``mask``, zeros elsewhere: ``(2, batch)``."""
        return self.streams.pairs(mask)

    def _pick(self, noise: np.ndarray) -> Any:
        return (float(noise[0, 0]), float(noise[1, 0])) if self.scalar else noise

    def reset(self, mask: np.ndarray, options: Mapping[str, Any] | None) -> None:
        idx = np.flatnonzero(mask)
        scenario, gust = self.task.sample([self.streams.rngs[i] for i in idx], options)
        self.streams.discard(mask)
        sock_noise = self._normals(mask)
        n = self.batch
        if self.scalar:
            self.scenario, self.gust = element(scenario, 0), element(gust, 0)
            self.throws_left = self.task.throws_per_episode
            self.last = _empty_throw(0)
            self.last_action = np.zeros(6)
        elif self.scenario is None or idx.size == n:
            self.scenario, self.gust = scenario, gust
            self.throws_left = np.full(n, self.task.throws_per_episode)
            self.last = _empty_throw(n)
            self.last_action = np.zeros((n, 6))
        else:
            for old, new in ((self.scenario, scenario), (self.gust, gust)):
                for f in fields(old):
                    getattr(old, f.name)[idx] = getattr(new, f.name)
            self.throws_left[idx] = self.task.throws_per_episode
            for key, value in _empty_throw(idx.size).items():
                if key == "reward_terms":
                    for term, zeros in value.items():
                        self.last[key][term][idx] = zeros
                else:
                    self.last[key][idx] = value
            self.last_action[idx] = 0.0
        if self.scalar or idx.size == n:
            self.sock_noise = sock_noise
        else:
            self.sock_noise[:, idx] = sock_noise[:, idx]
        self._read_windsock()

    def _read_windsock(self) -> None:
        """The windsock now: the wind plus each env's reading noise."""
        noise = self._pick(self.sock_noise)
        self.sock = self.task.windsock(self.scenario, self.gust, noise, self.xp)

    def step(self, action: np.ndarray, active: np.ndarray | None = None) -> tuple[Any, Any]:
        """One throw per env; returns ``(reward, terminated)``."""
        task, xp = self.task, self.xp
        velocity, spin = task.launch(action)
        result, wind_x, wind_y = task.throw(velocity, spin, self.scenario, self.gust, xp)
        miss, hit, terms = task.score(result, self.scenario, xp)
        active = np.ones(self.batch, dtype=bool) if active is None else active
        gust_noise = self._normals(active & np.atleast_1d(self.scenario.gusts))
        self.sock_noise = np.where(active, self._normals(active), self.sock_noise)
        self.gust = gust_step(
            self.gust, task.gust_params, task.throw_interval, self._pick(gust_noise),
            self.scenario.gusts, xp,
        )  # fmt: skip
        self._read_windsock()
        self.throws_left = self.throws_left - 1
        self.last_action = action.copy()
        self.last = _throw_record(result, miss, hit, terms, wind_x, wind_y, self.scalar)
        reward = terms["closeness"] + terms["hit"]
        return reward, hit | (self.throws_left <= 0)

    def observation(self) -> np.ndarray:
        task, sc, last = self.task, self.scenario, self.last
        screen = task.screen_geometry(sc, self.xp)
        thrown = np.asarray(last["thrown"], dtype=np.float64)
        d = DISTANCE_SCALE_M
        columns = [
            np.asarray(sc.target_x) / d,
            np.asarray(sc.target_y) / d,
            np.asarray(self.sock[0]) / WIND_SCALE_MPS,
            np.asarray(self.sock[1]) / WIND_SCALE_MPS,
            thrown * (np.asarray(last["landing_point"])[..., 0] - sc.target_x) / d,
            thrown * (np.asarray(last["landing_point"])[..., 1] - sc.target_y) / d,
            np.asarray(self.throws_left) / task.throws_per_episode,
            thrown,
        ]
        columns += [self.last_action[..., k] for k in range(6)]
        on = np.asarray(sc.screen, dtype=np.float64)
        columns += [
            on,
            on * np.asarray(screen.center_x) / d,
            on * np.asarray(screen.center_y) / d,
            on * task.screen_height / d,
            on * task.screen_half_width / d,
        ]
        stacked = np.stack(columns, axis=-1)
        return np.clip(stacked, -1.0, 1.0).astype(np.float32)

    def info(self) -> dict[str, Any]:
        info = dict(self.last)
        info["throws_left"] = self.throws_left
        info["target"] = _pair(self.scenario.target_x, self.scenario.target_y, self.scalar)
        info["windsock"] = _pair(self.sock[0], self.sock[1], self.scalar)
        return info


def _pair(x: Any, y: Any, scalar: bool) -> np.ndarray:
    return np.array([x, y]) if scalar else np.stack([x, y], axis=1)


def _empty_throw(n: int) -> dict[str, Any]:
    """The ``last`` record before any throw: for a batch of ``n``, or for one env (``n=0``:
    Python scalars, as after a throw)."""
    if n == 0:
        record: dict[str, Any] = {}
        for key, value in _empty_throw(1).items():
            if key == "reward_terms":
                record[key] = {k: 0.0 for k in value}
            elif value.dtype == object or value.ndim == 2:
                record[key] = value[0]
            else:
                record[key] = value[0].item()
        return record
    empty = {
        "thrown": np.zeros(n, dtype=bool),
        "landing_point": np.zeros((n, 2)),
        "miss_distance": np.zeros(n),
        "flight_time": np.zeros(n),
        "apex_height": np.zeros(n),
        "spin_parameter": np.zeros(n),
        "hit_screen": np.zeros(n, dtype=bool),
        "wind": np.zeros((n, 2)),
        "is_success": np.zeros(n, dtype=bool),
        "reward_terms": {"closeness": np.zeros(n), "hit": np.zeros(n)},
        "trajectory": np.empty(n, dtype=object),
        "orientations": np.empty(n, dtype=object),
    }
    for i in range(n):
        empty["trajectory"][i] = np.zeros((0, 3))
        empty["orientations"][i] = np.zeros((0, 4))
    return empty


def _throw_record(
    result: Any, miss: Any, hit: Any, terms: dict, wind_x: Any, wind_y: Any, scalar: bool
) -> dict[str, Any]:
    """What the info reports about a throw (Python scalars for one env, arrays for a batch)."""
    positions = np.array([(s.x, s.y, s.z) for s in result.trajectory], dtype=np.float64)
    quats = np.array([(s.qw, s.qx, s.qy, s.qz) for s in result.trajectory], dtype=np.float64)
    if scalar:
        k = int(result.steps)
        return {
            "thrown": True,
            "landing_point": np.array([result.landing_x, result.landing_y]),
            "miss_distance": float(miss),
            "flight_time": float(result.flight_time_s),
            "apex_height": float(result.apex_height_m),
            "spin_parameter": float(result.spin_parameter),
            "hit_screen": bool(result.hit_screen),
            "wind": np.array([wind_x, wind_y]),
            "is_success": bool(hit),
            "reward_terms": {key: float(v) for key, v in terms.items()},
            "trajectory": positions[:k],
            "orientations": quats[:k],
        }
    n = miss.shape[0]
    trajectory = np.empty(n, dtype=object)
    orientations = np.empty(n, dtype=object)
    for i in range(n):
        k = int(result.steps[i])
        trajectory[i] = positions[:k, :, i]
        orientations[i] = quats[:k, :, i]
    return {
        "thrown": np.ones(n, dtype=bool),
        "landing_point": np.stack([result.landing_x, result.landing_y], axis=1),
        "miss_distance": miss,
        "flight_time": result.flight_time_s,
        "apex_height": result.apex_height_m,
        "spin_parameter": result.spin_parameter,
        "hit_screen": result.hit_screen,
        "wind": np.stack([wind_x, wind_y], axis=1),
        "is_success": hit,
        "reward_terms": {key: np.asarray(v, dtype=np.float64) for key, v in terms.items()},
        "trajectory": trajectory,
        "orientations": orientations,
    }


_DOC_ARGS = """
    ## Arguments

    Keyword arguments of ``gym.make("BeachballThrow-v0", ...)`` and ``gym.make_vec``; the
    defaults are the preset in ``configs/beachball_throw.yaml`` (``BeachballCurve-v0``:
    ``screen=True``).

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"` or `"human"` |
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
    | `sim_dt`, `max_flight_time` | `0.01`, `6.0` | s |
    | `max_roll_time` | `2.0` | s a ball may roll after landing before the throw ends |
    | `field_radius` | `30.0` | m; a ball beyond it is out |
    | `miss_scale`, `hit_bonus` | `2.0`, `5.0` | reward shape |

    A value of the wrong type raises ``TypeError``, a non-finite or out-of-interval value
    ``ValueError``, each naming the argument (``dinghy.mass_kg``); an unknown argument or
    field raises ``TypeError``. The accepted intervals are in the README ("Validation and
    errors") and in ``ARGUMENT_TABLE`` and the parameter dataclasses.
"""


class BeachballThrowEnv(SingleEnv):
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
    little room to curve round the screen).

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
    0-3 m/s from a uniform direction; gusts start from their stationary distribution.
    `reset(options=...)` pins `wind` ((x, y) mean wind vector, m/s, where the air moves),
    `target` ((x, y) m), `gusts` (bool), `screen` (bool). Unknown keys raise `TypeError`.

    ## Episode End

    Terminated after a hit (`info["is_success"]`) or the last throw. Registered with
    `max_episode_steps=100`, which the default 3 throws never reach.
    {args}
    ## Info

    `landing_point` (first touchdown x, y), `miss_distance`, `flight_time` (to the first
    touchdown), `apex_height`, `spin_parameter` (`S = r omega / v` at launch),
    `trajectory` (`(K, 3)` positions every 0.05 s), `orientations` (`(K, 4)` quaternions),
    `hit_screen`, `wind` (the wind during the throw), `windsock`, `target`, `throws_left`,
    `is_success`, `reward_terms`.

    ## Version History

    * v0: Initial version.
    * v0, bbgym 0.2.0 (before any release): ground contact by friction impulses (a ball no
      longer gains energy when it starts to roll), drag and Magnus force integrated
      implicitly (first touchdowns moved by a median 0.12 m, toward the converged answer);
      arguments and options validated with accepted intervals; target ranges must lie
      outside the ring.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 20}
    task_class = ThrowTask
    sim_class = _ThrowSim

    def _on_reset(self) -> None:
        self._landings: list[tuple[float, float]] = []

    def _on_step(self, action: Any) -> None:
        self._landings.append(tuple(self._sim.last["landing_point"]))

    def _make_renderer(self) -> Any:
        return _make_renderer(self)

    def render(self) -> np.ndarray | None:
        renderer = ensure_renderer(self)
        if renderer is None:
            return None
        scene = _scene(self._sim, 0, tuple(self._landings[:-1]))
        if self._animate:
            # Human mode plays a new throw's flight in real time (one recorded point per
            # frame at render_fps = 1 / 0.05 s), then shows where it landed.
            self._animate = False
            for flight_scene in _flight_scenes(scene):
                renderer.render(flight_scene)
        return renderer.render(scene)

    def render_flight(self) -> list[np.ndarray]:
        """The frames of the last throw's flight, one per recorded point (every 0.05 s, so
        ``render_fps`` plays it in real time), without the landing frame that ``render()``
        returns; ``[]`` before the first throw. These are the frames human mode shows
        after a step. In ``rgb_array`` mode: a list of ``(H, W, 3)`` uint8 arrays; in
        ``human`` mode the flight is shown again and the list is empty."""
        renderer = ensure_renderer(self)
        if renderer is None:
            return []
        scene = _scene(self._sim, 0, tuple(self._landings[:-1]))
        frames = [renderer.render(s) for s in _flight_scenes(scene)]
        return [f for f in frames if f is not None]


def _flight_scenes(scene: Any) -> list[Any]:
    """The in-flight frames of a throw's scene: the ball at each recorded point but the
    last, with no landing shown yet."""
    in_flight = replace(scene, landing_m=None, hit=False, miss_distance_m=None)
    return [replace(in_flight, frame_index=k) for k in range(len(scene.trajectory_m) - 1)]


def _make_renderer(env: Any) -> Any:
    from bbgym.render.throw_view import ThrowRenderer

    return ThrowRenderer(env.render_mode, render_fps=env.metadata["render_fps"])


def _scene(sim: _ThrowSim, i: int, previous: tuple) -> Any:
    """Drawing description of env ``i``'s latest throw (no physics in the renderer)."""
    from bbgym.render.throw_view import ThrowScene, ThrowScreen

    task = sim.task
    if sim.scalar:
        scenario, gust, last = sim.scenario, sim.gust, sim.last
        sock, throws_left = sim.sock, sim.throws_left
    else:
        scenario, gust = element(sim.scenario, i), element(sim.gust, i)
        last = {k: (v[i] if k != "reward_terms" else None) for k, v in sim.last.items()}
        sock, throws_left = (sim.sock[0][i], sim.sock[1][i]), int(sim.throws_left[i])
    xp = backend.scalar
    wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed, scenario.wind_from, gust, xp)
    screen = None
    if scenario.screen:
        g = task.screen_geometry(scenario, xp)
        screen = ThrowScreen(
            center_m=(g.center_x, g.center_y),
            along_m=(g.along_x, g.along_y),
            half_width_m=task.screen_half_width,
            height_m=task.screen_height,
        )
    thrown = bool(last["thrown"])
    return ThrowScene(
        trajectory_m=last["trajectory"],
        orientations=last["orientations"],
        ball_radius_m=task.ball.radius_m,
        target_m=(scenario.target_x, scenario.target_y),
        target_radius_m=task.target_radius,
        wind_mps=(wind_x, wind_y),
        windsock_mps=(float(sock[0]), float(sock[1])),
        screen=screen,
        landing_m=tuple(float(c) for c in last["landing_point"]) if thrown else None,
        previous_landings_m=previous,
        hit=bool(last["is_success"]),
        throws_left=int(throws_left),
        throws_total=task.throws_per_episode,
        miss_distance_m=float(last["miss_distance"]) if thrown else None,
        spin_parameter=float(last["spin_parameter"]),
        flight_time_s=float(last["flight_time"]) if thrown else None,
        apex_height_m=float(last["apex_height"]) if thrown else None,
    )


class BeachballThrowVectorEnv(NativeVectorEnv):
    """Native vector version of :class:`BeachballThrowEnv`: all throws fly in one batch.

    Same task, spaces, arguments and info keys as the single env; `trajectory` and
    `orientations` are object arrays of per-env ``(K, 3)`` / ``(K, 4)`` arrays. See
    :class:`bbgym.envs.common.NativeVectorEnv` for seeding, autoreset and infos.
    """

    metadata = {**NativeVectorEnv.metadata, "render_fps": 20}
    task_class = ThrowTask
    sim_class = _ThrowSim
    default_max_episode_steps = 100

    def _make_renderer(self) -> Any:
        return _make_renderer(self)

    def _render_env(self, renderer: Any, i: int) -> np.ndarray | None:
        return renderer.render(_scene(self._sim, i, ()))


BeachballThrowEnv.__doc__ = BeachballThrowEnv.__doc__.replace("{args}", _DOC_ARGS)
