"""The race's functional core: a fleet of the sail core's dinghies on one course, the wind
shadow between them, the start, the marks and the finish, as pure functions over a batch
of races (see :mod:`bbgym.envs.functional` for the shape it follows).

Each boat is the sailing task's boat (:class:`~bbgym.envs.sail.task.SailTask`, stepped
over all boats of all races at once, ``races * K`` of them, boat ``k`` of race ``r`` at
``r * K + k``): its physics, its gusts and its measurements are the sail env's, so a boat
alone on the course sails exactly as the sail env's boat does. The fleet shares its wind:
one mean wind and one gust process per race (every boat of a race draws the same gust
noise). Each step the wind each boat feels is the race's wind turned by the shadows of
the others (:mod:`bbgym.physics.shadow`), held for the step, as the sail env holds its
wind. Between substeps the hulls that touch bounce off each other
(:mod:`bbgym.physics.collision`); after each step the right-of-way rules
(:mod:`bbgym.envs.race.rules`) find the boats that fouled another, and each foul costs a
penalty turn (a full circle before the boat may pass its next waypoint) or, with
``penalty="time"``, seconds added to its finishing time.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from typing import Any, NamedTuple

import numpy as np
from gymnasium import spaces

from bbgym.envs.common import option_path
from bbgym.envs.functional import InitialNoise, stack_pair, tree_select
from bbgym.envs.race import course as rc
from bbgym.envs.race import rules
from bbgym.envs.sail import task as sail_task
from bbgym.envs.sail.task import (
    BOAT_SPEED_SCALE_MPS,
    INITIAL_SPEED_MPS,
    UNIT_INTERVAL,
    WIND_SPEED_MPS,
    SailState,
    SailTask,
    build_dinghy,
)
from bbgym.physics.collision import collide, hull_contacts, hulls
from bbgym.physics.common import split_along, wrap_angle
from bbgym.physics.namespace import Array, replaced
from bbgym.physics.sailing import apparent_wind_body, rig_force
from bbgym.physics.shadow import ShadowParams, profile_area_m2, shadow_velocity, shadowed_wind
from bbgym.physics.validation import (
    ANGLE_RAD,
    build_params,
    check_bool,
    check_number,
    check_range,
    interval,
)
from bbgym.physics.wind import wind_vector

RESET_OPTIONS = ("wind_speed", "wind_from", "gusts")
SAIL_ONLY_OPTIONS = tuple(
    key for key in sail_task.RESET_OPTIONS + sail_task.SEA_OPTIONS if key not in RESET_OPTIONS
)
"""The sail env's reset options that the race does not take: refused by name (a user who
pins a boat's ``heading`` there would expect it pinned here), not ignored."""
NEAR_MISS = 0.8
"""How alike (:class:`difflib.SequenceMatcher`'s ratio, case aside) an unknown option key
must be to one of :data:`RESET_OPTIONS` to be refused as a typo of it: ``wind_sped``,
``windspeed``, ``gust`` are; ``options``, ``tide``, ``speed`` are not."""
BOAT_KEYS = ("sail_model", "dinghy", "initial_sheet", "initial_speed_range")
"""The sail core's arguments that a race's ``boat`` takes."""
BOATS = interval(1, 8)
"""Boats in a race: one (a time trial) to a fleet of eight."""
NEIGHBOURS = interval(0, 7)
LAPS = interval(1, 5)
LINE_LENGTH_M = interval(5.0, 500.0)
LEG_LENGTH_M = interval(20.0, 2000.0)
GATE_DEPTH_M = interval(0.0, 500.0)
GATE_WIDTH_M = interval(5.0, 200.0)
COUNTDOWN_S = interval(0.0, 300.0)
START_DEPTH_M = interval(0.0, 200.0)
RACE_TIME_S = interval(10.0, 7200.0)
REWARD_WEIGHT = interval(0.0, 1000.0)
REWARD_WEIGHTS = (
    "progress_weight",
    "waypoint_bonus",
    "finish_bonus",
    "ocs_penalty",
    "capsize_penalty",
    "time_penalty",
    "foul_penalty",
)
"""The reward's weights, each a constructor argument in :data:`REWARD_WEIGHT`."""
RESTITUTION = interval(0.0, 1.0)
KEEP_CLEAR_M = interval(0.0, 50.0)
PENALTY_TIME_S = interval(0.0, 600.0)
PENALTIES = ("turn", "time")
PENALTY_SCALE_S = 60.0
"""A time penalty owed is observed in minutes."""
ARGUMENT_TABLE = (
    ("`num_boats`", f"{BOATS}, an int"),
    ("`neighbours`", f"{NEIGHBOURS}, an int (at most `num_boats - 1` are observed)"),
    ("`laps`", f"{LAPS}, an int"),
    ("`line_length_m`", f"{LINE_LENGTH_M} m"),
    ("`leg_length_m`", f"{LEG_LENGTH_M} m"),
    ("`gate_depth_m`", f"{GATE_DEPTH_M} m"),
    ("`gate_width_m`", f"{GATE_WIDTH_M} m"),
    ("`countdown_s`", f"{COUNTDOWN_S} s"),
    ("`start_depth_range`", f"{START_DEPTH_M} m"),
    ("`max_race_time_s`", f"{RACE_TIME_S} s"),
    ("`wind_speed_range`, `options['wind_speed']`", f"{WIND_SPEED_MPS} m/s"),
    ("`options['wind_from']`", f"{ANGLE_RAD} rad"),
    ("`gusts`, `shadow`, `collisions`, `options['gusts']`", "bool"),
    ("`restitution`", f"{RESTITUTION}"),
    ("`keep_clear_m`", f"{KEEP_CLEAR_M} m"),
    ("`penalty`", " or ".join(f'`"{p}"`' for p in PENALTIES)),
    ("`penalty_time_s`", f"{PENALTY_TIME_S} s"),
    (
        "`progress_weight`, `waypoint_bonus`, `finish_bonus`, `ocs_penalty`, "
        "`capsize_penalty`, `time_penalty`, `foul_penalty`",
        f"{REWARD_WEIGHT}",
    ),
    (
        "`boat`",
        "a mapping of `sail_model`, `dinghy`, `initial_sheet`, `initial_speed_range` "
        "(the sail env's accepted values)",
    ),
    ("`shadow_params`", "a mapping of its fields (table below), or the dataclass"),
)
"""The documentation's table of the race's accepted arguments and options (the Race
page's generated table)."""
RELATIVE_SCALE_M = 50.0
"""Neighbours' positions are divided by this: boats within 50 m are inside [-1, 1]."""
RACE_COLUMNS = (
    "time_to_gun",
    "race_time",
    "started",
    "ocs",
    "waypoints_passed",
    "penalty_owed",
    "committee_cos",
    "committee_sin",
    "committee_distance",
    "pin_cos",
    "pin_sin",
    "pin_distance",
)
"""The race's columns, after the sail env's (the env's docstring table)."""
NEIGHBOUR_COLUMNS = (
    "present",
    "ahead",
    "port",
    "speed_ahead",
    "speed_port",
    "heading_cos",
    "heading_sin",
    "right_of_way",
)
"""Each neighbour's columns, after the race's: ``right_of_way`` is -1 where this boat must
keep clear of it, 1 where it must keep clear of this boat."""
RACE_OBS_SIZE = len(RACE_COLUMNS)
NEIGHBOUR_OBS_SIZE = len(NEIGHBOUR_COLUMNS)
REWARD_TERMS = {
    "progress": "progress",
    "waypoint": "waypoint",
    "finish": "finish",
    "ocs": "ocs_penalty",
    "capsize": "capsize",
    "foul": "foul",
    "time": "time",
}
"""Each reward term's name (in the infos) and the state's field that holds it."""


class RaceState(NamedTuple):
    """A batch of races, immutable. ``boats`` is the sail core's state of every boat, flat
    (``races * K``); the rest is ``(races,)`` per race, ``(races, K)`` per boat or
    ``(races, K, K)`` per pair."""

    boats: SailState
    wind_speed_mps: Array
    """The race's mean wind (the boats' own winds are it, shadowed)."""
    wind_from_rad: Array
    clock_s: Array
    """Time from the gun: negative during the countdown."""
    leg: Array
    """The waypoint each boat sails to next (an index into the course's waypoints)."""
    ocs: Array
    """On the course side at the gun, not yet back behind the line."""
    crossed_s: Array
    """When the boat crossed the finish line (race clock, inf before): it stops there."""
    finished: Array
    """Crossed, and any time penalty served."""
    place: Array
    """Finishing place, 1 first; 0 until finished."""
    capsized: Array
    fouling: Array
    """``(races, K, K)``: boat ``i`` was inside ``keep_clear_m`` of boat ``j`` it must keep
    clear of at the last step's end (an encounter goes on)."""
    fouls: Array
    turns_owed: Array
    turned_rad: Array
    """Heading turned since the boat began to owe a turn (signed)."""
    penalty_s: Array
    """Time penalty owed (``penalty="time"``)."""
    touched: Array
    """Its hull touched another's during the last step."""
    wind_factor: Array
    """The shadows' effect on each boat's wind over the last step: speed over the race's."""
    wind_bend_rad: Array
    """... and its turn (counterclockwise, seen from above)."""
    progress: Array
    waypoint: Array
    finish: Array
    ocs_penalty: Array
    capsize: Array
    foul: Array
    time: Array

    @property
    def stopped(self) -> Array:
        """Out of the sailing: crossed the finish or capsized (stays where it stopped,
        casts no shadow, touches no one)."""
        return (self.crossed_s < math.inf) | self.capsized

    @property
    def out(self) -> Array:
        """Out of the race: finished or capsized (the agent's episode has ended)."""
        return self.finished | self.capsized


def boat_mapping(boat: Any) -> dict[str, Any]:
    """``boat`` as a dict of :data:`BOAT_KEYS` (``None``: empty): anything but a mapping, or
    a key it does not know, raises ``TypeError`` naming ``boat``."""
    if boat is None:
        return {}
    if not isinstance(boat, Mapping):
        kind = type(boat).__name__
        raise TypeError(f"boat must be a mapping of {list(BOAT_KEYS)}, got {boat!r} ({kind})")
    for key in boat:
        if key not in BOAT_KEYS:
            raise TypeError(f"boat got an unexpected key {key!r}; known keys: {list(BOAT_KEYS)}")
    return dict(boat)


def check_boat(boat: Any) -> dict[str, Any]:
    """The sail core's boat arguments in ``boat`` (:func:`boat_mapping`), each checked as
    :class:`~bbgym.envs.sail.task.SailTask` checks it (the same validators and intervals)
    but named by the path the user wrote: ``boat.sail_model``, ``boat.dinghy.mass_kg``,
    ``boat.initial_sheet``, ``boat.initial_speed_range[1]``. The dinghy comes back as
    :class:`~bbgym.physics.dinghy.DinghyParams`, which the sail core takes as it is."""
    boat = boat_mapping(boat)
    dinghy = build_dinghy(boat.get("sail_model"), boat.get("dinghy"), prefix="boat.")
    checked: dict[str, Any] = {"dinghy": dinghy}
    if "initial_sheet" in boat:
        sheet = boat["initial_sheet"]
        checked["initial_sheet"] = check_number("boat.initial_sheet", sheet, UNIT_INTERVAL)
    if "initial_speed_range" in boat:
        checked["initial_speed_range"] = check_range(
            "boat.initial_speed_range", boat["initial_speed_range"], INITIAL_SPEED_MPS
        )
    return checked


def check_option_key(key: Any) -> None:
    """Raise ``TypeError`` for a reset option key the race does not take but a user may
    mean: one of the sail env's (:data:`SAIL_ONLY_OPTIONS`) or a near miss of one of the
    race's (:data:`NEAR_MISS`). Any other unknown key is ignored, as PettingZoo's and
    Gymnasium's envs ignore options they do not take."""
    if not isinstance(key, str):
        return
    known = list(RESET_OPTIONS)
    path = option_path(key)
    if key.lower() in SAIL_ONLY_OPTIONS:
        raise TypeError(
            f"{path}: the race does not take the sail env's option; its options: {known}"
        )
    close = difflib.get_close_matches(key.lower(), RESET_OPTIONS, n=1, cutoff=NEAR_MISS)
    if close:
        raise TypeError(
            f"{path}: no such race option; did you mean {close[0]!r}? Its options: {known}"
        )


class RaceTask:
    """The race's pure functions over a batch of :class:`RaceState` (NumPy arrays here; the
    same calls as the sail core's, through ``xp``). Holds the validated arguments of
    :class:`~bbgym.envs.race.parallel.BeachballRaceEnv`; its docstring says what each means."""

    def __init__(
        self,
        num_boats: int = 4,
        boat: Mapping[str, Any] | None = None,
        laps: int = 1,
        line_length_m: float = 60.0,
        leg_length_m: float = 120.0,
        gate_depth_m: float = 15.0,
        gate_width_m: float = 30.0,
        countdown_s: float = 30.0,
        start_depth_range: tuple[float, float] = (10.0, 40.0),
        max_race_time_s: float = 600.0,
        wind_speed_range: tuple[float, float] = (3.0, 7.0),
        gusts: bool = True,
        gust_params: Mapping[str, float] | None = None,
        shadow: bool = True,
        shadow_params: Mapping[str, float] | ShadowParams | None = None,
        neighbours: int = 3,
        progress_weight: float = 1.0,
        waypoint_bonus: float = 5.0,
        finish_bonus: float = 20.0,
        ocs_penalty: float = 5.0,
        capsize_penalty: float = 30.0,
        time_penalty: float = 0.1,
        collisions: bool = True,
        restitution: float = 0.3,
        keep_clear_m: float = 0.5,
        penalty: str = "turn",
        penalty_time_s: float = 30.0,
        foul_penalty: float = 2.0,
    ) -> None:
        def count(name: str, value: Any, accepted: Any) -> int:
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
                raise TypeError(f"{name} must be an int, got {value!r}")
            return int(check_number(name, value, accepted))

        self.num_boats = count("num_boats", num_boats, BOATS)
        self.neighbours = min(count("neighbours", neighbours, NEIGHBOURS), self.num_boats - 1)
        self.laps = count("laps", laps, LAPS)
        self.kinds = rc.waypoint_kinds(self.laps)
        self.line_length_m = check_number("line_length_m", line_length_m, LINE_LENGTH_M)
        self.leg_length_m = check_number("leg_length_m", leg_length_m, LEG_LENGTH_M)
        self.gate_depth_m = check_number("gate_depth_m", gate_depth_m, GATE_DEPTH_M)
        self.gate_width_m = check_number("gate_width_m", gate_width_m, GATE_WIDTH_M)
        self.countdown_s = check_number("countdown_s", countdown_s, COUNTDOWN_S)
        self.start_depth_range = check_range("start_depth_range", start_depth_range, START_DEPTH_M)
        self.max_race_time_s = check_number("max_race_time_s", max_race_time_s, RACE_TIME_S)
        self.shadow = check_bool("shadow", shadow)
        self.shadow_params = build_params(ShadowParams, "shadow_params", shadow_params)
        self.shadow_area_m2 = profile_area_m2(self.shadow_params)
        for name in REWARD_WEIGHTS:
            setattr(self, name, check_number(name, locals()[name], REWARD_WEIGHT))
        self.collisions = check_bool("collisions", collisions)
        self.restitution = check_number("restitution", restitution, RESTITUTION)
        self.keep_clear_m = check_number("keep_clear_m", keep_clear_m, KEEP_CLEAR_M)
        if penalty not in PENALTIES:
            raise ValueError(f"penalty must be one of {list(PENALTIES)}, got {penalty!r}")
        self.penalty = penalty
        self.penalty_time_s = check_number("penalty_time_s", penalty_time_s, PENALTY_TIME_S)
        # The boat: the sail core's, with the race's wind. Its reward arguments are unused
        # (the race scores its own); its marks are the race's waypoints, set every step.
        self.sail = SailTask(
            wind_speed_range=wind_speed_range,
            gusts=gusts,
            gust_params=gust_params,
            **check_boat(boat),
        )
        self.ctrl_dt = self.sail.ctrl_dt
        p = self.sail.params
        self.hulls = hulls(p.hull_length_m, p.hull_beam_m, p.mass_kg, p.yaw_inertia_kgm2)
        self.progress_scale_m = BOAT_SPEED_SCALE_MPS * self.ctrl_dt
        size = (
            self.sail.observation_space.shape[0]
            + RACE_OBS_SIZE
            + NEIGHBOUR_OBS_SIZE * self.neighbours
        )
        self.observation_space = spaces.Box(-1.0, 1.0, (size,), np.float32)
        self.action_space = self.sail.action_space
        self.race_column = size - RACE_OBS_SIZE - NEIGHBOUR_OBS_SIZE * self.neighbours
        """Where the race's columns begin (after the sail env's)."""

    # -- scenario ---------------------------------------------------------------------------
    def check_options(self, options: Mapping[str, Any] | None) -> dict[str, Any]:
        """Validate ``reset`` options (the race's mean wind, gusts on or off): a key the race
        does not take is ignored unless :func:`check_option_key` refuses it (a typo of one
        it takes, or the sail env's); bad values name ``options[key]``."""
        if options is None:
            return {}
        if not isinstance(options, Mapping):
            raise TypeError(f"options must be a dict, got {options!r}")
        checked = {}
        for key, value in options.items():
            if key in RESET_OPTIONS:
                checked[key] = value
            else:
                check_option_key(key)
        for key, value in checked.items():
            if key == "gusts":
                checked[key] = check_bool(option_path(key), value)
            else:
                accepted = ANGLE_RAD if key == "wind_from" else WIND_SPEED_MPS
                checked[key] = check_number(option_path(key), value, accepted)
        return checked

    def course(self, state: RaceState, xp: Any) -> rc.Course:
        return rc.lay_course(
            state.wind_from_rad,
            self.line_length_m,
            self.leg_length_m,
            self.gate_depth_m,
            self.gate_width_m,
            xp,
        )

    def initial(self, uniform: Any, normal: Any, options: Mapping[str, Any], xp: Any) -> RaceState:
        """Fresh races from their draws: ``uniform`` ``(races, 2 + 4 K)`` in [0, 1) (the
        mean wind's speed and direction, then each boat's place along the line, depth
        behind it, heading and speed), ``normal`` ``(races, 2)`` (the gusts' start);
        ``options`` pin the wind."""
        k = self.num_boats
        races = uniform.shape[0]
        per_race = [
            xp.reshape(xp.repeat(uniform[:, j : j + 1], k, axis=1), (-1,)) for j in range(2)
        ]
        boat_draws = [xp.reshape(uniform[:, 2 + j * k : 2 + (j + 1) * k], (-1,)) for j in range(4)]
        half = 0.5 + 0.0 * boat_draws[0]
        gust = [xp.reshape(xp.repeat(normal[:, j : j + 1], k, axis=1), (-1,)) for j in range(2)]
        # The sail core's boats: the race's wind, each boat's heading and speed.
        noise = InitialNoise(
            [per_race[0], per_race[1], half, half, boat_draws[2], boat_draws[3]], gust
        )
        boats = self.sail.initial(noise, {key: options[key] for key in options}, xp)
        wind_speed = xp.reshape(boats.scenario.wind_speed_mps, (races, k))[:, 0]
        wind_from = xp.reshape(boats.scenario.wind_from_rad, (races, k))[:, 0]
        course = rc.lay_course(
            wind_from,
            self.line_length_m,
            self.leg_length_m,
            self.gate_depth_m,
            self.gate_width_m,
            xp,
        )
        # Each boat in its own slot along the line, a draw deep behind it.
        slot = (
            xp.reshape(xp.arange(k, dtype=uniform.dtype), (1, k))
            + xp.reshape(boat_draws[0], (races, k))
        ) / k
        lateral = (2.0 * slot - 1.0) * course.line_half_m
        d_lo, d_hi = self.start_depth_range
        depth = d_lo + (d_hi - d_lo) * xp.reshape(boat_draws[1], (races, k))
        x = lateral * course.across_x - depth * course.upwind_x
        y = lateral * course.across_y - depth * course.upwind_y
        no = x > math.inf
        start = xp.zeros_like(x, dtype=xp.int64)
        target_x, target_y = rc.steer_target(course, start, x, y, xp)
        boat = replaced(boats.boat, x_m=xp.reshape(x, (-1,)), y_m=xp.reshape(y, (-1,)))
        scenario = replaced(
            boats.scenario,
            mark_x_m=xp.reshape(target_x, (-1,)),
            mark_y_m=xp.reshape(target_y, (-1,)),
        )
        boats = replaced(boats, boat=boat, scenario=scenario)
        zeros = 0.0 * x
        none = xp.zeros_like(x, dtype=xp.int64)
        return RaceState(
            boats=boats,
            wind_speed_mps=wind_speed,
            wind_from_rad=wind_from,
            clock_s=0.0 * wind_speed - self.countdown_s,
            leg=none,
            ocs=no,
            crossed_s=zeros + math.inf,
            finished=no,
            place=none,
            capsized=no,
            fouling=xp.zeros((races, k, k), dtype=xp.bool),
            fouls=none,
            turns_owed=none,
            turned_rad=zeros,
            penalty_s=zeros,
            touched=no,
            wind_factor=zeros + 1.0,
            wind_bend_rad=zeros,
            progress=zeros,
            waypoint=zeros,
            finish=zeros,
            ocs_penalty=zeros,
            capsize=zeros,
            foul=zeros,
            time=zeros,
        )

    # -- dynamics ---------------------------------------------------------------------------
    def flat(self, array: Array, xp: Any) -> Array:
        return xp.reshape(array, (-1,))

    def per_boat(self, array: Array, xp: Any) -> Array:
        return xp.reshape(array, (-1, self.num_boats))

    def felt_wind(self, state: RaceState, xp: Any) -> tuple[Array, Array]:
        """Each boat's wind for the next step, ``(speed factor, bend)`` ``(races, K)``: the
        race's wind (its mean and gusts) turned by the other boats' shadows, each cast by
        its rig's force in its apparent wind now (:mod:`bbgym.physics.shadow`)."""
        boats, k = state.boats, self.num_boats
        speed = xp.repeat(state.wind_speed_mps[:, None], k, axis=1)
        wind_from = xp.repeat(state.wind_from_rad[:, None], k, axis=1)
        wind_x, wind_y, _, _ = wind_vector(
            self.flat(speed, xp), self.flat(wind_from, xp), boats.gust, xp
        )
        ones = 1.0 + 0.0 * state.wind_bend_rad
        if not self.shadow or k == 1:
            return ones, 0.0 * ones
        boat = boats.boat
        cos_h, sin_h = xp.cos(boat.heading_rad), xp.sin(boat.heading_rad)
        aw_u, aw_v = apparent_wind_body(boat, wind_x, wind_y, cos_h, sin_h)
        jib_sheet = boats.jib_sheet if self.sail.sloop else None
        drive, side = rig_force(self.sail.params, boat, jib_sheet, aw_u, aw_v, xp)
        # body to world
        force_x, force_y = drive * cos_h - side * sin_h, drive * sin_h + side * cos_h
        flow_x, flow_y = wind_x - boat.vx_mps, wind_y - boat.vy_mps
        pb = self.per_boat
        dvx, dvy = shadow_velocity(
            self.shadow_params,
            pb(boat.x_m, xp),
            pb(boat.y_m, xp),
            pb(force_x, xp),
            pb(force_y, xp),
            pb(flow_x, xp),
            pb(flow_y, xp),
            xp.logical_not(state.stopped),
            pb(boat.x_m, xp),
            pb(boat.y_m, xp),
            xp,
            self.shadow_area_m2,
        )
        wx, wy = pb(wind_x, xp), pb(wind_y, xp)
        new_x, new_y = shadowed_wind(wx, wy, dvx, dvy, xp)
        factor = xp.hypot(new_x, new_y) / xp.maximum(xp.hypot(wx, wy), 1e-12)
        bend = wrap_angle(xp.atan2(new_y, new_x) - xp.atan2(wy, wx), xp)
        return factor, bend

    def transition(self, state: RaceState, action: Any, gust_noise: Any, xp: Any) -> RaceState:
        """One step of every race: ``action`` ``(races * K, 2 or 3)`` in [-1, 1] (a boat out
        of the sailing ignores its own), ``gust_noise`` ``(races, 2)`` standard normals (the
        fleet's gusts)."""
        k, course, pb, flat = self.num_boats, self.course(state, xp), self.per_boat, self.flat
        factor, bend = self.felt_wind(state, xp)
        kind = self.kind(state.leg, xp)
        # The point each boat steers for (set at the last step's end): its progress.
        target_x, target_y = (
            pb(state.boats.scenario.mark_x_m, xp),
            pb(state.boats.scenario.mark_y_m, xp),
        )
        speed = xp.repeat(state.wind_speed_mps[:, None], k, axis=1) * factor
        wind_from = xp.repeat(state.wind_from_rad[:, None], k, axis=1) + bend
        boats = state.boats
        scenario = replaced(
            boats.scenario, wind_speed_mps=flat(speed, xp), wind_from_rad=flat(wind_from, xp)
        )
        boats = replaced(boats, scenario=scenario)
        noise = [flat(xp.repeat(gust_noise[:, j : j + 1], k, axis=1), xp) for j in range(2)]
        moved, touched = self.sail_fleet(boats, action, noise, state.stopped, xp)
        moved = tree_select(flat(state.stopped, xp), boats, moved, xp)  # stopped: stays put
        x0, y0 = pb(boats.boat.x_m, xp), pb(boats.boat.y_m, xp)
        x1, y1 = pb(moved.boat.x_m, xp), pb(moved.boat.y_m, xp)
        sailing = xp.logical_not(state.stopped)

        clock = state.clock_s + self.ctrl_dt
        gun = (state.clock_s < 0.0) & (clock >= 0.0)
        after_gun = (clock >= 0.0)[:, None]
        above = rc.above_line(course, x1, y1)
        over_early = gun[:, None] & (above > 0.0) & sailing
        ocs = (state.ocs | over_early) & (above > 0.0)

        # Fouls: a boat that must keep clear, inside keep_clear_m of the other's hull.
        heading = pb(moved.boat.heading_rad, xp)
        gap = hull_contacts(self.hulls, x1, y1, heading, xp).gap_m
        must = rules.keeps_clear(
            self.sail.params.hull_length_m,
            course,
            self.wind_from(moved, xp),
            kind,
            x1,
            y1,
            heading,
            xp,
        )
        pairs = sailing[:, :, None] & sailing[:, None, :]
        fouling = must & pairs & (gap < self.keep_clear_m)
        new_fouls = xp.sum(xp.astype(fouling & xp.logical_not(state.fouling), xp.int64), axis=2)
        owed, turned, penalty_s = state.turns_owed, state.turned_rad, state.penalty_s
        if self.penalty == "turn":
            turned = xp.where(owed > 0, turned + heading - pb(boats.boat.heading_rad, xp), 0.0)
            done_turn = xp.abs(turned) >= 2.0 * math.pi
            owed = owed - xp.astype(done_turn, xp.int64) + new_fouls
            turned = xp.where(done_turn, 0.0, turned)
        else:
            penalty_s = penalty_s + self.penalty_time_s * new_fouls

        passed, fraction = rc.passed_waypoint(course, kind, x0, y0, x1, y1, xp)
        passed = passed & sailing & after_gun & xp.logical_not(ocs) & (state.turns_owed == 0)
        leg = state.leg + xp.astype(passed, xp.int64)
        crossing = passed & (leg >= len(self.kinds))
        crossed_s = xp.where(
            crossing, state.clock_s[:, None] + fraction * self.ctrl_dt, state.crossed_s
        )
        capsized = state.capsized | (
            pb(moved.boat.capsized, xp) & sailing & xp.logical_not(crossing)
        )
        # Finished: crossed and its time penalty served. Places: those before, then this
        # step's by their finishing time (crossing plus penalty), then by number.
        due = crossed_s + penalty_s
        finishing = (
            xp.logical_not(state.finished) & (due <= clock[:, None]) & xp.logical_not(capsized)
        )
        order = xp.arange(k)
        earlier = finishing[:, None, :] & (
            (due[:, None, :] < due[:, :, None])
            | ((due[:, None, :] == due[:, :, None]) & (order[None, None, :] < order[None, :, None]))
        )
        before = xp.sum(xp.astype(state.finished, xp.int64), axis=1)[:, None]
        place = xp.where(
            finishing, before + 1 + xp.sum(xp.astype(earlier, xp.int64), axis=2), state.place
        )

        # Rewards: progress to the point steered for (while sailing, after the gun).
        d0 = xp.hypot(target_x - x0, target_y - y0)
        d1 = xp.hypot(target_x - x1, target_y - y1)
        progress = sail_task.progress_reward(
            d0, d1, self.progress_scale_m, self.progress_weight, xp
        )
        zero = 0.0 * d0
        progress = xp.where(sailing & after_gun, progress, zero)
        waypoint = xp.where(passed & xp.logical_not(crossing), self.waypoint_bonus, zero)
        share = (k - place + 1.0) / k  # the winner takes the whole bonus, the last 1/K
        racing = xp.logical_not(state.out)
        finish_start = racing & after_gun & xp.logical_not(finishing)
        finished = state.finished | finishing
        # What each boat steers for now: the next waypoint's point, from where it is.
        next_x, next_y = rc.steer_target(course, self.kind(leg, xp), x1, y1, xp)
        scenario = replaced(moved.scenario, mark_x_m=flat(next_x, xp), mark_y_m=flat(next_y, xp))
        return RaceState(
            boats=replaced(moved, scenario=scenario),
            wind_speed_mps=state.wind_speed_mps,
            wind_from_rad=state.wind_from_rad,
            clock_s=clock,
            leg=leg,
            ocs=ocs,
            crossed_s=crossed_s,
            finished=finished,
            place=place,
            capsized=capsized,
            fouling=fouling,
            fouls=state.fouls + new_fouls,
            turns_owed=owed,
            turned_rad=turned,
            penalty_s=penalty_s,
            touched=touched,
            wind_factor=factor,
            wind_bend_rad=bend,
            progress=progress,
            waypoint=waypoint,
            finish=xp.where(finishing, self.finish_bonus * share, zero),
            ocs_penalty=xp.where(over_early, -self.ocs_penalty, zero),
            capsize=xp.where(
                capsized & racing & xp.logical_not(state.capsized), -self.capsize_penalty, zero
            ),
            foul=-self.foul_penalty * xp.astype(new_fouls, zero.dtype),
            time=xp.where(finish_start, -self.time_penalty, zero),
        )

    def sail_fleet(
        self, boats: SailState, action: Any, noise: Any, stopped: Array, xp: Any
    ) -> tuple[SailState, Array]:
        """The sail core's transition of every boat, the hulls that touch bouncing off each
        other after every substep (boats ``stopped`` take no part). Returns the boats and
        which touched another during the step ``(races, K)``."""
        if not self.collisions or self.num_boats == 1:
            moved, _ = self.sail.transition(boats, action, noise, xp)
            return moved, self.per_boat(0.0 * moved.boat.x_m, xp) > 0.0
        pb, flat = self.per_boat, self.flat
        active = xp.logical_not(stopped)
        touched = stopped & xp.logical_not(stopped)
        carry = self.sail.begin(boats, action, noise, xp)
        for _ in range(self.sail.n_substeps):
            carry = self.sail.substep(carry, xp)
            boat = carry[0].boat
            x, y, vx, vy, yaw_rate, touching = collide(
                self.hulls,
                self.restitution,
                pb(boat.x_m, xp),
                pb(boat.y_m, xp),
                pb(boat.heading_rad, xp),
                pb(boat.vx_mps, xp),
                pb(boat.vy_mps, xp),
                pb(boat.yaw_rate_rps, xp),
                active,
                xp,
            )
            touched = touched | xp.any(touching, axis=2)
            boat = replaced(
                boat,
                x_m=flat(x, xp),
                y_m=flat(y, xp),
                vx_mps=flat(vx, xp),
                vy_mps=flat(vy, xp),
                yaw_rate_rps=flat(yaw_rate, xp),
            )
            carry = (replaced(carry[0], boat=boat), *carry[1:])
        moved, _ = self.sail.end(boats, carry, xp)
        return moved, touched

    def kind(self, leg: Array, xp: Any) -> Array:
        """The kind of the waypoint each boat sails to (:mod:`bbgym.envs.race.course`);
        past the finish, the finish's."""
        kinds = xp.asarray(self.kinds, dtype=xp.int64)
        return kinds[xp.clip(leg, 0, len(self.kinds) - 1)]

    def reward(self, state: RaceState, xp: Any) -> Array:
        """Each boat's reward for the last step ``(races, K)``: the sum of its terms."""
        return sum(getattr(state, field) for field in REWARD_TERMS.values())

    def terminal(self, state: RaceState, xp: Any) -> Array:
        """Each boat's race has ended: finished (its penalty served) or capsized
        ``(races, K)``."""
        return state.out

    def timed_out(self, state: RaceState, xp: Any) -> Array:
        """The race's time is up ``(races,)``."""
        return state.clock_s >= self.max_race_time_s

    # -- what the boats see -----------------------------------------------------------------
    def observation(self, state: RaceState, xp: Any) -> Array:
        """Every boat's observation ``(races, K, size)``, float32, clipped to [-1, 1]: the
        sail core's columns (its mark the waypoint steered for), the race's, then the
        nearest neighbours' (the env's docstring table)."""
        boats, k = state.boats, self.num_boats
        m = self.sail.measure(boats, xp)
        own = xp.stack(self.sail.observation(boats, m, xp), axis=1)
        own = xp.reshape(own, (-1, k, own.shape[1]))
        course, boat = self.course(state, xp), boats.boat
        pb = self.per_boat
        x, y, heading = pb(boat.x_m, xp), pb(boat.y_m, xp), pb(boat.heading_rad, xp)
        cos_h, sin_h = xp.cos(heading), xp.sin(heading)
        scale = 2.0 * self.sail.mark_distance_range[1]
        columns = [
            xp.repeat((-state.clock_s / max(self.countdown_s, 1.0))[:, None], k, axis=1),
            xp.repeat((state.clock_s / self.max_race_time_s)[:, None], k, axis=1),
            xp.astype(state.leg > 0, x.dtype),
            xp.astype(state.ocs, x.dtype),
            xp.astype(state.leg, x.dtype) / len(self.kinds),
            xp.astype(state.turns_owed, x.dtype) / 2.0 + state.penalty_s / PENALTY_SCALE_S,
        ]
        for end_x, end_y in course.ends():
            ahead, left = split_along(end_x - x, end_y - y, cos_h, sin_h)
            distance = xp.maximum(xp.hypot(ahead, left), 1e-9)
            columns += [ahead / distance, left / distance, distance / scale]
        race = xp.stack(columns, axis=2)
        parts = [own, race]
        if self.neighbours:
            parts.append(self.neighbour_columns(state, xp))
        obs = xp.clip(xp.concat(parts, axis=2), -1.0, 1.0)
        return xp.astype(obs, xp.float32)

    def wind_from(self, boats: SailState, xp: Any) -> Array:
        """Where each boat's true wind comes from now ``(races, K)``: the race's, shadowed,
        with the gusts' shift (as :func:`bbgym.physics.wind.wind_vector` has it)."""
        return self.per_boat(boats.scenario.wind_from_rad + boats.gust.shift, xp)

    def right_of_way(self, state: RaceState, xp: Any) -> Array:
        """``[.., i, j]``: boat ``i`` must keep clear of boat ``j`` now
        (:func:`bbgym.envs.race.rules.keeps_clear`)."""
        boat, pb = state.boats.boat, self.per_boat
        return rules.keeps_clear(
            self.sail.params.hull_length_m,
            self.course(state, xp),
            self.wind_from(state.boats, xp),
            self.kind(state.leg, xp),
            pb(boat.x_m, xp),
            pb(boat.y_m, xp),
            pb(boat.heading_rad, xp),
            xp,
        )

    def neighbour_columns(self, state: RaceState, xp: Any) -> Array:
        """The nearest ``neighbours`` other boats still sailing, nearest first, each as
        (present, position ahead and to port, velocity ahead and to port relative to this
        boat's, cos and sin of its heading relative to this boat's, right of way: -1 this
        boat must keep clear of it, 1 it must keep clear of this boat); absent ones zeros."""
        boat, k = state.boats.boat, self.num_boats
        pb = self.per_boat
        x, y = pb(boat.x_m, xp), pb(boat.y_m, xp)
        vx, vy, heading = pb(boat.vx_mps, xp), pb(boat.vy_mps, xp), pb(boat.heading_rad, xp)
        dx, dy = x[:, None, :] - x[:, :, None], y[:, None, :] - y[:, :, None]  # (i, j)
        present = (
            xp.logical_not(state.stopped)[:, None, :]
            & xp.logical_not(xp.eye(k, dtype=xp.bool))[None, :, :]
        )
        distance = xp.where(present, xp.hypot(dx, dy), math.inf)
        order = xp.argsort(distance, axis=2)[:, :, : self.neighbours]
        cos_h, sin_h = xp.cos(heading)[:, :, None], xp.sin(heading)[:, :, None]
        ahead, left = split_along(dx, dy, cos_h, sin_h)
        v_ahead, v_left = split_along(
            vx[:, None, :] - vx[:, :, None], vy[:, None, :] - vy[:, :, None], cos_h, sin_h
        )
        turn = heading[:, None, :] - heading[:, :, None]
        must = self.right_of_way(state, xp)
        way = xp.astype(xp.matrix_transpose(must), x.dtype) - xp.astype(must, x.dtype)
        here = xp.astype(present, x.dtype)
        pick = [
            here,
            ahead / RELATIVE_SCALE_M,
            left / RELATIVE_SCALE_M,
            v_ahead / BOAT_SPEED_SCALE_MPS,
            v_left / BOAT_SPEED_SCALE_MPS,
            xp.cos(turn),
            xp.sin(turn),
            way,
        ]
        columns = [
            xp.take_along_axis(c, order, axis=2) * xp.take_along_axis(here, order, axis=2)
            for c in pick
        ]
        # (races, K, neighbours, 8) -> (races, K, 8 * neighbours), neighbour by neighbour
        stacked = xp.stack(columns, axis=3)
        return xp.reshape(stacked, (stacked.shape[0], k, -1))

    def info(self, state: RaceState, xp: Any) -> dict[str, Any]:
        """Each boat's physical quantities and race standing, ``(races, K, ...)`` arrays."""
        boats, k = state.boats, self.num_boats
        boat, pb = boats.boat, self.per_boat
        m = self.sail.measure(boats, xp)
        return {
            "position": xp.reshape(stack_pair(boat.x_m, boat.y_m, xp), (-1, k, 2)),
            "velocity": xp.reshape(stack_pair(boat.vx_mps, boat.vy_mps, xp), (-1, k, 2)),
            "heading": pb(wrap_angle(boat.heading_rad, xp), xp),
            "boat_speed": pb(m["boat_speed"], xp),
            "true_wind_speed": pb(m["true_wind_speed"], xp),
            "true_wind_angle": pb(m["true_wind_angle"], xp),
            "heel": pb(boat.heel_rad, xp),
            "capsized": pb(boat.capsized, xp),
            "wind_factor": state.wind_factor,
            "wind_bend": state.wind_bend_rad,
            "leg": state.leg,
            "ocs": state.ocs,
            "finished": state.finished,
            "is_success": state.finished,
            "place": state.place,
            "finish_time": state.crossed_s + state.penalty_s,
            "touched": state.touched,
            "fouls": state.fouls,
            "turns_owed": state.turns_owed,
            "penalty_owed": state.penalty_s,
            "race_clock": xp.repeat(state.clock_s[:, None], k, axis=1),
            "distance_to_waypoint": pb(m["distance_to_mark"], xp),
            "reward_terms": {name: getattr(state, f) for name, f in REWARD_TERMS.items()},
        }
