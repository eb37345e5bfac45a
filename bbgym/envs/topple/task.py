"""The toppling task's functional core: its state, its accepted intervals and the pure
functions of :class:`ToppleTask`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces

from bbgym.envs.ball import (
    BALL_GUSTS,
    BALL_SIM_DT_S,
    LAUNCH_HEIGHT_MAX_M,
    LAUNCH_SPEED_MPS,
    LAUNCH_SPIN_RPS,
    REWARD_WEIGHT,
    THROWS_PER_EPISODE,
    WIND_SPEED_MPS,
    WINDSOCK_NOISE_MPS,
    check_wind_option,
    rk4_task_wind_limit,
)
from bbgym.envs.common import (
    FULL_CIRCLE_RAD,
    check_box_action,
    check_multiple,
    check_option_keys,
    mean_wind,
    option_path,
)
from bbgym.envs.functional import InitialNoise, TaskCore, stack_pair
from bbgym.envs.throw.task import LastAction, launch_columns

# (validation.interval by its module: the constructor's argument `interval` shadows the name)
from bbgym.physics import validation
from bbgym.physics.ball import BallParams, ball_at
from bbgym.physics.namespace import Array, as_float, floats, replaced
from bbgym.physics.toppling import (
    INTEGRATORS,
    IntervalCarry,
    IntervalParams,
    interval_chunk,
    interval_start,
    noise_pair,
    noise_rows,
    run_interval,
)
from bbgym.physics.validation import (
    build_params,
    check_bool,
    check_choice,
    check_integer,
    check_number,
    check_range,
)
from bbgym.physics.wall import (
    FALLEN_AWAY,
    FALLEN_TOWARD,
    LOOSE,
    WallParams,
    WallState,
    wall_at,
)
from bbgym.physics.wind import GustParams, GustState, gust_init, wind_vector

RESET_OPTIONS = ("wind", "wall_distance", "gusts")
OBS_SIZE = 19
RECORD_DT_S = 0.05
COMPILED_CHUNK_SUBSTEPS = 1
"""Substeps per :meth:`ToppleTask.chunk`, the part of the step that torch compiles."""
# Accepted intervals of the toppling task's own arguments (those every ball task takes are
# in bbgym.envs.ball).
WALL_DISTANCE_MAX_M = 50.0
INTERVAL_S = validation.interval(0.0, 60.0, low_open=True)
WIND_FROM_RAD = validation.interval(-2.0 * math.pi, 2.0 * math.pi)
ARGUMENT_TABLE = (
    ("`wall`, `ball`, `gust_params`", "mappings of their fields (tables below), or the dataclass"),
    ("`throws_per_episode`", f"int in {THROWS_PER_EPISODE}"),
    (
        "`wall_distance_range`, `options['wall_distance']`",
        f"[wall.base_depth_m / 2 + 1, {WALL_DISTANCE_MAX_M:g}] m",
    ),
    ("`wind_speed_range`, length of `options['wind']`", f"{WIND_SPEED_MPS} m/s"),
    ("`wind_from_range`", f"{WIND_FROM_RAD} rad, spanning at most 2 pi"),
    ("`windsock_noise`", f"{WINDSOCK_NOISE_MPS} m/s"),
    ("`max_speed`", f"{LAUNCH_SPEED_MPS} m/s"),
    ("`max_spin`", f"{LAUNCH_SPIN_RPS} rad/s"),
    ("`launch_height`", f"[ball.radius_m, {LAUNCH_HEIGHT_MAX_M:g}] m"),
    ("`wait_speed`", "[0, max_speed] m/s"),
    ("`sim_dt`", f"{BALL_SIM_DT_S} s"),
    ("`interval`", f"{INTERVAL_S} s, a whole multiple of `sim_dt`"),
    ("`gust_dt`", "(0, interval] s, a whole multiple of `sim_dt`"),
    ("`interval_integrator`", ", ".join(f"`{name}`" for name in INTEGRATORS)),
    ("`success_bonus`, `failure_penalty`, `throw_cost`, `lean_weight`", f"{REWARD_WEIGHT}"),
    ("`gusts`, `options['gusts']`", "bool"),
)
"""The rows of the documentation's table of accepted arguments and options (the spec
carries it; docs/tables.py renders it and tests/test_validation.py checks the page)."""


class ToppleScenario(NamedTuple):
    """What an episode is about, per env: wall distance, mean wind, gusts."""

    wall_distance: Array
    wind_speed: Array
    wind_from: Array
    gusts: Array


class ToppleState(NamedTuple):
    """Everything an env is, immutable: the scenario, gusts and wall, this episode's
    counters, the windsock's noise, the last action and what the last step reported (its
    hit and reward terms)."""

    scenario: ToppleScenario
    gust: GustState
    wall: WallState
    throws_left: Array
    hits: Array
    throws: Array
    last_hit: Array
    hit_height: Array
    hit_y: Array
    sock_x: Array
    sock_y: Array
    last_action: LastAction
    success: Array
    failure: Array
    throw: Array
    lean: Array


REWARD_TERMS = ("success", "failure", "throw", "lean")


class ToppleCarry(NamedTuple):
    """A transition between its chunks: the interval, its noise rows, the scenario, and
    what :meth:`ToppleTask.end` needs of the throw: its launch speed (not whether a ball
    flies: that is the interval's ``flying`` at the start, and no two of a compiled
    chunk's inputs may be one tensor) and the action."""

    interval: IntervalCarry
    noise: tuple
    scenario: ToppleScenario
    speed: Array
    action: LastAction


class ToppleEvents(NamedTuple):
    """What a transition did, per env: noise pairs used (gusts, then the windsock's), the
    ball thrown, the samples (tuples of :data:`~bbgym.physics.toppling.SAMPLE_FIELDS`,
    ``None`` if not recording) and how many of them were taken while the env ran."""

    noise_used: Array
    thrown: Array
    taken: tuple | None
    samples: Array


class ToppleTask(TaskCore):
    """The toppling task's functional core (see :mod:`bbgym.envs.core`): pure functions
    over a batch of :class:`ToppleState`, for floats, NumPy and torch alike. A transition
    is a throw (:meth:`begin`), the interval in chunks (:meth:`chunk`, stopping early once
    no env runs) and the score (:meth:`end`).

    Holds the validated arguments shared by :class:`BeachballToppleEnv` and
    :class:`BeachballToppleVectorEnv`; see the env docstring for their meaning.
    """

    randomness = "generator"  # its versions' bits, pinned by golden replays

    initial_noise_counts = (3, 2)
    """Uniform draws (wall distance, wind speed, wind direction) and normals (the gusts)."""
    initial_stream_pairs = 1
    """The windsock's first noise pair."""
    stops_early = True

    def __init__(
        self,
        wall: Mapping[str, Any] | WallParams | None = None,
        ball: Mapping[str, Any] | BallParams | None = None,
        throws_per_episode: int = 8,
        wall_distance_range: tuple[float, float] = (4.0, 8.0),
        wind_speed_range: tuple[float, float] = (0.0, 3.0),
        wind_from_range: tuple[float, float] = FULL_CIRCLE_RAD,
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
        interval_integrator: str = "semi_implicit_euler",
        success_bonus: float = 10.0,
        failure_penalty: float = 5.0,
        throw_cost: float = 0.2,
        lean_weight: float = 1.0,
    ) -> None:
        """Validate every argument (the env's docstring says what each means) and derive the
        interval's fixed sizes and the compiled and host chunking. One function on purpose:
        it checks the arguments in order, each against its accepted interval or the one an
        earlier argument sets (``gust_dt`` at most ``interval``), so the first bad argument
        is the one reported."""
        self.wall = build_params(WallParams, "wall", wall)
        self.ball = build_params(BallParams, "ball", ball)
        self.throws_per_episode = check_integer(
            "throws_per_episode", throws_per_episode, THROWS_PER_EPISODE
        )
        # The wall stands clear of the thrower: one interval for the constructor's range and
        # the reset option alike.
        self.wall_distance = validation.interval(self.wall.half_base_m + 1.0, WALL_DISTANCE_MAX_M)
        self.wall_distance_range = check_range(
            "wall_distance_range",
            wall_distance_range,
            self.wall_distance,
            why=f"the wall's foot, half of wall.base_depth_m = {self.wall.base_depth_m:g} m, "
            "stands at least 1 m from the thrower",
        )
        self.wind_speed_range = check_range("wind_speed_range", wind_speed_range, WIND_SPEED_MPS)
        self.wind_from_range = check_range("wind_from_range", wind_from_range, WIND_FROM_RAD)
        # (A turn computed as low + 2 pi may round a hair beyond it: allowed.)
        if self.wind_from_range[1] - self.wind_from_range[0] > FULL_CIRCLE_RAD[1] + 1e-9:
            raise ValueError(
                f"wind_from_range must span at most 2 pi (one turn), got {wind_from_range!r}"
            )
        self.gusts = check_bool("gusts", gusts)
        gust_params = BALL_GUSTS if gust_params is None else gust_params
        self.gust_params = build_params(GustParams, "gust_params", gust_params)
        self.windsock_noise = check_number("windsock_noise", windsock_noise, WINDSOCK_NOISE_MPS)
        self.max_speed = check_number("max_speed", max_speed, LAUNCH_SPEED_MPS)
        self.max_spin = check_number("max_spin", max_spin, LAUNCH_SPIN_RPS)
        self.launch_height = check_number(
            "launch_height",
            launch_height,
            validation.interval(self.ball.radius_m, LAUNCH_HEIGHT_MAX_M),
            why=f"at least ball.radius_m = {self.ball.radius_m:g} m",
        )
        self.wait_speed = check_number(
            "wait_speed",
            wait_speed,
            validation.interval(0.0, self.max_speed),
            why=f"at most max_speed = {self.max_speed:g} m/s",
        )
        self.sim_dt = check_number("sim_dt", sim_dt, BALL_SIM_DT_S)
        self.interval_integrator = check_choice(
            "interval_integrator", interval_integrator, INTEGRATORS
        )
        self.wind_limit = rk4_task_wind_limit(self, "interval_integrator")
        """The strongest mean wind a ``reset`` option may pin (RK4 steps: what the step is
        stable for, :func:`~bbgym.envs.ball.check_rk4_ball`)."""
        self.interval = check_number("interval", interval, INTERVAL_S)
        self.gust_dt = check_number(
            "gust_dt",
            gust_dt,
            validation.interval(0.0, self.interval, low_open=True),
            why=f"at most interval = {self.interval:g} s: pass a longer interval or a shorter "
            "gust_dt",
        )
        self.n_substeps = check_multiple("interval", self.interval, "sim_dt", self.sim_dt)
        self.gust_every = check_multiple("gust_dt", self.gust_dt, "sim_dt", self.sim_dt)
        self.record_every = max(1, round(RECORD_DT_S / self.sim_dt))
        self.record_capacity = -(-self.n_substeps // self.record_every)
        """The most samples a step records (at substeps 0, ``record_every``, ... of the
        interval: 60 by default, 3 s every 0.05 s); the rows of the sample infos."""
        self.success_bonus = check_number("success_bonus", success_bonus, REWARD_WEIGHT)
        self.failure_penalty = check_number("failure_penalty", failure_penalty, REWARD_WEIGHT)
        self.throw_cost = check_number("throw_cost", throw_cost, REWARD_WEIGHT)
        self.lean_weight = check_number("lean_weight", lean_weight, REWARD_WEIGHT)

        self._derive_sizes()

    def _derive_sizes(self) -> None:
        """The spaces, and the interval's fixed sizes and its compiled and host chunking,
        from the checked arguments."""
        self.observation_space = spaces.Box(-1.0, 1.0, (OBS_SIZE,), np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, (6,), np.float32)
        self.reward_range = (
            -(self.failure_penalty + self.throw_cost + self.lean_weight),
            self.success_bonus + self.lean_weight,
        )
        # The compiled step's chunk is one substep (inductor's code for one takes about
        # 30 s to build on 2 CPU cores; a chunk of 25 took 10 minutes and crashed gcc),
        # the host's (floats, NumPy: no compiler) ``gust_every``: one gust update per
        # chunk, at its start (or per sample), each masked test known when tracing.
        self.interval_params = IntervalParams(
            wall=self.wall,
            ball=self.ball,
            gust=self.gust_params,
            sim_dt=self.sim_dt,
            gust_dt=self.gust_dt,
            n_substeps=self.n_substeps,
            gust_every=self.gust_every,
            record_every=self.record_every,
            chunk_substeps=COMPILED_CHUNK_SUBSTEPS,
            integrator=self.interval_integrator,
        )
        ge, re = self.gust_every, self.record_every
        self.host_interval_params = replace(
            self.interval_params, chunk_substeps=ge if ge % re == 0 else re
        )
        self.n_gust_updates = self.interval_params.n_gust_updates
        # A step uses one pair per gust update while the env runs with gusts, then the
        # windsock's next pair: a window of n + 1, of which ``noise_used`` are used.
        self.step_noise_pairs = self.n_gust_updates + 1
        self.chunks = self.interval_params.n_chunks

    # -- scenario ---------------------------------------------------------------------------
    def initial(self, noise: InitialNoise, options: Mapping[str, Any], xp: Any) -> ToppleState:
        """A fresh episode per env from its draws (``noise.uniform[0..2]``,
        ``noise.normal[0..1]``, the windsock's ``noise.stream[0..1]``); checked ``options``
        pin any of the draws' results."""
        draws = noise.uniform
        zero = xp.zeros_like(draws[0])
        d_lo, d_hi = self.wall_distance_range
        if "wall_distance" in options:
            distance = zero + options["wall_distance"]
        else:
            distance = d_lo + (d_hi - d_lo) * draws[0]
        wind_speed, wind_from = mean_wind(
            options, self.wind_speed_range, draws[1], draws[2], self.wind_from_range
        )
        gusts = xp.full_like(zero, options.get("gusts", self.gusts), dtype=xp.bool)
        scenario = ToppleScenario(distance, zero + wind_speed, zero + wind_from, gusts)

        def count(value: int = 0) -> Any:
            return xp.full_like(zero, value, dtype=xp.int64)

        return ToppleState(
            scenario=scenario,
            gust=gust_init(self.gust_params, noise.normal, gusts, xp),
            wall=wall_at(distance, xp),
            throws_left=count(self.throws_per_episode),
            hits=count(),
            throws=count(),
            last_hit=zero,
            hit_height=zero - 1.0,
            hit_y=zero,
            sock_x=zero + noise.stream[0],
            sock_y=zero + noise.stream[1],
            last_action=LastAction(*(zero for _ in range(6))),
            success=zero,
            failure=zero,
            throw=zero,
            lean=zero,
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
                checked[key] = check_wind_option(path, value, self.wind_limit)
            else:
                checked[key] = check_number(path, value, self.wall_distance)
        return checked

    # -- dynamics ---------------------------------------------------------------------------
    def check_action(self, action: Any, batch: int) -> Any:
        """Validate and clip actions to [-1, 1]: six floats for one env (``batch == 0``), a
        float64 ``(batch, 6)`` array for a batch. NaN/inf or a wrong shape raise
        ``ValueError``."""
        a = check_box_action(action, self.action_space.shape[0], batch)
        return tuple(a.tolist()) if batch == 0 else a

    def step_noise_mask(self, state: ToppleState, xp: Any) -> Any:
        """Every env may draw (its windsock does, every step; its gusts while it runs with
        them): the window is cut to what each used (``events.noise_used``)."""
        return xp.logical_not(xp.zeros_like(state.wall.angle, dtype=xp.bool))

    def transition(
        self, state: ToppleState, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> tuple[ToppleState, ToppleEvents]:
        """:meth:`begin`, the interval, :meth:`end`: on the host (floats, NumPy) in chunks
        of ``gust_every`` substeps, checked for an early stop between them (the results do
        not depend on the chunks: :meth:`chunk` runs the compiled step's short ones)."""
        carry = self.begin(state, action, noise, xp, record)
        return self.end(state, self._run(run_interval, self.host_interval_params, carry, xp), xp)

    def _run(self, run: Any, params: Any, carry: ToppleCarry, xp: Any) -> ToppleCarry:
        """``carry`` after ``run`` (the whole interval, or one chunk of it) in its wind."""
        sc = carry.scenario
        interval = run(
            params, carry.interval, sc.wind_speed, sc.wind_from, sc.gusts, carry.noise, xp
        )
        return replaced(carry, interval=interval)

    def begin(
        self, state: ToppleState, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> ToppleCarry:
        """Throw (a launch slower than ``wait_speed`` is a wait: no ball) and start the
        interval. ``action``: six floats or a ``(batch, 6)`` array; ``noise``: the window of
        ``step_noise_pairs`` pairs (``2 * step_noise_pairs`` rows)."""
        if xp is floats:
            a = tuple(action)
        else:
            # Columns of their own (clipped already: a copy), not strided views.
            a = tuple(xp.clip(action[:, k], -1.0, 1.0) for k in range(6))
        v, w = launch_columns(a, self.max_speed, self.max_spin, xp)
        speed = xp.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        thrown = speed >= self.wait_speed
        # Zeros of their own (a compiled chunk's inputs must not alias each other).
        x, y, z, qx, qy, qz = (xp.zeros_like(c) for c in (*v, *w))
        ball = replaced(ball_at(x, y, z + self.launch_height, *v, *w), qx=qx, qy=qy, qz=qz)
        # The interval starts with no stress on the foot, in a new state (states are never
        # changed once made).
        wall = replaced(state.wall, stress=0.0 * state.wall.stress)
        sc = state.scenario
        # Every env runs until its own interval ends (bbgym.physics.toppling): a stopped env
        # changes no more, draws no more gust pairs, takes no more samples.
        running = xp.logical_not(xp.zeros_like(speed, dtype=xp.bool))
        carry = interval_start(
            self.interval_params,
            ball,
            wall,
            state.gust,
            sc.wind_speed,
            sc.wind_from,
            thrown,
            running,
            xp,
            record,
        )
        rows = noise_rows(noise, 2 * self.step_noise_pairs)
        return ToppleCarry(carry, rows, sc, speed, LastAction(*a))

    def chunk(self, carry: ToppleCarry, xp: Any) -> ToppleCarry:
        """One chunk of the interval: ``chunk_substeps`` substeps
        (:func:`~bbgym.physics.toppling.interval_chunk`)."""
        return self._run(interval_chunk, self.interval_params, carry, xp)

    def all_done(self, carry: ToppleCarry, xp: Any) -> Any:
        """Per env: its interval has ended (its wall is down and its ball stopped)."""
        return xp.logical_not(carry.interval.running)

    def end(
        self, state: ToppleState, carry: ToppleCarry, xp: Any
    ) -> tuple[ToppleState, ToppleEvents]:
        """Finish a transition: read the windsock's next noise pair, count, score."""
        c, thrown = carry.interval, carry.speed >= self.wait_speed
        used = c.noise_used
        # The windsock's pair follows the gust pairs the env used.
        sock_x, sock_y = noise_pair(carry.noise, used, self.step_noise_pairs, xp)
        wall = c.wall
        status = wall.status
        success = (status == FALLEN_AWAY) | (status == LOOSE)
        failure = status == FALLEN_TOWARD
        zero = xp.zeros_like(wall.angle)
        hit = c.hits > 0
        new = ToppleState(
            scenario=state.scenario,
            gust=c.gust,
            wall=wall,
            throws_left=state.throws_left - 1,
            hits=state.hits + xp.astype(hit, xp.int64),
            throws=state.throws + xp.astype(thrown, xp.int64),
            last_hit=xp.where(hit, zero + 1.0, xp.where(thrown, zero - 1.0, zero)),
            hit_height=c.hit_height,
            hit_y=c.hit_y,
            sock_x=sock_x,
            sock_y=sock_y,
            last_action=carry.action,
            success=xp.where(success, zero + self.success_bonus, zero),
            failure=xp.where(failure, zero - self.failure_penalty, zero),
            throw=xp.where(thrown, zero - self.throw_cost, zero),
            lean=self.lean_weight * (xp.sin(wall.angle) - xp.sin(state.wall.angle)),
        )
        return new, ToppleEvents(used + 1, thrown, c.taken, c.samples)

    def reward(self, state: ToppleState, xp: Any) -> Array:
        """Success bonus, failure penalty, throw cost, change of the wall's lean."""
        return state.success + state.failure + state.throw + state.lean

    def terminal(self, state: ToppleState, xp: Any) -> Array:
        """The wall is down (either way) or loose, or the throws are used up."""
        status = state.wall.status
        down = (status == FALLEN_AWAY) | (status == LOOSE) | (status == FALLEN_TOWARD)
        return down | (state.throws_left <= 0)

    def measure(self, state: ToppleState, xp: Any) -> dict[str, Array]:
        """The true wind now and the windsock's (noisy) reading of it."""
        sc = state.scenario
        wind_x, wind_y, _, _ = wind_vector(sc.wind_speed, sc.wind_from, state.gust, xp)
        noise = self.windsock_noise
        return {
            "wind_x": wind_x,
            "wind_y": wind_y,
            "sock_x": wind_x + noise * state.sock_x,
            "sock_y": wind_y + noise * state.sock_y,
        }

    def observation(self, state: ToppleState, m: dict, xp: Any) -> tuple:
        """The 19 observation values (unclipped), in the order of the env's table."""
        wp, wall = self.wall, state.wall
        zero = xp.zeros_like(wall.angle)
        throws_left = as_float(state.throws_left, zero, xp)
        return (
            wall.angle / (0.5 * math.pi),
            wall.rate / 2.0,
            state.scenario.wall_distance / 10.0,
            zero + wp.height_m / 5.0,
            zero + wp.width_m / 5.0,
            m["sock_x"] / 10.0,
            m["sock_y"] / 10.0,
            throws_left / self.throws_per_episode,
            state.last_hit,
            xp.maximum(state.hit_height, 0.0) / wp.height_m,
            state.hit_y / (0.5 * wp.width_m),
            wall.stress,
            wall.pivot,
            *state.last_action,
        )

    def info(self, state: ToppleState, m: dict, xp: Any) -> dict[str, Any]:
        """Physical quantities: Python scalars for one env, arrays ``(batch,)`` for a batch
        (``wall_state``, a name, and the samples are added by the env on the host)."""
        wall = state.wall
        status = wall.status
        return {
            "wall_angle": wall.angle,
            "wall_angular_velocity": wall.rate,
            "wall_stress": wall.stress,
            "hits": state.hits,
            "throws": state.throws,
            "throws_left": state.throws_left,
            "is_success": (status == FALLEN_AWAY) | (status == LOOSE),
            "reward_terms": {k: getattr(state, k) for k in REWARD_TERMS},
            "windsock": stack_pair(m["sock_x"], m["sock_y"], xp),
        }
