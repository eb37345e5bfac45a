"""A throw's flight, from launch to rest: the ball's laws (:mod:`bbgym.physics.ball`) run
in fixed substeps, finished balls frozen, the ground touchdown, the screen and the apex
recorded (seed §3-§6, §8).

:func:`simulate_throw` flies a batch to the end, driving :func:`flight_start`,
:func:`flight_chunk` and :func:`flight_result`; a compiled backend runs the same three
parts (:func:`fly` is the loop they share). Like the laws, every function is pure and
written against an array namespace ``xp``.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.ball import (
    BallParams,
    BallState,
    ball_at_rest,
    ground_contact,
    magnus_force,
    panel_contact,
    substep,
)
from bbgym.physics.compaction import scatter, take
from bbgym.physics.namespace import Array, replaced, select, skippable


class Screen(NamedTuple):
    """A vertical panel the ball cannot pass through (see :func:`panel_contact`)."""

    center_x: Array
    center_y: Array
    along_x: Array
    along_y: Array
    half_width_m: Array
    height_m: Array
    enabled: Array
    restitution: float = 0.4


class BallPose(NamedTuple):
    """Where a ball is and how it is turned: what a trajectory records (for plots and for
    drawing the stripes), without the velocities and spin."""

    x: Array
    y: Array
    z: Array
    qw: Array
    qx: Array
    qy: Array
    qz: Array


def pose_of(s: BallState) -> BallPose:
    return BallPose(s.x, s.y, s.z, s.qw, s.qx, s.qy, s.qz)


class ThrowResult(NamedTuple):
    """Outcome of :func:`simulate_throw`, per ball."""

    landing_x: Array
    """First touchdown (where the ball was when it first touched the ground)."""
    landing_y: Array
    flight_time_s: Array
    """Time to the first touchdown."""
    apex_height_m: Array
    spin_parameter: Array
    """``S = r |omega| / |v|`` at launch."""
    hit_screen: Array
    final: BallState
    trajectory: list
    """Ball poses every ``record_dt_s``, first at launch (list of :class:`BallPose`)."""
    steps: Array
    """Number of recorded samples that belong to each ball's flight."""


class Flight(NamedTuple):
    """What a flight carries from substep to substep (:func:`flight_chunk`), per ball.

    Everything is an array of the batch (or a Python number for one ball), the substep
    counter included, so a compiled chunk sees the same kinds of inputs on every call."""

    ball: BallState
    landed: Array
    """Touched the ground at least once."""
    landing_x: Array
    """First touchdown (meaningful once ``landed``)."""
    landing_y: Array
    flight_time_s: Array
    """Time to the first touchdown (meaningful once ``landed``)."""
    apex_height_m: Array
    hit_screen: Array
    done: Array
    """Finished (at rest, rolled long enough or out of the field): frozen from then on."""
    end_time_s: Array
    """Time of the last substep flown."""
    steps: Array
    """Recorded samples that belong to the ball's flight (int64), the launch's included."""
    samples: Array
    """Recorded samples with any ball of the batch still flying (int64, the same count
    for every ball)."""
    substep: Array
    """Number of the next substep (substep ``i`` ends at ``i * dt_s``), in the balls'
    float dtype (exact: at most ``FLIGHT_SUBSTEPS_MAX`` substeps)."""


FLIGHT_SUBSTEPS_MAX = 2**24
"""Substeps a flight may have: float32 counts them exactly up to here."""


def flight_start(p: BallParams, launch: BallState, xp: Any = np) -> Flight:
    """A flight at its launch: nothing landed, hit or done; the launch recorded. Every
    field is an array of its own (none is another's, nor the launch's): a compiled chunk
    sees the same aliasing on every call."""
    return Flight(
        ball=launch,
        landed=xp.zeros_like(launch.x, dtype=xp.bool),
        landing_x=launch.x + 0.0,
        landing_y=launch.y + 0.0,
        flight_time_s=xp.zeros_like(launch.x),
        apex_height_m=launch.z + 0.0,
        hit_screen=xp.zeros_like(launch.x, dtype=xp.bool),
        done=xp.zeros_like(launch.x, dtype=xp.bool),
        end_time_s=xp.zeros_like(launch.x),
        steps=xp.zeros_like(launch.x, dtype=xp.int64) + 1,
        samples=xp.zeros_like(launch.x, dtype=xp.int64) + 1,
        substep=xp.zeros_like(launch.x) + 1.0,
    )


def flight_chunk(
    p: BallParams,
    flight: Flight,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None,
    dt_s: float,
    substeps: int,
    last: int,
    record_every: int,
    record: bool = True,
    xp: Any = np,
    max_roll_s: float | None = None,
    field_radius_m: float = 30.0,
) -> tuple[Flight, list]:
    """The next ``substeps`` substeps of a flight (from ``flight.substep`` on), a fixed
    number: a finished ball is frozen where it stopped, and so is every ball after substep
    ``last`` (every update is masked). The substep number is an array, so one compiled
    chunk serves every call. Returns the flight and, if ``record``, the pose after every
    substep (:func:`recorded_poses` keeps those of the record)."""
    poses = []
    for _ in range(substeps):
        flight, pose = _flight_substep(
            p,
            flight,
            wind_x,
            wind_y,
            screen,
            dt_s,
            last,
            record_every,
            xp,
            max_roll_s,
            field_radius_m,
        )
        if record:
            poses.append(pose)
    return flight, poses


def recorded_poses(poses: list, first_substep: int, record_every: int, last: int) -> list:
    """Of the poses after substeps ``first_substep, first_substep + 1, ...`` (from
    :func:`flight_chunk`), those the record keeps: every ``record_every``-th substep, up to
    substep ``last``."""
    return [
        pose for i, pose in enumerate(poses, first_substep) if i % record_every == 0 and i <= last
    ]


def _flight_substep(
    p: BallParams,
    f: Flight,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None,
    dt_s: float,
    last: int,
    record_every: int,
    xp: Any,
    max_roll_s: float | None,
    field_radius_m: float,
) -> tuple[Flight, BallPose]:
    """Substep ``f.substep`` of every ball still flying: air, screen, ground, then the
    bookkeeping."""
    i = f.substep
    before = f.ball
    frozen = f.done | (i > last)
    flying = xp.logical_not(frozen)
    s = substep(p, before, wind_x, wind_y, dt_s, xp)
    hit_screen = f.hit_screen
    if screen is not None:
        s, hit = _screen_contact(p, s, screen, xp)
        hit_screen = hit_screen | (hit & flying)
    flown = s
    s, touching = ground_contact(p, s, dt_s, xp)
    first = touching & xp.logical_not(f.landed) & flying
    landed, landing_x, landing_y, flight_time = f.landed, f.landing_x, f.landing_y, f.flight_time_s
    if not skippable(first):  # some ball touches down for the first time
        x, y, t = _touchdown(p, before, flown, i, dt_s, xp)
        landed = landed | first
        landing_x, landing_y = xp.where(first, x, landing_x), xp.where(first, y, landing_y)
        flight_time = xp.where(first, t, flight_time)
    if not skippable(frozen):
        s = select(frozen, before, s, xp)
    steps, samples = f.steps, f.samples
    recorded = (i % record_every) == 0
    if not skippable(recorded):
        steps = steps + xp.astype(flying & recorded, xp.int64)
        samples = samples + xp.astype(xp.any(flying) & recorded, xp.int64)
    now = i * dt_s
    finished = _finished(p, s, landed, flight_time, now, max_roll_s, field_radius_m, xp)
    new = Flight(
        ball=s,
        landed=landed,
        landing_x=landing_x,
        landing_y=landing_y,
        flight_time_s=flight_time,
        # a frozen ball's height is in its apex already: no mask needed
        apex_height_m=xp.maximum(f.apex_height_m, s.z),
        hit_screen=hit_screen,
        done=f.done | (flying & finished),
        end_time_s=xp.where(frozen, f.end_time_s, now),
        steps=steps,
        samples=samples,
        substep=i + 1.0,
    )
    # Only a recorded substep's pose is kept (recorded_poses): the host skips the others'.
    return new, None if skippable(recorded) else pose_of(s)


def flight_result(
    flight: Flight, spin_parameter: Array, trajectory: list, xp: Any = np
) -> ThrowResult:
    """The outcome: a ball that never touched down (it left the field, or time ran out)
    "lands" where it is, when the flight ended."""
    never = xp.logical_not(flight.landed)
    final = flight.ball
    return ThrowResult(
        xp.where(never, final.x, flight.landing_x),
        xp.where(never, final.y, flight.landing_y),
        xp.where(never, flight.end_time_s, flight.flight_time_s),
        flight.apex_height_m,
        spin_parameter,
        flight.hit_screen,
        final,
        trajectory,
        flight.steps,
    )


def sample_count(samples: Array, xp: Any = np) -> int:
    """The number of recorded samples of a batch (:attr:`Flight.samples`, or another count
    the same for every ball) as an int."""
    return int(samples) if isinstance(samples, (int, float)) else int(xp.max(samples))


def launch_spin_parameter(
    p: BallParams, launch: BallState, wind_x: Array, wind_y: Array, xp: Any = np
) -> Array:
    """``S = r |omega| / |v|`` at launch, against the air."""
    return magnus_force(
        p, launch.vx - wind_x, launch.vy - wind_y, launch.vz, launch.wx, launch.wy, launch.wz, xp
    )[3]


CHECK_EVERY_ARRAYS = 16
"""Substeps between the "all done?" checks of a batch (a device sync on a GPU)."""


def simulate_throw(
    p: BallParams,
    launch: BallState,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None = None,
    dt_s: float = 0.01,
    max_time_s: float = 6.0,
    max_roll_s: float | None = None,
    field_radius_m: float = 30.0,
    record_dt_s: float = 0.05,
    xp: Any = np,
    check_every: int | None = None,
    record: bool = True,
) -> ThrowResult:
    """Fly balls from launch until they rest on the ground, leave the field or time runs out
    (``max_time_s`` in all, or ``max_roll_s`` after the first touchdown).

    The wind is held during the flight (a gust outlasts a throw). A finished ball is frozen
    where it stopped; the loop stops once all are finished, checked every ``check_every``
    substeps (default: every substep for Python floats, where the check is free, else
    :data:`CHECK_EVERY_ARRAYS`). The results do not depend on ``check_every``. All fields of
    ``launch`` share one shape (as :func:`ball_at` makes them). Without ``record`` the
    trajectory is empty (``steps`` still counts).
    """
    spin_parameter = launch_spin_parameter(p, launch, wind_x, wind_y, xp)
    record_every = flight_record_every(dt_s, record_dt_s)
    last = flight_substeps(dt_s, max_time_s)
    flight, poses = fly(
        p,
        flight_start(p, launch, xp),
        wind_x,
        wind_y,
        screen,
        dt_s,
        last,
        record_every,
        record,
        xp,
        max_roll_s,
        field_radius_m,
        check_every,
    )
    trajectory = [pose_of(launch), *poses] if record else []
    return flight_result(flight, spin_parameter, trajectory, xp)


def fly(
    p: BallParams,
    flight: Flight,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None,
    dt_s: float,
    last: int,
    record_every: int,
    record: bool = True,
    xp: Any = np,
    max_roll_s: float | None = None,
    field_radius_m: float = 30.0,
    check_every: int | None = None,
) -> tuple[Flight, list]:
    """A flight from ``flight.substep`` to its end on the host: :func:`flight_chunk` of
    ``check_every`` substeps (default: 1 for Python floats, where the check is free, else
    :data:`CHECK_EVERY_ARRAYS`) until every ball is done or substep ``last`` is flown.
    Returns the flight and the recorded poses after the launch (those of the record, up to
    the last ball's finish).

    On NumPy the loop flies only the balls still in the air: it drops the finished ones from
    its working set between chunks and puts them back at the end, so a batch costs what its
    flights do rather than its longest flight times its size. A dropped ball is frozen
    either way: the results are those of the masked loop, bit for bit. (A compiled step
    cannot change shapes; it runs :func:`flight_chunk` with every ball.)"""
    if check_every is None:
        check_every = 8 if isinstance(flight.ball.x, (int, float)) else CHECK_EVERY_ARRAYS
    compacting = xp is np and np.ndim(flight.ball.x) == 1
    screen = _without_idle_screen(screen)
    full, working = flight, None  # working: indices of the balls flown (None: all)
    poses: list = []
    frozen_pose = pose_of(flight.ball)
    i = sample_count(flight.substep, xp)  # the same for every ball
    while i <= last:
        n = min(check_every, last + 1 - i)
        flight, chunk_poses = flight_chunk(
            p,
            flight,
            wind_x,
            wind_y,
            screen,
            dt_s,
            n,
            last,
            record_every,
            record,
            xp,
            max_roll_s,
            field_radius_m,
        )
        kept = recorded_poses(chunk_poses, i, record_every, last)
        poses += kept if working is None else [scatter(frozen_pose, working, q) for q in kept]
        i += n
        done = flight.done
        if bool(xp.all(done)):
            break
        if compacting and done.any():
            full = _scatter_flight(full, working, flight)
            frozen_pose = pose_of(full.ball)
            keep = np.flatnonzero(~done)
            working = keep if working is None else working[keep]
            size = done.shape[0]  # the working set's, before this drop
            flight = take(flight, keep)
            wind_x, wind_y = take(wind_x, keep, size), take(wind_y, keep, size)
            screen = None if screen is None else take(screen, keep, size)
        screen = _without_idle_screen(screen)
    if working is not None:
        flight = _scatter_flight(full, working, flight)
    if record:  # a chunk may run past the last ball's finish: those samples are not kept
        del poses[sample_count(flight.samples, xp) - 1 :]
    return flight, poses


def _without_idle_screen(screen: Screen | None) -> Screen | None:
    """``None`` for a screen no ball has (on the host: no panel contact to test)."""
    return None if screen is None or skippable(screen.enabled) else screen


def _scatter_flight(full: Flight, working: np.ndarray | None, flown: Flight) -> Flight:
    """:func:`~bbgym.physics.compaction.scatter` of a flight; the batch-wide counters
    (samples recorded, next substep) are the working set's: the masked loop counts them for
    every ball alike."""
    if working is None:
        return flown
    return replaced(
        scatter(full, working, flown),
        samples=np.full_like(full.samples, flown.samples[0]),
        substep=np.full_like(full.substep, flown.substep[0]),
    )


def flight_record_every(dt_s: float, record_dt_s: float = 0.05) -> int:
    """Substeps between two recorded poses."""
    return max(1, round(record_dt_s / dt_s))


def flight_substeps(dt_s: float, max_time_s: float) -> int:
    """The substeps of a flight of at most ``max_time_s``."""
    return int(round(max_time_s / dt_s))


def _touchdown(
    p: BallParams, before: BallState, after: BallState, i: Array, dt_s: float, xp: Any
) -> tuple[Array, Array, Array]:
    """Where and when the ball first touched the ground during substep ``i`` (an array or
    a number): linear interpolation to the moment its centre was one radius up, so the
    landing point does not depend on where the substep happened to end."""
    drop = before.z - after.z
    f = xp.clip((before.z - p.radius_m) / xp.where(drop > 0.0, drop, 1.0), 0.0, 1.0)
    x = before.x + f * (after.x - before.x)
    y = before.y + f * (after.y - before.y)
    return x, y, (i - 1 + f) * dt_s


def _screen_contact(p: BallParams, s: BallState, screen: Screen, xp: Any) -> tuple:
    return panel_contact(
        s,
        p.radius_m,
        screen.center_x,
        screen.center_y,
        screen.along_x,
        screen.along_y,
        screen.half_width_m,
        screen.height_m,
        screen.restitution,
        screen.enabled,
        xp,
    )


def _finished(
    p: BallParams,
    s: BallState,
    landed: Any,
    flight_time: Any,
    t: float,
    max_roll_s: Any,
    field_radius_m: float,
    xp: Any,
) -> Any:
    """Landed and at rest (:func:`ball_at_rest`), or rolled long enough after landing, or out of
    the field."""
    at_rest = landed & ball_at_rest(p, s)
    if max_roll_s is not None:  # a ball blown along the ground may never stop
        at_rest = at_rest | (landed & (t - flight_time > max_roll_s))
    return at_rest | (s.x * s.x + s.y * s.y > field_radius_m * field_radius_m)
