"""Friction (§6): a sliding block braked by kinetic friction, with and without the text's
check for the velocity crossing zero, and blocks on slopes of several angles (static
friction holds them below the friction angle, kinetic friction brakes them above).

Coulomb friction: at rest the friction matches the other forces along the surface up to
``mu_s N``; sliding, it is ``mu_k N`` against the motion (:func:`friction_step`). In
discrete time a friction force that would reverse the velocity in one step overshoots:
the block then rocks between two small velocities of opposite signs and creeps one way or
the other, by how its speed happened to fall (the text's "sliding block" demo). The fix is
the check: a step that would carry the velocity through zero stops it, and static
friction takes over.

Friction on a ball (the text's golf ball, after Palmer): the envs' contact law
(:func:`bbgym.physics.ball.ground_contact`) splits the ground's impulse into a normal part
(the bounce) and a tangential one, Coulomb friction at the contact point, which changes
both the ball's velocity and its spin: backspin checks a golf ball, topspin kicks it on.
And the same zero crossing in the envs' rolling ball: rolling resistance that would carry
a slow ball's rolling velocity through zero leaves it creeping unless the step checks it
(``BallParams.rolling_stop``, :func:`bbgym.physics.ball.rolling_resistance`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.ball import BallParams, BallState, ball_at, contact_slip, ground_contact, substep
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_at_least, check_fields, interval, param
from bbgym.scenes.projectiles import column
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment, state_fields

BLOCK_COLORS = ((230, 70, 60), (60, 120, 220))
"""Without the zero-crossing check, with it."""


class Blocks(NamedTuple):
    """Each block's distance along its surface and its velocity along it ``(rows,)``; the
    per-row constants: its slope, whether it checks the zero crossing."""

    s_m: Array
    v_mps: Array
    slope_rad: Array
    checks: Array


def friction_step(s: Blocks, mu_static: float, mu_kinetic: float, dt_s: float, xp: Any) -> Blocks:
    """One semi-implicit step of blocks on slopes (``s`` and ``v`` measured down the
    slope): gravity's share along it, ``g sin(theta)``; at rest, static friction holds
    the block if that is within ``mu_s g cos(theta)``; else kinetic friction
    ``mu_k g cos(theta)`` against the motion (down the slope for a block starting to
    slide). A block that checks the zero crossing stops where a step would reverse it."""
    along = GRAVITY_MPS2 * xp.sin(s.slope_rad)
    normal = GRAVITY_MPS2 * xp.cos(s.slope_rad)
    at_rest = s.v_mps == 0.0
    held = at_rest & (xp.abs(along) <= mu_static * normal)
    direction = xp.where(at_rest, xp.sign(along), xp.sign(s.v_mps))
    accel = xp.where(held, 0.0, along - mu_kinetic * normal * direction)
    v = s.v_mps + dt_s * accel
    reversed_ = (~at_rest) & (v * s.v_mps < 0.0) & (s.checks > 0.5)
    v = xp.where(reversed_, 0.0, v)
    return Blocks(s.s_m + dt_s * v, v, s.slope_rad, s.checks)


def check_coefficients(params: Any) -> None:
    """``mu_static >= mu_kinetic`` (static friction holds at least as hard as sliding
    friction brakes), or a ``ValueError`` naming the field."""
    check_at_least(params, "mu_static", "mu_kinetic")


# -- the sliding block ------------------------------------------------------------------------


@dataclass(frozen=True)
class SlidingParams:
    """Blocks pushed off at several speeds on a level floor, each twice: without and
    with the zero-crossing check."""

    speed_min_mps: float = param(2.0, interval(0.01, 100.0))
    speed_max_mps: float = param(3.0, interval(0.01, 100.0))
    blocks: int = param(7, interval(1, 64), integer=True)
    """Speeds evenly from the least to the greatest."""
    mu_kinetic: float = param(0.4, interval(0.0, 2.0))
    mu_static: float = param(0.6, interval(0.0, 2.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)
        check_coefficients(self)
        check_at_least(self, "speed_max_mps", "speed_min_mps")

    def speeds(self) -> np.ndarray:
        return np.linspace(self.speed_min_mps, self.speed_max_mps, self.blocks)


def sliding_initial(p: SlidingParams, xp: Any) -> Blocks:
    speeds = np.concatenate([p.speeds(), p.speeds()])
    checks = np.repeat([0.0, 1.0], p.blocks)
    return Blocks(
        *(xp.asarray(a, dtype=xp.float64) for a in (0.0 * speeds, speeds, 0.0 * speeds, checks))
    )


def sliding_step(p: SlidingParams, s: Blocks, xp: Any) -> Blocks:
    return friction_step(s, p.mu_static, p.mu_kinetic, p.dt_s, xp)


def sliding_measures(p: SlidingParams, s: Blocks, xp: Any) -> dict[str, Array]:
    return {"distance_m": s.s_m, "velocity_mps": s.v_mps}


def sliding_frame(p: SlidingParams, s: Blocks) -> Frame:
    distance = np.asarray(s.s_m)
    size = 0.3
    circles = []
    for row, d in enumerate(distance):
        check = row >= p.blocks
        lane = (row % p.blocks) + (p.blocks + 1) * check
        label = f"{p.speeds()[row % p.blocks]:.1f} m/s" if lane % (p.blocks + 1) == 0 else ""
        circles.append(Circle(float(d), 0.4 * lane + size, 0.5 * size, BLOCK_COLORS[check], label))
    far = p.speed_max_mps**2 / (2.0 * p.mu_kinetic * GRAVITY_MPS2) if p.mu_kinetic else 1.0
    line = "red: no check (they creep); blue: the zero-crossing check (they stop)"
    return Frame(
        circles, [Segment(far, 0.0, far, 0.4 * (2 * p.blocks + 2), (120, 120, 120), 1)], [line]
    )


def sliding_duration(p: SlidingParams) -> float:
    """Twice the longest stop, ``v0 / (mu_k g)``."""
    return 2.0 * p.speed_max_mps / (p.mu_kinetic * GRAVITY_MPS2) if p.mu_kinetic else 5.0


SLIDING_BLOCK = Scene(
    name="sliding-block",
    section="§6",
    title="Sliding block: the zero crossing",
    claim="braked by kinetic friction, a block that checks its velocity crossing zero "
    "stops at v0^2 / (2 mu_k g) and stays; without the check it never stops, rocks about "
    "zero and creeps, left or right by its starting speed",
    params=SlidingParams,
    functions=SceneFunctions(sliding_initial, sliding_step, sliding_measures, sliding_frame),
    view_box_m=lambda p: (
        -0.5,
        sliding_duration(p) * p.speed_max_mps * 0.5 + 0.5,
        -0.3,
        0.4 * (2 * p.blocks + 2) + 0.3,
    ),
    duration_s=sliding_duration,
    body_names=lambda p: tuple(
        f"{v:.2f} m/s{', check' * check}" for check in (0, 1) for v in p.speeds()
    ),
    test="test_sliding_block_stops_with_the_zero_crossing_check_and_creeps_without",
)


# -- blocks on slopes ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SlopeParams:
    """Blocks at rest on slopes from ``angle_min_deg`` to ``angle_max_deg``, released."""

    angle_min_deg: float = param(10.0, interval(0.0, 89.0))
    angle_max_deg: float = param(50.0, interval(0.0, 89.0))
    slopes: int = param(9, interval(1, 64), integer=True)
    mu_static: float = param(0.6, interval(0.0, 2.0))
    """Its friction angle, ``atan(mu_s)``: 31 deg."""
    mu_kinetic: float = param(0.4, interval(0.0, 2.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)
        check_coefficients(self)
        check_at_least(self, "angle_max_deg", "angle_min_deg")

    def angles_rad(self) -> np.ndarray:
        return np.radians(np.linspace(self.angle_min_deg, self.angle_max_deg, self.slopes))


def slope_initial(p: SlopeParams, xp: Any) -> Blocks:
    angles = p.angles_rad()
    return Blocks(
        *(
            xp.asarray(a, dtype=xp.float64)
            for a in (0.0 * angles, 0.0 * angles, angles, 1.0 + 0.0 * angles)
        )
    )


def slope_step(p: SlopeParams, s: Blocks, xp: Any) -> Blocks:
    return friction_step(s, p.mu_static, p.mu_kinetic, p.dt_s, xp)


def slope_frame(p: SlopeParams, s: Blocks) -> Frame:
    distance, angles = np.asarray(s.s_m), p.angles_rad()
    segments, circles = [], []
    for k, (d, a) in enumerate(zip(distance, angles, strict=True)):
        x0 = 3.0 * k
        segments.append(
            Segment(x0, 2.0, x0 + 2.0 * math.cos(a), 2.0 - 2.0 * math.sin(a), (120, 120, 120), 2)
        )
        along = min(float(d), 2.0)
        color = BLOCK_COLORS[int(float(d) > 0.0)]
        circles.append(
            Circle(
                x0 + along * math.cos(a),
                2.0 - along * math.sin(a) + 0.12,
                0.12,
                color,
                f"{math.degrees(a):.0f}",
            )
        )
    friction = math.degrees(math.atan(p.mu_static))
    return Frame(circles, segments, [f"friction angle {friction:.0f} deg: blue ones slide"])


SLIDING_BLOCK_2 = Scene(
    name="sliding-block-2",
    section="§6",
    title="Sliding block 2: static and kinetic friction on a slope",
    claim="a block stays put on a slope below the friction angle atan(mu_s) and slides "
    "above it, accelerating at g (sin theta - mu_k cos theta)",
    params=SlopeParams,
    functions=SceneFunctions(slope_initial, slope_step, sliding_measures, slope_frame),
    view_box_m=lambda p: (-0.5, 3.0 * p.slopes, -0.5, 2.8),
    duration_s=lambda p: 2.0,
    body_names=lambda p: tuple(f"{a:.0f} deg" for a in np.degrees(p.angles_rad())),
    test="test_blocks_on_slopes_hold_below_the_friction_angle_and_slide_above",
    floor=False,
)

# -- the golf ball: a bounce with friction --------------------------------------------------

GOLF_RADIUS_M = 0.0214
"""A golf ball's radius: the Rules of Golf's least diameter, 42.67 mm."""
GOLF_MASS_KG = 0.0459
"""A golf ball's mass: the Rules' greatest, 45.93 g."""
GOLF_DENSITY_KGM3 = GOLF_MASS_KG / (4.0 / 3.0 * math.pi * GOLF_RADIUS_M**3)
"""The density that gives a solid ball of that radius that mass (1118 kg/m^3): the envs'
:class:`~bbgym.physics.ball.BallParams` derives a solid ball's mass from its density, and
takes ``I = 2/5 m r^2`` (a real golf ball's core makes it a few percent less)."""
SPIN_SIGNS = (-1.0, 0.0, 1.0)
"""The rows: backspin, no spin, topspin (about the y axis; the ball flies along +x)."""
GOLF_NAMES = ("backspin", "no spin", "topspin")
GOLF_COLORS = ((60, 120, 220), (120, 120, 120), (230, 70, 60))
GOLF_LANE_M = 1.5
"""Height between the rows' grounds in the picture."""


@dataclass(frozen=True)
class GolfParams:
    """A golf ball coming down onto the ground at an angle, three times: with backspin,
    without spin and with topspin of the same rate; the envs' ball physics with a golf
    ball (:meth:`ball`)."""

    speed_mps: float = param(6.0, interval(0.1, 50.0))
    """Its speed at the start, just before the first bounce."""
    descent_deg: float = param(45.0, interval(1.0, 89.0))
    """The angle of its velocity below the horizontal."""
    spin_radps: float = param(600.0, interval(0.0, 1500.0))
    """The spin's rate (600 rad/s is 5700 rpm, a pitching wedge's; a driver's ~300)."""
    height_m: float = param(0.2, interval(0.0, 10.0))
    """Its lowest point's height above the ground at the start."""
    friction: float = param(0.5, interval(0.0, 2.0))
    """Coulomb's coefficient between ball and turf."""
    restitution: float = param(0.6, interval(0.0, 1.0))
    rolling_resistance: float = param(0.1, interval(0.0, 1.0))
    """Deceleration ``c g`` of the rolling ball (grass)."""
    drag_coefficient: float = param(0.25, interval(0.0, 2.0))
    """A dimpled ball's, about half a smooth sphere's."""
    dt_s: float = param(1.0 / 200.0, interval(1e-4, 0.05))

    def __post_init__(self) -> None:
        check_fields(self)
        # Derived once (not a field): the envs' ball with these values.
        object.__setattr__(
            self,
            "ball",
            BallParams(
                radius_m=GOLF_RADIUS_M,
                solid=True,
                density_kgm3=GOLF_DENSITY_KGM3,
                drag_coefficient=self.drag_coefficient,
                spin_decay_s=20.0,
                restitution=self.restitution,
                friction=self.friction,
                rolling_resistance=self.rolling_resistance,
            ),
        )


def golf_initial(p: GolfParams, xp: Any) -> BallState:
    spins = column(SPIN_SIGNS, xp) * p.spin_radps
    angle = math.radians(p.descent_deg)
    zero = column((0.0, 0.0, 0.0), xp)
    return ball_at(
        zero,
        zero,
        zero + (GOLF_RADIUS_M + p.height_m),
        zero + p.speed_mps * math.cos(angle),
        zero,
        zero - p.speed_mps * math.sin(angle),
        zero,
        spins,
        zero,
        xp,
    )


def golf_air(p: GolfParams, s: BallState, xp: Any) -> BallState:
    """The step's flight: gravity, drag and Magnus force, spin decay (the envs'
    :func:`~bbgym.physics.ball.substep`, no wind)."""
    calm = 0.0 * s.x
    return substep(p.ball, s, calm, calm, p.dt_s, xp)


def golf_contact(p: GolfParams, s: BallState, xp: Any) -> BallState:
    """The step's ground contact: bounce, Coulomb friction, rolling resistance (the envs'
    :func:`~bbgym.physics.ball.ground_contact`)."""
    return ground_contact(p.ball, s, p.dt_s, xp)[0]


def golf_step(p: GolfParams, s: BallState, xp: Any) -> BallState:
    """One step as the envs' flight takes it: the air, then the ground."""
    return golf_contact(p, golf_air(p, s, xp), xp)


def ball_energy_j(ball: BallParams, s: BallState) -> Array:
    """Kinetic (translation and rotation) plus potential energy above the resting height."""
    speed_sq = s.vx * s.vx + s.vy * s.vy + s.vz * s.vz
    spin_sq = s.wx * s.wx + s.wy * s.wy + s.wz * s.wz
    return (
        0.5 * ball.mass_kg * speed_sq
        + 0.5 * ball.inertia_kgm2 * spin_sq
        + ball.mass_kg * GRAVITY_MPS2 * (s.z - ball.radius_m)
    )


def golf_measures(p: GolfParams, s: BallState, xp: Any) -> dict[str, Array]:
    slip, _ = contact_slip(p.ball, s.vx, s.vy, s.wx, s.wy)
    return {
        "x_m": s.x,
        "height_m": s.z - GOLF_RADIUS_M,
        "velocity_mps": s.vx,
        "rim_speed_mps": GOLF_RADIUS_M * s.wy,
        "slip_mps": slip,
        "energy_j": ball_energy_j(p.ball, s),
    }


GOLF_DRAWN_RADIUS_M = 0.15
"""The balls are drawn 7 times their size, to be seen over metres of ground."""


def golf_frame(p: GolfParams, s: BallState) -> Frame:
    x, z, vx = np.asarray(s.x), np.asarray(s.z), np.asarray(s.vx)
    circles, segments = [], []
    for row in range(3):
        ground = GOLF_LANE_M * (2 - row)
        segments.append(Segment(-3.0, ground, 20.0, ground, (120, 160, 90), 2))
        height = float(z[row]) - GOLF_RADIUS_M
        circles.append(
            Circle(
                float(x[row]),
                ground + height + GOLF_DRAWN_RADIUS_M,
                GOLF_DRAWN_RADIUS_M,
                GOLF_COLORS[row],
                GOLF_NAMES[row],
            )
        )
    speeds = ", ".join(f"{name} {v:+.2f}" for name, v in zip(GOLF_NAMES, vx, strict=True))
    return Frame(
        circles, segments, [f"forward velocity (m/s): {speeds}", "balls drawn 7x their size"]
    )


GOLF_BALL = Scene(
    name="golf-ball",
    section="§6",
    title="Golf ball: a bounce with friction",
    claim="friction at the contact point, at most mu times the normal impulse, changes "
    "both the velocity and the spin: backspin checks the ball (slower after the bounce, "
    "back the way it came with enough spin), topspin kicks it on; where friction suffices "
    "the contact reaches rolling, v = omega r, and no bounce adds energy",
    params=GolfParams,
    functions=SceneFunctions(golf_initial, golf_step, golf_measures, golf_frame),
    view_box_m=lambda p: (-3.0, 20.0, -0.3, 3.0 * GOLF_LANE_M + 0.5),
    duration_s=lambda p: 3.0,
    bodies=GOLF_NAMES,
    test="test_golf_ball_backspin_checks_topspin_kicks_within_coulomb",
    floor=False,
)


# -- the envs' rolling ball: the zero crossing ------------------------------------------------

ROLLING_NAMES = ("rolling_stop off", "rolling_stop on")
"""The envs' law to date, and with the zero-crossing rule."""


class RollingBalls(state_fields(BallState, "moving_s")):
    """The envs' ball state (:class:`~bbgym.physics.ball.BallState`'s fields, one row per
    law) and how long each ball has moved at all (speed or spin not exactly 0),
    ``moving_s``."""

    __slots__ = ()


@dataclass(frozen=True)
class RollingParams:
    """The envs' beach ball set rolling along flat ground, twice: under the contact law of
    every env version to date and with the zero-crossing rule (``rolling_stop``)."""

    speed_mps: float = param(2.0, interval(0.01, 20.0))
    """Its speed at the start, rolling (``v = omega r``)."""
    rolling_resistance: float = param(0.1, interval(0.0, 1.0))
    """The envs' default: grass."""
    friction: float = param(0.6, interval(0.0, 2.0))
    dt_s: float = param(0.01, interval(1e-4, 0.05))
    """The envs' substep (``sim_dt``)."""

    def __post_init__(self) -> None:
        check_fields(self)
        object.__setattr__(
            self,
            "balls",
            tuple(
                BallParams(
                    friction=self.friction,
                    rolling_resistance=self.rolling_resistance,
                    rolling_stop=stop,
                )
                for stop in (False, True)
            ),
        )

    def stop_bound_s(self) -> float:
        """``v0 / (c g)``: when resistance alone stops the ball (drag stops it sooner);
        ``inf`` without resistance."""
        if self.rolling_resistance == 0.0:
            return math.inf
        return self.speed_mps / (self.rolling_resistance * GRAVITY_MPS2)


def rolling_initial(p: RollingParams, xp: Any) -> RollingBalls:
    zero = column((0.0, 0.0), xp)
    r = p.balls[0].radius_m
    ball = ball_at(
        zero, zero, zero + r, zero + p.speed_mps, zero, zero, zero, zero + p.speed_mps / r, zero, xp
    )
    return RollingBalls(*ball, zero)


def rolling_step(p: RollingParams, s: RollingBalls, xp: Any) -> RollingBalls:
    """Each row with its own law, as the envs' flight steps a ball: the air
    (:func:`~bbgym.physics.ball.substep`), then the ground."""
    rows = []
    for k, ball in enumerate(p.balls):
        row = BallState(*(value[k : k + 1] for value in s[:13]))
        calm = 0.0 * row.x
        rows.append(ground_contact(ball, substep(ball, row, calm, calm, p.dt_s, xp), p.dt_s, xp)[0])
    moved = BallState(*(xp.concat(values) for values in zip(*rows, strict=True)))
    moving = (moved.vx != 0.0) | (moved.vy != 0.0) | (moved.wx != 0.0) | (moved.wy != 0.0)
    return RollingBalls(*moved, s.moving_s + xp.where(moving, p.dt_s, 0.0 * s.moving_s))


def rolling_measures(p: RollingParams, s: RollingBalls, xp: Any) -> dict[str, Array]:
    r = p.balls[0].radius_m
    return {
        "distance_m": s.x,
        "speed_mps": xp.sqrt(s.vx * s.vx + s.vy * s.vy),
        "rim_speed_mps": r * xp.sqrt(s.wx * s.wx + s.wy * s.wy),
        "moving_s": s.moving_s,
    }


def rolling_frame(p: RollingParams, s: RollingBalls) -> Frame:
    x, speed = np.asarray(s.x), np.hypot(np.asarray(s.vx), np.asarray(s.vy))
    r = p.balls[0].radius_m
    circles, segments = [], []
    for row in range(2):
        ground = 3.0 * r * (1 - row)
        segments.append(Segment(-1.0, ground, 30.0, ground, (120, 120, 120), 2))
        circles.append(Circle(float(x[row]), ground + r, r, BLOCK_COLORS[row], ("off", "on")[row]))
    return Frame(circles, segments, [f"speed (m/s): off {speed[0]:.3g}, on {speed[1]:.3g}"])


ROLLING_BALL = Scene(
    name="rolling-ball",
    section="§6",
    title="Rolling ball: the zero crossing of rolling resistance",
    claim="the envs' rolling ball never stops: once rolling resistance would carry its "
    "rolling velocity through zero in a step, it only zeroes the spin and friction spins "
    "the ball up again at 3/5 of its speed, a decay by 0.6 a step; with the zero-crossing "
    "rule it stops, speed and spin exactly 0, within v0 / (c g)",
    params=RollingParams,
    functions=SceneFunctions(rolling_initial, rolling_step, rolling_measures, rolling_frame),
    view_box_m=lambda p: (-0.5, max(2.0, min(30.0, 0.6 * p.speed_mps**2 + 0.5)), -0.2, 1.2),
    duration_s=lambda p: min(20.0, max(1.0, 1.5 * p.stop_bound_s())),
    bodies=ROLLING_NAMES,
    test="test_rolling_ball_stops_exactly_with_the_zero_crossing_rule_and_creeps_without",
    floor=False,
)

SCENES = (SLIDING_BLOCK, SLIDING_BLOCK_2, GOLF_BALL, ROLLING_BALL)
