"""The throwing task's functional core (BeachballThrow and BeachballCurve): its state, its
accepted intervals and the pure functions of :class:`ThrowTask`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
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
    check_box_action,
    check_option_keys,
    mean_wind,
    option_path,
)
from bbgym.envs.functional import InitialNoise, TaskCore, stack_pair
from bbgym.physics.ball import BallParams, ball_at
from bbgym.physics.flight import (
    FLIGHT_SUBSTEPS_MAX,
    Flight,
    Screen,
    flight_chunk,
    flight_record_every,
    flight_result,
    flight_start,
    flight_substeps,
    fly,
    launch_spin_parameter,
    pose_of,
    recorded_poses,
    sample_count,
    simulate_throw,
)
from bbgym.physics.flight_events import (
    ROLL_DISPLAY_DT_S,
    event_flight_step,
    flight_steps,
    fly_events,
    roll_display,
    simulate_event_throw,
)
from bbgym.physics.namespace import Array, as_float, floats, replaced
from bbgym.physics.validation import (
    build_params,
    check_bool,
    check_choice,
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

# Accepted intervals of the throwing task's own arguments and reset options (those every
# ball task takes are in bbgym.envs.ball).
TARGET_RADIUS_M = interval(0.0, 10.0, low_open=True)
FIELD_RADIUS_M = interval(0.0, 1000.0, low_open=True)
BEARING_RAD = interval(-math.pi, math.pi)
THROW_INTERVAL_S = interval(0.0, 3600.0, low_open=True)
SCREEN_SIZE_M = interval(0.0, 100.0, low_open=True)
FLIGHT_TIME_MAX_S = 600.0
MISS_SCALE_M = interval(0.0, 100.0, low_open=True)
FLIGHT_INTEGRATORS = ("semi_implicit_euler", "rk4_events")
"""How a throw is flown: semi-implicit Euler substeps of ``sim_dt`` through the bounces
to rest (:mod:`bbgym.physics.flight`), or RK4 steps of ``sim_dt`` with the touchdown and
the screen hits located inside a step, ending at the touchdown
(:mod:`bbgym.physics.flight_events`)."""
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
    ("`flight_integrator`", ", ".join(f"`{name}`" for name in FLIGHT_INTEGRATORS)),
    ("`sim_dt`", f"{BALL_SIM_DT_S} s"),
    ("`max_flight_time`", f"[10 sim_dt, {FLIGHT_TIME_MAX_S:g}] s"),
    ("`max_roll_time`", f"(0, {FLIGHT_TIME_MAX_S:g}] s"),
    ("`miss_scale`", f"{MISS_SCALE_M} m"),
    ("`hit_bonus`", f"{REWARD_WEIGHT}"),
    ("`gusts`, `screen`, `options['gusts']`, `options['screen']`", "bool"),
)
"""The rows of the documentation's table of accepted arguments and options (the spec
carries it; docs/tables.py renders it and tests/test_validation.py checks the page)."""


CHUNK_SUBSTEPS = 2
"""Flight substeps per chunk of a batched throw (between two "all landed?" checks). Small,
because inductor's compile time grows faster than the chunk (one substep compiles in
about 8 s on two CPU cores, 4 in 35 s, 8 in 85 s) while a call costs little."""
RECORD_DT_S = 0.05
"""Time between two recorded poses of a trajectory."""
REWARD_TERMS = ("closeness", "hit")


class ThrowScenario(NamedTuple):
    """What an episode is about, per env (arrays ``(batch,)`` or floats): target, mean
    wind, screen, gusts."""

    target_x: Array
    target_y: Array
    wind_speed: Array
    wind_from: Array
    gusts: Array
    screen: Array


class LastAction(NamedTuple):
    """The last throw's action (clipped to [-1, 1]), as the observation shows it (both
    ball tasks')."""

    impulse_x: Array
    impulse_y: Array
    impulse_z: Array
    spin_x: Array
    spin_y: Array
    spin_z: Array


class ThrowState(NamedTuple):
    """Everything an env is, immutable: the scenario, the gusts, the windsock's reading,
    this episode's counters and what the last throw did (its reward terms included)."""

    scenario: ThrowScenario
    gust: GustState
    sock_x: Array
    sock_y: Array
    throws_left: Array
    thrown: Array
    """A throw has been made this episode (the fields below describe the last one)."""
    action: LastAction
    landing_x: Array
    landing_y: Array
    miss_distance: Array
    flight_time: Array
    apex_height: Array
    spin_parameter: Array
    hit_screen: Array
    wind_x: Array
    """The wind during the last throw."""
    wind_y: Array
    is_success: Array
    closeness: Array
    hit: Array


class ThrowCarry(NamedTuple):
    """What a throw carries from chunk to chunk: arrays only (``poses`` is ``None``
    unless recording, on NumPy or floats), so one compiled chunk serves every call."""

    flight: Flight
    wind_x: Array
    wind_y: Array
    screen: Screen
    spin_parameter: Array
    action: LastAction
    noise: tuple
    poses: list | None
    """The launch's pose, then the pose after every substep flown (when recording)."""


class ThrowEvents(NamedTuple):
    """What a transition reports besides the new state."""

    noise_used: Array
    """Pairs of the step's noise window used per env: 2 with gusts (gusts, then the
    windsock), else 1 (the windsock)."""
    trajectory: list
    """The recorded poses (every ``RECORD_DT_S``, the launch's first) of the batch, cut
    to the last flight's (empty unless recording)."""
    steps: Array
    """How many of them belong to each env's flight."""


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


def launch_columns(columns: tuple, max_speed: float, max_spin: float, xp: Any) -> tuple[list, list]:
    """:func:`launch_from_action` column by column, in any namespace (the same bits): the
    launch of both ball tasks' throws.

    Args:
        columns: The six action components in [-1, 1] (floats, or arrays ``(batch,)``).
        max_speed: The launch speed's limit, m/s.
        max_spin: The spin's limit, rad/s.
        xp: The array namespace.

    Returns:
        The launch velocity's three components and the spin's, each vector scaled by its
        limit and its norm clipped to it.
    """

    def scaled(c: tuple, limit: float) -> list:
        v = [x * limit for x in c]
        norm = xp.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        factor = xp.minimum(1.0, limit / xp.maximum(norm, 1e-12))
        return [x * factor for x in v]

    return scaled(columns[:3], max_speed), scaled(columns[3:], max_spin)


class ThrowTask(TaskCore):
    """The throwing task's functional core (see :mod:`bbgym.envs.core`): pure functions
    over a batch of :class:`ThrowState`, for floats, NumPy and torch alike. A transition
    is one throw: :meth:`begin` launches, :meth:`chunk` flies ``CHUNK_SUBSTEPS`` substeps
    (finished balls frozen), :meth:`end` scores it and moves the gusts on.

    Holds the validated arguments shared by :class:`BeachballThrowEnv` and
    :class:`BeachballThrowVectorEnv`; see the env docstring for their meaning.
    """

    randomness = "generator"  # its versions' bits, pinned by golden replays

    initial_noise_counts = (4, 2)
    """Uniform draws (target distance and bearing, wind speed and direction) and normal
    draws (the gusts' start) per env for :meth:`initial`."""
    initial_stream_pairs = 1
    """The windsock's first reading noise."""
    step_noise_pairs = 2
    """A window of two pairs per throw: the gusts' step (with gusts), then the windsock's
    reading noise; :attr:`ThrowEvents.noise_used` says how many an env used."""
    stops_early = True
    chunk_substeps = CHUNK_SUBSTEPS

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
        flight_integrator: str = "semi_implicit_euler",
        sim_dt: float = 0.01,
        max_flight_time: float = 6.0,
        max_roll_time: float = 2.0,
        field_radius: float = 30.0,
        miss_scale: float = 2.0,
        hit_bonus: float = 5.0,
    ) -> None:
        """Validate every argument (the env's docstring says what each means) and derive the
        step's fixed sizes. One function on purpose: it checks the arguments in the
        signature's order, each against its accepted interval or the one an earlier
        argument sets (a target beyond ``target_radius``), so the first bad argument is the
        one reported."""
        self.ball = build_params(BallParams, "ball", ball)
        self.throws_per_episode = check_integer(
            "throws_per_episode", throws_per_episode, THROWS_PER_EPISODE
        )
        self.target_radius = check_number("target_radius", target_radius, TARGET_RADIUS_M)
        self.field_radius = check_number("field_radius", field_radius, FIELD_RADIUS_M)
        # A target lies outside its own ring around the thrower and with its ring inside the
        # field: one interval for the constructor's range and the reset option alike.
        self.target_distance = interval(
            self.target_radius,
            self.field_radius - self.target_radius,
            low_open=True,
            high_open=True,
        )
        self.target_distance_range = check_range(
            "target_distance_range",
            target_distance_range,
            self.target_distance,
            why=f"a target lies beyond target_radius = {self.target_radius:g} m, its ring "
            f"within field_radius = {self.field_radius:g} m",
        )
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
            "launch_height",
            launch_height,
            interval(self.ball.radius_m, LAUNCH_HEIGHT_MAX_M),
            why=f"at least ball.radius_m = {self.ball.radius_m:g} m",
        )
        self.screen_height = check_number("screen_height", screen_height, SCREEN_SIZE_M)
        self.screen_half_width = check_number("screen_half_width", screen_half_width, SCREEN_SIZE_M)
        self.screen_position = check_number(
            "screen_position", screen_position, interval(0.0, 1.0, low_open=True, high_open=True)
        )
        self.flight_integrator = check_choice(
            "flight_integrator", flight_integrator, FLIGHT_INTEGRATORS
        )
        self.events = self.flight_integrator == "rk4_events"
        self.sim_dt = check_number("sim_dt", sim_dt, BALL_SIM_DT_S)
        self.wind_limit = rk4_task_wind_limit(self, "flight_integrator")
        """The strongest mean wind a ``reset`` option may pin (RK4 flights: what the step
        is stable for, :func:`~bbgym.envs.ball.check_rk4_ball`)."""
        self.max_flight_time = check_number(
            "max_flight_time", max_flight_time, interval(10 * self.sim_dt, FLIGHT_TIME_MAX_S)
        )
        self.max_roll_time = check_number(
            "max_roll_time", max_roll_time, interval(0.0, FLIGHT_TIME_MAX_S, low_open=True)
        )
        self.miss_scale = check_number("miss_scale", miss_scale, MISS_SCALE_M)
        self.hit_bonus = check_number("hit_bonus", hit_bonus, REWARD_WEIGHT)
        self._derive_sizes()

    def _derive_sizes(self) -> None:
        """The step's fixed sizes (the flight's substeps and recorded poses) and the
        spaces, from the checked arguments."""
        if self.events:  # RK4 steps (cut ones too), each recorded, then the roll's display
            self.flight_substeps = flight_steps(self.sim_dt, self.max_flight_time)
            self.record_every = 1
            roll_substeps = flight_substeps(ROLL_DISPLAY_DT_S, self.max_roll_time)
            roll_rows = roll_substeps // flight_record_every(ROLL_DISPLAY_DT_S, RECORD_DT_S)
            self.record_capacity = 1 + self.flight_substeps + roll_rows
            self.chunk_substeps = 1  # an RK4 step is four substeps' work already
        else:
            self.flight_substeps = flight_substeps(self.sim_dt, self.max_flight_time)
            self.record_every = flight_record_every(self.sim_dt, RECORD_DT_S)
            self.record_capacity = 1 + self.flight_substeps // self.record_every
        # record_capacity: the most poses a throw records, the rows of the ``trajectory``
        # and ``orientations`` infos: the launch's, then one every ``record_every``
        # substeps up to the flight's last (121 by default: 6 s every 0.05 s); with
        # ``rk4_events`` one per step, then the bounces and roll after the touchdown.
        assert self.flight_substeps < FLIGHT_SUBSTEPS_MAX  # 600 s / 1e-4 s = 6e6
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
                checked[key] = check_wind_option(path, value, self.wind_limit)
            else:
                checked[key] = check_norm(path, check_pair(path, value), self.target_distance)
        return checked

    def initial(self, noise: InitialNoise, options: Mapping[str, Any], xp: Any) -> ThrowState:
        """A fresh episode per env from its draws (``noise.uniform[0..3]``: target distance
        and bearing, wind speed and direction; ``noise.normal[0..1]``: the gusts' start;
        ``noise.stream[0..1]``: the windsock's reading noise); checked ``options`` pin
        any of the draws' results."""
        draws = noise.uniform
        zero = xp.zeros_like(draws[0])
        if "target" in options:
            target_x, target_y = zero + options["target"][0], zero + options["target"][1]
        else:
            d_lo, d_hi = self.target_distance_range
            b_lo, b_hi = self.target_bearing_range
            distance = d_lo + (d_hi - d_lo) * draws[0]
            bearing = b_lo + (b_hi - b_lo) * draws[1]
            target_x, target_y = distance * xp.cos(bearing), distance * xp.sin(bearing)
        wind_speed, wind_from = mean_wind(options, self.wind_speed_range, draws[2], draws[3])
        gusts = xp.full_like(zero, options.get("gusts", self.gusts), dtype=xp.bool)
        screen = xp.full_like(zero, options.get("screen", self.screen), dtype=xp.bool)
        scenario = ThrowScenario(
            target_x, target_y, zero + wind_speed, zero + wind_from, gusts, screen
        )
        gust = gust_init(self.gust_params, noise.normal, gusts, xp)
        sock_x, sock_y = self.windsock(scenario, gust, noise.stream, xp)
        no = zero > 0.0
        return ThrowState(
            scenario=scenario,
            gust=gust,
            sock_x=sock_x,
            sock_y=sock_y,
            throws_left=xp.zeros_like(zero, dtype=xp.int64) + self.throws_per_episode,
            thrown=no,
            action=LastAction(*(zero for _ in range(6))),
            landing_x=zero,
            landing_y=zero,
            miss_distance=zero,
            flight_time=zero,
            apex_height=zero,
            spin_parameter=zero,
            hit_screen=no,
            wind_x=zero,
            wind_y=zero,
            is_success=no,
            closeness=zero,
            hit=zero,
        )

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

    def windsock(self, scenario: ThrowScenario, gust: GustState, noise: Any, xp: Any = np) -> Any:
        """What the windsock shows: the wind now plus reading noise (a pair)."""
        wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed, scenario.wind_from, gust, xp)
        return wind_x + self.windsock_noise * noise[0], wind_y + self.windsock_noise * noise[1]

    # -- dynamics ---------------------------------------------------------------------------
    def check_action(self, action: Any, batch: int) -> np.ndarray:
        """Actions as float64 ``(6,)`` or ``(batch, 6)``, clipped to [-1, 1]."""
        return check_box_action(action, self.action_space.shape[0], batch)

    def launch(self, action: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Launch velocity and spin ``(..., 3)`` from actions: scaled, norms clipped."""
        return launch_from_action(action, self.max_speed, self.max_spin)

    def step_noise_mask(self, state: ThrowState, xp: Any) -> Any:
        """Every env may use its window (at least the windsock's pair)."""
        return xp.full_like(state.sock_x, True, dtype=xp.bool)

    @property
    def chunks(self) -> int:
        """Chunks (:meth:`chunk`) per throw: enough for the longest flight."""
        return -(-self.flight_substeps // self.chunk_substeps)

    def begin(
        self, state: ThrowState, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> ThrowCarry:
        """Launch a throw: actions in [-1, 1] (six floats, or a ``(batch, 6)`` array) scale
        to the launch velocity and spin (norms clipped); the wind now holds for the flight.
        ``noise`` (two pairs of standard normals per env) moves the gusts at the end."""
        if xp is floats:
            columns = tuple(float(c) for c in action)
        else:
            columns = tuple(action[:, k] for k in range(6))
        sc = state.scenario
        v, w = launch_columns(columns, self.max_speed, self.max_spin, xp)
        # Distinct arrays throughout: the compiled chunk sees the same aliasing every call.
        x, y = xp.zeros_like(state.sock_x), xp.zeros_like(state.sock_y)
        launch = ball_at(x, y, xp.zeros_like(state.sock_x) + self.launch_height, *v, *w)
        wind_x, wind_y, _, _ = wind_vector(sc.wind_speed, sc.wind_from, state.gust, xp)
        return ThrowCarry(
            flight=flight_start(self.ball, launch, xp),
            wind_x=wind_x,
            wind_y=wind_y,
            screen=self.screen_geometry(sc, xp),
            spin_parameter=launch_spin_parameter(self.ball, launch, wind_x, wind_y, xp),
            # clipped already: a new array (not a view of the action) of the batch's layout
            action=LastAction(*(xp.clip(c, -1.0, 1.0) for c in columns)),
            noise=tuple(noise),
            poses=[pose_of(launch)] if record else None,
        )

    def chunk(self, carry: ThrowCarry, xp: Any) -> ThrowCarry:
        """``CHUNK_SUBSTEPS`` substeps of the flight."""
        return self._fly(carry, self.chunk_substeps, xp)

    def _fly(self, carry: ThrowCarry, substeps: int, xp: Any) -> ThrowCarry:
        if self.events:  # (never recording: the host flies a throw in one go)
            flight = carry.flight
            for _ in range(substeps):
                flight, _ = self._event_step(flight, carry, xp, orient=False)
            return replaced(carry, flight=flight)
        recording = carry.poses is not None
        first = sample_count(carry.flight.substep, xp) if recording else 0
        flight, poses = self._substeps(flight_chunk, carry, recording, xp, substeps)
        if recording:  # (never on a compiled step: the substep number is read on the host)
            poses = carry.poses + recorded_poses(
                poses, first, self.record_every, self.flight_substeps
            )
        return replaced(carry, flight=flight, poses=poses if recording else None)

    def _substeps(
        self, run: Callable, carry: ThrowCarry, record: bool, xp: Any, *substeps: int
    ) -> tuple[Flight, list]:
        """``run`` on the throw's flight with the task's step and limits: :func:`flight_chunk`
        (of ``substeps``) or :func:`fly` (to the end), as the topple task runs its interval."""
        return run(
            self.ball,
            carry.flight,
            carry.wind_x,
            carry.wind_y,
            carry.screen,
            self.sim_dt,
            *substeps,
            self.flight_substeps,
            self.record_every,
            record,
            xp,
            self.max_roll_time,
            self.field_radius,
        )

    def _event_step(
        self, flight: Flight, carry: ThrowCarry, xp: Any, orient: bool
    ) -> tuple[Flight, Any]:
        """One RK4 step of a throw's flight (:func:`event_flight_step`); ``orient``: turn
        the balls too (for the poses recorded)."""
        return event_flight_step(
            self.ball,
            flight,
            carry.wind_x,
            carry.wind_y,
            carry.screen,
            self.sim_dt,
            self.max_flight_time,
            self.field_radius,
            xp,
            orient=orient,
        )

    def all_done(self, carry: ThrowCarry, xp: Any) -> Any:
        """Every ball has finished its flight."""
        return carry.flight.done

    def transition(
        self, state: ThrowState, action: Any, noise: Any, xp: Any, record: bool = False
    ) -> tuple[ThrowState, ThrowEvents]:
        """One throw. On the host (Python floats, NumPy) :func:`~bbgym.physics.flight.fly`
        flies it, on other namespaces the chunks do; the results are the same."""
        if xp is not floats and xp is not np:
            return super().transition(state, action, noise, xp, record)
        carry = self.begin(state, action, noise, xp, record)
        if self.events:
            return self.end(state, self._fly_events(carry, record, xp), xp)
        flight, poses = self._substeps(fly, carry, record, xp)
        recorded = carry.poses + poses if record else None
        return self.end(state, replaced(carry, flight=flight, poses=recorded), xp)

    def _fly_events(self, carry: ThrowCarry, record: bool, xp: Any) -> ThrowCarry:
        """A throw's RK4 flight on the host; when recording, the poses (one per step)
        go on with the bounces and roll after the touchdown, for display."""
        flight, poses = fly_events(
            lambda flight: self._event_step(flight, carry, xp, orient=True),
            carry.flight,
            self.flight_substeps,
            record,
            xp,
        )
        if not record:
            return replaced(carry, flight=flight)
        poses, steps = roll_display(
            self.ball,
            flight,
            carry.poses + poses,
            carry.wind_x,
            carry.wind_y,
            carry.screen,
            self.max_roll_time,
            self.field_radius,
            RECORD_DT_S,
            xp,
        )
        # the recorded rows: each ball's own, the longest's number for the batch
        counted = replaced(flight, steps=steps, samples=xp.zeros_like(steps) + len(poses))
        return replaced(carry, flight=counted, poses=poses)

    def end(self, state: ThrowState, carry: ThrowCarry, xp: Any) -> tuple[ThrowState, ThrowEvents]:
        """Score the throw (first touchdown against the ring), move the gusts on by
        ``throw_interval`` and read the windsock anew."""
        sc, flight = state.scenario, carry.flight
        trajectory = []
        if carry.poses is not None:  # the launch, then the record's poses
            trajectory = carry.poses[: sample_count(flight.samples, xp)]
        result = flight_result(flight, carry.spin_parameter, trajectory, xp)
        miss, hit, terms = self.score(result, sc, xp)
        n0, n1, n2, n3 = carry.noise
        gusts = sc.gusts
        gust_noise = (xp.where(gusts, n0, 0.0), xp.where(gusts, n1, 0.0))
        sock_noise = (xp.where(gusts, n2, n0), xp.where(gusts, n3, n1))
        gust = gust_step(state.gust, self.gust_params, self.throw_interval, gust_noise, gusts, xp)
        sock_x, sock_y = self.windsock(sc, gust, sock_noise, xp)
        new = ThrowState(
            scenario=sc,
            gust=gust,
            sock_x=sock_x,
            sock_y=sock_y,
            throws_left=state.throws_left - 1,
            thrown=xp.full_like(state.sock_x, True, dtype=xp.bool),
            action=carry.action,
            landing_x=result.landing_x,
            landing_y=result.landing_y,
            miss_distance=miss,
            flight_time=result.flight_time_s,
            apex_height=result.apex_height_m,
            spin_parameter=result.spin_parameter,
            hit_screen=result.hit_screen,
            wind_x=carry.wind_x,
            wind_y=carry.wind_y,
            is_success=hit,
            closeness=terms["closeness"],
            hit=terms["hit"],
        )
        events = ThrowEvents(
            noise_used=xp.astype(gusts, xp.int64) + 1,
            trajectory=result.trajectory,
            steps=result.steps,
        )
        return new, events

    def score(self, result: Any, scenario: ThrowScenario, xp: Any = np) -> tuple[Any, Any, dict]:
        """Miss distance, hit (first touchdown inside the ring), and reward terms."""
        dx = result.landing_x - scenario.target_x
        dy = result.landing_y - scenario.target_y
        miss = xp.sqrt(dx * dx + dy * dy)
        hit = miss <= self.target_radius
        closeness = xp.exp(-miss / self.miss_scale)
        terms = {"closeness": closeness, "hit": xp.where(hit, self.hit_bonus + 0.0 * miss, 0.0)}
        return miss, hit, terms

    def throw(
        self,
        velocity: np.ndarray,
        spin: np.ndarray,
        scenario: ThrowScenario,
        gust: GustState,
        xp: Any = np,
    ) -> tuple[Any, Any, Any]:
        """Simulate one throw per env from launch velocities and spins ``(batch, 3)``
        (NumPy; what a planner asks); returns ``(result, wind_x, wind_y)``. The same
        flight as a step's (:func:`simulate_throw` drives the same masked substeps)."""
        wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed, scenario.wind_from, gust, xp)
        start = ball_at(0.0, 0.0, self.launch_height, *velocity.T, *spin.T, xp=xp)
        # The event-located RK4 flight and the substepped one take the same arguments.
        simulate = simulate_event_throw if self.events else simulate_throw
        result = simulate(
            self.ball,
            start,
            wind_x,
            wind_y,
            self.screen_geometry(scenario, xp),
            self.sim_dt,
            self.max_flight_time,
            self.max_roll_time,
            self.field_radius,
            RECORD_DT_S,
            xp=xp,
        )
        return result, wind_x, wind_y

    # -- what the agent sees --------------------------------------------------------------------
    def reward(self, state: ThrowState, xp: Any) -> Array:
        """Closeness of the first touchdown to the ring's centre, plus the hit bonus."""
        return state.closeness + state.hit

    def terminal(self, state: ThrowState, xp: Any) -> Array:
        """A hit, or the last throw made."""
        return state.is_success | (state.throws_left <= 0)

    def measure(self, state: ThrowState, xp: Any) -> dict[str, Any]:
        """Where the screen stands (also where none does: then it is masked out)."""
        screen = self.screen_geometry(state.scenario, xp)
        return {"screen_x": screen.center_x, "screen_y": screen.center_y}

    def observation(self, state: ThrowState, m: dict, xp: Any) -> tuple:
        """The 19 observation values (unclipped), in the order of the env's table."""
        sc, d = state.scenario, DISTANCE_SCALE_M
        zero = xp.zeros_like(sc.target_x)
        thrown = xp.where(state.thrown, zero + 1.0, zero)
        on = xp.where(sc.screen, zero + 1.0, zero)
        return (
            sc.target_x / d,
            sc.target_y / d,
            state.sock_x / WIND_SCALE_MPS,
            state.sock_y / WIND_SCALE_MPS,
            thrown * (state.landing_x - sc.target_x) / d,
            thrown * (state.landing_y - sc.target_y) / d,
            as_float(state.throws_left, zero, xp) / self.throws_per_episode,
            thrown,
            *state.action,
            on,
            on * m["screen_x"] / d,
            on * m["screen_y"] / d,
            on * self.screen_height / d,
            on * self.screen_half_width / d,
        )

    def info(self, state: ThrowState, m: dict, xp: Any) -> dict[str, Any]:
        """The last throw and the scenario: Python scalars (pairs as NumPy arrays) for
        one env, arrays ``(batch,)`` or ``(batch, 2)`` for a batch."""
        sc = state.scenario
        return {
            "thrown": state.thrown,
            "landing_point": stack_pair(state.landing_x, state.landing_y, xp),
            "miss_distance": state.miss_distance,
            "flight_time": state.flight_time,
            "apex_height": state.apex_height,
            "spin_parameter": state.spin_parameter,
            "hit_screen": state.hit_screen,
            "wind": stack_pair(state.wind_x, state.wind_y, xp),
            "is_success": state.is_success,
            "reward_terms": {k: getattr(state, k) for k in REWARD_TERMS},
            "throws_left": state.throws_left,
            "target": stack_pair(sc.target_x, sc.target_y, xp),
            "windsock": stack_pair(state.sock_x, state.sock_y, xp),
        }
