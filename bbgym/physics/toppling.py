"""Topple's interval as pure physics: a ball flies, the wind gusts, hits and wind rock the wall.

One step of BeachballTopple is a throw (or a wait) followed by ``n_substeps`` substeps of
``sim_dt``. Substep ``i`` does, for every env still running:

1. if ``i`` is a positive multiple of ``gust_every``, the gust process takes its next pair
   of standard normals, pair ``i // gust_every - 1`` of the env's pre-drawn window (an env
   draws only while it runs with gusts: :attr:`IntervalCarry.noise_used` counts its pairs,
   so the caller consumes exactly those from the env's stream);
2. if ``i`` is a multiple of ``record_every``, a sample (ball pose, wall angle, loose
   panel) is kept, if recording, and counted for the envs running;
3. a moving ball flies, bounces, and may strike the wall (an impulse on both);
4. the wall rocks, topples, breaks loose or flies;
5. an env stops once its wall is down (a loose panel: landed) and its ball has stopped,
   or once its wall is down and no ball flies.

Steps 3 and 4 are the integrator's (:attr:`IntervalParams.integrator`): one semi-implicit
Euler substep of each body, its contacts found at the substep's end (:func:`euler_bodies`,
Topple-v0 and -v1, 0.01 s), or one RK4 step of each with the ball's bounce or hit located
inside it (:func:`event_bodies`, Topple-v2, 0.05 s).

Every update is masked (``xp.where``) instead of skipped: a stopped env, or a ball at rest,
keeps exactly its values, so the result does not depend on how the envs are batched nor on
how many substeps run past the last env's stop. :func:`interval_chunk` runs
:attr:`IntervalParams.chunk_substeps` substeps, always the same function: the substep
index is an int64 array in the carry (a Python int on floats), the gust update, the
choice of its noise pair and the samples' count are masks on it, and substeps past the
interval's end are masked off, so ``torch.compile`` traces one chunk once, and the
results do not depend on the chunk's length. :func:`run_interval` runs the chunks and
stops early when no env runs (``bool(xp.any(...))``, a device sync on a GPU, once per
chunk). Recording (NumPy or floats, never compiled) keeps every substep's sample (the
arrays as they are: no copies); the caller keeps every ``record_every``-th, the first
``samples[i]`` of them for env ``i``. One env on Python floats (never compiled) skips the
updates whose mask is false: the same values, faster. The states are immutable
NamedTuples of arrays (:func:`select` also takes dataclasses), on any array API namespace
(:mod:`bbgym.physics.namespace`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.ball import BallParams, ball_at_rest, ground_contact
from bbgym.physics.ball import substep as ball_substep
from bbgym.physics.compaction import scatter, take
from bbgym.physics.flight_events import (
    combine_cubics,
    cubic_at,
    descent_root,
    rk4_cubics,
    state_at,
)
from bbgym.physics.namespace import Array, floats, replaced, select, skippable
from bbgym.physics.wall import (
    LOOSE,
    STANDING,
    WallParams,
    ball_hits_wall,
    face_frame,
    wall_rk4_step,
    wall_step,
)
from bbgym.physics.wind import GustParams, gust_step, wind_vector

SAMPLE_FIELDS = (
    "x",
    "y",
    "z",
    "qw",
    "qx",
    "qy",
    "qz",
    "wall_angle",
    "loose_x",
    "loose_z",
    "loose_angle",
    "status",
)
"""What one recorded sample holds, in order: the ball's position and orientation, the
wall's lean, the loose panel's centre and angle, the wall's status code."""


INTEGRATORS = ("semi_implicit_euler", "rk4_events")
"""How an interval's substep moves the bodies: ``semi_implicit_euler``, one semi-implicit
Euler step of the ball and of the wall, each contact found at the substep's end
(Topple-v0, -v1, in substeps of 0.01 s: :func:`euler_bodies`); ``rk4_events``, one RK4
step of each with the ball's bouncing touchdown and its hit on the wall located inside
the step (Topple-v2, in steps of 0.05 s: :func:`event_bodies`)."""


@dataclass(frozen=True)
class IntervalParams:
    """What an interval needs besides the states: the bodies, the gusts and the clocks."""

    wall: WallParams
    ball: BallParams
    gust: GustParams
    sim_dt: float
    gust_dt: float
    n_substeps: int
    gust_every: int
    record_every: int
    chunk_substeps: int = 1
    """Substeps per :func:`interval_chunk` (any: the results do not depend on it)."""
    integrator: str = "semi_implicit_euler"
    """How a substep moves the ball and the wall (:data:`INTEGRATORS`)."""

    @property
    def n_gust_updates(self) -> int:
        """Gust updates in an interval (at substeps ``gust_every, 2 gust_every, ...``): the
        pairs of the noise window."""
        return (self.n_substeps - 1) // self.gust_every

    @property
    def n_chunks(self) -> int:
        """Chunks per interval (the last may run past its end, masked off)."""
        return -(-self.n_substeps // self.chunk_substeps)


class IntervalCarry(NamedTuple):
    """The interval's state between substeps, per env: the ball, wall and gust states, the
    wind now, whether the ball flies and the env runs, ball hits so far (int64), height and
    sideways position of the last hit (-1 and 0 if none), samples taken while running
    (int64), noise pairs used (int64), the next substep's index (int64; a Python int on
    floats) and the samples taken (when recording a tuple of one tuple of
    :data:`SAMPLE_FIELDS` per substep run, else ``None``)."""

    ball: Any
    wall: Any
    gust: Any
    wind_x: Array
    wind_y: Array
    flying: Array
    running: Array
    hits: Array
    hit_height: Array
    hit_y: Array
    samples: Array
    noise_used: Array
    substep: Array
    taken: tuple | None


def _with(state: Any, **changes: Any) -> Any:
    if isinstance(state, tuple):
        return replaced(state, **changes)
    return dataclasses.replace(state, **changes)


def _row(noise: Any, r: int) -> Any:
    """Row ``r`` of a window: of an array (``(2 k, batch)``) or of a sequence of rows."""
    return noise[r, ...] if hasattr(noise, "shape") else noise[r]


def noise_rows(noise: Any, count: int) -> tuple:
    """The ``count`` rows of a window (an array or a sequence of rows) as a tuple."""
    return tuple(_row(noise, r) for r in range(count))


def noise_pair(noise: Any, index: Array, count: int, xp: Any) -> tuple[Array, Array]:
    """Pair ``index[i]`` (per env) of a window of ``count`` pairs, given as a sequence of
    ``2 * count`` rows (pair ``j``: rows ``2j``, ``2j + 1``): a masked sum over the pairs
    (fixed shapes, no indexing by values; exact: the other terms are zeros), zeros where
    ``index`` is out of range. One env on floats indexes directly."""
    if xp is floats:
        if 0 <= index < count:
            return noise[2 * index], noise[2 * index + 1]
        return 0.0, 0.0
    first = second = None
    for j in range(count):
        pick = index == j
        a = xp.where(pick, _row(noise, 2 * j), 0.0)
        b = xp.where(pick, _row(noise, 2 * j + 1), 0.0)
        first, second = (a, b) if first is None else (first + a, second + b)
    return first, second


def interval_start(
    params: IntervalParams,
    ball: Any,
    wall: Any,
    gust: Any,
    wind_speed: Array,
    wind_from: Array,
    flying: Array,
    running: Array,
    xp: Any,
    record: bool = False,
) -> IntervalCarry:
    """The carry at substep 0: ``flying`` where a ball was thrown, ``running`` where the
    env takes part (a stopped env keeps all its values); ``record`` keeps the samples."""
    wind_x, wind_y, _, _ = wind_vector(wind_speed, wind_from, gust, xp)

    def count(like: Array) -> Array:
        return xp.zeros_like(like, dtype=xp.int64)

    # Each field its own array, made from a different one (torch.compile guards on which
    # of a compiled function's inputs are one tensor: aliases that part would recompile).
    return IntervalCarry(
        ball=ball,
        wall=wall,
        gust=gust,
        wind_x=wind_x,
        wind_y=wind_y,
        flying=flying,
        running=running,
        hits=count(wall.angle),
        hit_height=xp.zeros_like(wall.rate) - 1.0,
        hit_y=xp.zeros_like(wall.pivot),
        samples=count(wall.status),
        noise_used=count(wall.base_x),
        substep=0 if xp is floats else count(wall.loose_x),
        taken=() if record else None,
    )


def interval_substep(
    params: IntervalParams,
    c: IntervalCarry,
    offset: int,
    wind_speed: Array,
    wind_from: Array,
    gusts: Array,
    noise: Any,
    xp: Any,
) -> IntervalCarry:
    """One substep (module docstring), every update masked. ``offset``: the substep's place
    in its chunk (a Python int; ``c.substep`` is ``offset`` modulo the chunk's length);
    ``gusts``: per env, whether its wind gusts; ``noise``: the window, ``2 *
    n_gust_updates`` rows (:func:`noise_pair`)."""
    i = c.substep
    live = c.running & (i < params.n_substeps)
    if xp is floats and not live:  # one env, stopped or past the end: nothing changes
        return replaced(c, substep=i + 1)
    gust, wind_x, wind_y, noise_used = c.gust, c.wind_x, c.wind_y, c.noise_used
    ge, count = params.gust_every, params.n_gust_updates
    # A gust update can fall here only if the offset is a multiple of gcd(chunk, gust_every).
    if count and offset % math.gcd(params.chunk_substeps, ge) == 0:
        tick = live & (i % ge == 0) & (i > 0)
        if xp is not floats or tick:
            draw = gusts & tick
            pair = noise_pair(noise, i // ge - 1, count, xp)
            drawn = tuple(xp.where(draw, pair[j], 0.0) for j in (0, 1))
            stepped = gust_step(gust, params.gust, params.gust_dt, drawn, gusts, xp)
            gust = select(tick, stepped, gust, xp)
            # Unchanged gusts give the wind they gave: recomputed for all, the same values.
            wind_x, wind_y, _, _ = wind_vector(wind_speed, wind_from, gust, xp)
            noise_used = noise_used + xp.astype(draw, xp.int64)
    ball, wall = c.ball, c.wall
    samples, taken = c.samples, c.taken
    if taken is not None:  # recording (never compiled): every substep, cut by the caller
        sample = (
            ball.x,
            ball.y,
            ball.z,
            ball.qw,
            ball.qx,
            ball.qy,
            ball.qz,
            wall.angle,
            wall.loose_x,
            wall.loose_z,
            wall.loose_angle,
            wall.status,
        )
        taken = (*taken, sample)
    re = params.record_every
    if params.chunk_substeps % re:  # which substeps sample: known only per env
        samples = samples + xp.astype(live & (i % re == 0), xp.int64)
    elif offset % re == 0:  # chunks start at multiples of record_every
        samples = samples + xp.astype(live, xp.int64)
    bodies = euler_bodies if params.integrator == "semi_implicit_euler" else event_bodies
    ball, wall, flying, hits, hit_height, hit_y = bodies(params, c, live, wind_x, wind_y, xp)
    settled = (wall.status != STANDING) & ((wall.status != LOOSE) | wall.landed)
    done = (settled | xp.logical_not(flying)) & (wall.status != STANDING)
    running = c.running & xp.logical_not(done & live)
    return IntervalCarry(  # in field order (faster than keywords, every substep)
        ball,
        wall,
        gust,
        wind_x,
        wind_y,
        flying,
        running,
        hits,
        hit_height,
        hit_y,
        samples,
        noise_used,
        i + 1,
        taken,
    )


def euler_bodies(
    params: IntervalParams, c: IntervalCarry, live: Array, wind_x: Array, wind_y: Array, xp: Any
) -> tuple:
    """One semi-implicit Euler substep of the ball and the wall (``semi_implicit_euler``):
    the ball flies (:func:`~bbgym.physics.ball.substep`), bounces, and strikes the wall if
    it ends the substep within a radius of its face; then the wall steps
    (:func:`~bbgym.physics.wall.wall_step`). Returns ``(ball, wall, flying, hits,
    hit_height, hit_y)``."""
    wp, p, dt = params.wall, params.ball, params.sim_dt
    ball, wall = c.ball, c.wall
    # The ball: only a moving one flies and strikes (one at rest against the face must not
    # change the wall's rate).
    moving = c.flying & live
    flying, hits, hit_height, hit_y = c.flying, c.hits, c.hit_height, c.hit_y
    # One env on floats (never compiled, where a Python ``if`` costs nothing) skips an
    # update whose mask is false, which would leave every value as it is: the same result,
    # without the ball's substep. Arrays always take the masked update.
    if xp is not floats or moving:
        moved = ball_substep(p, ball, wind_x, wind_y, dt, xp)
        moved, _ = ground_contact(p, moved, dt, xp)
        ball = select(moving, moved, ball, xp)
        hit_wall, vx, vz, height = ball_hits_wall(
            wp, wall, p.mass_kg, p.radius_m, ball.x, ball.y, ball.z, ball.vx, ball.vz, xp
        )
        wall = select(moving, hit_wall, wall, xp)
        struck = moving & (height >= 0.0)
        if xp is not floats or struck:  # as above: a hit is rare
            vx, vz = xp.where(struck, vx, ball.vx), xp.where(struck, vz, ball.vz)
            ball = _with(ball, vx=vx, vz=vz)
            hits = hits + xp.astype(struck, xp.int64)
            hit_height = xp.where(struck, height, hit_height)
            hit_y = xp.where(struck, ball.y, hit_y)
        flying = flying & xp.logical_not(moving & ball_at_rest(p, ball, check_spin=False))
    wall = select(live, wall_step(wp, wall, wind_x, dt, xp), wall, xp)
    return ball, wall, flying, hits, hit_height, hit_y


def event_bodies(
    params: IntervalParams, c: IntervalCarry, live: Array, wind_x: Array, wind_y: Array, xp: Any
) -> tuple:
    """One step of the ball and the wall (``rk4_events``, Topple-v2), ``sim_dt`` long:

    - the ball: one RK4 step (:func:`~bbgym.physics.flight_events.rk4_cubics`), on whose
      dense output the first event is located, a touchdown that bounces (the centre falls
      to one radius faster than ``rest_speed_mps``) or the ball reaching the wall's face
      (its centre one radius from the face's plane, over the face, the wall as it stood
      at the step's start). The event happens at its moment (the bounce of
      :func:`~bbgym.physics.ball.ground_contact`, the impulse of
      :func:`~bbgym.physics.wall.ball_hits_wall`), and the rest of the step is a second
      RK4 step whose contacts, a rolling ball's and a second event's, are resolved at its
      end, as a substep's;
    - the wall: one RK4 step of its rocking (:func:`~bbgym.physics.wall.wall_rk4_step`)
      to the hit's moment, the hit's angular impulse, one over the rest of the step (a
      wall not hit takes the whole step at once), and a late hit's impulse at the end.

    Returns ``(ball, wall, flying, hits, hit_height, hit_y)``, as :func:`euler_bodies`.

    Every update is masked. On the host (floats, NumPy) one whose mask is false for the
    whole batch is skipped (``skippable``), and a NumPy batch computes the rare ones (the
    events' roots, the rest of a step after an event, the rest of a struck wall's step)
    for the elements that need them alone (:func:`_masked`): the same values, without the
    work."""
    wp, p, h = params.wall, params.ball, params.sim_dt
    ball, wall = c.ball, c.wall
    moving = c.flying & live
    flying, hits, hit_height, hit_y = c.flying, c.hits, c.hit_height, c.hit_y
    # One env on floats takes Python numbers; a batch, arrays (per ball: the rest of a cut
    # step differs from ball to ball).
    step = h if xp is floats else h + 0.0 * ball.x
    strike = late = moving & False
    kick = late_kick = 0.0 * step
    kick_pivot = late_pivot = wall.pivot
    hit_time = step
    if not skippable(moving):
        b = _ball_step(params, ball, wall, moving, step, wind_x, wind_y, c.taken is not None, xp)
        strike, late = b.strike, b.late
        ball = select(moving, b.ball, ball, xp)
        hits = hits + xp.astype(strike, xp.int64) + xp.astype(late, xp.int64)
        hit_height = xp.where(late, b.late_height, xp.where(strike, b.hit_height, hit_height))
        hit_y = xp.where(late, ball.y, xp.where(strike, b.hit_y, hit_y))
        flying = flying & xp.logical_not(moving & ball_at_rest(p, ball, check_spin=False))
        kick = xp.where(strike, b.struck.rate - wall.rate, 0.0)
        late_kick = xp.where(late, b.late_wall.rate - wall.rate, 0.0)
        kick_pivot, late_pivot = b.struck.pivot, b.late_wall.pivot
        hit_time = xp.where(strike, b.hit_theta * step, step)
    # The wall: to the hit, its angular impulse, the rest of the step (a wall not hit: the
    # whole step at once), a late hit's impulse. The step is cut at the hit rather than
    # corrected after it: the torque on a wall resting on its foot jumps once it turns.
    rocked = _kicked(wall_rk4_step(wp, wall, wind_x, hit_time, xp), kick, kick_pivot, xp)
    if not skippable(strike):
        # (A panel loose at the step's start is never hit: its step is all in the first
        # part; one that breaks loose in the first part flies from the next step, as in v1.)
        def rock_rest(wall: Any, wind_x: Array, rest: Array) -> Any:
            return wall_rk4_step(wp, wall, wind_x, rest, xp, fly_loose=False)

        rocked = _masked(strike, rock_rest, rocked, (rocked, wind_x, step - hit_time), xp)
    wall = select(live, _kicked(rocked, late_kick, late_pivot, xp), wall, xp)
    return ball, wall, flying, hits, hit_height, hit_y


class _BallStep(NamedTuple):
    """What :func:`_ball_step` did, per env: the ball after the step, whether it struck
    the wall at a located moment (at ``hit_theta`` of the step, ``hit_height`` up the
    face, ``hit_y`` across it, the wall then ``struck``) and whether it struck it late (at
    the step's end, ``late_height`` up it, the wall then ``late_wall``)."""

    ball: Any
    strike: Array
    hit_theta: Array
    hit_height: Array
    hit_y: Array
    struck: Any
    late: Array
    late_height: Array
    late_wall: Any


def _ball_step(
    params: IntervalParams,
    ball: Any,
    wall: Any,
    moving: Array,
    step: Array,
    wind_x: Array,
    wind_y: Array,
    orient: bool,
    xp: Any,
) -> _BallStep:
    """The ball's part of :func:`event_bodies`. ``orient``: turn the ball's orientation
    (nothing but the recorded samples reads it, and its turn in a step is exact, so a
    step that records nothing leaves it as it is)."""
    wp, p, r = params.wall, params.ball, params.ball.radius_m
    one = 1.0 + 0.0 * step
    no = moving & False
    cubics = rk4_cubics(p, ball, wind_x, wind_y, step, xp)
    # A touchdown that bounces: the centre falls to one radius, fast enough.
    height = (cubics[2][0] - r, *cubics[2][1:])
    touch = moving & (height[0] > 0.0) & (cubic_at(height, 1.0) <= 0.0)
    touch_theta = one
    if not skippable(touch):
        touch_theta = _root_where(touch, height, one, xp)
        touch = touch & (cubic_at(cubics[5], touch_theta) < -p.rest_speed_mps)
    # The ball reaching the face, the wall as it stood at the step's start.
    frame = face_frame(wp, wall, xp)  # the wall as it stands at the step's start
    face_theta, reaches = _face_contact(wp, wall, frame, cubics, r, moving, one, xp)
    strike, struck, hit_vx, hit_vz = no, wall, ball.vx, ball.vz
    hit_height, hit_y = 0.0 * step - 1.0, 0.0 * step
    if not skippable(reaches):
        hit_x, hit_y, hit_z, vx, vz = [cubic_at(cubics[k], face_theta) for k in (0, 1, 2, 3, 5)]
        struck, hit_vx, hit_vz, hit_height = ball_hits_wall(
            wp,
            wall,
            p.mass_kg,
            r,
            hit_x,
            hit_y,
            hit_z,
            vx,
            vz,
            xp,
            located=reaches,
            frame=frame,
        )
        first = xp.logical_not(touch) | (face_theta <= touch_theta)
        strike = reaches & (hit_height >= 0.0) & first
        touch = touch & xp.logical_not(strike)
    theta = xp.where(strike, face_theta, xp.where(touch, touch_theta, one))
    at = state_at(p, ball, cubics, theta, step, xp, orient)
    if not skippable(touch):  # bounced, the centre one radius up (the root's rounding aside)
        landed = replaced(at, z=xp.where(touch, r + 0.0 * at.z, at.z))
        at = select(touch, ground_contact(p, landed, params.sim_dt, xp)[0], at, xp)
    if not skippable(strike):
        at = replaced(at, vx=xp.where(strike, hit_vx, at.vx), vz=xp.where(strike, hit_vz, at.vz))
    evented = touch | strike
    if not skippable(evented):  # the rest of the step after the event
        rest = (1.0 - theta) * step

        def fly_rest(ball: Any, wind_x: Array, wind_y: Array, rest: Array, one: Array) -> Any:
            cubics = rk4_cubics(p, ball, wind_x, wind_y, rest, xp)
            return state_at(p, ball, cubics, one, rest, xp, orient)

        at = _masked(evented, fly_rest, at, (at, wind_x, wind_y, rest, one), xp)
    # Contacts at the step's end: a rolling ball's, a second event's.
    at, _ = ground_contact(p, at, params.sim_dt, xp)
    late_wall, late_vx, late_vz, late_height = ball_hits_wall(
        wp, wall, p.mass_kg, r, at.x, at.y, at.z, at.vx, at.vz, xp, frame=frame
    )
    late = moving & (late_height >= 0.0)
    if not skippable(late):
        at = replaced(at, vx=xp.where(late, late_vx, at.vx), vz=xp.where(late, late_vz, at.vz))
    return _BallStep(at, strike, theta, hit_height, hit_y, struck, late, late_height, late_wall)


def _masked(mask: Array, update: Any, old: Any, args: tuple, xp: Any) -> Any:
    """``update(*args)`` where ``mask``, ``old`` elsewhere (trees of one structure). A NumPy
    batch computes it for ``mask``'s elements alone (taken out and put back: the same
    values, each element's arithmetic its own); other namespaces for the whole batch."""
    if xp is np and isinstance(mask, np.ndarray):
        working = np.flatnonzero(mask)
        return scatter(old, working, update(*[take(a, working, mask.shape[0]) for a in args]))
    new = update(*args)
    return select(mask, new, old, xp) if isinstance(old, tuple) else xp.where(mask, new, old)


def _root_where(mask: Array, cubic: tuple, one: Array, xp: Any) -> Array:
    """Where ``mask``, the cubic's first fall to zero in the step
    (:func:`~bbgym.physics.flight_events.descent_root`); ``one`` elsewhere."""
    return _masked(mask, lambda *c: descent_root(c, xp), one, cubic, xp)


def _face_contact(
    wp: WallParams,
    wall: Any,
    frame: tuple,
    cubics: tuple,
    radius_m: float,
    moving: Array,
    one: Array,
    xp: Any,
) -> tuple[Array, Array]:
    """When in the step a moving ball first touches a standing wall's face, the wall as
    it stands at the step's start: ``(theta, reaches)``. It touches when its centre comes
    within one radius of the face's plane while over the face, or comes down over the
    face's top while within a radius of the plane (where ``reaches`` is false, ``theta``
    means nothing). ``frame``: the wall's :func:`~bbgym.physics.wall.face_frame`."""
    _, c, sn, _, foot_x, foot_z = frame
    # behind the face: (x - foot_x) cos - (z - foot_z) sin + t / 2; up it:
    # (x - foot_x) sin + (z - foot_z) cos
    behind = combine_cubics(
        cubics[0], cubics[2], c, -sn, foot_x * c - foot_z * sn - 0.5 * wp.thickness_m
    )
    up = combine_cubics(cubics[0], cubics[2], sn, c, foot_x * sn + foot_z * c)
    lateral = cubics[1]
    candidates = moving & (wall.status == STANDING)

    def across(theta: Array) -> Array:
        return xp.abs(cubic_at(lateral, theta)) <= 0.5 * wp.width_m

    gap = (-behind[0] - radius_m, *[-k for k in behind[1:]])  # > 0 clear, on the near side
    plane = candidates & (gap[0] > 0.0) & (cubic_at(gap, 1.0) <= 0.0)
    theta = one
    if not skippable(plane):
        theta = _root_where(plane, gap, one, xp)
        along = cubic_at(up, theta)
        plane = plane & across(theta) & (along >= 0.0) & (along <= wp.height_m)
    above = (up[0] - wp.height_m, *up[1:])  # > 0 over the top
    top = candidates & (above[0] > 0.0) & (cubic_at(above, 1.0) <= 0.0)
    if not skippable(top):
        top_theta = _root_where(top, above, one, xp)
        in_band = xp.abs(cubic_at(behind, top_theta)) < radius_m
        top = top & in_band & across(top_theta)
        top = top & (xp.logical_not(plane) | (top_theta < theta))
        theta = xp.where(top, top_theta, theta)
    return theta, plane | top


def _kicked(wall: Any, rate_change: Array, pivot: Array, xp: Any) -> Any:
    """A standing wall after a hit's angular impulse (``rate_change``, zero where none): a
    wall resting on its foot turns about the hit's edge from then on."""
    kicked = (rate_change != 0.0) & (wall.status == STANDING)
    return replaced(
        wall,
        rate=xp.where(kicked, wall.rate + rate_change, wall.rate),
        pivot=xp.where(kicked & (wall.pivot == 0), pivot, wall.pivot),
    )


def interval_chunk(
    params: IntervalParams,
    carry: IntervalCarry,
    wind_speed: Array,
    wind_from: Array,
    gusts: Array,
    noise: Any,
    xp: Any,
) -> IntervalCarry:
    """:attr:`IntervalParams.chunk_substeps` substeps from a carry at a chunk's start (those
    past the interval's end change nothing), with no branch on array values: the same
    function for every chunk."""
    for offset in range(params.chunk_substeps):
        carry = interval_substep(params, carry, offset, wind_speed, wind_from, gusts, noise, xp)
    return carry


def run_interval(
    params: IntervalParams,
    carry: IntervalCarry,
    wind_speed: Array,
    wind_from: Array,
    gusts: Array,
    noise: Any,
    xp: Any,
    *,
    stop_early: bool = True,
    chunk: Any = interval_chunk,
) -> IntervalCarry:
    """Run the interval from ``carry`` (at substep 0) chunk by chunk (``chunk``:
    :func:`interval_chunk` or a compiled version of it), stopping before a chunk once no
    env runs (``stop_early``). Substeps past an env's stop change nothing of it, so the
    result does not depend on where the loop stops; the samples do not either, once env
    ``i``'s are cut to its first ``samples[i]``."""
    for _ in range(params.n_chunks):
        if stop_early and not bool(xp.any(carry.running)):
            break
        carry = chunk(params, carry, wind_speed, wind_from, gusts, noise, xp)
    return carry
