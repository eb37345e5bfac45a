"""The course's first demos: a push between two balls (§2), arrows under gravity (§3) and
beach balls dropped on a floor by different update orders and floor handlings (§3), with
drag (§8's "Three beachballs 2").

Every body is a row of a :class:`Bodies` state (a side view: x along the floor, y up), and
each step is a pure function over the array namespace ``xp``. The beach-ball scenes give
each ball its own way of stepping as constants per row (the order of the velocity and
position updates, the floor handling), so the three balls of a demo are one batch stepped
by one branch-free function, as the text's three balls are one demo.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

from bbgym.physics.ball import BallParams, drag_rate_per_s
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, check_at_least, check_fields, interval, param
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment

BALL_COLORS = ((230, 70, 60), (250, 200, 40), (60, 120, 220))
"""Left, middle and right ball."""
ARROW_COLOR = (90, 60, 30)
APPLE_COLOR = (200, 30, 40)


class Bodies(NamedTuple):
    """Positions and velocities of a scene's bodies, one row each (m, m/s)."""

    x_m: Array
    y_m: Array
    vx_mps: Array
    vy_mps: Array


def column(values: tuple[float, ...], xp: Any) -> Array:
    """A float64 array of per-body constants in ``xp``."""
    return xp.asarray(values, dtype=xp.float64)


# -- §2: push -------------------------------------------------------------------------------


@dataclass(frozen=True)
class PushParams(CheckedFields):
    """Two balls side by side on a smooth floor; one impulse between them."""

    mass_left_kg: float = param(1.0, interval(0.01, 1000.0))
    mass_right_kg: float = param(3.0, interval(0.01, 1000.0))
    impulse_ns: float = param(2.0, interval(0.0, 1000.0))
    """The impulse each ball gets from the other, in opposite directions (third law)."""
    dt_s: float = param(1.0 / 30.0, interval(1e-4, 1.0))

    def radius_m(self, mass_kg: float) -> float:
        """A beach ball's shell mass grows with its area (§4): ``r ~ sqrt(m)``, 0.3 m at
        1 kg, for the picture."""
        return 0.3 * math.sqrt(mass_kg)


def push_initial(p: PushParams, xp: Any) -> Bodies:
    """The balls touching at x = 0 just after the push: each moves off at impulse / mass
    (second law), the lighter one faster."""
    r_left, r_right = p.radius_m(p.mass_left_kg), p.radius_m(p.mass_right_kg)
    return Bodies(
        x_m=column((-r_left, r_right), xp),
        y_m=column((r_left, r_right), xp),
        vx_mps=column((-p.impulse_ns / p.mass_left_kg, p.impulse_ns / p.mass_right_kg), xp),
        vy_mps=column((0.0, 0.0), xp),
    )


def push_step(p: PushParams, s: Bodies, xp: Any) -> Bodies:
    """No force after the push: each ball keeps its velocity (first law)."""
    return Bodies(s.x_m + p.dt_s * s.vx_mps, s.y_m, s.vx_mps, s.vy_mps)


def push_measures(p: PushParams, s: Bodies, xp: Any) -> dict[str, Array]:
    mass = column((p.mass_left_kg, p.mass_right_kg), xp)
    return {
        "momentum_ns": mass * s.vx_mps,
        "kinetic_energy_j": 0.5 * mass * s.vx_mps * s.vx_mps,
        "speed_mps": xp.abs(s.vx_mps),
    }


def push_frame(p: PushParams, s: Bodies) -> Frame:
    masses = (p.mass_left_kg, p.mass_right_kg)
    circles = [
        Circle(
            float(s.x_m[i]),
            float(s.y_m[i]),
            p.radius_m(m),
            BALL_COLORS[2 * i],
            f"{m:g} kg, {abs(float(s.vx_mps[i])):.2f} m/s",
        )
        for i, m in enumerate(masses)
    ]
    total = sum(m * float(v) for m, v in zip(masses, s.vx_mps, strict=True))
    return Frame(circles, lines=[f"impulse {p.impulse_ns:g} N s each way; momentum {total:+.3f}"])


PUSH = Scene(
    name="push",
    section="§2",
    title="Push: two beach balls, one impulse",
    claim="each ball moves off at impulse / mass, and the total momentum stays zero",
    params=PushParams,
    functions=SceneFunctions(push_initial, push_step, push_measures, push_frame),
    view_box_m=lambda p: (-4.0, 4.0, -0.5, 3.5),
    duration_s=lambda p: 2.0,
    bodies=("left", "right"),
    test="test_push_gives_each_ball_impulse_over_mass_and_keeps_momentum_zero",
)


# -- §3: arrow -------------------------------------------------------------------------------


@dataclass(frozen=True)
class ArrowParams:
    """Two arrows shot at an apple at their own height: one aimed straight at it, one
    aimed up by the angle gravity asks for."""

    speed_mps: float = param(60.0, interval(1.0, 500.0))
    """A longbow's arrow leaves at about 60 m/s."""
    target_distance_m: float = param(40.0, interval(1.0, 1000.0))
    height_m: float = param(1.5, interval(0.0, 100.0))
    """The bow's and the apple's height."""
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)
        if GRAVITY_MPS2 * self.target_distance_m > self.speed_mps**2:
            raise ValueError(
                "ArrowParams.target_distance_m: out of range at this speed_mps (no angle "
                f"reaches {self.target_distance_m} m at {self.speed_mps} m/s)"
            )

    @property
    def aim_rad(self) -> float:
        """The elevation that lands a projectile at the distance on its own height without
        drag: ``D = v^2 sin(2 theta) / g``, the lower of the two angles."""
        return 0.5 * math.asin(GRAVITY_MPS2 * self.target_distance_m / self.speed_mps**2)


def arrow_initial(p: ArrowParams, xp: Any) -> Bodies:
    up = p.aim_rad
    return Bodies(
        x_m=column((0.0, 0.0), xp),
        y_m=column((p.height_m, p.height_m), xp),
        vx_mps=column((p.speed_mps, p.speed_mps * math.cos(up)), xp),
        vy_mps=column((0.0, p.speed_mps * math.sin(up)), xp),
    )


def gravity_step(s: Bodies, dt_s: float, xp: Any) -> Bodies:
    """Semi-implicit Euler under gravity alone: the velocity first, then the position with
    the new velocity (the order the text's stable ball uses)."""
    vy = s.vy_mps - GRAVITY_MPS2 * dt_s
    return Bodies(s.x_m + dt_s * s.vx_mps, s.y_m + dt_s * vy, s.vx_mps, vy)


def arrow_step(p: ArrowParams, s: Bodies, xp: Any) -> Bodies:
    return gravity_step(s, p.dt_s, xp)


def arrow_measures(p: ArrowParams, s: Bodies, xp: Any) -> dict[str, Array]:
    return {"x_m": s.x_m, "drop_m": p.height_m - s.y_m}


def arrow_frame(p: ArrowParams, s: Bodies) -> Frame:
    segments = [
        Segment(0.0, 0.0, 0.0, p.height_m, ARROW_COLOR, 2),
        Segment(p.target_distance_m, 0.0, p.target_distance_m, p.height_m - 0.1, ARROW_COLOR, 2),
    ]
    for i in range(2):
        speed = math.hypot(float(s.vx_mps[i]), float(s.vy_mps[i]))
        tail = 2.0 / max(speed, 1e-9)  # a 2 m shaft: visible at the view's scale
        x, y = float(s.x_m[i]), float(s.y_m[i])
        segments.append(
            Segment(
                x - tail * float(s.vx_mps[i]),
                y - tail * float(s.vy_mps[i]),
                x,
                y,
                BALL_COLORS[2 * i],
            )
        )
    apple = Circle(p.target_distance_m, p.height_m, 0.05, APPLE_COLOR, "apple")
    drop = p.height_m - float(s.y_m[0])
    aim = math.degrees(p.aim_rad)
    line = f"level arrow {drop:.3f} m below its aim; the other aimed {aim:.2f} deg up"
    return Frame([apple], segments, [line])


ARROW = Scene(
    name="arrow",
    section="§3",
    title="Arrow: gravity only",
    claim="an arrow aimed level falls g t^2 / 2 below its aim (the integrator's exact "
    "g dt^2 n (n + 1) / 2 after n steps); aimed up by asin(g D / v^2) / 2 it hits the apple",
    params=ArrowParams,
    functions=SceneFunctions(arrow_initial, arrow_step, arrow_measures, arrow_frame),
    view_box_m=lambda p: (-2.0, p.target_distance_m + 4.0, -1.0, p.height_m + 3.0),
    duration_s=lambda p: 1.1 * p.target_distance_m / p.speed_mps,
    bodies=("level", "aimed"),
    test="test_a_level_arrow_falls_below_its_aim_and_an_aimed_one_hits",
)


# -- §3: three beach balls on a floor ---------------------------------------------------------

VELOCITY_FIRST, POSITION_FIRST = 0.0, 1.0
"""The order of a ball's updates: the velocity first (semi-implicit Euler), or the
position first with the old velocity (explicit Euler)."""
CLAMP, REVERSE_ONLY, REFLECT = 0.0, 1.0, 2.0
"""A ball's floor handling when it is found below the floor (its centre under one radius):
reverse the velocity and put it back on the floor; reverse the velocity only; reverse it
and move the ball up as far as it went down into the floor."""


def check_above_floor(params: Any) -> None:
    """A drop's balls start above the floor: ``drop_height_m >= radius_m``, or a
    ``ValueError`` naming the field."""
    check_at_least(params, "drop_height_m", "radius_m", ": the balls start above the floor")


@dataclass(frozen=True)
class DropParams:
    """Three beach balls dropped from rest onto a floor, gravity only (radius 1 as in
    the text)."""

    radius_m: float = param(1.0, interval(0.01, 10.0))
    drop_height_m: float = param(5.0, interval(0.0, 1000.0))
    """The centres' height at the start, above the floor."""
    dt_s: float = param(1.0 / 30.0, interval(1e-4, 0.2))

    def __post_init__(self) -> None:
        check_fields(self)
        check_above_floor(self)


def drop_initial(p: DropParams, xp: Any) -> Bodies:
    spacing = 3.0 * p.radius_m
    return Bodies(
        x_m=column((-spacing, 0.0, spacing), xp),
        y_m=column((p.drop_height_m,) * 3, xp),
        vx_mps=column((0.0,) * 3, xp),
        vy_mps=column((0.0,) * 3, xp),
    )


def bounce_step(
    s: Bodies,
    radius_m: Array,
    order: Array,
    floor: Array,
    drag_per_mps: Array,
    dt_s: float,
    xp: Any,
) -> Bodies:
    """One step of each ball by its own ``order`` and ``floor`` handling (per-row
    constants, above), with quadratic drag at ``drag_per_mps`` times the speed as a rate
    (1/s; the velocity update divides by ``1 + rate dt``: drag taken implicitly, so it
    never reverses the motion)."""
    accelerated = (s.vy_mps - GRAVITY_MPS2 * dt_s) / (1.0 + drag_per_mps * xp.abs(s.vy_mps) * dt_s)
    moved_with = xp.where(order == POSITION_FIRST, s.vy_mps, accelerated)
    y = s.y_m + dt_s * moved_with
    below = y < radius_m
    vy = xp.where(below, -accelerated, accelerated)
    y = xp.where(below & (floor == CLAMP), radius_m, y)
    y = xp.where(below & (floor == REFLECT), 2.0 * radius_m - y, y)
    return Bodies(s.x_m, y, s.vx_mps, vy)


def height_energy(s: Bodies, radius_m: float | Array) -> dict[str, Array]:
    """Each ball's mechanical energy per kilogram above the floor (J/kg), its height."""
    return {
        "energy_jpkg": GRAVITY_MPS2 * (s.y_m - radius_m) + 0.5 * s.vy_mps * s.vy_mps,
        "height_m": s.y_m - radius_m,
    }


def ball_circles(s: Bodies, radius_m: float, labels: tuple[str, ...]) -> list[Circle]:
    return [
        Circle(float(s.x_m[i]), float(s.y_m[i]), radius_m, BALL_COLORS[i], label)
        for i, label in enumerate(labels)
    ]


def energy_line(s: Bodies, radius_m: float) -> str:
    energy = height_energy(s, radius_m)["energy_jpkg"]
    return "energy per kg: " + ", ".join(f"{float(e):.1f}" for e in energy) + " J/kg"


def drop_scene(
    name: str,
    title: str,
    claim: str,
    floors: tuple[float, float, float],
    labels: tuple[str, str, str],
    test: str,
) -> Scene:
    """A three-ball drop: left velocity first, middle position first, right velocity
    first, with the floor handlings ``floors``."""
    orders = (VELOCITY_FIRST, POSITION_FIRST, VELOCITY_FIRST)

    def step(p: DropParams, s: Bodies, xp: Any) -> Bodies:
        return bounce_step(s, p.radius_m, column(orders, xp), column(floors, xp), 0.0, p.dt_s, xp)

    return Scene(
        name=name,
        section="§3",
        title=title,
        claim=claim,
        params=DropParams,
        functions=SceneFunctions(
            initial=drop_initial,
            step=step,
            measures=lambda p, s, xp: height_energy(s, p.radius_m),
            frame=lambda p, s: Frame(
                ball_circles(s, p.radius_m, labels), lines=[energy_line(s, p.radius_m)]
            ),
        ),
        view_box_m=lambda p: (
            -5.0 * p.radius_m,
            5.0 * p.radius_m,
            -2.0 * p.radius_m,
            p.drop_height_m + 2.0 * p.radius_m,
        ),
        duration_s=lambda p: 60.0,
        bodies=("left", "middle", "right"),
        test=test,
    )


THREE_BEACHBALLS_1 = drop_scene(
    "three-beachballs-1",
    "Three beachballs 1: update order and floor handling",
    "the left ball (velocity first, put back on the floor) keeps its energy within a few "
    "percent, the middle (position first) gains energy, the right (velocity reversed "
    "only) loses it and sinks through the floor",
    (CLAMP, CLAMP, REVERSE_ONLY),
    ("velocity first, put back", "position first, put back", "velocity first, reversed"),
    "test_three_beachballs_1_one_stable_one_gaining_one_sinking",
)
THREE_BEACHBALLS_1A = drop_scene(
    "three-beachballs-1a",
    "Three beachballs 1a: the right ball reflected out of the floor",
    "moving the right ball up as far as it went into the floor keeps its energy within a "
    "few percent, closer as the time step shrinks (fairly stable, not perfect)",
    (CLAMP, CLAMP, REFLECT),
    ("velocity first, put back", "position first, put back", "velocity first, reflected"),
    "test_three_beachballs_1a_reflected_ball_is_fairly_stable_not_perfect",
)


# -- §8: three beach balls with drag ----------------------------------------------------------


@dataclass(frozen=True)
class DragDropParams:
    """Three beach balls of one size dropped onto a floor: the left without drag, the
    middle a light shell with drag, the right a heavier shell with the same drag."""

    radius_m: float = param(0.2, interval(0.02, 2.0))
    light_areal_density_kgm2: float = param(0.5, interval(0.02, 5.0))
    """The middle ball's shell (:class:`~bbgym.physics.ball.BallParams`'s 250 g ball)."""
    heavy_areal_density_kgm2: float = param(2.0, interval(0.02, 5.0))
    """The right ball's shell: four times the mass by default."""
    drag_coefficient: float = param(0.47, interval(0.0, 2.0))
    drop_height_m: float = param(4.0, interval(0.0, 1000.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.2))

    def __post_init__(self) -> None:
        check_fields(self)
        check_above_floor(self)

    def balls(self) -> tuple[BallParams, BallParams, BallParams]:
        """The three balls as the envs' :class:`~bbgym.physics.ball.BallParams`."""
        light = BallParams(
            radius_m=self.radius_m,
            drag_coefficient=self.drag_coefficient,
            shell_areal_density_kgm2=self.light_areal_density_kgm2,
        )
        return (
            BallParams(
                radius_m=self.radius_m,
                drag_coefficient=0.0,
                shell_areal_density_kgm2=self.light_areal_density_kgm2,
            ),
            light,
            BallParams(
                radius_m=self.radius_m,
                drag_coefficient=self.drag_coefficient,
                shell_areal_density_kgm2=self.heavy_areal_density_kgm2,
            ),
        )


def drag_drop_step(p: DragDropParams, s: Bodies, xp: Any) -> Bodies:
    # The envs' drag law (rate = rho C_d A |u| / 2 m), at 1 m/s: the rate per speed.
    per_mps = column(tuple(float(drag_rate_per_s(b, 1.0)) for b in p.balls()), xp)
    return bounce_step(
        s,
        p.radius_m,
        column((VELOCITY_FIRST,) * 3, xp),
        column((CLAMP,) * 3, xp),
        per_mps,
        p.dt_s,
        xp,
    )


THREE_BEACHBALLS_2 = Scene(
    name="three-beachballs-2",
    section="§8",
    title="Three beachballs 2: drag, divided by the mass",
    claim="with drag the light ball's bounces die fastest, the heavier one's slower, and "
    "the ball without drag keeps bouncing",
    params=DragDropParams,
    functions=SceneFunctions(
        initial=lambda p, xp: drop_initial(DropParams(p.radius_m, p.drop_height_m, p.dt_s), xp),
        step=drag_drop_step,
        measures=lambda p, s, xp: height_energy(s, p.radius_m),
        frame=lambda p, s: Frame(
            ball_circles(s, p.radius_m, ("no drag", "drag, light", "drag, heavy")),
            lines=[energy_line(s, p.radius_m)],
        ),
    ),
    view_box_m=lambda p: (
        -5.0 * p.radius_m,
        5.0 * p.radius_m,
        -2.0 * p.radius_m,
        p.drop_height_m + 2.0 * p.radius_m,
    ),
    duration_s=lambda p: 15.0,
    bodies=("no drag", "light", "heavy"),
    test="test_three_beachballs_2_drag_is_divided_by_the_mass",
)

SCENES = (PUSH, ARROW, THREE_BEACHBALLS_1, THREE_BEACHBALLS_1A, THREE_BEACHBALLS_2)
