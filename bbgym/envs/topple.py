"""BeachballTopple-v0: bring down a wall standing in gusty wind by throwing beach balls.

Each step is one throw (or a wait) followed by a fixed interval in which the ball flies,
the wind gusts, and hits and wind act on the wall. The task code (:class:`ToppleTask`) is
batched; the single env runs it on Python floats, the native vector env on NumPy.
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
    check_multiple,
    check_option_keys,
    element,
    ensure_renderer,
    mean_wind,
    option_path,
)
from bbgym.envs.throw import (
    BALL_GUSTS,
    BALL_SIM_DT_S,
    LAUNCH_HEIGHT_MAX_M,
    LAUNCH_SPEED_MPS,
    LAUNCH_SPIN_RPS,
    REWARD_WEIGHT,
    THROWS_PER_EPISODE,
    WIND_SPEED_MPS,
    WINDSOCK_NOISE_MPS,
    launch_from_action,
)
from bbgym.physics import backend
from bbgym.physics.ball import BallParams, ball_at, ground_contact
from bbgym.physics.ball import substep as ball_substep
from bbgym.physics.validation import (
    build_params,
    check_bool,
    check_integer,
    check_norm,
    check_number,
    check_pair,
    check_range,
)
from bbgym.physics.validation import interval as span
from bbgym.physics.wall import (
    FALLEN_AWAY,
    FALLEN_TOWARD,
    LOOSE,
    STANDING,
    STATE_NAMES,
    WallParams,
    ball_hits_wall,
    wall_at,
    wall_step,
)
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector

RESET_OPTIONS = ("wind", "wall_distance", "gusts")
OBS_SIZE = 19
RECORD_DT_S = 0.05
# Accepted intervals (README, "Validation and errors"); the rest are shared with the throw envs.
WALL_DISTANCE_MAX_M = 50.0
INTERVAL_S = span(0.0, 60.0, low_open=True)
ARGUMENT_TABLE = (
    ("`wall`, `ball`, `gust_params`", "mappings of their fields (tables below), or the dataclass"),
    ("`throws_per_episode`", f"int in {THROWS_PER_EPISODE}"),
    (
        "`wall_distance_range`, `options['wall_distance']`",
        f"[wall.base_depth_m / 2 + 1, {WALL_DISTANCE_MAX_M:g}] m",
    ),
    ("`wind_speed_range`, length of `options['wind']`", f"{WIND_SPEED_MPS} m/s"),
    ("`windsock_noise`", f"{WINDSOCK_NOISE_MPS} m/s"),
    ("`max_speed`", f"{LAUNCH_SPEED_MPS} m/s"),
    ("`max_spin`", f"{LAUNCH_SPIN_RPS} rad/s"),
    ("`launch_height`", f"[ball.radius_m, {LAUNCH_HEIGHT_MAX_M:g}] m"),
    ("`wait_speed`", "[0, max_speed] m/s"),
    ("`sim_dt`", f"{BALL_SIM_DT_S} s"),
    ("`interval`", f"{INTERVAL_S} s, a whole multiple of `sim_dt`"),
    ("`gust_dt`", "(0, interval] s, a whole multiple of `sim_dt`"),
    ("`success_bonus`, `failure_penalty`, `throw_cost`, `lean_weight`", f"{REWARD_WEIGHT}"),
    ("`gusts`, `options['gusts']`", "bool"),
)
"""The README's table of this env's arguments and options (a test keeps them equal)."""


@dataclass
class ToppleScenario:
    """Per env (arrays ``(batch,)`` or floats): wall distance, mean wind, gusts."""

    wall_distance: Any
    wind_speed: Any
    wind_from: Any
    gusts: Any


class ToppleTask:
    """The toppling task over a batch; see :class:`BeachballToppleEnv` for the arguments."""

    def __init__(
        self,
        wall: Mapping[str, Any] | WallParams | None = None,
        ball: Mapping[str, Any] | BallParams | None = None,
        throws_per_episode: int = 8,
        wall_distance_range: tuple[float, float] = (4.0, 8.0),
        wind_speed_range: tuple[float, float] = (0.0, 3.0),
        gusts: bool = True,
        gust_params: Mapping[str, float] | GustParams | None = None,
        gust_dt: float = 0.25,
        windsock_noise: float = 0.3,
        max_speed: float = 18.0,
        max_spin: float = 60.0,
        launch_height: float = 1.5,
        wait_speed: float = 0.5,
        interval: float = 3.0,
        sim_dt: float = 0.01,
        success_bonus: float = 10.0,
        failure_penalty: float = 5.0,
        throw_cost: float = 0.2,
        lean_weight: float = 1.0,
    ) -> None:
        self.wall = build_params(WallParams, "wall", wall)
        self.ball = build_params(BallParams, "ball", ball)
        self.throws_per_episode = check_integer(
            "throws_per_episode", throws_per_episode, THROWS_PER_EPISODE
        )
        # The wall stands clear of the thrower: one interval for the constructor's range and
        # the reset option alike.
        self.wall_distance = span(self.wall.half_base_m + 1.0, WALL_DISTANCE_MAX_M)
        self.wall_distance_range = check_range(
            "wall_distance_range", wall_distance_range, self.wall_distance,
            why="the wall's foot stands at least 1 m from the thrower",
        )  # fmt: skip
        self.wind_speed_range = check_range("wind_speed_range", wind_speed_range, WIND_SPEED_MPS)
        self.gusts = check_bool("gusts", gusts)
        gust_params = BALL_GUSTS if gust_params is None else gust_params
        self.gust_params = build_params(GustParams, "gust_params", gust_params)
        self.windsock_noise = check_number("windsock_noise", windsock_noise, WINDSOCK_NOISE_MPS)
        self.max_speed = check_number("max_speed", max_speed, LAUNCH_SPEED_MPS)
        self.max_spin = check_number("max_spin", max_spin, LAUNCH_SPIN_RPS)
        self.launch_height = check_number(
            "launch_height", launch_height, span(self.ball.radius_m, LAUNCH_HEIGHT_MAX_M)
        )
        self.wait_speed = check_number("wait_speed", wait_speed, span(0.0, self.max_speed))
        self.sim_dt = check_number("sim_dt", sim_dt, BALL_SIM_DT_S)
        self.interval = check_number("interval", interval, INTERVAL_S)
        self.gust_dt = check_number("gust_dt", gust_dt, span(0.0, self.interval, low_open=True))
        self.n_substeps = check_multiple("interval", self.interval, "sim_dt", self.sim_dt)
        self.gust_every = check_multiple("gust_dt", self.gust_dt, "sim_dt", self.sim_dt)
        self.record_every = max(1, round(RECORD_DT_S / self.sim_dt))
        self.success_bonus = check_number("success_bonus", success_bonus, REWARD_WEIGHT)
        self.failure_penalty = check_number("failure_penalty", failure_penalty, REWARD_WEIGHT)
        self.throw_cost = check_number("throw_cost", throw_cost, REWARD_WEIGHT)
        self.lean_weight = check_number("lean_weight", lean_weight, REWARD_WEIGHT)

        self.observation_space = spaces.Box(-1.0, 1.0, (OBS_SIZE,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (6,), np.float32)
        self.reward_range = (
            -(self.failure_penalty + self.throw_cost + self.lean_weight),
            self.success_bonus + self.lean_weight,
        )

    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        """Validate ``reset`` options against the same intervals as the constructor's
        ranges; unknown keys raise ``TypeError``, bad values name ``options[key]``."""
        checked = check_option_keys(options, RESET_OPTIONS)
        for key, value in checked.items():
            path = option_path(key)
            if key == "gusts":
                checked[key] = check_bool(path, value)
            elif key == "wind":
                checked[key] = check_norm(path, check_pair(path, value), WIND_SPEED_MPS)
            else:
                checked[key] = check_number(path, value, self.wall_distance)
        return checked

    def sample(
        self, rngs: list[np.random.Generator], options: Mapping[str, Any] | None
    ) -> tuple[ToppleScenario, GustState]:
        options = self.check_options(options)
        batch = len(rngs)
        draws = np.array([rng.random(3) for rng in rngs]).T
        noise = np.array([rng.standard_normal(2) for rng in rngs]).T
        d_lo, d_hi = self.wall_distance_range
        distance = options.get("wall_distance", d_lo + (d_hi - d_lo) * draws[0])
        wind_speed, wind_from = mean_wind(options, self.wind_speed_range, draws[1], draws[2])

        def full(value: Any, dtype: Any = np.float64) -> np.ndarray:
            return np.broadcast_to(np.asarray(value, dtype=dtype), (batch,)).copy()

        scenario = ToppleScenario(
            wall_distance=full(distance),
            wind_speed=full(wind_speed),
            wind_from=full(wind_from),
            gusts=full(options.get("gusts", self.gusts), bool),
        )
        return scenario, gust_init(self.gust_params, noise, scenario.gusts)

    def check_action(self, action: Any, batch: int) -> np.ndarray:
        return check_box_action(action, 6, batch)


class _ToppleSim(TaskSim):
    """Task state over a batch (NumPy) or for one env (Python floats), with per-env random
    streams; ``step`` flies the ball and rocks the wall for one interval."""

    def _normals(self, mask: np.ndarray) -> Any:
        """Two standard normals per env where ``mask`` (floats for the single env)."""
        if self.scalar:
            return self.streams.one(bool(mask[0]))
        return self.streams.pairs(mask)

    def reset(self, mask: np.ndarray, options: Mapping[str, Any] | None) -> None:
        idx = np.flatnonzero(mask)
        scenario, gust = self.task.sample([self.streams.rngs[i] for i in idx], options)
        self.streams.discard(mask)
        wall = wall_at(scenario.wall_distance)
        sock = self._normals(mask)
        n = self.batch
        fresh = {
            "throws_left": np.full(idx.size, self.task.throws_per_episode),
            "hits": np.zeros(idx.size, dtype=np.int64),
            "throws": np.zeros(idx.size, dtype=np.int64),
            "last_hit": np.zeros(idx.size),
            "hit_height": np.full(idx.size, -1.0),
            "hit_y": np.zeros(idx.size),
            "last_action": np.zeros((idx.size, 6)),
        }
        if self.scalar:
            self.scenario, self.gust, self.wall = (element(x, 0) for x in (scenario, gust, wall))
            self.counters = {k: v[0].item() if v.ndim == 1 else v[0] for k, v in fresh.items()}
            self.sock_noise = sock
            self.record = _empty_record()
            self.terms = {k: 0.0 for k in ("success", "failure", "throw", "lean")}
        elif self.scenario is None or idx.size == n:
            self.scenario, self.gust, self.wall = scenario, gust, wall
            self.counters = fresh
            self.sock_noise = sock
            self.record = [_empty_record() for _ in range(n)]
            self.terms = {k: np.zeros(n) for k in ("success", "failure", "throw", "lean")}
        else:  # a partial reset builds new states (arrays are never written once made)
            self.scenario, self.gust, self.wall = (
                _scatter(old, idx, new)
                for old, new in ((self.scenario, scenario), (self.gust, gust), (self.wall, wall))
            )
            self.counters = {k: _put(v, idx, fresh[k]) for k, v in self.counters.items()}
            self.sock_noise = np.where(mask, sock, self.sock_noise)
            self.record = [
                _empty_record() if m else r for m, r in zip(mask, self.record, strict=True)
            ]
            self.terms = {k: np.where(mask, 0.0, v) for k, v in self.terms.items()}

    def windsock(self) -> tuple[Any, Any]:
        sc = self.scenario
        wind_x, wind_y, _, _ = wind_vector(sc.wind_speed, sc.wind_from, self.gust, self.xp)
        noise = self.task.windsock_noise
        return wind_x + noise * self.sock_noise[0], wind_y + noise * self.sock_noise[1]

    def step(self, action: np.ndarray, active: np.ndarray | None = None) -> tuple[Any, Any]:
        """Throw (or wait), then run the interval; returns ``(reward, terminated)``."""
        task, xp, p = self.task, self.xp, self.task.ball
        active = np.ones(self.batch, dtype=bool) if active is None else active
        velocity, spin = launch_from_action(action, task.max_speed, task.max_spin)
        speed = np.sqrt((velocity * velocity).sum(axis=-1))
        thrown = speed >= task.wait_speed
        if self.scalar:
            v, w, thrown = [float(c) for c in velocity], [float(c) for c in spin], bool(thrown)
            zero = 0.0
        else:
            v, w = velocity.T, spin.T
            zero = np.zeros(self.batch)
        ball = ball_at(zero, zero, zero + task.launch_height, *v, *w)
        flying = thrown
        # The interval starts with no stress on the foot, in a new state: states are never
        # changed once made, so whoever kept the old one does not see it change.
        wall = replace(self.wall, stress=0.0 * self.wall.stress)
        lean_before = xp.sin(wall.angle)
        hit_height, hit_y = zero - 1.0, zero
        hits = 0 * zero
        sc = self.scenario
        wind_x, wind_y, _, _ = wind_vector(sc.wind_speed, sc.wind_from, self.gust, xp)
        ball_track, wall_track, loose_track = [], [], []
        # An env's interval ends once its wall is down and its ball (if any) has stopped,
        # where the single env breaks out of this loop. A batch freezes each finished env
        # (no substeps, no gust draws from its stream, no samples) until all are done, so
        # sub-env i stays the single env seeded seed + i. Envs not ``active`` (restarting:
        # a reset replaces their state next) start frozen.
        running = True if self.scalar else active
        gusty = active & np.atleast_1d(sc.gusts)
        samples = 0 if self.scalar else np.zeros(self.batch, dtype=np.int64)  # while running
        for i in range(task.n_substeps):
            if i and i % task.gust_every == 0:
                noise = self._normals(gusty & running)
                gust = gust_step(self.gust, task.gust_params, task.gust_dt, noise, sc.gusts, xp)
                self.gust = _select(running, gust, self.gust, xp)
                wind_x, wind_y, _, _ = wind_vector(sc.wind_speed, sc.wind_from, self.gust, xp)
            if i % task.record_every == 0:
                ball_track.append((ball.x, ball.y, ball.z, ball.qw, ball.qx, ball.qy, ball.qz))
                wall_track.append(wall.angle)
                loose_track.append((wall.loose_x, wall.loose_z, wall.loose_angle, wall.status))
                samples = samples + running
            moving = flying & running
            if xp.any(moving):
                moved = ball_substep(p, ball, wind_x, wind_y, task.sim_dt, xp)
                moved, _ = ground_contact(p, moved, task.sim_dt, xp)
                ball = _select(moving, moved, ball, xp)
                # Only a moving ball strikes: one at rest against the face must not change
                # the wall's rate (the single env skips this block then).
                hit_wall, vx, vz, height = ball_hits_wall(
                    task.wall, wall, p.mass_kg, p.radius_m, ball.x, ball.y, ball.z, ball.vx,
                    ball.vz, xp,
                )  # fmt: skip
                wall = _select(moving, hit_wall, wall, xp)
                struck = moving & (height >= 0.0)
                if xp.any(struck):  # rare: skip building a new ball state when none hit
                    vx, vz = xp.where(struck, vx, ball.vx), xp.where(struck, vz, ball.vz)
                    ball = replace(ball, vx=vx, vz=vz)
                hits = hits + struck
                hit_height = xp.where(struck, height, hit_height)
                hit_y = xp.where(struck, ball.y, hit_y)
                resting = (ball.z <= p.radius_m * 1.001) & (
                    ball.vx * ball.vx + ball.vy * ball.vy + ball.vz * ball.vz < 0.01
                )
                flying = flying & xp.logical_not(resting)
            wall = _select(running, wall_step(task.wall, wall, wind_x, task.sim_dt, xp), wall, xp)
            settled = (wall.status != STANDING) & ((wall.status != LOOSE) | wall.landed)
            done = (settled | xp.logical_not(flying)) & (wall.status != STANDING)
            running = running & xp.logical_not(done)
            if not xp.any(running):
                break
        self.wall = wall
        self.sock_noise = _where2(active, self._normals(active), self.sock_noise, self.scalar)

        status = wall.status
        success = (status == FALLEN_AWAY) | (status == LOOSE)
        failure = status == FALLEN_TOWARD
        c = self.counters
        c["throws_left"] = c["throws_left"] - 1
        c["throws"] = c["throws"] + thrown
        c["hits"] = c["hits"] + (hits > 0)
        c["last_hit"] = xp.where(hits > 0, 1.0, xp.where(thrown, -1.0, 0.0))
        c["hit_height"], c["hit_y"] = hit_height, hit_y
        c["last_action"] = action.copy()
        self.terms = {
            "success": task.success_bonus * success,
            "failure": -task.failure_penalty * failure,
            "throw": -task.throw_cost * thrown,
            "lean": task.lean_weight * (xp.sin(wall.angle) - lean_before),
        }
        reward = self.terms["success"] + self.terms["failure"] + self.terms["throw"]
        reward = reward + self.terms["lean"]
        self._keep_record(ball_track, wall_track, loose_track, thrown, samples)
        return reward, success | failure | (c["throws_left"] <= 0)

    def _keep_record(
        self, ball_track: list, wall_track: list, loose_track: list, thrown: Any, samples: Any
    ) -> None:
        """Keep the step's samples (for info and rendering) per env: the first
        ``samples[i]`` rows, those taken while env ``i`` was running."""
        balls = np.array(ball_track, dtype=np.float64)  # (K, 7) or (K, 7, n)
        walls = np.array(wall_track, dtype=np.float64)
        loose = np.array(loose_track, dtype=np.float64)
        if self.scalar:
            self.record = _record(balls, walls, loose, thrown)
            return
        records = list(self.record)
        for i in range(self.batch):
            k = samples[i]
            records[i] = _record(balls[:k, :, i], walls[:k, i], loose[:k, :, i], thrown[i])
        self.record = records

    def observation(self) -> np.ndarray:
        task, sc, wall, c = self.task, self.scenario, self.wall, self.counters
        wp = task.wall
        sock_x, sock_y = self.windsock()
        columns = [
            np.asarray(wall.angle) / (0.5 * math.pi),
            np.asarray(wall.rate) / 2.0,
            np.asarray(sc.wall_distance) / 10.0,
            np.asarray(0.0 * wall.angle + wp.height_m / 5.0),
            np.asarray(0.0 * wall.angle + wp.width_m / 5.0),
            np.asarray(sock_x) / 10.0,
            np.asarray(sock_y) / 10.0,
            np.asarray(c["throws_left"]) / task.throws_per_episode,
            np.asarray(c["last_hit"], dtype=np.float64),
            np.maximum(np.asarray(c["hit_height"]), 0.0) / wp.height_m,
            np.asarray(c["hit_y"]) / (0.5 * wp.width_m),
            np.asarray(wall.stress),
            np.asarray(wall.pivot),
        ]
        columns += [np.asarray(c["last_action"])[..., k] for k in range(6)]
        return np.clip(np.stack(columns, axis=-1), -1.0, 1.0).astype(np.float32)

    def info(self) -> dict[str, Any]:
        wall, c = self.wall, self.counters
        sock = self.windsock()
        names = np.asarray(STATE_NAMES, dtype=object)
        status = np.asarray(wall.status).astype(int)
        success = (status == FALLEN_AWAY) | (status == LOOSE)
        info = {
            "wall_angle": wall.angle,
            "wall_angular_velocity": wall.rate,
            "wall_state": names[status] if not self.scalar else STATE_NAMES[int(status)],
            "wall_stress": wall.stress,
            "hits": c["hits"],
            "throws": c["throws"],
            "throws_left": c["throws_left"],
            "is_success": bool(success) if self.scalar else success,
            "reward_terms": dict(self.terms),
            "windsock": np.array(sock) if self.scalar else np.stack(sock, axis=1),
        }
        for key in _empty_record():
            if self.scalar:
                info[key] = self.record[key]
            else:
                column = np.empty(self.batch, dtype=object)
                for i in range(self.batch):
                    column[i] = self.record[i][key]
                info[key] = column
        if not self.scalar:
            info = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in info.items()}
        return info


_FIELD_NAMES: dict[type, tuple[str, ...]] = {}


def _select(mask: Any, new: Any, old: Any, xp: Any) -> Any:
    """A state with ``new``'s values where ``mask`` (per env) and ``old``'s elsewhere.

    It runs every substep, so it skips the ``where`` for a field that ``new`` took over
    unchanged from ``old`` (the same array: states are never written, so sharing it is
    safe), as ``ball_hits_wall`` does for most of the wall's fields."""
    if xp is not np:
        return new if mask else old
    cls = type(old)
    names = _FIELD_NAMES.get(cls)
    if names is None:
        names = _FIELD_NAMES[cls] = tuple(f.name for f in fields(cls))
    values = []
    for name in names:
        a, b = getattr(new, name), getattr(old, name)
        values.append(b if a is b else np.where(mask, a, b))
    return cls(*values)


def _put(old: np.ndarray, idx: np.ndarray, values: Any) -> np.ndarray:
    """A copy of ``old`` with rows ``idx`` set to ``values``."""
    new = old.copy()
    new[idx] = values
    return new


def _scatter(old: Any, idx: np.ndarray, new: Any) -> Any:
    """A batch dataclass like ``old`` with the envs ``idx`` taken from ``new`` (a batch of
    ``len(idx)``)."""
    return type(old)(
        **{f.name: _put(getattr(old, f.name), idx, getattr(new, f.name)) for f in fields(old)}
    )


def _where2(mask: np.ndarray, new: Any, old: Any, scalar: bool) -> Any:
    if scalar:
        return new if mask[0] else old
    return np.where(mask, new, old)


def _empty_record() -> dict[str, np.ndarray]:
    return {
        "ball_trajectory": np.zeros((0, 3)),
        "ball_orientations": np.zeros((0, 4)),
        "wall_angle_samples": np.zeros(0),
        "loose_samples": np.zeros((0, 3)),
        "loose_mask": np.zeros(0, dtype=bool),
    }


def _record(balls: np.ndarray, walls: np.ndarray, loose: np.ndarray, thrown: Any) -> dict:
    return {
        "ball_trajectory": balls[:, :3] if thrown else np.zeros((0, 3)),
        "ball_orientations": balls[:, 3:] if thrown else np.zeros((0, 4)),
        "wall_angle_samples": walls,
        "loose_samples": loose[:, :3],
        "loose_mask": loose[:, 3] == LOOSE,
    }


_DOC_ARGS = """
    ## Arguments

    Keyword arguments of ``gym.make("BeachballTopple-v0", ...)`` and ``gym.make_vec``; the
    defaults are the preset in ``configs/beachball_topple.yaml``.

    | argument | default | meaning |
    |---|---|---|
    | `render_mode` | `None` | `"rgb_array"` or `"human"` |
    | `wall` | `None` | mapping of `WallParams` fields (height, width, foot, mass, hold, ...) |
    | `ball` | `None` | mapping of `BallParams` fields |
    | `throws_per_episode` | `8` | steps (throws or waits) per episode |
    | `wall_distance_range` | `(4.0, 8.0)` | m along +x |
    | `wind_speed_range` | `(0.0, 3.0)` | mean wind, m/s, from any direction |
    | `gusts`, `gust_params`, `gust_dt` | `True`, `None`, `0.25` | gust renewal period, s |
    | `windsock_noise` | `0.3` | m/s per component |
    | `max_speed`, `max_spin` | `18.0`, `60.0` | launch speed (m/s), spin (rad/s) at full action |
    | `launch_height` | `1.5` | m |
    | `wait_speed` | `0.5` | a launch slower than this (m/s) is a wait: no ball is thrown |
    | `interval` | `3.0` | s simulated per step |
    | `sim_dt` | `0.01` | s |
    | `success_bonus`, `failure_penalty` | `10.0`, `5.0` | |
    | `throw_cost`, `lean_weight` | `0.2`, `1.0` | |

    A value of the wrong type raises ``TypeError``, a non-finite or out-of-interval value
    ``ValueError``, each naming the argument (``dinghy.mass_kg``); an unknown argument or
    field raises ``TypeError``. The accepted intervals are in the README ("Validation and
    errors") and in ``ARGUMENT_TABLE`` and the parameter dataclasses.
"""


class BeachballToppleEnv(SingleEnv):
    """Bring down a wall standing in gusty wind by throwing beach balls at it.

    ## Description

    A light stage-set panel (2.4 m high, 0.7 m wide, 8 kg, on a foot 0.4 m deep) stands
    4-8 m in front of the thrower along +x, its face toward the thrower, in a gusty wind
    from any direction. The wind on its face and the beach balls that hit it rock it about
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

    The wall stands upright at a uniform distance of 4-8 m; the mean wind is uniform in
    0-3 m/s from a uniform direction. `reset(options=...)` pins `wind` ((x, y) m/s, where
    the air moves), `wall_distance` (m), `gusts` (bool). Unknown keys raise `TypeError`.

    ## Episode End

    Terminated when the wall is down (either way) or loose, or after the 8th step.
    Registered with `max_episode_steps=100`, which the default 8 steps never reach.
    {args}
    ## Info

    `wall_angle` (rad, + away from the thrower), `wall_angular_velocity`, `wall_state`
    (`"standing"`, `"fallen_away"`, `"fallen_toward"`, `"loose"`), `wall_stress`, `hits`,
    `throws` (balls thrown, not waits), `throws_left`, `is_success`, `reward_terms`,
    `windsock`, and the last step's samples every 0.05 s: `ball_trajectory`,
    `ball_orientations`, `wall_angle_samples`, `loose_samples` (loose panel x, z, angle)
    with `loose_mask` (true once loose).

    ## Version History

    * v0: Initial version.
    * v0, bbgym 0.2.0 (before any release): the ball physics of BeachballThrow-v0 0.2.0;
      loose-panel drag and tumbling implicit; ball hits on the wall as an impulse; a vector
      sub-env stops its interval where the single env does (sub-env ``i`` equals the single
      env seeded ``seed + i`` again); arguments validated with accepted intervals.
    """

    metadata = {"render_modes": ["human", "rgb_array"], "render_fps": 20}
    task_class = ToppleTask
    sim_class = _ToppleSim

    def _make_renderer(self) -> Any:
        return _make_renderer(self)

    def render(self) -> np.ndarray | None:
        renderer = ensure_renderer(self)
        if renderer is None:
            return None
        scene = _scene(self._sim, 0)
        if self._animate:
            # Human mode plays the step's interval in real time, then shows its end.
            self._animate = False
            for flight_scene in _flight_scenes(scene):
                renderer.render(flight_scene)
        return renderer.render(scene)

    def render_flight(self) -> list[np.ndarray]:
        """The frames of the last step's interval (the ball's flight, the rocking wall), one
        per sample (every 0.05 s, so ``render_fps`` plays it in real time), without the end
        frame that ``render()`` returns; ``[]`` before the first step. These are the frames
        human mode shows after a step. In ``rgb_array`` mode: a list of ``(H, W, 3)`` uint8
        arrays; in ``human`` mode the interval is shown again and the list is empty."""
        renderer = ensure_renderer(self)
        if renderer is None:
            return []
        frames = [renderer.render(s) for s in _flight_scenes(_scene(self._sim, 0))]
        return [f for f in frames if f is not None]


def _flight_scenes(scene: Any) -> list[Any]:
    """The frames of a step's interval: the scene at each sample."""
    return [replace(scene, frame_index=k) for k in range(len(scene.wall_angle_samples))]


def _make_renderer(env: Any) -> Any:
    from bbgym.render.topple_view import ToppleRenderer

    return ToppleRenderer(env.render_mode, render_fps=env.metadata["render_fps"])


def _scene(sim: _ToppleSim, i: int) -> Any:
    """Drawing description of env ``i`` (no physics in the renderer)."""
    from bbgym.render.topple_view import ToppleScene

    task = sim.task
    if sim.scalar:
        sc, gust, wall, record = sim.scenario, sim.gust, sim.wall, sim.record
        counters = sim.counters
        sock_noise = sim.sock_noise
    else:
        sc, gust, wall = (element(x, i) for x in (sim.scenario, sim.gust, sim.wall))
        record = sim.record[i]
        counters = {k: np.asarray(v)[i] for k, v in sim.counters.items()}
        sock_noise = (sim.sock_noise[0][i], sim.sock_noise[1][i])
    xp = backend.scalar
    wind_x, wind_y, _, _ = wind_vector(sc.wind_speed, sc.wind_from, gust, xp)
    noise = task.windsock_noise
    status = int(wall.status)
    hit = float(counters["hit_height"]) >= 0.0 and float(counters["last_hit"]) > 0
    trajectory = record["ball_trajectory"]
    hit_point = None
    if hit:
        height = float(counters["hit_height"])
        hit_point = (sc.wall_distance, float(counters["hit_y"]), height)
    wp = task.wall
    return ToppleScene(
        wall_distance_m=float(sc.wall_distance),
        wall_height_m=wp.height_m,
        wall_width_m=wp.width_m,
        wall_thickness_m=wp.thickness_m,
        base_depth_m=wp.base_depth_m,
        wall_angle_rad=float(wall.angle),
        pivot_side=int(wall.pivot),
        wall_state=STATE_NAMES[status],
        loose_panel=(wall.loose_x, wall.loose_z, wall.loose_angle) if status == LOOSE else None,
        ball_trajectory_m=trajectory,
        ball_orientations=record["ball_orientations"],
        ball_radius_m=task.ball.radius_m,
        wall_angle_samples=record["wall_angle_samples"],
        # The renderer marks samples of an attached wall as NaN rows.
        loose_samples=np.where(record["loose_mask"][:, None], record["loose_samples"], np.nan),
        hit_point_m=hit_point,
        wind_mps=(wind_x, wind_y),
        windsock_mps=(wind_x + noise * sock_noise[0], wind_y + noise * sock_noise[1]),
        throws_left=int(counters["throws_left"]),
        throws_total=task.throws_per_episode,
        hits=int(counters["hits"]),
    )


class BeachballToppleVectorEnv(NativeVectorEnv):
    """Native vector version of :class:`BeachballToppleEnv`: all walls and balls in one
    batch. Same task, spaces, arguments and info keys as the single env (the per-step
    samples are object arrays); see :class:`bbgym.envs.common.NativeVectorEnv`."""

    metadata = {**NativeVectorEnv.metadata, "render_fps": 20}
    task_class = ToppleTask
    sim_class = _ToppleSim
    default_max_episode_steps = 100

    def _make_renderer(self) -> Any:
        return _make_renderer(self)

    def _render_env(self, renderer: Any, i: int) -> np.ndarray | None:
        return renderer.render(_scene(self._sim, i))


BeachballToppleEnv.__doc__ = BeachballToppleEnv.__doc__.replace("{args}", _DOC_ARGS)
