"""Collisions (§4): an arrow stuck in an apple (plastic), and two beach balls dropped one on
the other (the restitution formula, with a beach ball's mass growing with its area).

Both use the envs' collision law, :func:`bbgym.physics.ball.collide_balls` (the text's
restitution formula along the line of centres, after Palmer): nothing is written again
here but the setup.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from bbgym.physics.ball import BallParams, collide_balls
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, interval, param
from bbgym.scenes.projectiles import (
    APPLE_COLOR,
    ARROW_COLOR,
    BALL_COLORS,
    Bodies,
    column,
    gravity_step,
)
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment


def collide_rows(
    s: Bodies, masses: tuple[float, float], restitution: float, touching: Array, xp: Any
) -> Bodies:
    """Bodies 0 and 1 collide where ``touching`` (and approaching: the law leaves bodies
    moving apart alone), by :func:`~bbgym.physics.ball.collide_balls` in the x-y plane."""
    zero = 0.0 * s.x_m[0:1]
    first = (s.vx_mps[0:1], s.vy_mps[0:1], zero)
    second = (s.vx_mps[1:2], s.vy_mps[1:2], zero)
    at_first, at_second = (s.x_m[0:1], s.y_m[0:1], zero), (s.x_m[1:2], s.y_m[1:2], zero)
    v1, v2 = collide_balls(
        masses[0], first, at_first, masses[1], second, at_second, restitution, xp
    )
    vx = xp.where(touching, xp.concat([v1[0], v2[0]]), s.vx_mps)
    vy = xp.where(touching, xp.concat([v1[1], v2[1]]), s.vy_mps)
    return Bodies(s.x_m, s.y_m, vx, vy)


# -- Arrow 2: a plastic collision ------------------------------------------------------------


@dataclass(frozen=True)
class Arrow2Params(CheckedFields):
    """An arrow flying level into an apple at rest; they stick (gravity left out: the
    arrow demo shows it)."""

    arrow_mass_kg: float = param(0.03, interval(0.001, 10.0))
    """A hunting arrow: 20-40 g."""
    apple_mass_kg: float = param(0.15, interval(0.001, 10.0))
    speed_mps: float = param(60.0, interval(0.1, 500.0))
    distance_m: float = param(3.0, interval(0.1, 100.0))
    """From the arrow's tip to the apple's centre at the start."""
    dt_s: float = param(1.0 / 600.0, interval(1e-5, 0.01))

    @property
    def apple_radius_m(self) -> float:
        return 0.04


def arrow2_initial(p: Arrow2Params, xp: Any) -> Bodies:
    return Bodies(
        x_m=column((-p.distance_m, 0.0), xp),
        y_m=column((0.0, 0.0), xp),
        vx_mps=column((p.speed_mps, 0.0), xp),
        vy_mps=column((0.0, 0.0), xp),
    )


def arrow2_step(p: Arrow2Params, s: Bodies, xp: Any) -> Bodies:
    """The two move on; the arrow's tip inside the apple, they collide plastically
    (restitution 0: one common velocity)."""
    moved = Bodies(s.x_m + p.dt_s * s.vx_mps, s.y_m, s.vx_mps, s.vy_mps)
    surface = moved.x_m[1:2] - p.apple_radius_m
    touching = moved.x_m[0:1] >= surface
    # The contact is at the apple's surface (a step may carry the tip past its centre).
    contact = Bodies(xp.concat([surface, moved.x_m[1:2]]), moved.y_m, moved.vx_mps, moved.vy_mps)
    hit = collide_rows(contact, (p.arrow_mass_kg, p.apple_mass_kg), 0.0, touching, xp)
    return Bodies(moved.x_m, moved.y_m, hit.vx_mps, hit.vy_mps)


def arrow2_measures(p: Arrow2Params, s: Bodies, xp: Any) -> dict[str, Array]:
    mass = column((p.arrow_mass_kg, p.apple_mass_kg), xp)
    return {
        "velocity_mps": s.vx_mps,
        "momentum_ns": mass * s.vx_mps,
        "kinetic_energy_j": 0.5 * mass * s.vx_mps * s.vx_mps,
    }


def arrow2_frame(p: Arrow2Params, s: Bodies) -> Frame:
    tip = float(s.x_m[0])
    apple = Circle(
        float(s.x_m[1]), 1.5, p.apple_radius_m, APPLE_COLOR, f"apple {float(s.vx_mps[1]):.1f} m/s"
    )
    shaft = Segment(tip - 0.7, 1.5, tip, 1.5, ARROW_COLOR)
    common = p.speed_mps * p.arrow_mass_kg / (p.arrow_mass_kg + p.apple_mass_kg)
    return Frame(
        [apple],
        [shaft],
        [
            f"arrow {float(s.vx_mps[0]):.1f} m/s; after the hit both "
            f"move at v m1 / (m1 + m2) = {common:.1f} m/s"
        ],
    )


ARROW_2 = Scene(
    name="arrow-2",
    section="§4",
    title="Arrow 2: a plastic collision",
    claim="the arrow sticks in the apple and both move on at v1 m1 / (m1 + m2): momentum is "
    "kept, and the kinetic energy loses the share m2 / (m1 + m2)",
    params=Arrow2Params,
    functions=SceneFunctions(arrow2_initial, arrow2_step, arrow2_measures, arrow2_frame),
    view_box_m=lambda p: (-p.distance_m - 1.0, 0.5 * p.distance_m + 1.0, 0.0, 3.0),
    duration_s=lambda p: 1.5 * p.distance_m / p.speed_mps,
    bodies=("arrow", "apple"),
    test="test_arrow_2_sticks_and_keeps_momentum",
)


# -- Double bounce: the restitution formula --------------------------------------------------


@dataclass(frozen=True)
class DoubleBounceParams(CheckedFields):
    """A small beach ball on top of a large one, dropped together onto a floor (our take
    on the text's two colliding beach balls: a vertical line of centres)."""

    bottom_radius_m: float = param(0.4, interval(0.05, 2.0))
    top_radius_m: float = param(0.2, interval(0.05, 2.0))
    """A beach ball's mass grows with its area (§4): half the radius, a quarter the mass."""
    drop_height_m: float = param(1.0, interval(0.01, 100.0))
    """The bottom ball's height above the floor at the start."""
    restitution: float = param(1.0, interval(0.0, 1.0))
    """Of both bounces, floor and ball: 1 elastic, 0 plastic."""
    dt_s: float = param(1.0 / 480.0, interval(1e-5, 0.01))

    def masses(self) -> tuple[float, float]:
        return (
            BallParams(radius_m=self.bottom_radius_m).mass_kg,
            BallParams(radius_m=self.top_radius_m).mass_kg,
        )

    def rebound_ratio(self) -> float:
        """The top ball's speed after the bounce over the impact speed: the bottom ball
        comes up at ``e v`` and meets the top one coming down at ``v``; the formula gives
        the top one ``v (e (2 + e) m1 - m2) / (m1 + m2)``."""
        m1, m2 = self.masses()
        e = self.restitution
        return (e * (2.0 + e) * m1 - m2) / (m1 + m2)


def double_initial(p: DoubleBounceParams, xp: Any) -> Bodies:
    bottom = p.drop_height_m + p.bottom_radius_m
    return Bodies(
        x_m=column((0.0, 0.0), xp),
        y_m=column((bottom, bottom + p.bottom_radius_m + p.top_radius_m), xp),
        vx_mps=column((0.0, 0.0), xp),
        vy_mps=column((0.0, 0.0), xp),
    )


def double_step(p: DoubleBounceParams, s: Bodies, xp: Any) -> Bodies:
    """Gravity (semi-implicit), the floor (a ball under it is moved up as far as it went
    in and its velocity reversed times the restitution), then the two balls where they
    overlap."""
    s = gravity_step(s, p.dt_s, xp)
    radius = column((p.bottom_radius_m, p.top_radius_m), xp)
    below = s.y_m < radius
    s = Bodies(
        s.x_m,
        xp.where(below, 2.0 * radius - s.y_m, s.y_m),
        s.vx_mps,
        xp.where(below, -p.restitution * s.vy_mps, s.vy_mps),
    )
    gap = s.y_m[1:2] - s.y_m[0:1] - (p.bottom_radius_m + p.top_radius_m)
    return collide_rows(s, p.masses(), p.restitution, gap < 0.0, xp)


def double_measures(p: DoubleBounceParams, s: Bodies, xp: Any) -> dict[str, Array]:
    mass = column(p.masses(), xp)
    radius = column((p.bottom_radius_m, p.top_radius_m), xp)
    height = s.y_m - radius
    return {
        "height_m": height,
        "velocity_mps": s.vy_mps,
        "momentum_ns": mass * s.vy_mps,
        "energy_j": mass * (GRAVITY_MPS2 * height + 0.5 * s.vy_mps * s.vy_mps),
    }


def double_frame(p: DoubleBounceParams, s: Bodies) -> Frame:
    radii, masses = (p.bottom_radius_m, p.top_radius_m), p.masses()
    circles = [
        Circle(
            float(s.x_m[i]),
            float(s.y_m[i]),
            radii[i],
            BALL_COLORS[2 * i],
            f"{masses[i] * 1000:.0f} g",
        )
        for i in range(2)
    ]
    ratio = p.rebound_ratio()
    line = f"top ball leaves at {ratio:.2f} x the impact speed: up to {ratio**2:.2f} x the drop"
    return Frame(circles, lines=[line])


DOUBLE_BOUNCE = Scene(
    name="double-bounce",
    section="§4",
    title="Double bounce: the restitution formula",
    claim="the bottom ball bounces off the floor into the top one, which leaves at "
    "(e (2 + e) m1 - m2) / (m1 + m2) times the impact speed (2.2 x for elastic beach balls "
    "of radius 0.4 and 0.2 m, masses ~ r^2); elastic, the pair keeps its energy",
    params=DoubleBounceParams,
    functions=SceneFunctions(double_initial, double_step, double_measures, double_frame),
    view_box_m=lambda p: (
        -2.5,
        2.5,
        -0.3,
        (1.0 + p.rebound_ratio() ** 2) * p.drop_height_m
        + 2.0 * (p.bottom_radius_m + p.top_radius_m)
        + 0.3,
    ),
    duration_s=lambda p: (
        3.0 * math.sqrt(2.0 * p.drop_height_m / GRAVITY_MPS2) * max(p.rebound_ratio(), 1.0)
    ),
    bodies=("bottom", "top"),
    test="test_double_bounce_follows_the_restitution_formula",
)

SCENES = (ARROW_2, DOUBLE_BOUNCE)
