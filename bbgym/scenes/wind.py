"""Wind effects (§8): dropping large things ("bowling balls": the elephant and the mouse),
and the Magnus effect of a spinning beach ball.

Both fly the envs' own balls by the envs' own step in the air,
:func:`bbgym.physics.ball.substep`: gravity, the drag ``1/2 rho C_d A v^2`` and the Magnus
force (both taken implicitly, so any step is stable), the spin decaying. The side view's
x is the ball laws' x, its y their z (up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from bbgym.physics.ball import BallParams, BallState, ball_at, substep
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_fields, interval, param
from bbgym.scenes.projectiles import BALL_COLORS, column
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


def in_the_air(balls: tuple[BallParams, ...], s: BallState, dt_s: float, xp: Any) -> BallState:
    """One step of the envs' ball physics (:func:`~bbgym.physics.ball.substep`, no wind)
    for each row with its own ball, and a ball that reaches the ground stops there."""
    rows = []
    for k, ball in enumerate(balls):
        row = BallState(*(field[k : k + 1] for field in s))
        calm = 0.0 * row.x
        rows.append(substep(ball, row, calm, calm, dt_s, xp))
    moved = BallState(*(xp.concat(fields) for fields in zip(*rows, strict=True)))
    radius = column(tuple(b.radius_m for b in balls), xp)
    down = moved.z <= radius
    flying = [xp.where(down, 0.0, v) for v in (moved.vx, moved.vy, moved.vz)]
    still = [xp.where(down, old, new) for old, new in ((s.x, moved.x), (s.y, moved.y))]
    return BallState(still[0], still[1], xp.where(down, radius, moved.z), *flying,
                     *moved[6:])  # fmt: skip


def fall_initial(p: FallParams, xp: Any) -> BallState:
    heights = tuple(p.drop_height_m + b.radius_m for b in p.balls())
    return ball_at(column((-15.0, -5.0, 5.0, 15.0), xp), 0.0, column(heights, xp), 0.0, 0.0,
                   0.0, 0.0, 0.0, 0.0, xp=xp)  # fmt: skip


def fall_step(p: FallParams, s: BallState, xp: Any) -> BallState:
    return in_the_air(p.balls(), s, p.dt_s, xp)


def fall_measures(p: FallParams, s: BallState, xp: Any) -> dict[str, Array]:
    radius = column(tuple(b.radius_m for b in p.balls()), xp)
    return {"speed_mps": 0.0 - s.vz, "height_m": s.z - radius}


def fall_frame(p: FallParams, s: BallState) -> Frame:
    balls = p.balls()
    circles = [Circle(float(s.x[k]), float(s.z[k]), b.radius_m, BALL_COLORS[k % 3],
                      f"{FALL_NAMES[k]}: {-float(s.vz[k]):.1f} m/s")
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


def magnus_initial(p: MagnusParams, xp: Any) -> BallState:
    """Thrown along x; backspin (the ball's top turning back toward the thrower) spins
    about -y, the thrower's right, topspin about +y."""
    spin = column((-p.spin_radps, 0.0, p.spin_radps), xp)
    return ball_at(column((0.0,) * 3, xp), 0.0, p.launch_height_m, p.speed_mps, 0.0, 0.0, 0.0,
                   spin, 0.0, xp=xp)  # fmt: skip


def magnus_step(p: MagnusParams, s: BallState, xp: Any) -> BallState:
    return in_the_air((BALL,) * 3, s, p.dt_s, xp)


def magnus_measures(p: MagnusParams, s: BallState, xp: Any) -> dict[str, Array]:
    return {"distance_m": s.x, "height_m": s.z - BALL.radius_m}


def magnus_frame(p: MagnusParams, s: BallState) -> Frame:
    circles = [Circle(float(s.x[k]), float(s.z[k]), BALL.radius_m, BALL_COLORS[k],
                      f"{MAGNUS_NAMES[k]}: {float(s.x[k]):.1f} m")
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
        2.0 * p.speed_mps * math.sqrt(2.0 * p.launch_height_m / GRAVITY_MPS2) + 2.0,
        -0.5,
        3.0 * p.launch_height_m + 1.0,
    ),  # fmt: skip
    # twice a drop's time from the launch height, and a half second: every ball lands
    duration_s=lambda p: 2.0 * math.sqrt(2.0 * p.launch_height_m / GRAVITY_MPS2) + 0.5,
    bodies=MAGNUS_NAMES,
    test="test_magnus_backspin_carries_farther_topspin_lands_sooner",
)

SCENES = (BOWLING_BALLS, MAGNUS)
