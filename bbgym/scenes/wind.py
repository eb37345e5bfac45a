"""Wind effects (§8): dropping large things ("bowling balls": the elephant and the mouse),
the Magnus effect of a spinning beach ball, laminar and turbulent flow (the drag crisis at
the critical Reynolds number, and turbulence as random gusts), and the falling wall.

The balls fly by the envs' own step in the air,
:func:`bbgym.physics.ball.substep`: gravity, the drag ``1/2 rho C_d A v^2`` and the Magnus
force (both taken implicitly, so any step is stable), the spin decaying. The side view's
x is the ball laws' x, its y their z (up). The falling wall is the Topple envs' wall
(:mod:`bbgym.physics.wall`), stepped by its own RK4 step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from bbgym.physics.ball import BallParams, BallState, ball_at, ball_released_at, substep
from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2
from bbgym.physics.namespace import Array, replaced
from bbgym.physics.validation import CheckedFields, check_at_least, check_fields, interval, param
from bbgym.physics.wall import (
    LOOSE,
    WallParams,
    WallState,
    face_frame,
    wall_at,
    wall_rk4_step,
    wall_torques,
)
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector
from bbgym.scenes.projectiles import BALL_COLORS, column
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment, state_fields

# -- bowling balls: the elephant falls faster -------------------------------------------------


@dataclass(frozen=True)
class FallParams(CheckedFields):
    """Four balls dropped together: a small and a large solid ball (the text's mouse and
    elephant: light, so the drag shows within the drop), a small and a large beach ball."""

    small_radius_m: float = param(0.05, interval(0.02, 2.0))
    large_radius_m: float = param(0.5, interval(0.02, 2.0))
    solid_density_kgm3: float = param(20.0, interval(10.0, 20000.0))
    """Expanded polystyrene: light enough that drag matters over the drop."""
    drop_height_m: float = param(30.0, interval(1.0, 1000.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

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
    return stopped_on_ground(column(tuple(b.radius_m for b in balls), xp), s, moved, xp)


def stopped_on_ground(radius: Array, s: BallState, moved: BallState, xp: Any) -> BallState:
    """``moved`` (the step from ``s``), except that a ball that reaches the ground (its
    centre ``radius`` up) stops there, where it was along the ground."""
    down = moved.z <= radius
    flying = [xp.where(down, 0.0, v) for v in (moved.vx, moved.vy, moved.vz)]
    still = [xp.where(down, old, new) for old, new in ((s.x, moved.x), (s.y, moved.y))]
    return BallState(still[0], still[1], xp.where(down, radius, moved.z), *flying, *moved[6:])


def fall_initial(p: FallParams, xp: Any) -> BallState:
    heights = tuple(p.drop_height_m + b.radius_m for b in p.balls())
    return ball_released_at(column((-15.0, -5.0, 5.0, 15.0), xp), 0.0, column(heights, xp), xp)


def fall_step(p: FallParams, s: BallState, xp: Any) -> BallState:
    return in_the_air(p.balls(), s, p.dt_s, xp)


def fall_measures(p: FallParams, s: BallState, xp: Any) -> dict[str, Array]:
    radius = column(tuple(b.radius_m for b in p.balls()), xp)
    return {"speed_mps": 0.0 - s.vz, "height_m": s.z - radius}


def fall_frame(p: FallParams, s: BallState) -> Frame:
    balls = p.balls()
    circles = [
        Circle(
            float(s.x[k]),
            float(s.z[k]),
            b.radius_m,
            BALL_COLORS[k % 3],
            f"{FALL_NAMES[k]}: {-float(s.vz[k]):.1f} m/s",
        )
        for k, b in enumerate(balls)
    ]
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
    functions=SceneFunctions(fall_initial, fall_step, fall_measures, fall_frame),
    view_box_m=lambda p: (-20.0, 20.0, -1.0, p.drop_height_m + 2.0 * p.large_radius_m + 1.0),
    duration_s=lambda p: 8.0,
    bodies=FALL_NAMES,
    test="test_bowling_balls_the_elephant_falls_faster_beach_balls_alike",
)


# -- Magnus: spin bends a beach ball's flight ---------------------------------------------------


@dataclass(frozen=True)
class MagnusParams(CheckedFields):
    """Three beach balls thrown level at one speed: with backspin, without spin, with
    topspin (the envs' 40 cm, 250 g ball)."""

    speed_mps: float = param(8.0, interval(0.1, 50.0))
    spin_radps: float = param(20.0, interval(0.0, 200.0))
    launch_height_m: float = param(1.5, interval(0.0, 100.0))
    dt_s: float = param(1.0 / 120.0, interval(1e-4, 0.05))


MAGNUS_NAMES = ("backspin", "no spin", "topspin")
BALL = BallParams()


def magnus_initial(p: MagnusParams, xp: Any) -> BallState:
    """Thrown along x; backspin (the ball's top turning back toward the thrower) spins
    about -y, the thrower's right, topspin about +y."""
    spin = column((-p.spin_radps, 0.0, p.spin_radps), xp)
    return ball_at(
        column((0.0,) * 3, xp), 0.0, p.launch_height_m, p.speed_mps, 0.0, 0.0, 0.0, spin, 0.0, xp=xp
    )


def magnus_step(p: MagnusParams, s: BallState, xp: Any) -> BallState:
    return in_the_air((BALL,) * 3, s, p.dt_s, xp)


def magnus_measures(p: MagnusParams, s: BallState, xp: Any) -> dict[str, Array]:
    return {"distance_m": s.x, "height_m": s.z - BALL.radius_m}


def magnus_frame(p: MagnusParams, s: BallState) -> Frame:
    circles = [
        Circle(
            float(s.x[k]),
            float(s.z[k]),
            BALL.radius_m,
            BALL_COLORS[k],
            f"{MAGNUS_NAMES[k]}: {float(s.x[k]):.1f} m",
        )
        for k in range(3)
    ]
    return Frame(
        circles,
        [Segment(0.0, 0.0, 0.0, p.launch_height_m, (120, 120, 120), 2)],
        [f"thrown level at {p.speed_mps:g} m/s, spin {p.spin_radps:g} rad/s"],
    )


MAGNUS = Scene(
    name="magnus",
    section="§8",
    title="The Magnus effect: spin bends the flight",
    claim="thrown level at the same speed, backspin holds a beach ball up and carries it "
    "farther, topspin brings it down sooner, the ball without spin lands between",
    params=MagnusParams,
    functions=SceneFunctions(magnus_initial, magnus_step, magnus_measures, magnus_frame),
    # the flights fill the frame: a third past a drop's reach, and room above for the labels
    view_box_m=lambda p: (
        -1.0,
        1.2 * p.speed_mps * math.sqrt(2.0 * p.launch_height_m / GRAVITY_MPS2) + 0.8,
        -0.3,
        1.3 * p.launch_height_m + 1.0,
    ),
    # one and a half drop times from the launch height, and 0.3 s: the backspin ball lands
    # (at 0.75 s of the defaults' 1.13 s) and the clip ends soon after
    duration_s=lambda p: 1.5 * math.sqrt(2.0 * p.launch_height_m / GRAVITY_MPS2) + 0.3,
    bodies=MAGNUS_NAMES,
    test="test_magnus_backspin_carries_farther_topspin_lands_sooner",
)


# -- turbulence: the drag crisis and random gusts -----------------------------------------------

AIR_VISCOSITY_PAS = 1.81e-5
"""Dynamic viscosity of air at 20 C (Pa s)."""
MINSTD_MODULUS = 2147483647.0
"""``2^31 - 1``, the modulus of the Lehmer ("minimal standard") generator."""
MINSTD_MULTIPLIER = 16807.0
"""Its multiplier: ``16807 x < 2^53``, so every product and remainder is exact in float64,
on every backend alike."""


def reynolds_number(speed_mps: Array, diameter_m: Array) -> Array:
    """``Re = rho |u| d / mu`` of a sphere of diameter ``d`` moving at ``|u|`` through air:
    how far inertia outweighs viscosity, which decides whether its boundary layer is laminar
    or turbulent."""
    return AIR_DENSITY_KGM3 * speed_mps * diameter_m / AIR_VISCOSITY_PAS


def sphere_drag_coefficient(
    reynolds: Array, laminar: float, turbulent: float, critical: float, xp: Any
) -> Array:
    """The drag crisis of a sphere (§8's table, after Palmer: laminar ``C_d`` 0.4-0.47,
    turbulent 0.2): below the critical Reynolds number (about 3e5 for a smooth sphere) the
    laminar coefficient, at and above it the turbulent one."""
    return xp.where(reynolds >= critical, turbulent, laminar)


def next_uniform(x: Array, xp: Any) -> tuple[Array, Array]:
    """One draw of the Lehmer generator ``x' = 16807 x mod (2^31 - 1)`` on integer-valued
    float64 arrays (exact on NumPy, torch and array_api_strict alike): ``(x', u)`` with
    ``u = x' / (2^31 - 1)`` uniform in (0, 1)."""
    y = MINSTD_MULTIPLIER * x
    y = y - MINSTD_MODULUS * xp.floor(y / MINSTD_MODULUS)
    return y, y / MINSTD_MODULUS


def normal_pair(x: Array, xp: Any) -> tuple[Array, Array, Array]:
    """Two independent standard normal draws per row from two uniforms (Box-Muller), and the
    generator's next state."""
    x, u1 = next_uniform(x, xp)
    x, u2 = next_uniform(x, xp)
    radius = xp.sqrt(-2.0 * xp.log(u1))
    return radius * xp.cos(2.0 * math.pi * u2), radius * xp.sin(2.0 * math.pi * u2), x


@dataclass(frozen=True)
class TurbulenceParams(CheckedFields):
    """Five balls dropped together in a light wind: a large beach ball with the laminar
    drag coefficient, the same with the turbulent one, the same with its coefficient chosen
    by its Reynolds number (the drag crisis), a small beach ball so chosen, and the laminar
    large ball in a gusty wind (the gust process of the sailing envs)."""

    large_radius_m: float = param(0.5, interval(0.02, 2.0))
    """1 m across: at 4.5 m/s its Reynolds number passes 3e5."""
    small_radius_m: float = param(0.2, interval(0.02, 2.0))
    """The envs' 40 cm ball: its terminal speed (8.3 m/s) stays under the crisis (Re 2.2e5)."""
    laminar_drag_coefficient: float = param(0.47, interval(0.0, 2.0))
    turbulent_drag_coefficient: float = param(0.2, interval(0.0, 2.0))
    critical_reynolds: float = param(3e5, interval(1e3, 1e7))
    """Where a smooth sphere's boundary layer turns turbulent (2e5 to 3e5 measured)."""
    wind_mps: float = param(2.0, interval(0.0, 30.0))
    """The mean wind, along +x."""
    gust_speed_std: float = param(0.3, interval(0.0, 1.0))
    """The gusts' standard deviation, a fraction of the mean wind (``GustParams``)."""
    gust_shift_std_rad: float = param(0.3, interval(0.0, 0.5 * math.pi))
    gust_time_constant_s: float = param(0.25, interval(0.01, 1000.0))
    """Short-lived eddies rather than weather: the gusts' correlation time."""
    gust_smoothing_s: float = param(0.1, interval(0.01, 1000.0))
    drop_height_m: float = param(100.0, interval(1.0, 1000.0))
    seed: int = param(0, interval(0, 2**31 - 1), integer=True)
    """Seeds the gusty ball's random stream (the same seed, the same gusts)."""
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def ball_pairs(self) -> tuple[tuple[BallParams, BallParams], ...]:
        """Each row's ``(laminar, turbulent)`` ball (the envs' ball): one coefficient twice
        for a row that keeps it, both for a row that the Reynolds number decides."""
        large, small = self.large_radius_m, self.small_radius_m
        lam = BallParams(radius_m=large, drag_coefficient=self.laminar_drag_coefficient)
        turb = BallParams(radius_m=large, drag_coefficient=self.turbulent_drag_coefficient)
        small_lam = BallParams(radius_m=small, drag_coefficient=self.laminar_drag_coefficient)
        small_turb = BallParams(radius_m=small, drag_coefficient=self.turbulent_drag_coefficient)
        return (lam, lam), (turb, turb), (lam, turb), (small_lam, small_turb), (lam, lam)

    def gusts(self) -> GustParams:
        return GustParams(
            self.gust_speed_std,
            self.gust_shift_std_rad,
            self.gust_time_constant_s,
            self.gust_smoothing_s,
        )


TURBULENCE_NAMES = ("laminar", "turbulent", "by Reynolds", "small, by Reynolds", "gusty")
GUSTY = 4
WIND_FROM_WEST = math.pi
"""Where the mean wind blows from (sailing usage, :func:`bbgym.physics.wind.wind_vector`):
the air moves along +x."""


class Turbulence(state_fields(BallState, GustState, "random")):
    """The balls (:class:`BallState`'s fields), the gust process per row
    (:class:`~bbgym.physics.wind.GustState`'s fields: zero but in the gusty row) and each
    row's random generator state, ``random`` (an integer in float64)."""

    __slots__ = ()


def gusty_rows(xp: Any) -> Array:
    return column(tuple(float(k == GUSTY) for k in range(len(TURBULENCE_NAMES))), xp) > 0.5


def turbulence_initial(p: TurbulenceParams, xp: Any) -> Turbulence:
    """At rest at the drop height; the random numbers are drawn here, in NumPy, from the
    seed: each row's generator state and the gusts' start in their stationary spread."""
    rng = np.random.default_rng(p.seed)
    rows = len(TURBULENCE_NAMES)
    random = rng.integers(1, int(MINSTD_MODULUS), size=rows).astype(np.float64)
    noise = rng.standard_normal((2, rows))
    gust = gust_init(
        p.gusts(), (xp.asarray(noise[0, :]), xp.asarray(noise[1, :])), gusty_rows(xp), xp
    )
    heights = tuple(p.drop_height_m + pair[0].radius_m for pair in p.ball_pairs())
    ball = ball_released_at(
        column((-20.0, -10.0, 0.0, 10.0, 20.0), xp), 0.0, column(heights, xp), xp
    )
    return Turbulence(*ball, *gust, xp.asarray(random))


def turbulence_wind(p: TurbulenceParams, s: Turbulence, xp: Any) -> tuple[Array, Array]:
    """The wind at each ball now: the mean wind, and the gusts where there are any."""
    gust = GustState(s.speed_raw, s.speed, s.shift_raw, s.shift)
    wind_x, wind_y, _, _ = wind_vector(p.wind_mps, WIND_FROM_WEST, gust, xp)
    return wind_x, wind_y


def turbulence_reynolds(p: TurbulenceParams, s: Turbulence, xp: Any) -> Array:
    wind_x, wind_y = turbulence_wind(p, s, xp)
    rel_x, rel_y = s.vx - wind_x, s.vy - wind_y
    speed = xp.sqrt(rel_x * rel_x + rel_y * rel_y + s.vz * s.vz)
    return reynolds_number(speed, column(tuple(2.0 * a.radius_m for a, _ in p.ball_pairs()), xp))


def turbulence_step(p: TurbulenceParams, s: Turbulence, xp: Any) -> Turbulence:
    """The envs' step in the air (:func:`~bbgym.physics.ball.substep`) for each row with the
    drag coefficient its Reynolds number gives at the step's start (the step freezes its
    coefficients there anyway), in the wind of the step's start; then the gusts move on
    (:func:`~bbgym.physics.wind.gust_step`, fed by the row's generator)."""
    wind_x, wind_y = turbulence_wind(p, s, xp)
    reynolds = turbulence_reynolds(p, s, xp)
    ball = BallState(*s[:13])
    rows = []
    for k, (lam, turb) in enumerate(p.ball_pairs()):
        row = BallState(*(f[k : k + 1] for f in ball))
        wx, wy = wind_x[k : k + 1], wind_y[k : k + 1]
        laminar = substep(lam, row, wx, wy, p.dt_s, xp)
        if turb is not lam:  # a row the Reynolds number decides
            turbulent = substep(turb, row, wx, wy, p.dt_s, xp)
            crisis = reynolds[k : k + 1] >= p.critical_reynolds
            laminar = BallState(
                *(xp.where(crisis, t, la) for t, la in zip(turbulent, laminar, strict=True))
            )
        rows.append(laminar)
    moved = BallState(*(xp.concat(fields) for fields in zip(*rows, strict=True)))
    radius = column(tuple(a.radius_m for a, _ in p.ball_pairs()), xp)
    ball = stopped_on_ground(radius, ball, moved, xp)
    speed_noise, shift_noise, random = normal_pair(s.random, xp)
    gust = gust_step(
        GustState(*s[13:17]), p.gusts(), p.dt_s, (speed_noise, shift_noise), gusty_rows(xp), xp
    )
    return Turbulence(*ball, *gust, random)


def turbulence_measures(p: TurbulenceParams, s: Turbulence, xp: Any) -> dict[str, Array]:
    pairs = p.ball_pairs()
    reynolds = turbulence_reynolds(p, s, xp)
    drag = sphere_drag_coefficient(
        reynolds,
        column(tuple(a.drag_coefficient for a, _ in pairs), xp),
        column(tuple(b.drag_coefficient for _, b in pairs), xp),
        p.critical_reynolds,
        xp,
    )
    radius = column(tuple(a.radius_m for a, _ in pairs), xp)
    return {
        "fall_speed_mps": 0.0 - s.vz,
        "drift_speed_mps": s.vx,
        "height_m": s.z - radius,
        "reynolds": reynolds,
        "drag_coefficient": drag,
    }


def turbulence_frame(p: TurbulenceParams, s: Turbulence) -> Frame:
    circles, segments = [], []
    for k, (lam, _) in enumerate(p.ball_pairs()):
        x, z = float(s.x[k]), float(s.z[k])
        circles.append(
            Circle(
                x,
                z,
                lam.radius_m,
                BALL_COLORS[k % 3],
                f"{TURBULENCE_NAMES[k]}: {-float(s.vz[k]):.1f} m/s",
            )
        )
        # the velocity, a second's worth: the balls are small in a 100 m drop
        segments.append(Segment(x, z, x + float(s.vx[k]), z + float(s.vz[k]), (90, 90, 90), 2))
    return Frame(
        circles,
        segments,
        [
            f"C_d {p.laminar_drag_coefficient:g} below Re {p.critical_reynolds:.3g}, "
            f"{p.turbulent_drag_coefficient:g} above; wind {p.wind_mps:g} m/s, "
            f"gusts {p.gust_speed_std:g} of it"
        ],
    )


TURBULENCE = Scene(
    name="turbulence",
    section="§8",
    title="Laminar and turbulent flow: the drag crisis and random gusts",
    claim="a sphere's drag coefficient falls from the laminar 0.47 to the turbulent 0.2 "
    "once its Reynolds number passes the critical ~3e5, so a large beach ball that passes it "
    "falls on to the faster terminal speed sqrt(2 m g / (rho C_d A)) of C_d = 0.2 while a "
    "small one stays laminar; turbulence as random gusts makes a ball wobble about the "
    "steady wind's drift (the same mean, a nonzero spread), the same seed the same run",
    params=TurbulenceParams,
    functions=SceneFunctions(
        turbulence_initial, turbulence_step, turbulence_measures, turbulence_frame
    ),
    view_box_m=lambda p: (-25.0, 25.0 + 8.0 * p.wind_mps, -2.0, p.drop_height_m + 5.0),
    duration_s=lambda p: 8.0,
    bodies=TURBULENCE_NAMES,
    test="test_turbulence_drag_crisis_switches_at_the_critical_reynolds_number",
)


# -- the falling wall: Buster Keaton's house front ----------------------------------------------


@dataclass(frozen=True)
class FallingWallParams:
    """Four walls of Topple's kind (:class:`~bbgym.physics.wall.WallParams`: a panel
    standing in the middle of a foot, turning about the foot's edges), side by side: one
    in calm air nudged just past its balance, and three upright ones in a breeze under the
    wind speed that tips them, a gale over it, and a storm past the one that tears the foot
    loose."""

    height_m: float = param(2.4, interval(0.2, 20.0))
    mass_kg: float = param(8.0, interval(0.1, 1000.0))
    thickness_m: float = param(0.03, interval(1e-3, 0.5))
    base_depth_m: float = param(0.4, interval(1e-3, 5.0))
    """The foot, along x: at least the panel's thickness."""
    nudge_deg: float = param(2.0, interval(0.01, 45.0))
    """How far past its balance angle (its centre of mass over the foot's edge) the calm
    wall starts, at rest."""
    breeze_mps: float = param(2.5, interval(0.0, 50.0))
    gale_mps: float = param(5.0, interval(0.0, 50.0))
    storm_mps: float = param(14.0, interval(0.0, 50.0))
    dt_s: float = param(0.01, interval(1e-4, 0.05))

    def __post_init__(self) -> None:
        check_fields(self)
        check_at_least(self, "base_depth_m", "thickness_m")

    def wall(self) -> WallParams:
        """The env's wall with these dimensions (its face's drag, friction and pegs as the
        Topple envs have them)."""
        return WallParams(
            height_m=self.height_m,
            thickness_m=self.thickness_m,
            base_depth_m=self.base_depth_m,
            mass_kg=self.mass_kg,
        )

    def balance_rad(self) -> float:
        """The lean that puts the centre of mass over the foot's edge: ``tan = b / (h/2)``."""
        return math.atan2(0.5 * self.base_depth_m, 0.5 * self.height_m)

    def winds(self) -> tuple[float, ...]:
        return (0.0, self.breeze_mps, self.gale_mps, self.storm_mps)


WALL_NAMES = ("calm, nudged", "breeze", "gale", "storm")
WALL_SPACING_M = 5.0
WALL_COLORS = ((120, 80, 50), (60, 120, 220), (230, 70, 60), (130, 60, 160))


def falling_wall_initial(p: FallingWallParams, xp: Any) -> WallState:
    """Upright on their feet, but the calm wall: on its far edge, leaning ``nudge_deg``
    past its balance, at rest."""
    base_x = column(tuple(WALL_SPACING_M * k for k in range(len(WALL_NAMES))), xp)
    upright = wall_at(base_x, xp)
    nudged = column((1.0, 0.0, 0.0, 0.0), xp)
    lean = p.balance_rad() + math.radians(p.nudge_deg)
    return replaced(upright, angle=nudged * lean, pivot=nudged)


def falling_wall_step(p: FallingWallParams, s: WallState, xp: Any) -> WallState:
    """The Topple-v2 wall's step (:func:`~bbgym.physics.wall.wall_rk4_step`: RK4 about the
    edge, then landing, breaking loose, the loose panel's flight), each wall in its wind."""
    return wall_rk4_step(p.wall(), s, column(p.winds(), xp), p.dt_s, xp)


def falling_wall_measures(p: FallingWallParams, s: WallState, xp: Any) -> dict[str, Array]:
    """The lean, the wall's mechanical energy less the work its wind has done (the wind's
    torque ``h/2 F_w cos(phi)`` has the potential ``-h/2 F_w sin(phi)``: the sum stays put
    while a wall turns on its edge) and the status code (0 standing, 1 fallen away, 3
    loose). A loose panel's energy is its kinetic and potential energy alone."""
    w = p.wall()
    wind = column(p.winds(), xp)
    side, c, sn, _, foot_x, foot_z = face_frame(w, s, xp)
    z_cm = foot_z + 0.5 * w.height_m * c
    upright_torque, _, _ = wall_torques(w, 0.0 * wind, side, wind, xp)  # h/2 F_w
    turning = 0.5 * w.inertia_kgm2 * s.rate * s.rate + w.mass_kg * GRAVITY_MPS2 * z_cm
    turning = turning - upright_torque * sn
    inertia_cm = w.mass_kg * (w.height_m**2 + w.thickness_m**2) / 12.0
    speed_sq = s.loose_vx * s.loose_vx + s.loose_vz * s.loose_vz
    flying = (
        0.5 * w.mass_kg * speed_sq
        + 0.5 * inertia_cm * s.loose_rate * s.loose_rate
        + w.mass_kg * GRAVITY_MPS2 * s.loose_z
    )
    loose = s.status == LOOSE
    return {
        "lean_deg": xp.where(loose, s.loose_angle, s.angle) * (180.0 / math.pi),
        "energy_j": xp.where(loose, flying, turning),
        "status": s.status,
    }


def falling_wall_frame(p: FallingWallParams, s: WallState) -> Frame:
    w = p.wall()
    side, c, sn, pivot_x, foot_x, foot_z = face_frame(w, s, np)
    circles, segments = [], []
    for k, name in enumerate(WALL_NAMES):
        color = WALL_COLORS[k]
        base = float(s.base_x[k])
        segments.append(
            Segment(base - w.half_base_m, 0.0, base + w.half_base_m, 0.0, (60, 60, 60), 5)
        )
        if s.status[k] == LOOSE:  # the panel, centred where it flies, along its angle
            x, z, a = float(s.loose_x[k]), float(s.loose_z[k]), float(s.loose_angle[k])
            dx, dz = 0.5 * w.height_m * math.sin(a), 0.5 * w.height_m * math.cos(a)
            segments.append(Segment(x - dx, z - dz, x + dx, z + dz, color, 6))
        else:
            x0, z0 = float(foot_x[k]), float(foot_z[k])
            segments.append(
                Segment(
                    x0, z0, x0 + w.height_m * float(sn[k]), z0 + w.height_m * float(c[k]), color, 6
                )
            )
        lean = math.degrees(float(s.loose_angle[k] if s.status[k] == LOOSE else s.angle[k]))
        label = f"{name}: {lean:.0f} deg" + (", torn loose" if s.status[k] == LOOSE else "")
        circles.append(Circle(float(pivot_x[k]), 0.0, 0.06, color, label))
    winds = ", ".join(f"{v:g}" for v in p.winds()[1:])
    return Frame(
        circles,
        segments,
        [
            f"winds {winds} m/s; tips at {w.tipping_wind_speed_mps():.1f}, "
            f"tears loose at {w.breakaway_wind_speed_mps():.1f} m/s"
        ],
    )


FALLING_WALL = Scene(
    name="falling-wall",
    section="§8",
    title="The falling wall (Buster Keaton)",
    claim="a wall turns about its edge under gravity and the wind's torque h/2 F_w cos(phi): "
    "nudged past its balance it falls with I phi'' = m g r sin(phi - phi_b) "
    "(phi'' = 3 g / 2 h sin(phi) for a thin slab), its energy kept until it lands; a breeze "
    "under the tipping speed leaves it standing, a gale over it tips it and it falls sooner, "
    "and a storm whose force passes what the foot holds tears it loose",
    params=FallingWallParams,
    functions=SceneFunctions(
        falling_wall_initial, falling_wall_step, falling_wall_measures, falling_wall_frame
    ),
    view_box_m=lambda p: (
        -1.5,
        WALL_SPACING_M * 3.0 + p.height_m + 1.5,
        -0.3,
        1.5 * p.height_m,
    ),
    duration_s=lambda p: 3.0,
    bodies=WALL_NAMES,
    floor=True,
    test="test_falling_wall_falls_by_the_pendulum_law_and_the_wind_tips_or_tears_it",
)

SCENES = (BOWLING_BALLS, MAGNUS, TURBULENCE, FALLING_WALL)
