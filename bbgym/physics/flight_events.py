"""A throw's flight in RK4 steps with event location: the flight of the throwing
family's later versions (``flight_integrator="rk4_events"``; seed §1, §3, §8).

:mod:`bbgym.physics.flight` flies a ball in semi-implicit Euler substeps of 0.01 s and
keeps flying it through its bounces until it rests. Here the same forces
(:func:`~bbgym.physics.ball.air_force`: gravity, drag against the wind, the Magnus force)
are integrated by the classical fourth-order Runge-Kutta method in steps of 0.05 s, and
what happens inside a step is found rather than stepped over:

- the **touchdown** (the centre one radius up) is the root of the step's dense output, a
  cubic in time; the flight ends there, since a throw is scored at its first touchdown
  (the bounces and the roll after it change nothing a step returns);
- a **screen hit** (the centre one radius from the panel's plane, over its face) cuts the
  step at the root: the ball bounces there (:func:`~bbgym.physics.ball.panel_bounce`)
  and the next step starts from the bounce. A contact slower than
  :data:`CUT_SPEED_MPS` (a ball leaning on the screen) is resolved at the step's end
  instead: the ball is put back on the side it came from, so the cuts of one flight stay
  few and no step carries a ball through the screen;
- the **apex** is the height's cubic where the vertical velocity crosses zero (at the
  secant's root: the height is flat there, so its error is second order in the root's).

The spin decays exponentially and keeps its axis, so it and the orientation are exact at
any time of a step. The dense output is the classical third-order continuous extension
of RK4 (Hairer, Norsett and Wanner, *Solving ODEs I*, II.6): it reuses the step's four
stages, so locating an event costs no force evaluation. Roots come from a bracketed
Newton iteration of fixed length (no branch on array values).

:func:`event_flight_step` is one step of every ball, finished balls frozen; like the rest
of the physics it is pure and written against an array namespace ``xp``.
:func:`simulate_event_throw` flies a batch to its end and, for display, lets the landed
balls bounce and roll in the substeps of :mod:`bbgym.physics.flight`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from bbgym.physics.ball import (
    BallParams,
    BallState,
    air_force,
    panel_bounce,
    spin_decay,
)
from bbgym.physics.common import AIR_DENSITY_KGM3, quadratic_drag_rate
from bbgym.physics.flight import (
    Flight,
    Screen,
    ThrowResult,
    flight_record_every,
    flight_result,
    flight_start,
    fly,
    launch_spin_parameter,
    pose_of,
    sample_count,
)
from bbgym.physics.namespace import Array, replaced, select, skippable

CUT_SPEED_MPS = 0.5
"""A screen contact approaching faster than this cuts the step at its moment; a slower
one is resolved at the step's end. Every cut leaves the ball ``restitution`` times its
approach speed, so a flight has few cuts (from 18 m/s at ``e = 0.4``: at most 5)."""
SCREEN_CUTS_MAX = 8
"""Steps a flight gets beyond those its time needs, for its cut steps: a ball that used
them all before landing ends where it is (only a ball pinned to the screen could)."""
NEWTON_ITERATIONS = 4
"""Of the bracketed Newton iteration for an event's time in a step: from the secant's
start, the cubic's root to about 1e-12 of a step (Newton converges quadratically; the
touchdown of a parabola is exact to rounding, tests/throw/test_flight_events.py)."""
ROLL_DISPLAY_DT_S = 0.01
"""Substep of the bounces and the roll after the touchdown, flown for display only."""


RK4_AIR_LIMIT = 2.5
"""The largest ``2 h (c + w)`` at which a ball's RK4 step is taken: ``h`` the step, ``c``
the drag's damping rate and ``w`` the Magnus force's largest turning rate, both at the
air-relative speed ``u`` (``rho A C |u| / (2 m)`` with ``C_d`` and ``C_L``'s saturation,
seed §8). Quadratic drag ``-c(|u|) u`` damps a perturbation along ``u`` at ``2 c``; the
Magnus force ``c_L |u| u`` turned a right angle rotates ``u`` at ``w`` and, growing with
``|u|``, couples at up to ``2 w``. RK4 is stable on the negative real axis to ``-2.785``,
on the imaginary axis to ``2.83``, and on the left half-disk of radius 2.5 between them:
past it each step multiplies the error, the forces grow with the speed they overshoot to,
and the flight runs to inf, then NaN (a 0.02 kg/m^2 shell thrown at 18 m/s, ``2 h c``
about 6 at ``h = 0.05``; a 3 m shell with ``C_L`` 0.94 in a 20 m/s wind, ``2 h w`` about
11). Near the limit the step is stable but coarse: RK4 damps by 0.65 a step where the
drag alone would damp by 0.08, so such a flight is stable, not accurate; accurate to
about 1% needs ``2 h (c + w)`` below about 1."""


def rk4_stable_air_speed_mps(p: BallParams, dt_s: float) -> float:
    """The fastest air-relative speed ``u`` at which one RK4 step of ``dt_s`` is stable
    against the ball's drag and Magnus force: ``2 dt (c(u) + w(u)) = RK4_AIR_LIMIT``
    with ``c(u) + w(u) = rho A (C_d + C_L,max) u / (2 m)``
    (:func:`~bbgym.physics.common.quadratic_drag_rate` of the summed coefficient; seed §8);
    ``inf`` with neither. A ball never flies faster through the air than the larger of its
    launch's air speed and its terminal speed (drag exceeds gravity above terminal speed;
    the Magnus force turns the velocity without speeding it up), so a throw's launch
    bounds the whole flight, bounces included."""
    area_m2 = (p.drag_coefficient + p.lift_coefficient_max) * p.area_m2
    rate_per_speed = float(quadratic_drag_rate(area_m2, AIR_DENSITY_KGM3, 1.0)) / p.mass_kg
    if rate_per_speed == 0.0:
        return math.inf
    return RK4_AIR_LIMIT / (2.0 * dt_s * rate_per_speed)


def flight_steps(dt_s: float, max_time_s: float) -> int:
    """The steps a flight of at most ``max_time_s`` may take: those its time needs and
    :data:`SCREEN_CUTS_MAX` more."""
    return math.ceil(max_time_s / dt_s - 1e-9) + SCREEN_CUTS_MAX


def _acceleration(p: BallParams, s: BallState, wind_x: Array, wind_y: Array, xp: Any) -> tuple:
    fx, fy, fz = air_force(p, s, wind_x, wind_y, xp)
    return fx / p.mass_kg, fy / p.mass_kg, fz / p.mass_kg


def rk4_stages(
    p: BallParams, s: BallState, wind_x: Array, wind_y: Array, h: Array, xp: Any
) -> tuple:
    """The four RK4 stages of ``(position, velocity)`` over a step ``h``: the velocities
    (position rates) and accelerations at each. The spin at each stage is exact."""
    half_decay = spin_decay(p, 0.5 * h, xp)
    spins = ((s.wx, s.wy, s.wz), tuple(w * half_decay for w in (s.wx, s.wy, s.wz)))
    spins = (*spins, spins[1], tuple(w * half_decay for w in spins[1]))
    velocities, accelerations = [], []
    v = (s.vx, s.vy, s.vz)
    for k, fraction in enumerate((0.0, 0.5, 0.5, 1.0)):
        if k > 0:
            v = tuple(
                v0 + fraction * h * a
                for v0, a in zip((s.vx, s.vy, s.vz), accelerations[-1], strict=True)
            )
        at = replaced(s, vx=v[0], vy=v[1], vz=v[2], wx=spins[k][0], wy=spins[k][1], wz=spins[k][2])
        velocities.append(v)
        accelerations.append(_acceleration(p, at, wind_x, wind_y, xp))
    return velocities, accelerations


def dense_cubic(value: Array, rates: tuple, h: Array) -> tuple:
    """The dense output ``y(theta) = c0 + c1 theta + c2 theta^2 + c3 theta^3`` of one
    component over the step (``theta`` in [0, 1]) from its four stage rates: the weights
    ``b1 = theta - 3/2 theta^2 + 2/3 theta^3``, ``b2 = b3 = theta^2 - 2/3 theta^3``,
    ``b4 = -1/2 theta^2 + 2/3 theta^3``; at ``theta = 1`` the RK4 step."""
    r1, r2, r3, r4 = rates
    middle = r2 + r3
    return (
        value,
        h * r1,
        h * (-1.5 * r1 + middle - 0.5 * r4),
        h * ((2.0 / 3.0) * (r1 - middle + r4)),
    )


def rk4_cubics(
    p: BallParams, s: BallState, wind_x: Array, wind_y: Array, h: Array, xp: Any
) -> tuple:
    """One RK4 step of the ball over ``h`` as its dense output: the cubics of ``x, y, z,
    vx, vy, vz`` in ``theta`` (:func:`dense_cubic`; at ``theta = 1`` the RK4 step)."""
    velocities, accelerations = rk4_stages(p, s, wind_x, wind_y, h, xp)
    start = (s.x, s.y, s.z, s.vx, s.vy, s.vz)
    rates = [tuple(v[k] for v in velocities) for k in range(3)]
    rates += [tuple(a[k] for a in accelerations) for k in range(3)]
    return tuple(dense_cubic(y0, r, h) for y0, r in zip(start, rates, strict=True))


def cubic_at(c: tuple, theta: Array) -> Array:
    return c[0] + theta * (c[1] + theta * (c[2] + theta * c[3]))


def cubic_slope(c: tuple, theta: Array) -> Array:
    return c[1] + theta * (2.0 * c[2] + theta * 3.0 * c[3])


def combine_cubics(a: tuple, b: tuple, wa: Array, wb: Array, shift: Array) -> tuple:
    """The cubic ``wa a + wb b - shift`` (a linear combination of two components)."""
    return (
        wa * a[0] + wb * b[0] - shift,
        *[wa * ca + wb * cb for ca, cb in zip(a[1:], b[1:], strict=True)],
    )


def descent_root(c: tuple, xp: Any) -> Array:
    """Where the cubic ``c``, positive at ``theta = 0`` and not at 1, first falls to zero
    on [0, 1] (0 if it starts at or below zero): Newton's iteration kept inside a shrinking
    bracket (a step that leaves it, or goes uphill, bisects instead), started at the
    secant's root. Where the cubic does not fall to zero, the result is meaningless and
    masked by the caller."""
    start, end = c[0], cubic_at(c, 1.0)
    drop = start - end
    theta = xp.clip(start / xp.where(drop > 0.0, drop, 1.0), 0.0, 1.0)
    low, high = xp.zeros_like(theta), xp.zeros_like(theta) + 1.0
    for _ in range(NEWTON_ITERATIONS):
        value, slope = cubic_at(c, theta), cubic_slope(c, theta)
        above = value > 0.0
        low, high = xp.where(above, theta, low), xp.where(above, high, theta)
        newton = theta - value / xp.where(slope < 0.0, slope, -1.0)
        inside = (slope < 0.0) & (newton >= low) & (newton <= high)
        theta = xp.where(inside, newton, 0.5 * (low + high))
    return xp.where(start > 0.0, theta, 0.0 * theta)


def state_at(
    p: BallParams,
    s: BallState,
    cubics: tuple,
    theta: Array,
    h: Array,
    xp: Any,
    orient: bool = True,
) -> BallState:
    """The ball at ``theta`` of the step: position and velocity from the dense output,
    spin and orientation exact (the spin keeps its axis and decays exponentially, so the
    ball turns by ``|omega| tau (1 - exp(-t / tau))`` about it). Without ``orient`` the
    orientation is left as it was."""
    x, y, z, vx, vy, vz = [cubic_at(c, theta) for c in cubics]
    elapsed = theta * h
    decay = spin_decay(p, elapsed, xp)
    if not orient:
        return BallState(
            x, y, z, vx, vy, vz, s.wx * decay, s.wy * decay, s.wz * decay, s.qw, s.qx, s.qy, s.qz
        )
    spin = xp.sqrt(s.wx * s.wx + s.wy * s.wy + s.wz * s.wz)
    angle = spin * p.spin_decay_s * (1.0 - decay)
    # sin(angle / 2) along the unit axis; a ball without spin does not turn
    per_spin = xp.sin(0.5 * angle) / xp.maximum(spin, 1e-12)
    dw, dx, dy, dz = xp.cos(0.5 * angle), per_spin * s.wx, per_spin * s.wy, per_spin * s.wz
    # (dw, d) * q: the turn in the world frame applied to the body-to-world quaternion
    qw = dw * s.qw - dx * s.qx - dy * s.qy - dz * s.qz
    qx = dw * s.qx + dx * s.qw + dy * s.qz - dz * s.qy
    qy = dw * s.qy + dy * s.qw + dz * s.qx - dx * s.qz
    qz = dw * s.qz + dz * s.qw + dx * s.qy - dy * s.qx
    norm = xp.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    return BallState(
        x,
        y,
        z,
        vx,
        vy,
        vz,
        s.wx * decay,
        s.wy * decay,
        s.wz * decay,
        qw / norm,
        qx / norm,
        qy / norm,
        qz / norm,
    )


def event_flight_step(
    p: BallParams,
    f: Flight,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None,
    dt_s: float,
    max_time_s: float,
    field_radius_m: float,
    xp: Any = np,
    orient: bool = True,
) -> tuple[Flight, Any]:
    """One RK4 step of every ball still flying (the module docstring says what it
    locates), finished balls frozen. Returns the flight and the pose after the step.
    Without ``orient`` the balls' orientations stay as they are: nothing of a throw's
    outcome reads them, so a step that records no poses leaves them out.

    ``f.end_time_s`` is each ball's time (the steps cut at a screen hit are shorter), and
    ``f.substep`` counts the steps. A ball is done at its touchdown, out of the field, at
    ``max_time_s`` or after :func:`flight_steps` steps."""
    s, t0 = f.ball, f.end_time_s
    flying = xp.logical_not(f.done)
    h = xp.maximum(xp.minimum(dt_s + 0.0 * t0, max_time_s - t0), 0.0)
    cubics = rk4_cubics(p, s, wind_x, wind_y, h, xp)

    # Touchdown: the height's cubic falls to one radius.
    height = (cubics[2][0] - p.radius_m, *cubics[2][1:])
    touch = flying & (cubic_at(height, 1.0) <= 0.0)
    touch_theta = xp.where(touch, descent_root(height, xp), 1.0 + 0.0 * t0)
    end_theta = touch_theta

    cut = leaning = xp.zeros_like(touch, dtype=xp.bool)
    if screen is not None and not skippable(screen.enabled):
        cut, leaning, cut_theta, bounced, side = _screen_cut(
            p, s, cubics, h, screen, flying, xp, orient
        )
        leaning = leaning & (cut_theta <= touch_theta)
        cut = cut & (cut_theta <= touch_theta)
        touch = touch & xp.logical_not(cut)
        end_theta = xp.where(cut, cut_theta, end_theta)

    ended = state_at(p, s, cubics, end_theta, h, xp, orient)
    if screen is not None and not skippable(cut):
        ended = select(cut, bounced, ended, xp)
    if screen is not None and not skippable(leaning):  # slow contacts, at the step's end
        ended = _lean(p, ended, screen, leaning, side, xp)
        cut = cut | leaning
    now = t0 + end_theta * h

    # Apex: where the vertical velocity falls to zero, if before the step's end.
    vertical = cubics[5]
    falling_at_end = cubic_at(vertical, end_theta)
    drop = vertical[0] - falling_at_end
    apex_theta = end_theta * vertical[0] / xp.where(drop > 0.0, drop, 1.0)
    apex_inside = (vertical[0] > 0.0) & (falling_at_end <= 0.0)
    apex = xp.maximum(f.apex_height_m, ended.z)
    apex = xp.where(apex_inside, xp.maximum(apex, cubic_at(cubics[2], apex_theta)), apex)

    out = ended.x * ended.x + ended.y * ended.y > field_radius_m * field_radius_m
    last = f.substep >= flight_steps(dt_s, max_time_s)
    timed_out = now >= max_time_s - 1e-3 * dt_s
    finished = touch | out | timed_out | last
    frozen = f.done
    new_ball = select(frozen, s, ended, xp)
    landed = f.landed | (touch & flying)
    first = touch & flying
    new = Flight(
        ball=new_ball,
        landed=landed,
        landing_x=xp.where(first, ended.x, f.landing_x),
        landing_y=xp.where(first, ended.y, f.landing_y),
        flight_time_s=xp.where(first, now, f.flight_time_s),
        apex_height_m=xp.where(frozen, f.apex_height_m, apex),
        hit_screen=f.hit_screen | (cut & flying),
        done=f.done | finished,
        end_time_s=xp.where(frozen, t0, now),
        steps=f.steps + xp.astype(flying, xp.int64),
        samples=f.samples + xp.astype(xp.any(flying), xp.int64),
        substep=f.substep + 1.0,
    )
    return new, pose_of(new_ball)


def _lean(
    p: BallParams, s: BallState, screen: Screen, leaning: Array, side: Array, xp: Any
) -> BallState:
    """A slow contact resolved at the step's end: a ball that reached the screen on
    ``side`` is put back one radius from its plane on that side (even if the step took it
    through), its velocity toward the panel reflected times the restitution."""
    normal_x, normal_y = -screen.along_y, screen.along_x
    offset = (s.x - screen.center_x) * normal_x + (s.y - screen.center_y) * normal_y
    approach = s.vx * normal_x + s.vy * normal_y
    closing = xp.where(side * approach < 0.0, approach, 0.0 * approach)
    return panel_bounce(
        s, p.radius_m, normal_x, normal_y, offset, side, closing, screen.restitution, leaning, xp
    )


def _screen_cut(
    p: BallParams,
    s: BallState,
    cubics: tuple,
    h: Array,
    screen: Screen,
    flying: Array,
    xp: Any,
    orient: bool,
) -> tuple:
    """Where a ball reaches the screen during the step: ``(cut, leaning, theta, bounced,
    side)``. ``cut``: it reaches it at :data:`CUT_SPEED_MPS` or faster, at ``theta``,
    where ``bounced`` is its state just after the bounce (a ball that starts the step
    within a radius of the panel, over it, bounces at ``theta = 0``). ``leaning``: it
    reaches it slower, or starts within a radius of it, and ends the step within a radius
    of the plane or past it (resolved at the step's end). ``side``: the side of the
    panel's plane the ball starts on."""
    r = p.radius_m
    normal_x, normal_y = -screen.along_y, screen.along_x
    shift = screen.center_x * normal_x + screen.center_y * normal_y
    offset = combine_cubics(cubics[0], cubics[1], normal_x, normal_y, shift)
    side = xp.where(offset[0] >= 0.0, 1.0, xp.zeros_like(offset[0]) - 1.0)
    gap = (side * offset[0] - r, *[side * c for c in offset[1:]])  # centre's gap to the band
    reaching = (gap[0] >= 0.0) & (cubic_at(gap, 1.0) < 0.0)
    theta = xp.where(reaching, descent_root(gap, xp), 0.0 * gap[0])
    at = state_at(p, s, cubics, theta, h, xp, orient)
    lateral = (at.x - screen.center_x) * screen.along_x + (at.y - screen.center_y) * screen.along_y
    over_face = (xp.abs(lateral) <= screen.half_width_m) & (at.z <= screen.height_m)
    approach = at.vx * normal_x + at.vy * normal_y
    closing = -side * approach
    inside = gap[0] < 0.0  # within a radius of the plane at the step's start
    contact = screen.enabled & flying & over_face & (reaching | inside)
    cut = contact & (closing >= CUT_SPEED_MPS)
    # the rest of the contacts, if the step ends within a radius of the plane (or past it)
    leaning = contact & xp.logical_not(cut) & (cubic_at(gap, 1.0) < 0.0)
    bounced = panel_bounce(
        at,
        r,
        normal_x,
        normal_y,
        cubic_at(offset, theta),
        side,
        approach,
        screen.restitution,
        cut,
        xp,
    )
    return cut, leaning, theta, bounced, side


def simulate_event_throw(
    p: BallParams,
    launch: BallState,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None = None,
    dt_s: float = 0.05,
    max_time_s: float = 6.0,
    max_roll_s: float = 2.0,
    field_radius_m: float = 30.0,
    record_dt_s: float = 0.05,
    xp: Any = np,
    record: bool = True,
) -> ThrowResult:
    """Fly balls from launch to their first touchdown (or out of the field, or out of
    time) in RK4 steps; the outcome is :func:`~bbgym.physics.flight.flight_result`'s. With
    ``record``, the trajectory has the pose after every step (``dt_s`` apart but for the
    cut steps), then the landed balls' bounces and roll for display (:func:`roll_display`)."""
    spin_parameter = launch_spin_parameter(p, launch, wind_x, wind_y, xp)

    def step(flight: Flight) -> tuple[Flight, Any]:
        return event_flight_step(
            p, flight, wind_x, wind_y, screen, dt_s, max_time_s, field_radius_m, xp
        )

    start = flight_start(p, launch, xp)
    flight, poses = fly_events(step, start, flight_steps(dt_s, max_time_s), record, xp)
    trajectory, steps = [], flight.steps
    if record:
        trajectory, steps = roll_display(
            p,
            flight,
            [pose_of(launch), *poses],
            wind_x,
            wind_y,
            screen,
            max_roll_s,
            field_radius_m,
            record_dt_s,
            xp,
        )
    return replaced(flight_result(flight, spin_parameter, trajectory, xp), steps=steps)


def fly_events(
    step: Callable[[Flight], tuple[Flight, Any]],
    flight: Flight,
    steps: int,
    record: bool = True,
    xp: Any = np,
) -> tuple[Flight, list]:
    """A flight to its end on the host: ``step`` (:func:`event_flight_step` with the
    throw's arguments bound) until every ball is done, at most ``steps`` times
    (:func:`flight_steps`).

    Args:
        step: One RK4 step of the flight: the flight after it, and the pose.
        flight: The flight so far.
        steps: The most steps the flight takes.
        record: Keep the poses.
        xp: The array namespace.

    Returns:
        The flight and, if ``record``, the pose after every step (cut to the last ball's
        end).
    """
    poses: list = []
    for _ in range(steps):
        flight, pose = step(flight)
        if record:
            poses.append(pose)
        if bool(xp.all(flight.done)):
            break
    if record:
        del poses[sample_count(flight.samples, xp) - 1 :]
    return flight, poses


def roll_display(
    p: BallParams,
    flight: Flight,
    poses: list,
    wind_x: Array,
    wind_y: Array,
    screen: Screen | None,
    max_roll_s: float,
    field_radius_m: float,
    record_dt_s: float,
    xp: Any,
) -> tuple[list, Array]:
    """The recorded flight (``poses``: the launch's, then one per step) followed, for each
    landed ball, by its bounces and roll from the touchdown, flown in the substeps of
    :mod:`bbgym.physics.flight` (:data:`ROLL_DISPLAY_DT_S`) until it rests or
    ``max_roll_s`` passes. Nothing of it reaches a step's outcome: it is what a viewer
    shows. Returns the poses (one list for the batch, each ball's own rows first and its
    last pose repeated after them) and each ball's count of rows."""
    no = xp.zeros_like(flight.landed, dtype=xp.bool)
    # the roll's clock starts at the touchdown (``flight_time_s`` 0, substep 1)
    roll = replaced(
        flight,
        flight_time_s=xp.zeros_like(flight.flight_time_s),
        done=xp.logical_not(flight.landed),
        hit_screen=no,
        substep=xp.zeros_like(flight.substep) + 1.0,
        steps=0 * flight.steps + 1,
        samples=0 * flight.samples + 1,
    )
    rolled, roll_poses = fly(
        p,
        roll,
        wind_x,
        wind_y,
        screen,
        ROLL_DISPLAY_DT_S,
        round(max_roll_s / ROLL_DISPLAY_DT_S),
        flight_record_every(ROLL_DISPLAY_DT_S, record_dt_s),
        True,
        xp,
        max_roll_s,
        field_radius_m,
    )
    steps = flight.steps + rolled.steps - 1
    if isinstance(flight.steps, int):  # one ball on floats
        return poses[: flight.steps] + roll_poses[: rolled.steps - 1], steps
    # Each ball's rows: its flight's, then its roll's (from after the touchdown).
    flown, rolling = _stack(poses), _stack(roll_poses) if roll_poses else None
    rows = int(np.max(steps))
    index = np.arange(rows)[:, None]
    own = np.minimum(index, flight.steps[None, :] - 1)
    out = np.take_along_axis(flown, own[:, None, :], axis=0)
    if rolling is not None:
        after = index - flight.steps[None, :]
        rolled_rows = np.take_along_axis(
            rolling, np.clip(after, 0, len(rolling) - 1)[:, None, :], axis=0
        )
        in_roll = (after >= 0) & (after < rolled.steps[None, :] - 1)
        last_roll = np.take_along_axis(
            rolling,
            np.clip(rolled.steps - 2, 0, len(rolling) - 1)[None, None, :].repeat(7, 1),
            axis=0,
        )
        past = after >= rolled.steps[None, :] - 1
        out = np.where(in_roll[:, None, :], rolled_rows, out)
        out = np.where((past & (rolled.steps[None, :] > 1))[:, None, :], last_roll, out)
    return [type(poses[0])(*row) for row in out], steps


def _stack(poses: list) -> np.ndarray:
    """Poses as an array ``(rows, 7, batch)``."""
    return np.stack([np.stack(pose) for pose in poses])
