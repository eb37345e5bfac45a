"""Beach balls: gravity, drag, Magnus force, spin, bounces and collisions (seed §3-§6, §8).

3D, world frame x east, y north, z up, SI units. Like the sailing physics every function is
pure and written against an array namespace ``xp`` (:mod:`bbgym.physics.backend`): NumPy
arrays for a batch, Python floats for one ball. Vectors are passed as separate components.

==========================  ============================================================
law                         function
==========================  ============================================================
mass of a shell or a solid  :class:`BallParams` (``mass_kg``, ``inertia_kgm2``)
gravity and drag            :func:`air_force` (drag ``-1/2 C_d A rho |v-w| (v-w)``, §8)
Magnus force                :func:`magnus_force` (``1/2 rho A C_L |v|^2``, §8)
spin decay                  :func:`substep` (exponential, time constant ``spin_decay_s``)
bounce, friction, rolling   :func:`ground_contact` (restitution §3, friction §6, §5)
panel (screen, wall) hits   :func:`panel_contact`
ball-ball collision         :func:`collide_balls` (restitution formula of §4)
flight to rest              :func:`simulate_throw`
==========================  ============================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from bbgym.physics.backend import Array
from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2, quadratic_drag


@dataclass(frozen=True)
class BallParams:
    """A beach ball (a thin PVC shell) or, with ``solid=True``, a solid ball.

    A shell's mass grows with its area, ``4 pi r^2 * shell_areal_density`` (seed §4: "the
    mass is the square of the radius, which is correct for a beach ball"); a solid ball's
    with its volume. Defaults: a sturdy 40 cm vinyl beach ball of 250 g (terminal speed
    8.3 m/s; a light 100 g one falls at 5.3 m/s and cannot be thrown much past 5 m).
    """

    radius_m: float = 0.2
    shell_areal_density_kgm2: float = 0.5
    """Thick vinyl (about 0.35 mm at 1.4 g/cm^3) plus seams and valve."""
    solid: bool = False
    density_kgm3: float = 1500.0
    """Density of a solid ball (a bowling ball: about 1300-1600 kg/m^3); used if ``solid``."""
    drag_coefficient: float = 0.47
    """Sphere in laminar flow (seed §8 table: 0.4-0.47)."""
    lift_coefficient_max: float = 0.35
    """Saturation of the Magnus lift coefficient: ``C_L = C_max tanh(S / C_max)``, so
    ``C_L ~ S = r omega / v`` for slow spin (seed §8) and levels off near 0.3-0.4 for
    ``S >~ 0.5``, as measured for spinning smooth spheres and sports balls (Nathan 2008,
    Am. J. Phys. 76:119; Sawicki, Hubbard & Stronge 2003, Am. J. Phys. 71:1152)."""
    spin_decay_s: float = 2.5
    """Time constant of the spin's exponential decay by air friction. A light ball with a
    large surface loses its spin in seconds (a golf ball keeps it for ~20 s)."""
    restitution: float = 0.75
    """Ground bounce: rebound speed / impact speed; the rebound height ratio is its square."""
    friction: float = 0.6
    """Coulomb friction coefficient between ball and ground (seed §6)."""
    rolling_resistance: float = 0.1
    """Rolling resistance coefficient on grass: deceleration ``c g`` while rolling."""
    rest_speed_mps: float = 0.3
    """Impacts slower than this do not bounce: the ball stays on the ground and rolls."""

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "solid":
                if not isinstance(value, (bool, np.bool_)):
                    raise ValueError(f"solid must be a bool, got {value!r}")
                continue
            if not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0:
                raise ValueError(f"{f.name} must be a finite number >= 0, got {value!r}")
        for name in ("radius_m", "shell_areal_density_kgm2", "density_kgm3", "spin_decay_s"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")
        if self.restitution > 1.0:
            raise ValueError(f"restitution must be in [0, 1], got {self.restitution!r}")

    @property
    def mass_kg(self) -> float:
        r = self.radius_m
        if self.solid:
            return self.density_kgm3 * 4.0 / 3.0 * math.pi * r**3
        return self.shell_areal_density_kgm2 * 4.0 * math.pi * r**2

    @property
    def inertia_kgm2(self) -> float:
        """Moment of inertia about a diameter: thin shell 2/3 m r^2, solid 2/5 m r^2 (§5)."""
        return (0.4 if self.solid else 2.0 / 3.0) * self.mass_kg * self.radius_m**2

    @property
    def area_m2(self) -> float:
        return math.pi * self.radius_m**2

    def terminal_speed_mps(self) -> float:
        """``sqrt(2 m g / (rho C_d A))``: where drag balances gravity (§8)."""
        return math.sqrt(
            2
            * self.mass_kg
            * GRAVITY_MPS2
            / (AIR_DENSITY_KGM3 * self.drag_coefficient * self.area_m2)
        )


@dataclass
class BallState:
    """Position, velocity, spin (rad/s, world frame) and orientation (unit quaternion
    ``(qw, qx, qy, qz)``, body to world: it only serves to draw the stripes)."""

    x: Array
    y: Array
    z: Array
    vx: Array
    vy: Array
    vz: Array
    wx: Array
    wy: Array
    wz: Array
    qw: Array
    qx: Array
    qy: Array
    qz: Array


def ball_at(
    x: Array, y: Array, z: Array, vx: Array, vy: Array, vz: Array, wx: Array, wy: Array, wz: Array
) -> BallState:
    """A ball at a position with a velocity and spin, in its reference orientation."""
    one = 1.0 + 0.0 * x
    zero = 0.0 * x
    return BallState(x, y, z, vx, vy, vz, wx, wy, wz, one, zero, zero, zero)


def magnus_force(
    p: BallParams, rel_x: Array, rel_y: Array, rel_z: Array, wx: Array, wy: Array, wz: Array,
    xp: Any = np,
) -> tuple[Array, Array, Array, Array]:  # fmt: skip
    """Magnus force ``1/2 rho A C_L |v|^2`` along ``omega x v`` (seed §8).

    ``rel`` is the ball's velocity relative to the air. ``C_L`` grows like the spin
    parameter ``S = r |omega| / |v|`` and saturates at ``lift_coefficient_max``; for slow
    spin the force is the seed's ``k (omega x v)`` with ``k = 1/2 rho A r``. Only the spin
    component perpendicular to the flight acts (``|omega x v| = |omega| |v| sin``).
    Returns ``(Fx, Fy, Fz, S)``.
    """
    speed = xp.sqrt(rel_x * rel_x + rel_y * rel_y + rel_z * rel_z)
    spin = xp.sqrt(wx * wx + wy * wy + wz * wz)
    spin_parameter = p.radius_m * spin / xp.maximum(speed, 1e-9)
    lift = p.lift_coefficient_max * xp.tanh(spin_parameter / p.lift_coefficient_max)
    # 1/2 rho A C_L |v|^2 times the unit-free (omega x v) / (|omega| |v|).
    k = 0.5 * AIR_DENSITY_KGM3 * p.area_m2 * lift * speed / xp.maximum(spin, 1e-9)
    return (
        k * (wy * rel_z - wz * rel_y),
        k * (wz * rel_x - wx * rel_z),
        k * (wx * rel_y - wy * rel_x),
        spin_parameter,
    )


def air_force(
    p: BallParams, s: BallState, wind_x: Array, wind_y: Array, xp: Any = np
) -> tuple[Array, Array, Array]:
    """Gravity, drag against ``v - wind`` and Magnus force, summed (N)."""
    rel_x, rel_y, rel_z = s.vx - wind_x, s.vy - wind_y, s.vz
    drag_x, drag_y, drag_z = quadratic_drag(
        p.drag_coefficient * p.area_m2, AIR_DENSITY_KGM3, rel_x, rel_y, rel_z, xp=xp
    )
    mag_x, mag_y, mag_z, _ = magnus_force(p, rel_x, rel_y, rel_z, s.wx, s.wy, s.wz, xp)
    return drag_x + mag_x, drag_y + mag_y, drag_z + mag_z - p.mass_kg * GRAVITY_MPS2


def ground_contact(
    p: BallParams, s: BallState, dt_s: float, xp: Any = np
) -> tuple[BallState, Array]:
    """Bounce on the ground ``z = 0`` with restitution and friction; roll when slow.

    * Normal: the impact speed reverses times ``restitution`` (rebound height ``e^2``);
      impacts slower than ``rest_speed_mps`` do not bounce (resting contact), and the ball
      is put back on the ground (seed §3: moving it up as much as it sank in).
    * Tangential: Coulomb friction (seed §6) with impulse at most ``friction * J_n`` drives
      the contact point's slip to zero, which is the rolling condition ``v = omega x r``
      (seed §5, kinematic rotation): a ball landing with backspin is braked, with topspin
      it is kicked forward.
    * Rolling resistance decelerates a ball on the ground by ``c g``, never reversing it
      (the zero-crossing check of seed §6's sliding block).

    Returns the new state and whether the ball touched the ground in this substep.
    """
    r, m, inertia = p.radius_m, p.mass_kg, p.inertia_kgm2
    if not xp.any(s.z <= r):  # all in the air: nothing touches (the common case mid-flight)
        return s, s.z < 0.0 * s.z
    touching = (s.z <= r) & (s.vz <= 0.0)
    bounce = touching & (-s.vz > p.rest_speed_mps)
    e = xp.where(bounce, p.restitution, 0.0)
    normal_impulse = xp.where(touching, -(1.0 + e) * m * s.vz, 0.0)
    vz = xp.where(touching, -e * s.vz, s.vz)
    z = xp.where(s.z <= r, r + e * (r - s.z), s.z)

    # Slip of the contact point (at -r z): v + omega x (0, 0, -r).
    slip_x = s.vx - r * s.wy
    slip_y = s.vy + r * s.wx
    slip = xp.sqrt(slip_x * slip_x + slip_y * slip_y)
    # Impulse that would stop the slip: effective mass 1 / (1/m + r^2/I).
    stopping = slip / (1.0 / m + r * r / inertia)
    friction = xp.minimum(p.friction * normal_impulse, stopping)
    jx = -friction * slip_x / xp.maximum(slip, 1e-12)
    jy = -friction * slip_y / xp.maximum(slip, 1e-12)
    vx, vy = s.vx + jx / m, s.vy + jy / m
    # Angular impulse (0, 0, -r) x J = (r J_y, -r J_x, 0).
    wx, wy = s.wx + r * jy / inertia, s.wy - r * jx / inertia

    # Rolling resistance while on the ground (not bouncing).
    on_ground = (s.z <= r) & xp.logical_not(bounce)
    speed = xp.sqrt(vx * vx + vy * vy)
    slowed = xp.maximum(speed - p.rolling_resistance * GRAVITY_MPS2 * dt_s, 0.0)
    factor = xp.where(on_ground, slowed / xp.maximum(speed, 1e-12), 1.0)
    vx, vy = vx * factor, vy * factor
    wx, wy = xp.where(on_ground, -vy / r, wx), xp.where(on_ground, vx / r, wy)

    new = BallState(s.x, s.y, z, vx, vy, vz, wx, wy, s.wz, s.qw, s.qx, s.qy, s.qz)
    return new, touching


def panel_contact(
    s: BallState,
    radius_m: float,
    center_x: Array,
    center_y: Array,
    along_x: Array,
    along_y: Array,
    half_width_m: Array,
    height_m: Array,
    restitution: float,
    enabled: Array,
    xp: Any = np,
) -> tuple[BallState, Array]:
    """Bounce off a thin vertical panel standing on the ground (a screen or a wall).

    The panel's bottom edge runs through ``center`` along the unit vector ``along``. A ball
    within its radius of the panel's plane, over its face, moving toward it, has its normal
    velocity reversed times ``restitution`` and is pushed back out of the panel. Returns the
    new state and whether it hit.
    """
    normal_x, normal_y = -along_y, along_x
    dx, dy = s.x - center_x, s.y - center_y
    offset = dx * normal_x + dy * normal_y
    lateral = dx * along_x + dy * along_y
    approach = s.vx * normal_x + s.vy * normal_y
    over_face = (xp.abs(lateral) <= half_width_m) & (s.z <= height_m)
    hit = enabled & over_face & (xp.abs(offset) < radius_m) & (approach * offset < 0.0)
    side = xp.where(offset >= 0.0, 1.0, -1.0)
    change = xp.where(hit, -(1.0 + restitution) * approach, 0.0)
    push = xp.where(hit, side * radius_m - offset, 0.0)
    new = BallState(
        s.x + push * normal_x, s.y + push * normal_y, s.z,
        s.vx + change * normal_x, s.vy + change * normal_y, s.vz,
        s.wx, s.wy, s.wz, s.qw, s.qx, s.qy, s.qz,
    )  # fmt: skip
    return new, hit


def substep(
    p: BallParams, s: BallState, wind_x: Array, wind_y: Array, dt_s: float, xp: Any = np
) -> BallState:
    """One semi-implicit Euler step in the air: velocity first, then position (seed §1, §3).

    The spin decays exponentially (exact over the step) and turns the orientation
    quaternion, ``dq/dt = 1/2 (0, omega) q``.
    """
    fx, fy, fz = air_force(p, s, wind_x, wind_y, xp)
    inv_m = 1.0 / p.mass_kg
    vx, vy, vz = s.vx + fx * inv_m * dt_s, s.vy + fy * inv_m * dt_s, s.vz + fz * inv_m * dt_s
    decay = math.exp(-dt_s / p.spin_decay_s)
    wx, wy, wz = s.wx * decay, s.wy * decay, s.wz * decay
    h = 0.5 * dt_s
    qw = s.qw - h * (wx * s.qx + wy * s.qy + wz * s.qz)
    qx = s.qx + h * (wx * s.qw + wy * s.qz - wz * s.qy)
    qy = s.qy + h * (wy * s.qw + wz * s.qx - wx * s.qz)
    qz = s.qz + h * (wz * s.qw + wx * s.qy - wy * s.qx)
    norm = xp.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    return BallState(
        s.x + vx * dt_s, s.y + vy * dt_s, s.z + vz * dt_s, vx, vy, vz, wx, wy, wz,
        qw / norm, qx / norm, qy / norm, qz / norm,
    )  # fmt: skip


def collide_balls(
    m1: float, v1: tuple, p1: tuple, m2: float, v2: tuple, p2: tuple, restitution: float,
    xp: Any = np,
) -> tuple[tuple, tuple]:  # fmt: skip
    """Two balls touching at positions ``p1``, ``p2`` (3-tuples of components) collide.

    Along the line of centres the seed's restitution formula (§4, after Palmer) gives

    ``u1' = (u1 (m1 - e m2) + (1 + e) u2 m2) / (m1 + m2)``,
    ``u2' = ((1 + e) u1 m1 + u2 (m2 - e m1)) / (m1 + m2)``;

    ``e = 1`` is elastic, ``e = 0`` plastic (common velocity). Across the line of centres
    the velocities are unchanged. Balls moving apart are left alone. Returns ``(v1', v2')``.
    """
    nx, ny, nz = (b - a for a, b in zip(p1, p2, strict=True))
    dist = xp.sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx / dist, ny / dist, nz / dist
    u1 = v1[0] * nx + v1[1] * ny + v1[2] * nz
    u2 = v2[0] * nx + v2[1] * ny + v2[2] * nz
    approaching = u1 > u2
    total = m1 + m2
    u1_after = (u1 * (m1 - restitution * m2) + (1.0 + restitution) * u2 * m2) / total
    u2_after = ((1.0 + restitution) * u1 * m1 + u2 * (m2 - restitution * m1)) / total
    d1 = xp.where(approaching, u1_after - u1, 0.0)
    d2 = xp.where(approaching, u2_after - u2, 0.0)
    n = (nx, ny, nz)
    return (
        tuple(c + d1 * k for c, k in zip(v1, n, strict=True)),
        tuple(c + d2 * k for c, k in zip(v2, n, strict=True)),
    )


@dataclass
class Screen:
    """A vertical panel the ball cannot pass through (see :func:`panel_contact`)."""

    center_x: Array
    center_y: Array
    along_x: Array
    along_y: Array
    half_width_m: Array
    height_m: Array
    enabled: Array
    restitution: float = 0.4


@dataclass
class BallPose:
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


@dataclass
class ThrowResult:
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
) -> ThrowResult:
    """Fly balls from launch until they rest on the ground, leave the field or time runs out
    (``max_time_s`` in all, or ``max_roll_s`` after the first touchdown).

    The wind is held during the flight (a gust outlasts a throw). A batch keeps only the
    balls still flying in its working set (early exit: a finished ball costs nothing more,
    and the loop ends with the last one); a finished ball stays where it stopped.
    """
    _, _, _, spin_parameter = magnus_force(
        p, launch.vx - wind_x, launch.vy - wind_y, launch.vz, launch.wx, launch.wy, launch.wz, xp
    )
    if xp is np:
        return _simulate_batch(
            p, launch, wind_x, wind_y, screen, dt_s, max_time_s, max_roll_s, field_radius_m,
            record_dt_s, spin_parameter,
        )  # fmt: skip
    record_every = max(1, round(record_dt_s / dt_s))
    s, landed, hit_screen = launch, False, False
    landing_x, landing_y, flight_time, apex = s.x, s.y, 0.0, s.z
    trajectory, steps = [pose_of(s)], 1
    for i in range(1, int(round(max_time_s / dt_s)) + 1):
        before = s
        s = substep(p, s, wind_x, wind_y, dt_s, xp)
        if screen is not None:
            s, hit = _screen_contact(p, s, screen, xp)
            hit_screen = hit_screen or bool(hit)
        flown = s
        s, touching = ground_contact(p, s, dt_s, xp)
        if touching and not landed:
            landed = True
            landing_x, landing_y, flight_time = _touchdown(p, before, flown, i, dt_s, xp)
        apex = max(apex, s.z)
        if i % record_every == 0:
            trajectory.append(pose_of(s))
            steps += 1
        if _finished(p, s, landed, flight_time, i * dt_s, max_roll_s, field_radius_m, xp):
            break
    if not landed:  # it left the field, or time ran out: it "lands" where it is
        landing_x, landing_y, flight_time = s.x, s.y, i * dt_s
    return ThrowResult(
        landing_x, landing_y, flight_time, apex, spin_parameter, hit_screen, s, trajectory, steps
    )


def _touchdown(
    p: BallParams, before: BallState, after: BallState, i: int, dt_s: float, xp: Any
) -> tuple[Array, Array, Array]:
    """Where and when the ball first touched the ground during substep ``i``: linear
    interpolation to the moment its centre was one radius up, so the landing point does
    not depend on where the substep happened to end."""
    drop = before.z - after.z
    f = xp.clip((before.z - p.radius_m) / xp.where(drop > 0.0, drop, 1.0), 0.0, 1.0)
    x = before.x + f * (after.x - before.x)
    y = before.y + f * (after.y - before.y)
    return x, y, (i - 1 + f) * dt_s


def _screen_contact(p: BallParams, s: BallState, screen: Screen, xp: Any) -> tuple:
    return panel_contact(
        s, p.radius_m, screen.center_x, screen.center_y, screen.along_x, screen.along_y,
        screen.half_width_m, screen.height_m, screen.restitution, screen.enabled, xp,
    )  # fmt: skip


def _finished(
    p: BallParams, s: BallState, landed: Any, flight_time: Any, t: float, max_roll_s: Any,
    field_radius_m: float, xp: Any,
) -> Any:  # fmt: skip
    """Resting on the ground (or rolled long enough after landing), or out of the field."""
    speed_sq = s.vx * s.vx + s.vy * s.vy + s.vz * s.vz
    at_rest = landed & (s.z <= p.radius_m * 1.001) & (speed_sq < 0.01)
    if max_roll_s is not None:  # a ball blown along the ground may never stop
        at_rest = at_rest | (landed & (t - flight_time > max_roll_s))
    return at_rest | (s.x * s.x + s.y * s.y > field_radius_m * field_radius_m)


def _simulate_batch(
    p: BallParams, launch: BallState, wind_x: Array, wind_y: Array, screen: Screen | None,
    dt_s: float, max_time_s: float, max_roll_s: float | None, field_radius_m: float,
    record_dt_s: float, spin_parameter: Array,
) -> ThrowResult:  # fmt: skip
    """:func:`simulate_throw` for a batch, on the working set of balls still flying."""
    n = launch.x.shape[0]
    record_every = max(1, round(record_dt_s / dt_s))
    names = [f.name for f in fields(BallState)]
    final = BallState(*(np.array(getattr(launch, k), dtype=np.float64) for k in names))
    pose = pose_of(BallState(*(getattr(final, k).copy() for k in names)))
    out = {
        "landing_x": final.x.copy(), "landing_y": final.y.copy(), "flight_time": np.zeros(n),
        "apex": final.z.copy(), "hit_screen": np.zeros(n, dtype=bool),
        "landed": np.zeros(n, dtype=bool), "end_time": np.zeros(n),
    }  # fmt: skip
    steps = np.ones(n, dtype=np.int64)
    trajectory = [pose_of(BallState(*(getattr(final, k).copy() for k in names)))]

    # The working set: indices of flying balls and their own copies of everything per ball.
    act = np.arange(n)
    s = final
    wx, wy = np.broadcast_to(wind_x, (n,)), np.broadcast_to(wind_y, (n,))
    scr = None
    if screen is not None:
        scr = Screen(*(np.broadcast_to(getattr(screen, k), (n,)) for k in
                       ("center_x", "center_y", "along_x", "along_y", "half_width_m",
                        "height_m", "enabled")), restitution=screen.restitution)  # fmt: skip
    w = {k: v.copy() for k, v in out.items()}

    def store(rows: np.ndarray, keep: np.ndarray) -> None:
        """Write the working set's rows ``keep`` back into the full arrays at ``rows``."""
        for k in names:
            getattr(final, k)[rows] = getattr(s, k)[keep]
        for k in out:
            out[k][rows] = w[k][keep]

    for i in range(1, int(round(max_time_s / dt_s)) + 1):
        before = s
        s = substep(p, s, wx, wy, dt_s)
        if scr is not None:
            s, hit = _screen_contact(p, s, scr, np)
            w["hit_screen"] = w["hit_screen"] | hit
        flown = s
        s, touching = ground_contact(p, s, dt_s)
        first = touching & ~w["landed"]
        if first.any():
            x, y, t = _touchdown(p, before, flown, i, dt_s, np)
            w["landing_x"] = np.where(first, x, w["landing_x"])
            w["landing_y"] = np.where(first, y, w["landing_y"])
            w["flight_time"] = np.where(first, t, w["flight_time"])
        w["landed"] = w["landed"] | first
        w["apex"] = np.maximum(w["apex"], s.z)
        if i % record_every == 0:
            for k in ("x", "y", "z", "qw", "qx", "qy", "qz"):
                getattr(pose, k)[act] = getattr(s, k)
            trajectory.append(BallPose(*(getattr(pose, k).copy() for k in
                                         ("x", "y", "z", "qw", "qx", "qy", "qz"))))  # fmt: skip
            steps[act] += 1
        done = _finished(p, s, w["landed"], w["flight_time"], i * dt_s, max_roll_s,
                         field_radius_m, np)  # fmt: skip
        w["end_time"] = np.full(act.size, i * dt_s)
        if done.any():
            store(act[done], done)
            keep = ~done
            act = act[keep]
            if act.size == 0:
                break
            s = BallState(*(getattr(s, k)[keep] for k in names))
            w = {k: v[keep] for k, v in w.items()}
            wx, wy = wx[keep], wy[keep]
            if scr is not None:
                scr = Screen(*(getattr(scr, k)[keep] for k in
                               ("center_x", "center_y", "along_x", "along_y", "half_width_m",
                                "height_m", "enabled")), restitution=scr.restitution)  # fmt: skip
    if act.size:
        store(act, np.ones(act.size, dtype=bool))
    # A ball that never touched down (left the field, or still flying) lands where it is.
    never = ~out["landed"]
    out["landing_x"] = np.where(never, final.x, out["landing_x"])
    out["landing_y"] = np.where(never, final.y, out["landing_y"])
    out["flight_time"] = np.where(never, out["end_time"], out["flight_time"])
    return ThrowResult(
        out["landing_x"], out["landing_y"], out["flight_time"], out["apex"], spin_parameter,
        out["hit_screen"], final, trajectory, steps,
    )  # fmt: skip
