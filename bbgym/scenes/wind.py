"""Wind effects (§8): dropping large things ("bowling balls": the elephant and the mouse),
and the Magnus effect of a spinning beach ball.

Both run the envs' own ball laws (:mod:`bbgym.physics.ball`): the drag ``1/2 rho C_d A v^2``
as the damping rate :func:`~bbgym.physics.ball.drag_rate_per_s` (taken implicitly, so any
step is stable), and the Magnus force :func:`~bbgym.physics.ball.magnus_force`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from bbgym.physics.ball import BallParams, drag_rate_per_s, magnus_force
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_fields, interval, param
from bbgym.scenes.projectiles import BALL_COLORS, Bodies, column
from bbgym.scenes.scene import Circle, Frame, Scene, Segment

# -- bowling balls: the elephant falls faster -------------------------------------------------


@dataclass(frozen=True)
class FallParams:
    """Four balls dropped together: a small and a large solid ball (the text's mouse and
    elephant: light, so the drag shows within the drop), a small and a large beach ball."""

    small_radius_m: float = param(0.05, interval(0.02, 2.0))
    large_radius_m: float = param(0.5, interval(0.02, 2.0))
    solid_density_kgm3: float = param(20.0, interval(10.0, 20000.0))
    """Expanded polystyrene: light enough that drag matters over the drop."""
    drop_height_m: float = param(30.0, interval(1.0, 1000.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)

    def balls(self) -> tuple[BallParams, ...]:
        """Small solid, large solid, small shell, large shell (the envs' ball)."""
        return tuple(
            BallParams(radius_m=r, solid=solid, density_kgm3=self.solid_density_kgm3)
            for solid in (True, False)
            for r in (self.small_radius_m, self.large_radius_m)
        )


FALL_NAMES = ("small solid", "large solid", "small beach ball", "large beach ball")


def fall_initial(p: FallParams, xp: Any) -> Bodies:
    radii = [b.radius_m for b in p.balls()]
    return Bodies(
        x_m=column((-15.0, -5.0, 5.0, 15.0), xp),
        y_m=column(tuple(p.drop_height_m + r for r in radii), xp),
        vx_mps=column((0.0,) * 4, xp),
        vy_mps=column((0.0,) * 4, xp),
    )


def fall_step(p: FallParams, s: Bodies, xp: Any) -> Bodies:
    """Gravity, and the drag taken implicitly (``v' = (v - g dt) / (1 + c |v| dt)``, ``c``
    the envs' rate per speed); a ball that reaches the ground stops there."""
    balls = p.balls()
    per_mps = column(tuple(float(drag_rate_per_s(b, 1.0)) for b in balls), xp)
    radius = column(tuple(b.radius_m for b in balls), xp)
    vy = (s.vy_mps - GRAVITY_MPS2 * p.dt_s) / (1.0 + per_mps * xp.abs(s.vy_mps) * p.dt_s)
    y = s.y_m + p.dt_s * vy
    landed = y <= radius
    return Bodies(s.x_m, xp.where(landed, radius, y), s.vx_mps, xp.where(landed, 0.0, vy))


def fall_measures(p: FallParams, s: Bodies, xp: Any) -> dict[str, Array]:
    radius = column(tuple(b.radius_m for b in p.balls()), xp)
    return {"speed_mps": 0.0 - s.vy_mps, "height_m": s.y_m - radius}


def fall_frame(p: FallParams, s: Bodies) -> Frame:
    balls = p.balls()
    circles = [Circle(float(s.x_m[k]), float(s.y_m[k]), b.radius_m, BALL_COLORS[k % 3],
                      f"{FALL_NAMES[k]}: {-float(s.vy_mps[k]):.1f} m/s")
               for k, b in enumerate(balls)]  # fmt: skip
    terminal = ", ".join(f"{b.terminal_speed_mps():.1f}" for b in balls)
    return Frame(circles, lines=[f"terminal speeds {terminal} m/s"])


BOWLING_BALLS = Scene(
    name="bowling-balls",
    section="§8",
    title="Bowling balls: the elephant and the mouse",
    claim="with drag the large solid ball falls faster than the small one (mass ~ r^3, "
    "area ~ r^2: terminal speed ~ sqrt(r)), while beach balls of any size fall alike "
    "(mass and area both ~ r^2); each approaches sqrt(2 m g / (rho C_d A))",
    params=FallParams,
    initial=fall_initial,
    step=fall_step,
    measures=fall_measures,
    frame=fall_frame,
    view_box_m=lambda p: (-20.0, 20.0, -1.0, p.drop_height_m + 2.0 * p.large_radius_m + 1.0),
    duration_s=lambda p: 8.0,
    bodies=FALL_NAMES,
    test="test_bowling_balls_the_elephant_falls_faster_beach_balls_alike",
)


# -- Magnus: spin bends a beach ball's flight ---------------------------------------------------


@dataclass(frozen=True)
class MagnusParams:
    """Three beach balls thrown level at one speed: with backspin, without spin, with
    topspin (the envs' 40 cm, 250 g ball)."""

    speed_mps: float = param(8.0, interval(0.1, 50.0))
    spin_radps: float = param(20.0, interval(0.0, 200.0))
    launch_height_m: float = param(1.5, interval(0.0, 100.0))
    dt_s: float = param(1.0 / 120.0, interval(1e-4, 0.05))

    def __post_init__(self) -> None:
        check_fields(self)


MAGNUS_NAMES = ("backspin", "no spin", "topspin")
BALL = BallParams()


def magnus_initial(p: MagnusParams, xp: Any) -> Bodies:
    return Bodies(
        x_m=column((0.0, 0.0, 0.0), xp),
        y_m=column((p.launch_height_m,) * 3, xp),
        vx_mps=column((p.speed_mps,) * 3, xp),
        vy_mps=column((0.0,) * 3, xp),
    )


def magnus_step(p: MagnusParams, s: Bodies, xp: Any) -> Bodies:
    """Gravity, drag (implicit, the envs' rate) and the Magnus force (the envs' law: spin
    about the horizontal axis across the flight; backspin, the ball's top turning back
    toward the thrower, has its vector to the thrower's right, and lifts the ball), the
    spin held (a short flight); a ball on the ground stays."""
    # x ahead, y up here; the ball laws' frame has z up: map (x, y) -> (x, z), spin about y.
    spin = column((p.spin_radps, 0.0, -p.spin_radps), xp)
    zero = 0.0 * s.vx_mps
    fx, _, fz, _ = magnus_force(BALL, s.vx_mps, zero, s.vy_mps, zero, -spin, zero, xp)
    speed = xp.sqrt(s.vx_mps * s.vx_mps + s.vy_mps * s.vy_mps)
    damping = 1.0 + drag_rate_per_s(BALL, speed) * p.dt_s
    vx = (s.vx_mps + p.dt_s * fx / BALL.mass_kg) / damping
    vy = (s.vy_mps + p.dt_s * (fz / BALL.mass_kg - GRAVITY_MPS2)) / damping
    flying = s.y_m > BALL.radius_m
    x = xp.where(flying, s.x_m + p.dt_s * vx, s.x_m)
    y = xp.where(flying, xp.maximum(s.y_m + p.dt_s * vy, BALL.radius_m), s.y_m)
    return Bodies(x, y, xp.where(flying, vx, 0.0), xp.where(flying, vy, 0.0))


def magnus_measures(p: MagnusParams, s: Bodies, xp: Any) -> dict[str, Array]:
    return {"distance_m": s.x_m, "height_m": s.y_m - BALL.radius_m}


def magnus_frame(p: MagnusParams, s: Bodies) -> Frame:
    circles = [Circle(float(s.x_m[k]), float(s.y_m[k]), BALL.radius_m, BALL_COLORS[k],
                      f"{MAGNUS_NAMES[k]}: {float(s.x_m[k]):.1f} m")
               for k in range(3)]  # fmt: skip
    return Frame(circles, [Segment(0.0, 0.0, 0.0, p.launch_height_m, (120, 120, 120), 2)],
                 [f"thrown level at {p.speed_mps:g} m/s, spin {p.spin_radps:g} rad/s"])  # fmt: skip


MAGNUS = Scene(
    name="magnus",
    section="§8",
    title="The Magnus effect: spin bends the flight",
    claim="thrown level at the same speed, backspin holds a beach ball up and carries it "
    "farther, topspin brings it down sooner, the ball without spin lands between",
    params=MagnusParams,
    initial=magnus_initial,
    step=magnus_step,
    measures=magnus_measures,
    frame=magnus_frame,
    view_box_m=lambda p: (
        -1.0,
        2.0 * p.speed_mps * math.sqrt(2.0 * p.launch_height_m / 9.81) + 2.0,
        -0.5,
        3.0 * p.launch_height_m + 1.0,
    ),  # fmt: skip
    # twice a drop's time from the launch height, and a half second: every ball lands
    duration_s=lambda p: 2.0 * math.sqrt(2.0 * p.launch_height_m / GRAVITY_MPS2) + 0.5,
    bodies=MAGNUS_NAMES,
    test="test_magnus_backspin_carries_farther_topspin_lands_sooner",
)

SCENES = (BOWLING_BALLS, MAGNUS)
