"""Rotations (§5): spin given by the contact alone (kinematic rotation in a box, and the
double bounce with an offset line of centres), a ball hitting a plank, free or on an axis
(torque, the impulse turned into rotation by the moment of inertia), and many beach balls
whose spins are matched where they collide, or not.

The view is a side view: x right, y up; a spin ``omega`` (rad/s) is about the axis out of
the picture, positive counter-clockwise, and the state carries each body's angle so a
frame can show it turn (a dot near each ball's rim).

The kinematic rule (§5, "Kinematic rotations"): when a ball touches a surface of unit
normal ``n`` (pointing into the ball), its spin is set so that its contact point rolls:
``omega = v_t / r`` with ``v_t = (z x n) . v`` the velocity along the surface
(:func:`kinematic_spin`); rolling right along a floor is clockwise, ``omega = -v_x / r``.
No force and no inertia are involved: the spin does not act back on the motion. The
bounces themselves are the envs' plane bounce, :func:`bbgym.physics.ball.panel_bounce`,
and the collisions between balls the envs' :func:`bbgym.physics.ball.collide_balls` (§4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.ball import TINY, BallParams, ball_at, collide_balls, panel_bounce
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, interval, param
from bbgym.scenes.collisions import DOUBLE_BOUNCE, DoubleBounceParams, collide_rows
from bbgym.scenes.projectiles import BALL_COLORS, Bodies, column
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment

MARK_COLOR = (30, 30, 30)
"""The dot that shows a ball's angle (a beach ball's valve)."""
PLANK_COLOR = (150, 100, 50)
WALL_COLOR = (120, 110, 95)


class Spinning(NamedTuple):
    """Bodies in the side view, one row each: position (m), velocity (m/s), angle (rad) and
    spin (rad/s, counter-clockwise positive)."""

    x_m: Array
    y_m: Array
    vx_mps: Array
    vy_mps: Array
    angle_rad: Array
    angular_velocity_radps: Array


def kinematic_spin(
    vx: Array, vy: Array, nx: Array | float, ny: Array | float, radius_m: float
) -> Array:
    """§5's kinematic rule: the spin (rad/s) that makes a ball of velocity ``v`` roll on a
    surface of unit normal ``n`` (pointing into the ball): ``omega = v_t / r`` with the
    velocity along the surface ``v_t = (z x n) . v``. Its contact point, at ``-r n``, then
    moves at ``v + omega z x (-r n)``, nothing along the surface (the rolling condition of
    :func:`bbgym.physics.ball.contact_slip`). The text's ``SetRotation``: the axis
    ``v x n``, the rate ``|v_t| / r``."""
    return (nx * vy - ny * vx) / radius_m


def turned(s: Spinning, dt_s: float) -> Spinning:
    """The angles advanced by the spins over a step (the text's ``rotmat = diffrot *
    rotmat``, in 2D a sum)."""
    return Spinning(
        s.x_m,
        s.y_m,
        s.vx_mps,
        s.vy_mps,
        s.angle_rad + dt_s * s.angular_velocity_radps,
        s.angular_velocity_radps,
    )


def plane_contact(
    s: Spinning,
    radius_m: float,
    normal: tuple[float, float],
    at_m: float,
    restitution: float,
    xp: Any,
) -> Spinning:
    """A plane (a floor or a wall) of unit ``normal`` (into the box) through the point
    ``at_m`` times the normal: a ball overlapping it is put back on it and, moving in, bounces
    by the envs' :func:`~bbgym.physics.ball.panel_bounce` (the normal velocity reversed
    times ``restitution``) and gets its spin by the kinematic rule."""
    nx, ny = normal
    offset = s.x_m * nx + s.y_m * ny - at_m
    approach = s.vx_mps * nx + s.vy_mps * ny
    overlapping = offset < radius_m
    zero = 0.0 * s.x_m
    ball = ball_at(s.x_m, s.y_m, zero, s.vx_mps, s.vy_mps, zero, zero, zero, zero)
    # Moving out already, only the position is put back (no bounce pulls it in again).
    out = panel_bounce(
        ball, radius_m, nx, ny, offset, 1.0, xp.minimum(approach, 0.0), restitution, overlapping, xp
    )
    hit = overlapping & (approach < 0.0)
    spin = xp.where(hit, kinematic_spin(out.vx, out.vy, nx, ny, radius_m), s.angular_velocity_radps)
    return Spinning(out.x, out.y, out.vx, out.vy, s.angle_rad, spin)


def fall(s: Spinning, dt_s: float) -> Spinning:
    """Gravity (semi-implicit: velocity first) and the angles turned by the spins."""
    vy = s.vy_mps - GRAVITY_MPS2 * dt_s
    return turned(
        Spinning(
            s.x_m + dt_s * s.vx_mps,
            s.y_m + dt_s * vy,
            s.vx_mps,
            vy,
            s.angle_rad,
            s.angular_velocity_radps,
        ),
        dt_s,
    )


def box_step(
    s: Spinning, radius_m: float, half_width_m: float, restitution: float, dt_s: float, xp: Any
) -> Spinning:
    """:func:`fall`, then the left wall, the right wall and the floor of an open box (x in
    ``+-half_width_m``): each contact bounces the ball and sets its spin by the rule (the
    floor, last, wins a corner)."""
    s = fall(s, dt_s)
    s = plane_contact(s, radius_m, (1.0, 0.0), -half_width_m, restitution, xp)
    s = plane_contact(s, radius_m, (-1.0, 0.0), -half_width_m, restitution, xp)
    return plane_contact(s, radius_m, (0.0, 1.0), 0.0, restitution, xp)


def spin_circles(
    s: Spinning,
    radii: tuple[float, ...],
    colors: tuple[tuple[int, int, int], ...],
    labels: tuple[str, ...] = (),
) -> list[Circle]:
    """Each ball and, drawn over it, a dot at its angle (its valve: the spin shows)."""
    circles = []
    for k, r in enumerate(radii):
        x, y, angle = float(s.x_m[k]), float(s.y_m[k]), float(s.angle_rad[k])
        label = labels[k] if k < len(labels) else ""
        circles.append(Circle(x, y, r, colors[k % len(colors)], label))
        circles.append(
            Circle(
                x + 0.65 * r * math.cos(angle), y + 0.65 * r * math.sin(angle), 0.2 * r, MARK_COLOR
            )
        )
    return circles


def box_walls(half_width_m: float, height_m: float) -> list[Segment]:
    return [
        Segment(side * half_width_m, 0.0, side * half_width_m, height_m, WALL_COLOR, 4)
        for side in (-1.0, 1.0)
    ]


def spin_measures(radius_m: float, s: Spinning) -> dict[str, Array]:
    return {
        "height_m": s.y_m - radius_m,
        "vx_mps": s.vx_mps,
        "vy_mps": s.vy_mps,
        "spin_radps": s.angular_velocity_radps,
        "angle_rad": s.angle_rad,
    }


# -- Kinematic rotation: spin from the contact ------------------------------------------------


@dataclass(frozen=True)
class RotationBoxParams(CheckedFields):
    """Beach balls thrown about in an open box, each on its own (they pass through each
    other: here only the walls and the floor turn them)."""

    balls: int = param(3, interval(1, 16), integer=True)
    radius_m: float = param(0.2, interval(0.05, 0.5))
    box_width_m: float = param(4.0, interval(2.0, 20.0))
    speed_mps: float = param(4.0, interval(0.0, 10.0))
    """Each ball's speed at the start, in its own direction."""
    restitution: float = param(1.0, interval(0.0, 1.0))
    """Of every bounce; the text's demo keeps the speed (1)."""
    dt_s: float = param(1.0 / 120.0, interval(1e-4, 0.02))

    def starts(self) -> tuple[np.ndarray, ...]:
        """Positions spread across the box at 1 to 2 m, directions fanned upwards."""
        k = np.arange(self.balls)
        share = (k + 0.5) / self.balls
        free = 0.5 * self.box_width_m - self.radius_m
        x = free * (2.0 * share - 1.0) * 0.9
        y = self.radius_m + 1.0 + share
        direction = math.radians(20.0) + math.radians(140.0) * share
        return (x, y, self.speed_mps * np.cos(direction), self.speed_mps * np.sin(direction))


def box_initial(p: RotationBoxParams, xp: Any) -> Spinning:
    x, y, vx, vy = p.starts()
    still = np.zeros_like(x)
    return Spinning(*(xp.asarray(a, dtype=xp.float64) for a in (x, y, vx, vy, still, still)))


def box_scene_step(p: RotationBoxParams, s: Spinning, xp: Any) -> Spinning:
    return box_step(s, p.radius_m, 0.5 * p.box_width_m, p.restitution, p.dt_s, xp)


def box_frame(p: RotationBoxParams, s: Spinning) -> Frame:
    circles = spin_circles(s, (p.radius_m,) * p.balls, BALL_COLORS)
    spins = ", ".join(f"{float(w):+.1f}" for w in s.angular_velocity_radps[:4])
    return Frame(
        circles,
        box_walls(0.5 * p.box_width_m, 4.0),
        [f"spin (rad/s) {spins}: set at each contact to v_t / r"],
    )


def box_height_m(p: RotationBoxParams) -> float:
    """How high a ball can get: its start plus its energy's worth."""
    return p.radius_m + 2.0 + p.speed_mps**2 / (2.0 * GRAVITY_MPS2) + p.radius_m


ROTATION_BOX = Scene(
    name="rotation-box",
    section="§5",
    title="Kinematic rotation: spin from the contact",
    claim="at every bounce off a wall or the floor a ball's spin is set to v_t / r, the "
    "velocity along the surface over the radius, so its contact point rolls (clockwise "
    "rolling right on the floor); between contacts the spin does not change",
    params=RotationBoxParams,
    functions=SceneFunctions(
        initial=box_initial,
        step=box_scene_step,
        measures=lambda p, s, xp: spin_measures(p.radius_m, s),
        frame=box_frame,
    ),
    view_box_m=lambda p: (
        -0.5 * p.box_width_m - 0.3,
        0.5 * p.box_width_m + 0.3,
        -0.3,
        box_height_m(p) + 0.3,
    ),
    duration_s=lambda p: 6.0,
    body_names=lambda p: tuple(f"ball {k + 1}" for k in range(p.balls)),
    test="test_rotation_box_spin_is_set_by_the_contact_and_only_there",
)


# -- Double bounce 2: an offset line of centres ----------------------------------------------


@dataclass(frozen=True)
class DoubleBounce2Params(DoubleBounceParams):
    """§4's double bounce (the same balls and drop) with the top ball set off to the right:
    the line of centres leans, the bounce sends the balls apart sideways and the contact
    turns them."""

    offset_share: float = param(0.25, interval(0.0, 0.9))
    """The top ball's offset to the right, as a share of the sum of the radii (0: the
    upright double bounce)."""

    def offset_m(self) -> float:
        return self.offset_share * (self.bottom_radius_m + self.top_radius_m)


def double2_initial(p: DoubleBounce2Params, xp: Any) -> Spinning:
    """The two touching, dropped from rest."""
    bottom = p.drop_height_m + p.bottom_radius_m
    reach = p.bottom_radius_m + p.top_radius_m
    rise = math.sqrt(reach**2 - p.offset_m() ** 2)
    zero = column((0.0, 0.0), xp)
    return Spinning(
        column((0.0, p.offset_m()), xp), column((bottom, bottom + rise), xp), zero, zero, zero, zero
    )


def double2_fall(p: DoubleBounce2Params, s: Spinning, xp: Any) -> Spinning:
    """:func:`fall` and the floor, each ball with its own radius (no walls)."""
    rows = []
    for k, r in enumerate((p.bottom_radius_m, p.top_radius_m)):
        row = Spinning(*(a[k : k + 1] for a in s))
        rows.append(plane_contact(fall(row, p.dt_s), r, (0.0, 1.0), 0.0, p.restitution, xp))
    return Spinning(*(xp.concat([a, b]) for a, b in zip(*rows, strict=True)))


def double2_collide(p: DoubleBounce2Params, s: Spinning, xp: Any) -> Spinning:
    """Where the balls overlap and approach: the envs' collision along the line of centres
    (:func:`~bbgym.scenes.collisions.collide_rows`, §4), and each ball's spin set by the
    kinematic rule, the other ball taken as a surface moving with it: ``omega_i = (z x n_i)
    . (v_i - v_j) / r_i`` with ``n_i`` from the other's centre to its own. The collision
    changes only the velocities along the line of centres, so the velocity along the
    contact is the same before and after."""
    dx, dy = s.x_m[1:2] - s.x_m[0:1], s.y_m[1:2] - s.y_m[0:1]
    distance = xp.sqrt(dx * dx + dy * dy)
    rel_x, rel_y = s.vx_mps[0:1] - s.vx_mps[1:2], s.vy_mps[0:1] - s.vy_mps[1:2]
    touching = distance < p.bottom_radius_m + p.top_radius_m
    hit = touching & (rel_x * dx + rel_y * dy > 0.0)  # approaching: collide_balls' test
    out = collide_rows(
        Bodies(s.x_m, s.y_m, s.vx_mps, s.vy_mps), p.masses(), p.restitution, touching, xp
    )
    nx, ny = dx / xp.maximum(distance, TINY), dy / xp.maximum(distance, TINY)
    # n_bottom = -n (from the top ball down to the bottom one), n_top = n, v_rel flips too:
    # both balls get the same sign.
    along = kinematic_spin(rel_x, rel_y, -nx, -ny, 1.0)
    spins = xp.concat([along / p.bottom_radius_m, along / p.top_radius_m])
    spin = xp.where(xp.concat([hit, hit]), spins, s.angular_velocity_radps)
    return Spinning(out.x_m, out.y_m, out.vx_mps, out.vy_mps, s.angle_rad, spin)


def double2_step(p: DoubleBounce2Params, s: Spinning, xp: Any) -> Spinning:
    return double2_collide(p, double2_fall(p, s, xp), xp)


def double2_frame(p: DoubleBounce2Params, s: Spinning) -> Frame:
    radii, masses = (p.bottom_radius_m, p.top_radius_m), p.masses()
    labels = tuple(
        f"{m * 1000:.0f} g, {float(w):+.1f} rad/s"
        for m, w in zip(masses, s.angular_velocity_radps, strict=True)
    )
    circles = spin_circles(s, radii, (BALL_COLORS[0], BALL_COLORS[2]), labels)
    return Frame(
        circles,
        lines=["the contact turns both balls clockwise: v_t / r each, v_t their velocity along it"],
    )


DOUBLE_BOUNCE_2 = Scene(
    name="double-bounce-2",
    section="§5",
    title="Double bounce 2: the contact turns the balls",
    claim="with the top ball off centre the bounce sends the balls apart sideways by the "
    "restitution formula along the line of centres (momentum along it kept, the approach "
    "speed reversed times e), and the contact sets each ball's spin to v_t / r_i, v_t "
    "their relative velocity along the contact: both turn the same way, the small one faster",
    params=DoubleBounce2Params,
    functions=SceneFunctions(
        initial=double2_initial,
        step=double2_step,
        measures=lambda p, s, xp: spin_measures(column((p.bottom_radius_m, p.top_radius_m), xp), s),
        frame=double2_frame,
    ),
    view_box_m=lambda p: (-4.0, 4.0, *DOUBLE_BOUNCE.view_box_m(p)[2:]),
    duration_s=DOUBLE_BOUNCE.duration_s,
    bodies=("bottom", "top"),
    test="test_double_bounce_2_spins_by_the_contact_and_keeps_the_formula",
)


# -- The plank: an impulse off the centre turns it ------------------------------------------


@dataclass(frozen=True)
class PlankParams(CheckedFields):
    """A ball flying down onto a plank lying level at rest, no gravity (the text's plank
    floats: seen from above on ice, or in space)."""

    ball_mass_kg: float = param(0.5, interval(0.01, 100.0))
    ball_radius_m: float = param(0.2, interval(0.02, 1.0))
    speed_mps: float = param(3.0, interval(0.1, 50.0))
    plank_mass_kg: float = param(2.0, interval(0.01, 100.0))
    plank_length_m: float = param(5.0, interval(0.5, 20.0))
    """The text's plank: 2.5 + 2.5 m, thin (``l >> r``: ``I = m l^2 / 12``)."""
    hit_share: float = param(0.6, interval(-1.0, 1.0))
    """Where the ball hits, from the plank's centre, as a share of its half-length (1: the
    right end)."""
    restitution: float = param(1.0, interval(0.0, 1.0))
    dt_s: float = param(1.0 / 240.0, interval(1e-5, 0.01))

    def hit_m(self) -> float:
        """The ball's x: its distance from the plank's centre (``d``)."""
        return 0.5 * self.hit_share * self.plank_length_m

    def centre_inertia_kgm2(self) -> float:
        """A thin rod about its centre: ``m l^2 / 12`` (§5's table, ``l >> r``)."""
        return self.plank_mass_kg * self.plank_length_m**2 / 12.0

    def pivot_m(self) -> float | None:
        """The axis's x on the plank (from its centre); ``None``: the plank is free."""
        return None


@dataclass(frozen=True)
class AnchoredPlankParams(PlankParams):
    """The plank on an axis through it, perpendicular to the picture."""

    axis_share: float = param(-1.0, interval(-1.0, 1.0))
    """The axis's place from the centre as a share of the half-length (-1: the left end,
    the text's ``axisPosition`` over 2.5 m)."""

    def pivot_m(self) -> float:
        return 0.5 * self.axis_share * self.plank_length_m

    def axis_inertia_kgm2(self) -> float:
        """§5's split: the plank is two rods, ``d1`` and ``d2`` long, each turning about
        its end at the axis, ``1/3 m_k d_k^2``. Each piece has its share of the mass,
        ``m_k = m d_k / l`` (the text's code gives each the whole mass, right only with the
        axis at an end; it doubles ``m l^2 / 12`` with the axis in the middle). The sum is
        ``m l^2 / 12 + m s^2``, the parallel-axis theorem, ``s`` the axis's offset."""
        half = 0.5 * self.plank_length_m
        d1, d2 = half - self.pivot_m(), half + self.pivot_m()
        mass_per_m = self.plank_mass_kg / self.plank_length_m
        return sum(mass_per_m * d / 3.0 * d * d for d in (d1, d2))


def plank_initial(p: PlankParams, xp: Any) -> Spinning:
    """The ball one metre above the plank, falling at ``speed_mps``; the plank level,
    centred on the origin, at rest. Row 0 the ball (no spin of its own), row 1 the
    plank."""
    zero = column((0.0, 0.0), xp)
    return Spinning(
        column((p.hit_m(), 0.0), xp),
        column((1.0 + p.ball_radius_m, 0.0), xp),
        zero,
        column((-p.speed_mps, 0.0), xp),
        zero,
        zero,
    )


def plank_step(p: PlankParams, s: Spinning, xp: Any) -> Spinning:
    """Both move on (the anchored plank turns about its axis); where the ball touches the
    plank's face moving in, §4's restitution formula (:func:`collide_balls`) acts between
    the ball and the plank's contact point, which weighs its effective mass ``m_eff``
    along the face's normal: free, ``1/m_eff = 1/m + d^2/I``; on an axis, ``I_axis / a^2``
    (``d`` and ``a`` the contact's distance from the centre and from the axis). The
    impulse ``J`` it takes gives the plank ``J / m`` and ``J d / I`` (free) or only
    ``J a / I_axis``; the ball gets ``-J``. One line of action: the pair's momentum (free)
    and its angular momentum about any fixed point (about the axis, anchored) are kept."""
    dt, pivot = p.dt_s, p.pivot_m()
    ball, plank = (Spinning(*(a[k : k + 1] for a in s)) for k in (0, 1))
    angle = plank.angle_rad + dt * plank.angular_velocity_radps
    along_x, along_y = xp.cos(angle), xp.sin(angle)
    if pivot is None:
        cx, cy = plank.x_m + dt * plank.vx_mps, plank.y_m + dt * plank.vy_mps
    else:  # the centre on its circle about the axis, which is at (pivot, 0)
        cx, cy = pivot - pivot * along_x, -pivot * along_y
    bx, by = ball.x_m + dt * ball.vx_mps, ball.y_m + dt * ball.vy_mps
    along = (bx - cx) * along_x + (by - cy) * along_y
    across = (by - cy) * along_x - (bx - cx) * along_y
    touching = (xp.abs(across) < p.ball_radius_m) & (xp.abs(along) <= 0.5 * p.plank_length_m)
    # The face's unit normal from the ball into the plank.
    side = xp.where(across >= 0.0, 0.0 * across - 1.0, 0.0 * across + 1.0)
    nx, ny = -along_y * side, along_x * side
    w = plank.angular_velocity_radps
    if pivot is None:  # the contact point: the centre's velocity plus w z x (along e)
        lever, inertia = along, p.centre_inertia_kgm2()
        inverse_mass = 1.0 / p.plank_mass_kg + lever * lever / inertia
        vx_point, vy_point = plank.vx_mps - w * lever * along_y, plank.vy_mps + w * lever * along_x
    else:  # the contact point turns about the axis: w z x (lever e)
        lever, inertia = along - pivot, p.axis_inertia_kgm2()
        inverse_mass = lever * lever / inertia
        vx_point, vy_point = -w * lever * along_y, w * lever * along_x
    # On the axis itself the plank cannot give: its effective mass is bounded, not infinite.
    m_eff = 1.0 / xp.maximum(inverse_mass, TINY)
    zero = 0.0 * bx
    v_ball, v_point = collide_balls(
        p.ball_mass_kg,
        (ball.vx_mps, ball.vy_mps, zero),
        (bx, by, zero),
        m_eff,
        (vx_point, vy_point, zero),
        (bx + nx, by + ny, zero),
        p.restitution,
        xp,
    )
    jx = xp.where(touching, m_eff * (v_point[0] - vx_point), 0.0)
    jy = xp.where(touching, m_eff * (v_point[1] - vy_point), 0.0)
    w = w + lever * (along_x * jy - along_y * jx) / inertia
    if pivot is None:
        vx, vy = plank.vx_mps + jx / p.plank_mass_kg, plank.vy_mps + jy / p.plank_mass_kg
    else:  # the centre's velocity, w z x (centre - axis), the centre -pivot along the plank
        vx, vy = w * pivot * along_y, -w * pivot * along_x
    return Spinning(
        xp.concat([bx, cx]),
        xp.concat([by, cy]),
        xp.concat([xp.where(touching, v_ball[0], ball.vx_mps), vx]),
        xp.concat([xp.where(touching, v_ball[1], ball.vy_mps), vy]),
        xp.concat([ball.angle_rad, angle]),
        xp.concat([ball.angular_velocity_radps, w]),
    )


def plank_measures(p: PlankParams, s: Spinning, xp: Any) -> dict[str, Array]:
    """Per body: momentum, angular momentum about the fixed point (the plank's start's
    centre; the axis, anchored), kinetic energy and spin. The plank's angular momentum
    is its own, ``I omega``, plus its centre's, ``m r x v``."""
    pivot = p.pivot_m()
    ox = 0.0 if pivot is None else pivot
    mass = column((p.ball_mass_kg, p.plank_mass_kg), xp)
    inertia = column((0.0, p.centre_inertia_kgm2()), xp)
    w = s.angular_velocity_radps
    orbit = mass * ((s.x_m - ox) * s.vy_mps - s.y_m * s.vx_mps)
    speed_sq = s.vx_mps * s.vx_mps + s.vy_mps * s.vy_mps
    return {
        "momentum_x_ns": mass * s.vx_mps,
        "momentum_y_ns": mass * s.vy_mps,
        "angular_momentum_js": orbit + inertia * w,
        "kinetic_energy_j": 0.5 * mass * speed_sq + 0.5 * inertia * w * w,
        "spin_radps": w,
    }


def plank_frame(p: PlankParams, s: Spinning) -> Frame:
    cx, cy, angle = float(s.x_m[1]), float(s.y_m[1]), float(s.angle_rad[1])
    half = 0.5 * p.plank_length_m
    dx, dy = half * math.cos(angle), half * math.sin(angle)
    circles = [Circle(float(s.x_m[0]), float(s.y_m[0]), p.ball_radius_m, BALL_COLORS[0])]
    pivot = p.pivot_m()
    if pivot is not None:
        circles.append(Circle(pivot, 0.0, 0.06, MARK_COLOR, "axis"))
    w = float(s.angular_velocity_radps[1])
    return Frame(
        circles,
        [Segment(cx - dx, cy - dy, cx + dx, cy + dy, PLANK_COLOR, 6)],
        [f"plank spin {w:+.2f} rad/s, centre moving at {float(s.vy_mps[1]):+.2f} m/s"],
    )


def plank_view(p: PlankParams) -> tuple[float, float, float, float]:
    reach = 0.6 * p.plank_length_m + p.speed_mps * plank_duration(p)
    return (-reach, reach, -reach, reach)


def plank_duration(p: PlankParams) -> float:
    """Until the ball is as far past the plank as it started above it."""
    return 2.0 / p.speed_mps


def plank_scene(name: str, title: str, claim: str, params: type, test: str) -> Scene:
    return Scene(
        name=name,
        section="§5",
        title=title,
        claim=claim,
        params=params,
        functions=SceneFunctions(plank_initial, plank_step, plank_measures, plank_frame),
        view_box_m=plank_view,
        duration_s=plank_duration,
        bodies=("ball", "plank"),
        test=test,
        floor=False,
    )


PLANK_FREE = plank_scene(
    "plank-free",
    "The plank: an impulse off the centre turns it",
    "the ball's impulse J at d from the centre moves the plank at J / m and turns it at "
    "J d / I, I = m l^2 / 12; J follows from the restitution formula with the plank's "
    "effective mass 1 / (1/m + d^2/I); momentum and angular momentum are kept, and the "
    "kinetic energy too when elastic (lost, never gained, when not)",
    PlankParams,
    "test_plank_free_moves_and_turns_by_the_impulse_and_keeps_momentum",
)
PLANK_ANCHORED = plank_scene(
    "plank-anchored",
    "The plank on an axis",
    "on an axis the plank does not move off, it only turns, at J a / I_axis with "
    "I_axis = m l^2 / 3 about an end (the text's split into two rods, each piece with its "
    "share of the mass: m l^2 / 12 + m s^2); the angular momentum about the axis is kept, "
    "the momentum is not (the axis pushes)",
    AnchoredPlankParams,
    "test_plank_anchored_turns_about_its_axis_and_keeps_angular_momentum_there",
)


# -- Many beach balls: spins matched where they collide, or not -----------------------------


@dataclass(frozen=True)
class ManyParams(CheckedFields):
    """Beach balls started in rows in an open box, thrown about and colliding."""

    balls: int = param(12, interval(2, 32), integer=True)
    radius_m: float = param(0.2, interval(0.05, 0.4))
    box_width_m: float = param(2.4, interval(1.0, 20.0))
    speed_mps: float = param(3.0, interval(0.0, 10.0))
    """Each ball's speed at the start, in a direction drawn by ``seed``."""
    restitution: float = param(0.8, interval(0.0, 1.0))
    """Of the bounces and of the collisions."""
    seed: int = param(0, interval(0, 2**31 - 1), integer=True)
    dt_s: float = param(1.0 / 120.0, interval(1e-4, 0.02))

    def starts(self) -> tuple[np.ndarray, ...]:
        """Rows of balls 2.5 radii apart from 0.5 m up, directions drawn by ``seed``."""
        columns = max(int((self.box_width_m - 2.0 * self.radius_m) // (2.5 * self.radius_m)), 1)
        k = np.arange(self.balls)
        x = -0.5 * self.box_width_m + self.radius_m * (1.25 + 2.5 * (k % columns))
        x = np.minimum(x, 0.5 * self.box_width_m - self.radius_m)
        y = self.radius_m + 0.5 + 2.5 * self.radius_m * (k // columns)
        direction = np.random.default_rng(self.seed).uniform(0.0, 2.0 * math.pi, self.balls)
        return (x, y, self.speed_mps * np.cos(direction), self.speed_mps * np.sin(direction))

    def mass_kg(self) -> float:
        return BallParams(radius_m=self.radius_m).mass_kg


def many_initial(p: ManyParams, xp: Any) -> Spinning:
    x, y, vx, vy = p.starts()
    still = np.zeros_like(x)
    return Spinning(*(xp.asarray(a, dtype=xp.float64) for a in (x, y, vx, vy, still, still)))


def row_sum(a: Array, n: int) -> Array:
    """``a`` (``(n, n)``) summed along its rows, column by column in a fixed order: every
    backend adds the same numbers in the same order (a reduction's order is its own)."""
    total = a[:, 0]
    for j in range(1, n):
        total = total + a[:, j]
    return total


class Pairs(NamedTuple):
    """Every pair ``(i, j)`` of balls, ``(n, n)``: the unit vector from ``i`` to ``j``,
    the overlap (m, > 0 touching) and whether ``i`` and ``j`` approach."""

    nx: Array
    ny: Array
    overlap_m: Array
    approaching: Array


def pairs(s: Spinning, radius_m: float, xp: Any) -> Pairs:
    n = s.x_m.shape[0]
    dx, dy = s.x_m[None, :] - s.x_m[:, None], s.y_m[None, :] - s.y_m[:, None]
    distance = xp.sqrt(dx * dx + dy * dy)
    others = xp.logical_not(xp.eye(n, dtype=xp.bool))
    nx, ny = dx / xp.maximum(distance, TINY), dy / xp.maximum(distance, TINY)
    overlap = xp.where(others, 2.0 * radius_m - distance, 0.0 * distance - 1.0)
    closing = (s.vx_mps[:, None] - s.vx_mps[None, :]) * nx + (
        s.vy_mps[:, None] - s.vy_mps[None, :]
    ) * ny
    return Pairs(nx, ny, overlap, (overlap > 0.0) & (closing > 0.0))


def matched_spins(spin: Array, colliding: Array, n: int, xp: Any) -> Array:
    """§5's matching ("Many beachballs"): two colliding balls take half the difference of
    their spins, one each way, ``omega_i' = (omega_i - omega_j) / 2 = -omega_j'``: they
    turn against each other like meshed gears, their surfaces moving together at the
    contact. A ball in several collisions at once takes the mean over them."""
    halves = xp.where(colliding, 0.5 * (spin[:, None] - spin[None, :]), 0.0)
    count = row_sum(xp.astype(colliding, xp.float64), n)
    return xp.where(count > 0.0, row_sum(halves, n) / xp.maximum(count, 1.0), spin)


def many_collide(p: ManyParams, s: Spinning, match: bool, xp: Any) -> Spinning:
    """Every approaching touching pair collides by the envs' :func:`collide_balls` (each
    ball summing its pairs' velocity changes), spins matched if ``match``; then each
    touching pair is pushed apart, half the overlap each (positions only)."""
    n, m, r = p.balls, p.mass_kg(), p.radius_m
    g = pairs(s, r, xp)
    zero = 0.0 * g.nx
    mine = (s.vx_mps[:, None] + zero, s.vy_mps[:, None] + zero, zero)
    theirs = (s.vx_mps[None, :] + zero, s.vy_mps[None, :] + zero, zero)
    at_mine, at_theirs = (zero, zero, zero), (g.nx, g.ny, zero)
    after, _ = collide_balls(m, mine, at_mine, m, theirs, at_theirs, p.restitution, xp)
    vx = s.vx_mps + row_sum(xp.where(g.approaching, after[0] - mine[0], 0.0), n)
    vy = s.vy_mps + row_sum(xp.where(g.approaching, after[1] - mine[1], 0.0), n)
    spin = s.angular_velocity_radps
    if match:
        spin = matched_spins(spin, g.approaching, n, xp)
    push = 0.5 * xp.maximum(g.overlap_m, 0.0)
    x, y = s.x_m - row_sum(push * g.nx, n), s.y_m - row_sum(push * g.ny, n)
    return Spinning(x, y, vx, vy, s.angle_rad, spin)


def gear_slip(p: ManyParams, s: Spinning, xp: Any) -> Array:
    """Per ball, the largest ``r |omega_i + omega_j|`` over the balls ``j`` it touches
    (within 1% of a radius): the spins' share of the slip at their contact (m/s; 0 for
    balls turning as meshed gears, and for a ball touching none)."""
    g = pairs(s, p.radius_m, xp)
    touching = g.overlap_m > -0.01 * p.radius_m
    spin = s.angular_velocity_radps
    slip = xp.where(touching, p.radius_m * xp.abs(spin[:, None] + spin[None, :]), 0.0)
    return xp.max(slip, axis=1)


def many_top_m(p: ManyParams) -> float:
    """The view's top: the highest start, its energy's worth above."""
    top = float(np.max(p.starts()[1])) + p.radius_m
    return top + p.speed_mps**2 / (2.0 * GRAVITY_MPS2) + 0.3


def many_scene(name: str, title: str, claim: str, match: bool) -> Scene:
    def step(p: ManyParams, s: Spinning, xp: Any) -> Spinning:
        s = box_step(s, p.radius_m, 0.5 * p.box_width_m, p.restitution, p.dt_s, xp)
        return many_collide(p, s, match, xp)

    def measures(p: ManyParams, s: Spinning, xp: Any) -> dict[str, Array]:
        g = pairs(s, p.radius_m, xp)
        contacts = row_sum(xp.astype(g.overlap_m > -0.01 * p.radius_m, xp.float64), p.balls)
        return {
            "height_m": s.y_m - p.radius_m,
            "spin_radps": s.angular_velocity_radps,
            "contacts": contacts,
            "gear_slip_mps": gear_slip(p, s, xp),
        }

    def frame(p: ManyParams, s: Spinning) -> Frame:
        circles = spin_circles(s, (p.radius_m,) * p.balls, BALL_COLORS)
        worst = float(np.max(np.asarray(gear_slip(p, s, np))))
        rule = "matched where they collide" if match else "set by the walls and floor only"
        return Frame(
            circles,
            box_walls(0.5 * p.box_width_m, many_top_m(p)),
            [f"spins {rule}; worst slip at a contact {worst:.2f} m/s"],
        )

    return Scene(
        name=name,
        section="§5",
        title=title,
        claim=claim,
        params=ManyParams,
        functions=SceneFunctions(many_initial, step, measures, frame),
        view_box_m=lambda p: (
            -0.5 * p.box_width_m - 0.3,
            0.5 * p.box_width_m + 0.3,
            -0.3,
            many_top_m(p),
        ),
        duration_s=lambda p: 5.0,
        body_names=lambda p: tuple(f"ball {k + 1}" for k in range(p.balls)),
        test="test_many_beachballs_match_spins_where_they_collide_the_bad_ones_do_not",
    )


MANY_BEACHBALLS = many_scene(
    "many-beachballs",
    "Many beachballs: spins matched where they collide",
    "two colliding balls take half their spins' difference, one each way (omega_i' = "
    "-omega_j'), so touching balls turn as meshed gears: the spins' slip at their contacts "
    "is a fraction of the unmatched one's",
    True,
)
MANY_BEACHBALLS_BAD = many_scene(
    "many-beachballs-bad",
    "Many beachballs bad: spins from the walls only",
    "without the matching a collision leaves the spins alone: piled balls keep the spins "
    "the walls and the floor gave them, unrelated to their neighbours'",
    False,
)

SCENES = (
    ROTATION_BOX,
    DOUBLE_BOUNCE_2,
    PLANK_FREE,
    PLANK_ANCHORED,
    MANY_BEACHBALLS,
    MANY_BEACHBALLS_BAD,
)
