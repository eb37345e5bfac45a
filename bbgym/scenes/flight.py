"""Panels and planes (§8): the wind panel (confetti, a loose roof panel) and the aeroplane.

Both are rigid bodies in 3-D: a position, a velocity, an orientation (a unit quaternion,
body to world) and an angular velocity in the body's axes, stepped by semi-implicit Euler
(velocities first). What is new here, each in one function:

==============================  =========================================================
law                             function
==============================  =========================================================
turning an orientation          :func:`turned` (``q <- q exp(omega dt / 2)``, body rates)
body and world axes             :func:`body_axes`, :func:`to_body`
Euler's equations               :func:`euler_rotation_step` (``I w' = tau - w x I w``)
a panel's normal force          :func:`panel_normal_force` (``1/2 rho C A |u_n| u_n``)
where that force acts           :func:`centre_of_pressure_m` (toward the leading edge)
a panel's rotational drag       :func:`panel_rotation_drag` (the same law, strip by strip)
the propeller's gyro torque     :func:`propeller_gyro_torque` (``L x omega``)
an aeroplane's trim             :meth:`PlaneParams.trim` (lift = weight, thrust = drag)
==============================  =========================================================

The laws that exist already are the envs': the quadratic drag rate
(:func:`bbgym.physics.common.quadratic_drag_rate`), the air's density and gravity
(:mod:`bbgym.physics.common`) and the gusts of the true wind (an Ornstein-Uhlenbeck process,
:mod:`bbgym.physics.wind`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2, quadratic_drag_rate
from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, check_fields, interval, param
from bbgym.physics.wind import GustParams, GustState, gust_init, gust_step, wind_vector
from bbgym.scenes.projectiles import column
from bbgym.scenes.scene import Frame, Scene, SceneFunctions, Segment, state_fields

TINY = 1e-12
"""Floor of a norm we divide by: the direction of a zero vector is taken as zero."""

Vector = tuple[Array, Array, Array]
Quaternion = tuple[Array, Array, Array, Array]


# -- rotations ---------------------------------------------------------------------------------


def quaternion_product(a: Quaternion, b: Quaternion) -> Quaternion:
    """The Hamilton product ``a b``: the rotation ``b`` first, then ``a``."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    )


def turned(q: Quaternion, w: Vector, dt_s: float, xp: Any) -> Quaternion:
    """The orientation ``q`` (body to world) turned for ``dt_s`` at the body rates ``w``:
    ``q exp(w dt / 2)``, exact for rates held over the step, then renormalised (so the
    rotation matrix stays orthonormal to rounding however long the run)."""
    wx, wy, wz = w
    rate = xp.sqrt(wx * wx + wy * wy + wz * wz)
    half = 0.5 * dt_s * rate
    # sin(half) / rate, which tends to dt / 2 as the rate goes to 0
    scale = xp.where(rate > TINY, xp.sin(half) / xp.maximum(rate, TINY), 0.5 * dt_s)
    qw, qx, qy, qz = quaternion_product(q, (xp.cos(half), scale * wx, scale * wy, scale * wz))
    norm = xp.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    return qw / norm, qx / norm, qy / norm, qz / norm


def body_axes(q: Quaternion) -> tuple[Vector, Vector, Vector]:
    """The body's x, y and z axes in the world (the rotation matrix's columns)."""
    qw, qx, qy, qz = q
    return (
        (1.0 - 2.0 * (qy * qy + qz * qz), 2.0 * (qx * qy + qw * qz), 2.0 * (qx * qz - qw * qy)),
        (2.0 * (qx * qy - qw * qz), 1.0 - 2.0 * (qx * qx + qz * qz), 2.0 * (qy * qz + qw * qx)),
        (2.0 * (qx * qz + qw * qy), 2.0 * (qy * qz - qw * qx), 1.0 - 2.0 * (qx * qx + qy * qy)),
    )


def dot(a: Vector, b: Vector) -> Array:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def to_body(axes: tuple[Vector, Vector, Vector], v: Vector) -> Vector:
    """A world vector in the body's axes (``R^T v``)."""
    return dot(axes[0], v), dot(axes[1], v), dot(axes[2], v)


def to_world(axes: tuple[Vector, Vector, Vector], v: Vector) -> Vector:
    """A body vector in the world (``R v``)."""
    ex, ey, ez = axes
    return tuple(ex[k] * v[0] + ey[k] * v[1] + ez[k] * v[2] for k in range(3))  # type: ignore[return-value]


def euler_rotation_step(
    inertia: tuple[float, float, float],
    w: Vector,
    torque: Vector,
    damping: Vector,
    dt_s: float,
) -> Vector:
    """Euler's equations in the body's principal axes, ``I dw/dt = tau - w x (I w) - c w``,
    one step: the torque and the gyroscopic term explicit, the damping ``c`` (N m s, each
    axis its own) implicit, so a light body's fast aerodynamic damping never overshoots."""
    ix, iy, iz = inertia
    wx, wy, wz = w
    hx, hy, hz = ix * wx, iy * wy, iz * wz
    gx, gy, gz = wy * hz - wz * hy, wz * hx - wx * hz, wx * hy - wy * hx
    return (
        (wx + dt_s * (torque[0] - gx) / ix) / (1.0 + dt_s * damping[0] / ix),
        (wy + dt_s * (torque[1] - gy) / iy) / (1.0 + dt_s * damping[1] / iy),
        (wz + dt_s * (torque[2] - gz) / iz) / (1.0 + dt_s * damping[2] / iz),
    )


# -- the wind panel ----------------------------------------------------------------------------


def panel_normal_force(
    normal_coefficient: float,
    area_m2: float,
    mass_kg: float,
    normal_speed_mps: Array,
    gravity_along_normal: Array,
    dt_s: float,
    xp: Any,
) -> Array:
    """The air's force on a flat panel along its normal, per kg (§8: "projected to F_wn
    normal to the panel"): only the relative wind's component along the normal, ``u_n``,
    pushes, ``F = -1/2 rho C A |u_n| u_n`` (the drag law of the normal component; a wind
    along the panel pushes nothing). Taken implicitly over the step like the balls' drag
    (the rate ``1/2 rho C A |u_n| / m`` frozen, ``u_n`` the one at the step's end), so a
    light panel never overshoots; the terminal speed is unchanged."""
    rate = (
        quadratic_drag_rate(
            normal_coefficient * area_m2, AIR_DENSITY_KGM3, xp.abs(normal_speed_mps)
        )
        / mass_kg
    )
    after = (normal_speed_mps + dt_s * gravity_along_normal) / (1.0 + dt_s * rate)
    return -rate * after


def centre_of_pressure_m(chord_m: Array, sin_attack: Array) -> Array:
    """How far ahead of the panel's centre (toward its leading edge, along the flow over
    it) the normal force acts: a quarter chord ahead when the air meets the panel at a
    grazing angle, at the centre when it meets it square on, ``c/4 (1 - sin(alpha))`` (the
    classic flat-plate fit, after Rayleigh). The offset is what makes a panel turn
    broadside to its fall and then rock: the fluttering of falling paper."""
    return 0.25 * chord_m * (1.0 - sin_attack)


def panel_rotation_drag(
    normal_coefficient: float, chord_m: float, span_m: float, w: Vector, xp: Any
) -> Vector:
    """The damping (N m s) of a panel turning about its in-plane axes: each strip at ``s``
    from the axis moves along the normal at ``w s`` and feels the normal force's law,
    ``1/2 rho C |w s| w s`` per area, at the arm ``s``; over the panel that is a torque
    ``1/2 rho C (a b^4 / 32) |w| w`` about the chord (x) axis and ``b a^4 / 32`` about the
    span (y) axis. Spinning about its normal the panel meets no air (0)."""
    wx, wy, wz = w
    about_chord = quadratic_drag_rate(
        normal_coefficient * chord_m * span_m**4 / 32.0, AIR_DENSITY_KGM3, xp.abs(wx)
    )
    about_span = quadratic_drag_rate(
        normal_coefficient * span_m * chord_m**4 / 32.0, AIR_DENSITY_KGM3, xp.abs(wy)
    )
    return about_chord, about_span, 0.0 * wz


@dataclass(frozen=True)
class ConfettiParams(CheckedFields):
    """Four square-ish panels (a playing card by default) dropped in a steady wind: one
    flat, one tilted, one started spinning (the text's rotating panel) and one edge-on."""

    chord_m: float = param(0.1, interval(0.01, 2.0))
    """Side along the panel's x axis (the tilt turns it about the other side)."""
    span_m: float = param(0.1, interval(0.01, 2.0))
    areal_density_kgm2: float = param(0.2, interval(0.01, 20.0))
    """Card stock: 0.2-0.3 kg/m^2; a roof's sheet metal some 5-10."""
    normal_coefficient: float = param(1.17, interval(0.1, 2.0))
    """``C`` of the force along the normal: a flat plate broadside on, 1.17 (Hoerner)."""
    wind_speed_mps: float = param(2.0, interval(0.0, 20.0))
    """A steady wind along +x."""
    tilt_deg: float = param(20.0, interval(-85.0, 85.0))
    """The tilted panel's start: its normal leans this far from the vertical toward +x."""
    spin_radps: float = param(10.0, interval(0.0, 100.0))
    """The spinning panel's start: turning about its span axis."""
    drop_height_m: float = param(10.0, interval(1.0, 1000.0))
    dt_s: float = param(1.0 / 240.0, interval(1e-4, 0.01))

    @property
    def area_m2(self) -> float:
        return self.chord_m * self.span_m

    @property
    def mass_kg(self) -> float:
        return self.areal_density_kgm2 * self.area_m2

    @property
    def inertia_kgm2(self) -> tuple[float, float, float]:
        """A thin plate about its chord, span and normal axes: ``m b^2 / 12``,
        ``m a^2 / 12``, ``m (a^2 + b^2) / 12``."""
        m, a, b = self.mass_kg, self.chord_m, self.span_m
        return m * b * b / 12.0, m * a * a / 12.0, m * (a * a + b * b) / 12.0

    def terminal_speed_mps(self) -> float:
        """A panel falling flat: ``sqrt(2 m g / (rho C A))``, where its normal force
        balances its weight (§8)."""
        return math.sqrt(
            2.0
            * self.mass_kg
            * GRAVITY_MPS2
            / (AIR_DENSITY_KGM3 * self.normal_coefficient * self.area_m2)
        )


CONFETTI_NAMES = ("flat", "tilted", "spinning", "edge-on")
PANEL_COLORS = ((220, 60, 60), (40, 130, 220), (240, 170, 30), (60, 160, 80))


class Panels(NamedTuple):
    """Each panel's centre and velocity (world: x downwind, y across, z up), its angular
    velocity in its own axes (x chord, y span, z normal) and its orientation quaternion."""

    x_m: Array
    y_m: Array
    z_m: Array
    vx_mps: Array
    vy_mps: Array
    vz_mps: Array
    wx_radps: Array
    wy_radps: Array
    wz_radps: Array
    qw: Array
    qx: Array
    qy: Array
    qz: Array


def confetti_initial(p: ConfettiParams, xp: Any) -> Panels:
    """Flat (normal up), tilted about the world's y axis by ``tilt_deg``, flat but spinning
    about its span, and edge-on (turned 90 deg about its chord: its normal across the wind
    and the fall), all at rest at one height."""
    half_tilt = 0.5 * math.radians(p.tilt_deg)
    edge = math.sqrt(0.5)
    zero = column((0.0,) * 4, xp)
    return Panels(
        column((-3.0, -1.0, 1.0, 3.0), xp),
        zero,
        zero + p.drop_height_m,
        zero,
        zero,
        zero,
        zero,
        column((0.0, 0.0, p.spin_radps, 0.0), xp),
        zero,
        column((1.0, math.cos(half_tilt), 1.0, edge), xp),
        column((0.0, 0.0, 0.0, edge), xp),
        column((0.0, math.sin(half_tilt), 0.0, 0.0), xp),
        zero,
    )


def confetti_step(p: ConfettiParams, s: Panels, xp: Any) -> Panels:
    """One step: the normal force (implicit along the normal) and gravity move the panel;
    the normal force at the centre of pressure, the rotational drag and Euler's equations
    turn it; a panel that reaches the ground stays there."""
    q = (s.qw, s.qx, s.qy, s.qz)
    axes = body_axes(q)
    normal = axes[2]
    v = (s.vx_mps, s.vy_mps, s.vz_mps)
    u = (v[0] - p.wind_speed_mps, v[1], v[2])  # the panel's velocity through the air
    u_body = to_body(axes, u)
    speed = xp.sqrt(dot(u, u))
    along = xp.sqrt(u_body[0] * u_body[0] + u_body[1] * u_body[1])
    sin_attack = xp.abs(u_body[2]) / xp.maximum(speed, TINY)
    # The flow's direction over the panel (in its plane) and the panel's length along it.
    tx, ty = u_body[0] / xp.maximum(along, TINY), u_body[1] / xp.maximum(along, TINY)
    chord = p.chord_m * xp.abs(tx) + p.span_m * xp.abs(ty)
    force = panel_normal_force(
        p.normal_coefficient, p.area_m2, p.mass_kg, u_body[2], -GRAVITY_MPS2 * normal[2], p.dt_s, xp
    )
    vx = v[0] + p.dt_s * force * normal[0]
    vy = v[1] + p.dt_s * force * normal[1]
    vz = v[2] + p.dt_s * (force * normal[2] - GRAVITY_MPS2)
    # r x F with r = d (tx, ty, 0) and F = m f (0, 0, 1) in the panel's axes
    moment = centre_of_pressure_m(chord, sin_attack) * p.mass_kg * force
    w = (s.wx_radps, s.wy_radps, s.wz_radps)
    damping = panel_rotation_drag(p.normal_coefficient, p.chord_m, p.span_m, w, xp)
    w = euler_rotation_step(
        p.inertia_kgm2, w, (moment * ty, -moment * tx, 0.0 * moment), damping, p.dt_s
    )
    qw, qx, qy, qz = turned(q, w, p.dt_s, xp)
    moved = (s.x_m + p.dt_s * vx, s.y_m + p.dt_s * vy, s.z_m + p.dt_s * vz)
    down = moved[2] <= 0.0
    kept = [xp.where(down, old, new) for old, new in ((s.x_m, moved[0]), (s.y_m, moved[1]))]
    still = [xp.where(down, 0.0, new) for new in (vx, vy, vz, *w)]
    return Panels(kept[0], kept[1], xp.where(down, 0.0, moved[2]), *still, qw, qx, qy, qz)


def confetti_measures(p: ConfettiParams, s: Panels, xp: Any) -> dict[str, Array]:
    normal = body_axes((s.qw, s.qx, s.qy, s.qz))[2]
    level = xp.sqrt(normal[0] * normal[0] + normal[1] * normal[1])
    return {
        "height_m": s.z_m,
        "drift_m": s.x_m - column((-3.0, -1.0, 1.0, 3.0), xp),
        "vertical_velocity_mps": s.vz_mps,
        # the normal's angle from the vertical: 0 flat, 90 edge-on, 180 upside down
        "tilt_deg": xp.atan2(level, normal[2]) * (180.0 / math.pi),
    }


PANEL_DRAWN_X = 8.0
"""Panels are drawn this many times their size (a card is a dot in a 10 m view)."""


def confetti_frame(p: ConfettiParams, s: Panels) -> Frame:
    """Side view (x downwind, up): each panel's chord and span, projected."""
    segments = []
    for k in range(4):
        ex, ey, _ = body_axes((s.qw[k], s.qx[k], s.qy[k], s.qz[k]))
        cx, cz = float(s.x_m[k]), float(s.z_m[k])
        for axis, size, width in ((ex, p.chord_m, 4), (ey, p.span_m, 2)):
            dx, dz = (0.5 * PANEL_DRAWN_X * size * float(axis[i]) for i in (0, 2))
            segments.append(Segment(cx - dx, cz - dz, cx + dx, cz + dz, PANEL_COLORS[k], width))
    speeds = ", ".join(
        f"{n} {float(v):+.2f}" for n, v in zip(CONFETTI_NAMES, s.vz_mps, strict=True)
    )
    note = (
        f"flat terminal speed {p.terminal_speed_mps():.2f} m/s; wind "
        f"{p.wind_speed_mps:g} m/s; panels drawn x{PANEL_DRAWN_X:g}"
    )
    return Frame([], segments, [f"vertical velocity (m/s): {speeds}", note])


CONFETTI = Scene(
    name="confetti",
    section="§8",
    title="The wind panel: confetti and loose roof panels",
    claim="the air pushes a panel only along its normal, from the relative wind's normal "
    "component: falling flat it reaches sqrt(2 m g / (rho C A)), edge-on it falls freely, "
    "tilted it glides toward its lean and rocks with growing swings as the centre of "
    "pressure turns it, then tumbles, its fall speeding up and slowing",
    params=ConfettiParams,
    functions=SceneFunctions(confetti_initial, confetti_step, confetti_measures, confetti_frame),
    view_box_m=lambda p: (
        -5.0,
        5.0 + 0.6 * p.wind_speed_mps * p.drop_height_m,
        -0.5,
        p.drop_height_m + 1.0,
    ),
    duration_s=lambda p: 1.3 * p.drop_height_m / p.terminal_speed_mps() + 0.5,
    bodies=CONFETTI_NAMES,
    test="test_confetti_normal_force_terminal_speed_glide_and_rocking",
)


# -- the aeroplane ------------------------------------------------------------------------------


def propeller_gyro_torque(angular_momentum_kgm2ps: float, w: Vector) -> Vector:
    """The torque a spinning propeller puts on the airframe when the airframe turns (§8,
    the gyro effect), in the body's axes (x forward, y left, z up). The propeller's angular
    momentum ``L`` lies along x (clockwise seen from the cockpit: ``L > 0``); turned at
    ``omega`` it must change at ``omega x L``, a torque the airframe gives it, so the
    airframe feels ``-(omega x L) = L x omega``: a yaw to the left (``omega_z > 0``)
    pitches the nose up, a yaw to the right pitches it down, ``|L| |omega_z|`` either way."""
    wx, wy, wz = w
    return 0.0 * wx, -angular_momentum_kgm2ps * wz, angular_momentum_kgm2ps * wy


class Airframe(NamedTuple):
    """A light single-engine aeroplane (about a Cessna 172's size and inertia)."""

    mass_kg: float = 750.0
    wing_area_m2: float = 15.0
    span_m: float = 10.0
    chord_m: float = 1.5
    lift_slope_per_rad: float = 5.0
    """``C_L = a alpha`` below the stall (thin-wing theory's 2 pi, less for a finite wing)."""
    stall_rad: float = math.radians(16.0)
    """Past it the lift coefficient stays at its stall value (no stall break modelled)."""
    drag_coefficient: float = 0.03
    inertia_kgm2: tuple[float, float, float] = (1300.0, 1800.0, 2700.0)
    """Roll, pitch, yaw."""
    pitch_stiffness: float = 1.0
    """The tail's pull of the nose toward the trimmed angle of attack, ``C_m`` per radian
    (times ``q S c``)."""
    pitch_damping: float = 12.0
    yaw_stiffness: float = 0.1
    """The fin's weathercock pull of the nose into the relative wind (times ``q S b``)."""
    yaw_damping: float = 0.3
    bank_gain: float = 0.05
    """The pilot's ailerons holding a bank angle (per radian of error, times ``q S b``)."""
    roll_damping: float = 0.5


AIRFRAME = Airframe()


@dataclass(frozen=True)
class PlaneParams:
    """Four aeroplanes trimmed for level flight at one speed: flying straight, banked into
    a left and a right turn, and straight through gusts."""

    trim_speed_mps: float = param(40.0, interval(30.0, 80.0))
    """Airspeed of the trim: the angle of attack that makes lift hold the weight there,
    and the thrust that matches the drag."""
    bank_deg: float = param(30.0, interval(5.0, 45.0))
    """The turning planes' bank (left and right)."""
    propeller_rpm: float = param(2500.0, interval(0.0, 3000.0))
    propeller_inertia_kgm2: float = param(1.5, interval(0.0, 20.0))
    """A two-blade metal propeller: 1-2 kg m^2."""
    wind_speed_mps: float = param(5.0, interval(0.0, 20.0))
    """A headwind (from +x) for all four; the gusts are a fraction of it."""
    gust_std: float = param(0.3, interval(0.0, 1.0))
    """The gusty plane's wind speed varies by this standard deviation (fraction of the
    mean), its direction by as many radians over two (the envs' gust process)."""
    seed: int = param(0, interval(0, 2**31 - 1), integer=True)
    """The gusts' random draws (NumPy, at the start: the run is deterministic)."""
    dt_s: float = param(0.02, interval(1e-3, 0.05))

    def __post_init__(self) -> None:
        check_fields(self)
        alpha, _ = self.trim()
        if alpha / math.cos(math.radians(self.bank_deg)) > AIRFRAME.stall_rad:
            raise ValueError(
                "PlaneParams.trim_speed_mps is too slow for bank_deg: a level turn would "
                f"need more than the stall's {math.degrees(AIRFRAME.stall_rad):g} deg"
            )

    def dynamic_pressure_pa(self) -> float:
        return 0.5 * AIR_DENSITY_KGM3 * self.trim_speed_mps**2

    def trim(self) -> tuple[float, float]:
        """``(alpha, thrust_n)`` of level flight at ``trim_speed_mps``: the lift ``q S a
        alpha`` along the plane's up vector (tilted back by alpha) and the thrust along its
        nose (tilted up by alpha) balance the weight and the drag ``q S C_d``:
        ``L / cos(alpha) + D tan(alpha) = m g`` (Newton's method) and
        ``T = (D + L sin(alpha)) / cos(alpha)``."""
        f = AIRFRAME
        qs = self.dynamic_pressure_pa() * f.wing_area_m2
        drag, weight = qs * f.drag_coefficient, f.mass_kg * GRAVITY_MPS2
        alpha = weight / (qs * f.lift_slope_per_rad)
        for _ in range(30):
            c, s = math.cos(alpha), math.sin(alpha)
            lift = qs * f.lift_slope_per_rad * alpha
            residual = lift / c + drag * s / c - weight
            slope = qs * f.lift_slope_per_rad / c + (lift * s + drag) / (c * c)
            alpha -= residual / slope
        lift = qs * f.lift_slope_per_rad * alpha
        return alpha, (drag + lift * math.sin(alpha)) / math.cos(alpha)

    def turn_rate_radps(self) -> float:
        """A level banked turn's rate, ``g tan(bank) / V``."""
        return GRAVITY_MPS2 * math.tan(math.radians(self.bank_deg)) / self.trim_speed_mps

    def propeller_momentum_kgm2ps(self) -> float:
        return self.propeller_inertia_kgm2 * self.propeller_rpm * (2.0 * math.pi / 60.0)


PLANE_NAMES = ("level", "left turn", "right turn", "gusts")
PLANE_COLORS = ((60, 60, 60), (40, 130, 220), (220, 60, 60), (60, 160, 80))
PLANE_START_Y_M = (30.0, 60.0, -60.0, -30.0)
GUST_KNOTS = 256
GUST_KNOT_S = 0.1
"""The gusts are drawn at knots this far apart (a table of ``GUST_KNOTS``, repeating) and
interpolated between them."""


class Planes(state_fields(Panels, "time_s", "gust_speed", "gust_shift")):
    """Each plane's position and velocity (world: x east, y north, z up), its body rates
    (x forward, y left, z up) and its orientation quaternion (:class:`Panels`' fields), the
    clock and the gusts' table (``(GUST_KNOTS, planes)``: speed fraction and direction
    shift at each knot)."""

    __slots__ = ()


def gust_table(p: PlaneParams) -> tuple[np.ndarray, np.ndarray]:
    """The gusty plane's gusts at each knot, by the envs' gust process
    (:func:`~bbgym.physics.wind.gust_step`) from NumPy draws of ``seed``; the others'
    zero."""
    gusts = GustParams(
        speed_std=p.gust_std, shift_std_rad=0.5 * p.gust_std, time_constant_s=2.0, smoothing_s=0.3
    )
    rng = np.random.default_rng(p.seed)
    enabled = np.array([False, False, False, True])
    state = gust_init(gusts, rng.standard_normal((2, 4)), enabled, np)
    speed, shift = [], []
    for _ in range(GUST_KNOTS):
        speed.append(state.speed)
        shift.append(state.shift)
        state = gust_step(state, gusts, GUST_KNOT_S, rng.standard_normal((2, 4)), enabled, np)
    return np.stack(speed), np.stack(shift)


def plane_initial(p: PlaneParams, xp: Any) -> Planes:
    """Each plane at 500 m, flying east at the trim airspeed through the air (the wind
    added), its nose up by the trim angle of attack, wings level."""
    alpha, _ = p.trim()
    zero = column((0.0,) * 4, xp)
    speed, shift = gust_table(p)
    return Planes(
        zero,
        column(PLANE_START_Y_M, xp),
        zero + 500.0,
        zero + (p.trim_speed_mps - p.wind_speed_mps),
        zero,
        zero,
        zero,
        zero,
        zero,
        zero + math.cos(0.5 * alpha),
        zero,
        zero - math.sin(0.5 * alpha),
        zero,
        zero,
        xp.asarray(speed, dtype=xp.float64),
        xp.asarray(shift, dtype=xp.float64),
    )


def plane_wind(p: PlaneParams, s: Planes, xp: Any) -> tuple[Array, Array]:
    """The wind now: the headwind with the gusts of the table, interpolated linearly
    between knots (the table repeats), through the envs' :func:`wind_vector`."""
    knots = xp.expand_dims(xp.arange(GUST_KNOTS, dtype=xp.float64) * GUST_KNOT_S, axis=1)
    span = GUST_KNOTS * GUST_KNOT_S
    apart = xp.abs(xp.expand_dims(xp.remainder(s.time_s, span), axis=0) - knots)
    apart = xp.minimum(apart, span - apart)  # around the repeat
    weight = xp.maximum(1.0 - apart / GUST_KNOT_S, 0.0)
    speed = xp.sum(weight * s.gust_speed, axis=0)
    shift = xp.sum(weight * s.gust_shift, axis=0)
    vx, vy, _, _ = wind_vector(p.wind_speed_mps, 0.0, GustState(speed, speed, shift, shift), xp)
    return vx, vy


def plane_air(p: PlaneParams, s: Planes, xp: Any) -> tuple[Any, Vector, Array, Array]:
    """``(axes, velocity through the air in body axes, airspeed, angle of attack)``."""
    axes = body_axes((s.qw, s.qx, s.qy, s.qz))
    wind_x, wind_y = plane_wind(p, s, xp)
    u = to_body(axes, (s.vx_mps - wind_x, s.vy_mps - wind_y, s.vz_mps))
    speed = xp.sqrt(dot(u, u))
    return axes, u, speed, xp.atan2(-u[2], u[0])


def plane_lift_n(speed_mps: Array, alpha_rad: Array, xp: Any) -> Array:
    """The wings' lift, along the plane's up vector (§8): ``1/2 rho S a alpha V^2``, the
    angle of attack held at the stall's beyond it."""
    f = AIRFRAME
    attack = xp.clip(alpha_rad, -f.stall_rad, f.stall_rad)
    return (
        (0.5 * AIR_DENSITY_KGM3 * f.wing_area_m2 * f.lift_slope_per_rad)
        * attack
        * (speed_mps * speed_mps)
    )


def plane_bank_rad(axes: Any, xp: Any) -> Array:
    """The bank, left wing down positive: the world's up seen from the body."""
    return xp.atan2(-axes[1][2], axes[2][2])


def plane_step(p: PlaneParams, s: Planes, xp: Any) -> Planes:
    """One step: lift along the up vector, drag against the air, the trim thrust along
    the nose and gravity move the plane; the tail and fin (stiffness toward the trimmed
    angle of attack and into the relative wind, and damping), the pilot's ailerons holding
    the bank, and the propeller's gyro torque turn it (Euler's equations)."""
    f = AIRFRAME
    alpha_trim, thrust = p.trim()
    bank = math.radians(p.bank_deg)
    # The pilot banks the turning planes and raises the nose by 1 / cos(bank) (level turn).
    bank_wanted = column((0.0, bank, -bank, 0.0), xp)
    turning = alpha_trim / math.cos(bank)
    sin_attack_wanted = column(
        tuple(math.sin(a) for a in (alpha_trim, turning, turning, alpha_trim)), xp
    )
    axes, u, speed, alpha = plane_air(p, s, xp)
    lift = plane_lift_n(speed, alpha, xp)
    drag_rate = quadratic_drag_rate(f.drag_coefficient * f.wing_area_m2, AIR_DENSITY_KGM3, speed)
    force = to_world(axes, (thrust - drag_rate * u[0], -drag_rate * u[1], lift - drag_rate * u[2]))
    vx = s.vx_mps + p.dt_s * force[0] / f.mass_kg
    vy = s.vy_mps + p.dt_s * force[1] / f.mass_kg
    vz = s.vz_mps + p.dt_s * (force[2] / f.mass_kg - GRAVITY_MPS2)
    q_dyn = 0.5 * AIR_DENSITY_KGM3 * speed * speed
    qs = q_dyn * f.wing_area_m2
    inv_speed = 1.0 / xp.maximum(speed, TINY)
    # The nose turned toward the relative wind: x x u / |u| = (0, -u_z, u_y) / |u|.
    pitch = f.pitch_stiffness * qs * f.chord_m * (-u[2] * inv_speed - sin_attack_wanted)
    yaw = f.yaw_stiffness * qs * f.span_m * u[1] * inv_speed
    roll = f.bank_gain * qs * f.span_m * (plane_bank_rad(axes, xp) - bank_wanted)
    w = (s.wx_radps, s.wy_radps, s.wz_radps)
    gyro = propeller_gyro_torque(p.propeller_momentum_kgm2ps(), w)
    # Damping of rates: q S l * C * (w l / (2 V)) = rho V S l^2 C / 4.
    rate = 0.25 * AIR_DENSITY_KGM3 * speed * f.wing_area_m2
    damping = (
        rate * f.span_m**2 * f.roll_damping,
        rate * f.chord_m**2 * f.pitch_damping,
        rate * f.span_m**2 * f.yaw_damping,
    )
    w = euler_rotation_step(
        f.inertia_kgm2, w, (roll + gyro[0], pitch + gyro[1], yaw + gyro[2]), damping, p.dt_s
    )
    qw, qx, qy, qz = turned((s.qw, s.qx, s.qy, s.qz), w, p.dt_s, xp)
    return Planes(
        s.x_m + p.dt_s * vx,
        s.y_m + p.dt_s * vy,
        s.z_m + p.dt_s * vz,
        vx,
        vy,
        vz,
        *w,
        qw,
        qx,
        qy,
        qz,
        s.time_s + p.dt_s,
        s.gust_speed,
        s.gust_shift,
    )


def plane_measures(p: PlaneParams, s: Planes, xp: Any) -> dict[str, Array]:
    axes, u, speed, alpha = plane_air(p, s, xp)
    _, thrust = p.trim()
    lift = plane_lift_n(speed, alpha, xp)
    w_world = to_world(axes, (s.wx_radps, s.wy_radps, s.wz_radps))
    gyro = propeller_gyro_torque(
        p.propeller_momentum_kgm2ps(), (s.wx_radps, s.wy_radps, s.wz_radps)
    )
    degrees = 180.0 / math.pi
    weight = AIRFRAME.mass_kg * GRAVITY_MPS2
    return {
        "altitude_m": s.z_m,
        "airspeed_mps": speed,
        "attack_deg": alpha * degrees,
        "bank_deg": plane_bank_rad(axes, xp) * degrees,
        "turn_rate_degps": w_world[2] * degrees,
        # The weight held up: lift's and thrust's vertical parts over m g.
        "lift_over_weight": (lift * axes[2][2] + thrust * axes[0][2]) / weight,
        "gyro_nose_up_nm": 0.0 - gyro[1],
    }


PLANE_DRAWN_X = 15.0
"""Planes are drawn this many times their size."""


def plane_frame(p: PlaneParams, s: Planes) -> Frame:
    """Top view (x east, y north): each plane's fuselage and wings, projected."""
    segments, lines = [], []
    for k in range(4):
        ex, ey, _ = body_axes((s.qw[k], s.qx[k], s.qy[k], s.qz[k]))
        cx, cy = float(s.x_m[k]), float(s.y_m[k])
        length, span = 0.5 * PLANE_DRAWN_X * 8.0, 0.5 * PLANE_DRAWN_X * AIRFRAME.span_m
        nose = (cx + 0.6 * length * float(ex[0]), cy + 0.6 * length * float(ex[1]))
        tail = (cx - 0.4 * length * float(ex[0]), cy - 0.4 * length * float(ex[1]))
        segments.append(Segment(*tail, *nose, PLANE_COLORS[k], 3))
        segments.append(
            Segment(
                cx - span * float(ey[0]),
                cy - span * float(ey[1]),
                cx + span * float(ey[0]),
                cy + span * float(ey[1]),
                PLANE_COLORS[k],
                3,
            )
        )
        lines.append(f"{PLANE_NAMES[k]} {float(s.z_m[k]):.0f} m")
    return Frame(
        [],
        segments,
        [
            "altitude: " + ", ".join(lines),
            f"trim {p.trim_speed_mps:g} m/s, bank {p.bank_deg:g} deg, "
            f"propeller {p.propeller_rpm:g} rpm; planes drawn "
            f"x{PLANE_DRAWN_X:g}",
        ],
    )


def plane_view_box_m(p: PlaneParams) -> tuple[float, float, float, float]:
    radius = p.trim_speed_mps / p.turn_rate_radps()
    reach = p.trim_speed_mps * 15.0
    return (-100.0, max(reach, 2.0 * radius) + 100.0, -2.0 * radius - 150.0, 2.0 * radius + 150.0)


AEROPLANE = Scene(
    name="aeroplane",
    section="§8",
    title="The aeroplane: lift, the propeller's gyro effect, gusts",
    claim="trimmed, lift along the up vector holds the weight and the plane flies level; "
    "banked, it turns at g tan(bank) / V; the propeller's angular momentum L pitches the "
    "nose up in a left turn and down in a right one, by the torque L x omega; gusts make "
    "the level flight wander",
    params=PlaneParams,
    functions=SceneFunctions(plane_initial, plane_step, plane_measures, plane_frame),
    view_box_m=plane_view_box_m,
    duration_s=lambda p: 15.0,
    bodies=PLANE_NAMES,
    test="test_aeroplane_trim_turns_gyro_pitch_and_gusts",
    floor=False,
)

SCENES = (CONFETTI, AEROPLANE)
