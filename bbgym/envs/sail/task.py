"""The sailing task's functional core: its state, its accepted intervals and the pure
functions of :class:`SailTask` (see :mod:`bbgym.envs.core`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces

from bbgym.envs.common import (
    check_box_action,
    check_multiple,
    check_option_keys,
    option_path,
)
from bbgym.envs.functional import InitialNoise, TaskCore, stack_pair
from bbgym.physics.common import wrap_angle
from bbgym.physics.dinghy import (
    RIGS,
    SAIL_MODELS,
    DinghyParams,
    DinghyState,
    StepEvents,
    dinghy_moving,
)
from bbgym.physics.namespace import Array, floats
from bbgym.physics.sailing import apparent_wind_body, jib_angle, split_along
from bbgym.physics.sailing_step import step_begin, step_end, step_substep
from bbgym.physics.validation import (
    ANGLE_RAD,
    build_params,
    check_bool,
    check_choice,
    check_norm,
    check_number,
    check_pair,
    check_range,
    choices_text,
    interval,
)
from bbgym.physics.water import (
    Sea,
    WaterParams,
    current_velocity,
    sea_at_start,
    waves_at,
)
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector

RESET_OPTIONS = ("wind_speed", "wind_from", "mark", "heading", "speed", "gusts")
SEA_OPTIONS = ("current_speed", "current_set", "wave_direction", "wave_phase")
"""Reset options of an env whose water moves (a current range or waves)."""
OBS_SIZE = 16
SEA_OBS_SIZE = 7
"""Columns 16-22, there when the boat is a sloop or the water moves: the jib and the sea."""
# Scales that bring each observation into roughly [-1, 1]; values beyond are clipped.
WIND_SCALE_MPS = 15.0
BOAT_SPEED_SCALE_MPS = 6.0
YAW_RATE_SCALE_RPS = 1.5
HEEL_RATE_SCALE_RPS = 2.0
WAVE_OFF_WIND_RAD = math.radians(30.0)
"""Waves raised by the wind run within this angle of its direction: an episode's waves
travel downwind, turned by a uniform draw in [-30, 30] deg."""
# Accepted intervals of the task's arguments and reset options (the documentation's
# "Validation and errors" page shows them). The physics is stable for any boat at any of
# these (tests/sail/test_sailing_stability.py).
WIND_SPEED_MPS = interval(0.0, 25.0)
"""True wind, mean of an episode: calm to a full gale (50 knots); gusts add to it."""
INITIAL_SPEED_MPS = interval(0.0, 15.0)
"""Boat speed ahead at the start: at rest to a planing skiff's top speed."""
MARK_RADIUS_M = interval(0.0, 100.0, low_open=True)
UNIT_INTERVAL = interval(0.0, 1.0)
CURRENT_SPEED_MPS = interval(0.0, 3.0)
"""A tidal stream: still water to 6 knots, as in the fastest sounds dinghies race in."""
MARK_DISTANCE_MAX_M = 5000.0
CTRL_DT_S = interval(0.0, 5.0, low_open=True)
SIM_DT_S = interval(1e-3, 0.25)
REWARD_WEIGHT = interval(0.0, 1000.0)
ARGUMENT_TABLE = (
    ("`sail_model`, `dinghy.sail_model`", choices_text(SAIL_MODELS)),
    ("`dinghy.rig`", choices_text(RIGS)),
    ("`dinghy`, `gust_params`", "mappings of their fields (tables below), or the dataclass"),
    ("`wind_speed_range`, `options['wind_speed']`", f"{WIND_SPEED_MPS} m/s"),
    ("`initial_speed_range`, `options['speed']`", f"{INITIAL_SPEED_MPS} m/s"),
    ("`initial_sheet`", f"{UNIT_INTERVAL} (0 in, 1 eased)"),
    ("`mark_radius`", f"{MARK_RADIUS_M} m"),
    (
        "`mark_distance_range`, length of `options['mark']`",
        f"(mark_radius, {MARK_DISTANCE_MAX_M:g}] m",
    ),
    ("`options['wind_from']`, `options['heading']`", f"{ANGLE_RAD} rad"),
    ("`water`", "a mapping of `WaterParams` fields (table below), or the dataclass"),
    ("`current_speed_range`, `options['current_speed']`", f"{CURRENT_SPEED_MPS} m/s"),
    (
        "`options['current_set']`, `options['wave_direction']`, `options['wave_phase']`",
        f"{ANGLE_RAD} rad (water that moves only)",
    ),
    ("`sim_dt`", f"{SIM_DT_S} s"),
    ("`ctrl_dt`", f"{CTRL_DT_S} s, a whole multiple of `sim_dt`"),
    ("`progress_weight`, `arrival_bonus`, `capsize_penalty`, `time_penalty`", f"{REWARD_WEIGHT}"),
    ("`gusts`, `options['gusts']`", "bool"),
)
"""The rows of the documentation's table of accepted arguments and options (the spec
carries it; docs/tables.py renders it and tests/test_validation.py checks the page)."""
# Zoom of the top view: the 4.2 m hull is about 70 px long.
RENDER_PIXELS_PER_M = 16.0


def build_dinghy(
    sail_model: str | None,
    dinghy: Mapping[str, Any] | DinghyParams | None,
    prefix: str = "",
) -> DinghyParams:
    """The boat from ``dinghy`` (``None``, a mapping of fields or the dataclass) with
    ``sail_model``, a shorthand for its field ``dinghy.sail_model``: ``None`` leaves the
    boat's own (``"lift"`` by default). Given both ways with different values, which was
    meant is unclear, so that raises ``ValueError`` naming both; a ``DinghyParams`` always
    gives its own. Errors name ``prefix + "sail_model"`` and ``prefix + "dinghy.<field>"``
    (the race's boat passes ``prefix="boat."``)."""
    model_path, dinghy_path = f"{prefix}sail_model", f"{prefix}dinghy"
    if sail_model is not None:
        check_choice(model_path, sail_model, SAIL_MODELS)
    own = None
    if isinstance(dinghy, DinghyParams):
        own = dinghy.sail_model
    elif isinstance(dinghy, Mapping) and "sail_model" in dinghy:
        own = check_choice(f"{dinghy_path}.sail_model", dinghy["sail_model"], SAIL_MODELS)
    if sail_model is None or own == sail_model:
        return build_params(DinghyParams, dinghy_path, dinghy)
    if own is not None:
        raise ValueError(
            f"{model_path}={sail_model!r} and {dinghy_path}.sail_model={own!r} disagree; give "
            "one of them (or the same value in both)"
        )
    return build_params(DinghyParams, dinghy_path, dinghy, sail_model=sail_model)


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
    sea: Sea
    """The water: its current and waves (static zeros and no waves for still water)."""
    jib_sheet: Array
    """The jib sheet held over the last step (0 for a cat rig and at a reset)."""


REWARD_TERMS = ("progress", "arrival", "capsize", "time")


def progress_reward(
    distance_before_m: Array, distance_m: Array, scale_m: float, weight: float, xp: Any
) -> Array:
    """The dense progress term of a sailing reward (the solo sail and the race): the
    distance made good toward a point over the step, in units of ``scale_m`` (what a boat
    at the speed scale sails in a step), clipped to [-1, 1] so that a fast reach pays no
    more than the scale, times ``weight``."""
    return weight * xp.clip((distance_before_m - distance_m) / scale_m, -1.0, 1.0)


class SailTask(TaskCore):
    """The sailing task's functional core (see :mod:`bbgym.envs.core`): pure functions
    over a batch of :class:`SailState`, for floats, NumPy and torch alike.

    Holds the validated arguments shared by :class:`BeachballSailEnv` and
    :class:`BeachballSailVectorEnv`; see the env docstring for their meaning.
    """

    randomness = "generator"  # its versions' bits, pinned by golden replays

    initial_noise_counts = (6, 2)
    """Uniform and normal draws per env for :meth:`initial`."""
    step_noise_pairs = 1
    """Pairs of standard normals a transition may use per env (the gusts)."""

    def __init__(
        self,
        sail_model: str | None = None,
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
        water: Mapping[str, Any] | WaterParams | None = None,
        current_speed_range: tuple[float, float] = (0.0, 0.0),
        initial_sheet: float = 0.0,
    ) -> None:
        self.params = build_dinghy(sail_model, dinghy)
        self.sloop = self.params.rig == "sloop"
        self.water = build_params(WaterParams, "water", water)
        self.current_speed_range = check_range(
            "current_speed_range", current_speed_range, CURRENT_SPEED_MPS
        )
        # Still water (no current can be drawn, no waves) runs the first versions' physics
        # bit for bit: no sea in the step, no extra draws, the 16 observations.
        self.moving_water = self.current_speed_range[1] > 0.0 or bool(self.water.components)
        self.extended = self.sloop or self.moving_water
        if self.moving_water:
            self.initial_noise_counts = (9 + len(self.water.components), 2)
        self.gust_params = build_params(GustParams, "gust_params", gust_params)
        self.wind_speed_range = check_range("wind_speed_range", wind_speed_range, WIND_SPEED_MPS)
        self.gusts = check_bool("gusts", gusts)
        self.mark_radius = check_number("mark_radius", mark_radius, MARK_RADIUS_M)
        # Marks lie outside the arrival circle of the start: the same interval serves the
        # constructor's range and the reset option, so the two always agree.
        self.mark_distance = interval(self.mark_radius, MARK_DISTANCE_MAX_M, low_open=True)
        self.mark_distance_range = check_range(
            "mark_distance_range",
            mark_distance_range,
            self.mark_distance,
            why=f"a mark lies beyond mark_radius = {self.mark_radius:g} m",
        )
        self.initial_speed_range = check_range(
            "initial_speed_range", initial_speed_range, INITIAL_SPEED_MPS
        )
        self.initial_sheet = check_number("initial_sheet", initial_sheet, UNIT_INTERVAL)
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

        obs_size = OBS_SIZE + (SEA_OBS_SIZE if self.extended else 0)
        self.observation_space = spaces.Box(-1.0, 1.0, (obs_size,), np.float32)
        # rudder, main sheet, and a sloop's jib sheet
        self.action_space = spaces.Box(-1.0, 1.0, (3 if self.sloop else 2,), np.float32)
        amplitudes = [c.amplitude_m for c in self.water.components]
        self._wave_scales = (
            max(sum(amplitudes), 1e-9),
            max(sum(c.amplitude_m * c.angular_frequency_rps for c in self.water.components), 1e-9),
        )
        self.reward_range = (
            -(self.progress_weight + self.time_penalty + self.capsize_penalty),
            self.progress_weight + self.arrival_bonus,
        )

    # -- scenario ---------------------------------------------------------------------------
    def initial(self, noise: InitialNoise, options: Mapping[str, Any], xp: Any) -> SailState:
        """A fresh episode per env from its draws (``noise.uniform[0..5]``,
        ``noise.normal[0..1]``; in moving water also ``uniform[6..8]`` for the current's
        drift and set and the waves' direction and ``uniform[9..]`` for each wave's phase);
        checked ``options`` pin any of the draws' results."""
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
        # Start with the boom to leeward, where the wind would put it, as far out as the
        # initial sheet lets it.
        p = self.params
        out = p.sheet_min_rad + self.initial_sheet * (p.sheet_max_rad - p.sheet_min_rad)
        wind_side = xp.sin(wind_from - heading)
        boom = xp.where(wind_side >= 0.0, zero - out, out)
        scenario = Scenario(wind_speed, wind_from, mark_x, mark_y, gusts)
        count = xp.zeros_like(zero, dtype=xp.int64)
        if self.moving_water:
            c_lo, c_hi = self.current_speed_range
            drift = pinned("current_speed", c_lo + (c_hi - c_lo) * draws[6])
            set_rad = pinned("current_set", 2.0 * math.pi * draws[7])
            downwind = wind_from + math.pi + WAVE_OFF_WIND_RAD * (2.0 * draws[8] - 1.0)
            waves = pinned("wave_direction", downwind)
            # sea_at_start takes each phase as a fraction of a turn
            turns = [pinned("wave_phase", 0.0) / (2.0 * math.pi) for _ in draws[9:]]
            if "wave_phase" not in options:
                turns = list(draws[9:])
            sea = sea_at_start(self.water, drift, set_rad, waves, turns, xp)
        else:
            sea = Sea(zero, zero, zero, (), (), ())
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
            sea=sea,
            jib_sheet=zero,
        )

    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        """Validate ``reset`` options against the same intervals as the constructor's
        ranges; unknown keys raise ``TypeError``, bad values name ``options[key]``."""
        checked = check_option_keys(options, RESET_OPTIONS + SEA_OPTIONS)
        accepted = {
            "wind_speed": WIND_SPEED_MPS,
            "speed": INITIAL_SPEED_MPS,
            "wind_from": ANGLE_RAD,
            "heading": ANGLE_RAD,
            "current_speed": CURRENT_SPEED_MPS,
            "current_set": ANGLE_RAD,
            "wave_direction": ANGLE_RAD,
            "wave_phase": ANGLE_RAD,
        }
        for key, value in checked.items():
            path = option_path(key)
            if key in SEA_OPTIONS and not self.moving_water:
                raise ValueError(
                    f"{path} needs water that moves; this env's is still "
                    f"(current_speed_range=(0, 0) and water.wave_amplitude_m=0)"
                )
            if key in ("wave_direction", "wave_phase") and not self.water.components:
                raise ValueError(f"{path} needs waves; this env has water.wave_amplitude_m=0")
            if key == "gusts":
                checked[key] = check_bool(path, value)
            elif key == "mark":
                checked[key] = check_norm(path, check_pair(path, value), self.mark_distance)
            else:
                checked[key] = check_number(path, value, accepted[key])
        return checked

    # -- dynamics ---------------------------------------------------------------------------
    def check_action(self, action: Any, batch: int) -> Any:
        """Validate and clip actions to [-1, 1]: a ``(rudder, sheet[, jib sheet])`` tuple of
        floats for one env (``batch == 0``), a float64 ``(batch, 2 or 3)`` array for a batch.
        NaN/inf or a wrong shape raise ``ValueError``."""
        a = check_box_action(action, self.action_space.shape[0], batch)
        return tuple(a.tolist()) if batch == 0 else a

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
        """Start a transition: hold rudder and sheets (actions in [-1, 1]: a ``(rudder,
        sheet[, jib sheet])`` tuple of floats or a ``(batch, 2 or 3)`` array) and the wind
        for ``ctrl_dt``; ``noise`` (a pair of standard normals per env) moves the gusts at
        the end."""
        if xp is floats:
            rudder_action, sheet_action = action[0], action[1]
        else:
            rudder_action, sheet_action = action[:, 0], action[:, 1]
        jib_sheet = None
        if self.sloop:
            jib_sheet = action[2] if xp is floats else action[:, 2]
        rudder = rudder_action * self.params.rudder_max_rad
        sheet = 0.5 * (sheet_action + 1.0)
        wind_x, wind_y, _, _ = self.wind(state, xp)
        sea = state.sea if self.moving_water else None
        carry = step_begin(
            self.params, state.boat, rudder, sheet, wind_x, wind_y, xp, sea, jib_sheet
        )
        return (carry, noise[0], noise[1])

    @property
    def chunks(self) -> int:
        """Chunks (:meth:`chunk`) per transition."""
        return self.n_substeps // self.substeps_per_chunk

    stops_early = False

    def chunk(self, carry: tuple, xp: Any) -> tuple:
        """``substeps_per_chunk`` physics substeps."""
        for _ in range(self.substeps_per_chunk):
            carry = self.substep(carry, xp)
        return carry

    def substep(self, carry: tuple, xp: Any) -> tuple:
        """One physics substep of ``sim_dt`` (what a fleet steps between its collisions)."""
        return (step_substep(self.params, carry[0], self.sim_dt, xp, self.water), *carry[1:])

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
        progress = progress_reward(
            distance_before, distance, self.progress_scale_m, self.progress_weight, xp
        )
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
            sea=carry[0].sea if self.moving_water else state.sea,
            jib_sheet=state.jib_sheet if carry[0].jib_sheet is None else carry[0].jib_sheet,
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
        m = {
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
        if not self.extended:
            return m
        zero = 0.0 * surge
        m["jib_angle"] = (
            jib_angle(self.params, state.jib_sheet, aw_u, aw_v, xp) if self.sloop else zero
        )
        water_x, water_y, heave, height = zero, zero, zero, zero
        if self.moving_water:
            water_x, water_y = current_velocity(self.water, state.sea, boat.x_m, boat.y_m, xp)
        if self.water.components:
            wave_x, wave_y, heave, height = waves_at(self.water, state.sea, boat.x_m, boat.y_m, xp)
            water_x, water_y = water_x + wave_x, water_y + wave_y
            # Where the main wave comes from, relative to the bow (+ = from port).
            from_rad = xp.atan2(-state.sea.wave_y[0], -state.sea.wave_x[0])
            m["waves_from_angle"] = wrap_angle(from_rad - boat.heading_rad, xp)
        else:
            m["waves_from_angle"] = zero
        m["water_velocity"] = (water_x, water_y)
        m["water_surge"], m["water_sway"] = split_along(water_x, water_y, cos_h, sin_h)
        m["wave_height"], m["wave_heave"] = height, heave
        return m

    def observation(self, state: SailState, m: dict, xp: Any) -> tuple:
        """The 16 (or 23) observation values (unclipped), in the order of the env's table."""
        p, boat = self.params, state.boat
        columns = (
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
        if not self.extended:
            return columns
        waves = bool(self.water.components)
        height_scale, heave_scale = self._wave_scales
        return columns + (
            m["jib_angle"] / p.jib_sheet_max_rad,
            m["water_surge"] / BOAT_SPEED_SCALE_MPS,
            m["water_sway"] / BOAT_SPEED_SCALE_MPS,
            m["wave_height"] / height_scale,
            m["wave_heave"] / heave_scale,
            xp.cos(m["waves_from_angle"]) if waves else m["waves_from_angle"],
            xp.sin(m["waves_from_angle"]),
        )

    def info(self, state: SailState, m: dict, xp: Any) -> dict[str, Any]:
        """Physical quantities: Python scalars for one env, arrays ``(batch,)`` for a batch."""
        boat, sc = state.boat, state.scenario
        info = {
            "position": stack_pair(boat.x_m, boat.y_m, xp),
            "velocity": stack_pair(boat.vx_mps, boat.vy_mps, xp),
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
            "mark": stack_pair(sc.mark_x_m, sc.mark_y_m, xp),
            "jibes": state.jibes,
            "jibe_severity": state.last_jibe_severity,
            "max_jibe_severity": state.max_jibe_severity,
            "tacks": state.tacks,
            "capsized": boat.capsized,
            "elapsed_time": state.elapsed_s,
            "is_success": state.arrived,
            "reward_terms": {k: getattr(state, k) for k in REWARD_TERMS},
        }
        if self.extended:
            info["jib_angle"] = m["jib_angle"]
            info["water_velocity"] = stack_pair(*m["water_velocity"], xp)
            info["wave_height"] = m["wave_height"]
        return info
