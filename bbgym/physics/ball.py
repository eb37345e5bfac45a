"""Beach balls: gravity, drag, Magnus force, spin, bounces and collisions (seed §3-§6, §8).

3D, world frame x east, y north, z up, SI units. Like the sailing physics every function is
pure and written against an array namespace ``xp`` (:mod:`bbgym.physics.namespace`): NumPy
arrays for a batch, Python floats for one ball, or any namespace of the array API standard
(``array_api_strict``, torch): only the standard's names, no Python branch on array values,
states are immutable NamedTuples. Vectors are passed as separate components.

==========================  ============================================================
law                         function
==========================  ============================================================
mass of a shell or a solid  :class:`BallParams` (``mass_kg``, ``inertia_kgm2``)
gravity and drag            :func:`air_force` (drag ``-1/2 C_d A rho |v-w| (v-w)``, §8)
Magnus force                :func:`magnus_force` (``1/2 rho A C_L |v|^2``, §8)
spin decay                  :func:`spin_decay` (exponential, time constant ``spin_decay_s``)
drag and Magnus, implicit   :func:`drag_rate_per_s`, :func:`magnus_coefficient`
bounce, friction, rolling   :func:`ground_contact` (restitution §3, friction §6, §5):
                            :func:`friction_impulse`, :func:`rolling_resistance`
panel (screen, wall) hits   :func:`panel_contact`, the bounce :func:`panel_bounce`
ball-ball collision         :func:`collide_balls` (restitution formula of §4)
at rest                     :func:`ball_at_rest`
==========================  ============================================================

A throw's flight from launch to rest, which runs these laws substep by substep, is
:mod:`bbgym.physics.flight`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2, quadratic_drag_rate
from bbgym.physics.namespace import Array, skippable
from bbgym.physics.validation import check_fields, interval, param

TINY = 1e-12
"""Floor of a norm we divide by (m/s, rad/s, m): a direction of a zero vector is taken as
zero, and the product it multiplies vanishes with the vector itself."""


@dataclass(frozen=True)
class BallParams:
    """A beach ball (a thin PVC shell) or, with ``solid=True``, a solid ball.

    A shell's mass grows with its area, ``4 pi r^2 * shell_areal_density`` (seed §4: "the
    mass is the square of the radius, which is correct for a beach ball"); a solid ball's
    with its volume. Defaults: a sturdy 40 cm vinyl beach ball of 250 g (terminal speed
    8.3 m/s; a light 100 g one falls at 5.3 m/s and cannot be thrown much past 5 m).

    Derived on construction (attributes, not fields): ``mass_kg``, ``inertia_kgm2`` (about
    a diameter: thin shell ``2/3 m r^2``, solid ``2/5 m r^2``, §5) and ``area_m2`` (the
    cross-section ``pi r^2``).
    """

    radius_m: float = param(0.2, interval(0.02, 2.0))
    """Accepted [0.02, 2] m: from a table-tennis ball to a 4 m inflatable giant."""
    shell_areal_density_kgm2: float = param(0.5, interval(0.02, 5.0))
    """Thick vinyl (about 0.35 mm at 1.4 g/cm^3) plus seams and valve. Accepted
    [0.02, 5] kg/m^2: from a toy balloon's film (~0.03) to a thick rubber shell."""
    solid: bool = param(False)
    """A solid ball (mass ~ r^3, ``I = 2/5 m r^2``) instead of a thin shell. A bool."""
    density_kgm3: float = param(1500.0, interval(10.0, 20000.0))
    """Density of a solid ball (a bowling ball: about 1300-1600 kg/m^3); used if ``solid``.
    Accepted [10, 20000] kg/m^3: from expanded polystyrene to tungsten."""
    drag_coefficient: float = param(0.47, interval(0.0, 2.0))
    """Sphere in laminar flow (seed §8 table: 0.4-0.47). Accepted [0, 2]: 0 is a vacuum
    (the analytic parabola); no sphere-like body has more than ~1.2."""
    lift_coefficient_max: float = param(0.35, interval(0.0, 1.0))
    """Saturation of the Magnus lift coefficient: ``C_L = C_max tanh(S / C_max)``, so
    ``C_L ~ S = r omega / v`` for slow spin (seed §8) and levels off near 0.3-0.4 for
    ``S >~ 0.5``, as measured for spinning smooth spheres and sports balls (Nathan 2008,
    Am. J. Phys. 76:119; Sawicki, Hubbard & Stronge 2003, Am. J. Phys. 71:1152).
    Accepted [0, 1]: 0 turns the Magnus force off; no measured sphere passes ~0.6."""
    spin_decay_s: float = param(2.5, interval(0.01, 1000.0))
    """Time constant of the spin's exponential decay by air friction. A light ball with a
    large surface loses its spin in seconds (a golf ball keeps it for ~20 s). Accepted
    [0.01, 1000] s (integrated exactly, so any of it is stable)."""
    restitution: float = param(0.75, interval(0.0, 1.0))
    """Ground bounce: rebound speed / impact speed; the rebound height ratio is its square.
    Accepted [0, 1]: 0 plastic (no bounce), 1 elastic (seed §4)."""
    friction: float = param(0.6, interval(0.0, 2.0))
    """Coulomb friction coefficient between ball and ground (seed §6). Accepted [0, 2]:
    0 is ice, rubber on concrete is ~0.8-1, and the seed's anecdote reaches 1.1."""
    rolling_resistance: float = param(0.1, interval(0.0, 1.0))
    """Rolling resistance coefficient on grass: deceleration ``c g`` while rolling (a ball
    on a hard floor ~0.01, on grass ~0.1, in sand ~0.3). Accepted [0, 1]."""
    rest_speed_mps: float = param(0.3, interval(0.0, 5.0))
    """Impacts slower than this do not bounce: the ball stays on the ground and rolls.
    Accepted [0, 5] m/s (0: every impact bounces, as an elastic ball must)."""
    rolling_stop: bool = param(False)
    """The zero-crossing rule for rolling (seed §6, the sliding block's check): a ball in
    resting contact whose rolling velocity the step's rolling resistance would carry
    through zero stops, speed and horizontal spin exactly 0 (where friction can hold it).
    Off (the default, every env version to date): the resistance only zeroes the spin and
    friction spins the ball up again at 3/5 (shell) or 5/7 (solid) of its speed, a
    geometric decay that never reaches 0. A bool."""

    def __post_init__(self) -> None:
        check_fields(self)
        # Derived constants, computed once here rather than on first read: the physics
        # reads them every substep, and a lazily cached attribute would be filled while
        # torch.compile traces a step (a graph break). Not fields: equality, hashing, repr
        # and dataclasses.replace see the parameters only.
        r = self.radius_m
        if self.solid:
            mass_kg = self.density_kgm3 * 4.0 / 3.0 * math.pi * r**3
        else:
            mass_kg = self.shell_areal_density_kgm2 * 4.0 * math.pi * r**2
        derived = {
            "mass_kg": mass_kg,
            # About a diameter: thin shell 2/3 m r^2, solid 2/5 m r^2 (§5).
            "inertia_kgm2": (0.4 if self.solid else 2.0 / 3.0) * mass_kg * r**2,
            "area_m2": math.pi * r**2,
        }
        for name, value in derived.items():
            object.__setattr__(self, name, value)

    def terminal_speed_mps(self) -> float:
        """``sqrt(2 m g / (rho C_d A))``: where drag balances gravity (§8); ``inf`` without
        drag (``C_d = 0``)."""
        drag_per_speed_sq = AIR_DENSITY_KGM3 * self.drag_coefficient * self.area_m2
        if drag_per_speed_sq == 0.0:
            return math.inf
        return math.sqrt(2 * self.mass_kg * GRAVITY_MPS2 / drag_per_speed_sq)


class BallState(NamedTuple):
    """Position, velocity, spin (rad/s, world frame) and orientation (unit quaternion
    ``(qw, qx, qy, qz)``, body to world: it only serves to draw the stripes). Immutable:
    make a changed copy with ``_replace``."""

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
    x: Array,
    y: Array,
    z: Array,
    vx: Array,
    vy: Array,
    vz: Array,
    wx: Array,
    wy: Array,
    wz: Array,
    xp: Any = None,
) -> BallState:
    """A ball at a position with a velocity and spin, in its reference orientation.

    Without ``xp`` the components are taken as they are (Python floats for one ball, arrays
    of one shape for a batch). With an array namespace ``xp`` they may mix Python numbers
    and arrays: all become arrays of ``xp`` of the arrays' common shape and float dtype
    (float64 if all are numbers)."""
    if xp is not None and hasattr(xp, "asarray"):  # the namespace, never array values
        x, y, z, vx, vy, vz, wx, wy, wz = _as_arrays(xp, x, y, z, vx, vy, vz, wx, wy, wz)
    # an array per component (none shared): a compiled step sees the same aliasing on every call
    return BallState(x, y, z, vx, vy, vz, wx, wy, wz, 1.0 + 0.0 * x, 0.0 * x, 0.0 * x, 0.0 * x)


def ball_released_at(x: Array, y: Array, z: Array, xp: Any = None) -> BallState:
    """A ball let go at a position: :func:`ball_at` with no velocity and no spin.

    Args:
        x: East position (m).
        y: North position (m).
        z: Height of the centre (m).
        xp: The array namespace, as for :func:`ball_at`.

    Returns:
        The ball's state.
    """
    return ball_at(x, y, z, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, xp)


def _as_arrays(xp: Any, *values: Any) -> list:
    """``values`` as arrays of ``xp`` broadcast to one shape, in the first array's float
    dtype (numbers keep their exact value: no arithmetic touches them)."""
    arrays = [v for v in values if not isinstance(v, (int, float))]
    dtype = arrays[0].dtype if arrays else xp.float64
    converted = [xp.asarray(v, dtype=dtype) for v in values]
    return list(xp.broadcast_arrays(*converted))


def magnus_force(
    p: BallParams,
    rel_x: Array,
    rel_y: Array,
    rel_z: Array,
    wx: Array,
    wy: Array,
    wz: Array,
    xp: Any = np,
) -> tuple[Array, Array, Array, Array]:
    """Magnus force ``1/2 rho A C_L |v|^2`` along ``omega x v`` (seed §8).

    ``rel`` is the ball's velocity relative to the air. ``C_L`` grows like the spin
    parameter ``S = r |omega| / |v|`` and saturates at ``lift_coefficient_max``; for slow
    spin the force is the seed's ``k (omega x v)`` with ``k = 1/2 rho A r``. Only the spin
    component perpendicular to the flight acts (``|omega x v| = |omega| |v| sin``).
    Returns ``(Fx, Fy, Fz, S)``.
    """
    speed = xp.sqrt(rel_x * rel_x + rel_y * rel_y + rel_z * rel_z)
    spin = xp.sqrt(wx * wx + wy * wy + wz * wz)
    k, spin_parameter = magnus_coefficient(p, speed, spin, xp)
    return (
        k * (wy * rel_z - wz * rel_y),
        k * (wz * rel_x - wx * rel_z),
        k * (wx * rel_y - wy * rel_x),
        spin_parameter,
    )


def magnus_coefficient(
    p: BallParams, speed_mps: Array, spin_radps: Array, xp: Any = np
) -> tuple[Array, Array]:
    """``(k, S)`` with the Magnus force ``F_M = k (omega x v)`` (N per (rad/s * m/s)), seed §8.

    ``F_M = 1/2 rho A C_L |v|^2`` along ``omega x v`` makes ``k = 1/2 rho A C_L |v| / |omega|``;
    with ``C_L = C_max tanh(S / C_max)`` and ``S = r |omega| / |v|`` it tends to the seed's
    ``1/2 rho A r`` for slow spin, and to 0 with the speed. ``C_max = 0`` means no lift.
    """
    spin_parameter = p.radius_m * spin_radps / xp.maximum(speed_mps, TINY)
    if p.lift_coefficient_max > 0.0:  # tanh(S / C_max) has no limit at C_max = 0
        # tanh is 1.0 in float64 past 20: capping its argument there changes nothing and
        # keeps S / C_max from overflowing (a ball at rest in the air has S ~ r omega / 1e-12).
        capped = xp.minimum(spin_parameter, 20.0 * p.lift_coefficient_max)
        lift = p.lift_coefficient_max * xp.tanh(capped / p.lift_coefficient_max)
    else:
        lift = 0.0 * spin_parameter
    k = 0.5 * AIR_DENSITY_KGM3 * p.area_m2 * lift * speed_mps / xp.maximum(spin_radps, TINY)
    return k, spin_parameter


def drag_rate_per_s(p: BallParams, speed_mps: Array) -> Array:
    """Quadratic drag ``F = -1/2 rho C_d A |u| u`` against the air-relative velocity ``u``
    (seed §8), written as the damping rate ``c`` (1/s) of ``F = -m c u``:
    ``c = rho C_d A |u| / (2 m)``. The rate is what the implicit step needs."""
    drag_area_m2 = p.drag_coefficient * p.area_m2
    return quadratic_drag_rate(drag_area_m2, AIR_DENSITY_KGM3, speed_mps) / p.mass_kg


def air_force(
    p: BallParams, s: BallState, wind_x: Array, wind_y: Array, xp: Any = np
) -> tuple[Array, Array, Array]:
    """Gravity, drag against ``v - wind`` and Magnus force, summed (N), at the state ``s``
    (:func:`substep` integrates the same forces, drag and Magnus implicitly)."""
    rel_x, rel_y, rel_z = s.vx - wind_x, s.vy - wind_y, s.vz
    speed = xp.sqrt(rel_x * rel_x + rel_y * rel_y + rel_z * rel_z)
    mc = p.mass_kg * drag_rate_per_s(p, speed)
    mag_x, mag_y, mag_z, _ = magnus_force(p, rel_x, rel_y, rel_z, s.wx, s.wy, s.wz, xp)
    return (
        mag_x - mc * rel_x,
        mag_y - mc * rel_y,
        mag_z - mc * rel_z - p.mass_kg * GRAVITY_MPS2,
    )


def _implicit_velocity(
    alpha: Array, bx: Array, by: Array, bz: Array, tx: Array, ty: Array, tz: Array
) -> tuple[Array, Array, Array]:
    """Solve ``alpha u - t x u = b`` for ``u``: the linearly implicit (backward Euler) step of
    ``du/dt = a - c u + Omega x u`` with the rates frozen at the start of the step,
    ``alpha = 1 + dt c``, ``t = dt Omega``, ``b = u0 + dt a``. In closed form,
    ``(alpha I - [t]x)^-1 = (alpha^2 I + alpha [t]x + t t^T) / (alpha (alpha^2 + |t|^2))``.

    Damping (``c >= 0``) then never overshoots and a turn (``Omega``, the Magnus force)
    never grows ``|u|``, whatever ``dt c`` and ``dt |Omega|``: the step is stable for every
    accepted ball (a light, large one has ``dt c > 2``, where explicit Euler diverges).
    """
    cross_x, cross_y, cross_z = ty * bz - tz * by, tz * bx - tx * bz, tx * by - ty * bx
    along = tx * bx + ty * by + tz * bz
    inv = 1.0 / (alpha * (alpha * alpha + tx * tx + ty * ty + tz * tz))  # >= 1: alpha >= 1
    return (
        (alpha * alpha * bx + alpha * cross_x + along * tx) * inv,
        (alpha * alpha * by + alpha * cross_y + along * ty) * inv,
        (alpha * alpha * bz + alpha * cross_z + along * tz) * inv,
    )


def ground_contact(
    p: BallParams, s: BallState, dt_s: float, xp: Any = np
) -> tuple[BallState, Array]:
    """Bounce on the ground ``z = 0``, slide, roll: every change an impulse (seed §3-§6).

    * Normal (:func:`_normal_impulse`): the impact speed reverses times ``restitution``
      (rebound height ``e^2``, seed §3); impacts slower than ``rest_speed_mps`` do not
      bounce (resting contact: the impulse is the one that holds the ball up, cancelling the
      downward velocity gravity and air gave it this substep, ``~ m g dt``). The ball is put
      back on the ground (seed §3: moving it up as much as it sank in, times ``e``).
    * Tangential (:func:`friction_impulse`): Coulomb friction (seed §6), at most
      ``friction * J_n``, brakes the contact point's slip toward the rolling condition
      ``v = omega x r`` (seed §5, "Kinematic rotations"), but by impulses: the slip stops
      exactly at zero (the sliding block's zero crossing, §6) and the angular momentum about
      the contact point is kept. A ball sliding without spin rolls on at ``1 / (1 + I / m
      r^2)`` of its speed (3/5 for a thin shell, 5/7 for a solid ball); one with backspin
      ``omega r > (m r^2 / I) v`` (3/2 v for a shell, 5/2 v for a solid ball) comes back
      (a little more with rolling resistance, whose couple also brakes the backspin);
      topspin kicks it forward.
    * Rolling resistance (:func:`rolling_resistance`), a couple against the
      spin, slows a rolling ball by ``c J_n / m`` (``c g dt`` on flat ground), never
      reversing it; friction keeps it rolling. With ``rolling_stop`` a ball whose rolling
      velocity would cross zero in the step stops there (the zero crossing, §6).

    No step adds kinetic energy (translational plus rotational). ``dt_s`` is not needed:
    the normal impulse carries the substep's length. Returns the new state and whether the
    ball touched the ground in this substep.
    """
    near = s.z <= p.radius_m
    if skippable(near):  # every ball in the air: no impulse
        return s, near
    touching, bounce, normal_impulse, z, vz = _normal_impulse(p, s, xp)
    # A bounce is over in an instant: rolling resistance acts in resting contact only. It
    # goes first, so that friction (if it can) leaves the ball rolling at the end.
    resting = touching & xp.logical_not(bounce)
    vx, vy, wx, wy = rolling_resistance(
        p, s.vx, s.vy, s.wx, s.wy, xp.where(resting, normal_impulse, 0.0), xp
    )
    slip_x, slip_y = contact_slip(p, vx, vy, wx, wy)
    jx, jy = friction_impulse(p, slip_x, slip_y, normal_impulse, xp)
    vx, vy, wx, wy = _apply_contact_impulse(p, vx, vy, wx, wy, jx, jy)
    # A ball in the air keeps its values exactly (zero impulses could flip a zero's sign).
    vx, vy = xp.where(near, vx, s.vx), xp.where(near, vy, s.vy)
    wx, wy = xp.where(near, wx, s.wx), xp.where(near, wy, s.wy)
    new = BallState(s.x, s.y, z, vx, vy, vz, wx, wy, s.wz, s.qw, s.qx, s.qy, s.qz)
    return new, touching


def _normal_impulse(p: BallParams, s: BallState, xp: Any) -> tuple:
    """``(touching, bounce, J_n, z, vz)``: the ground's normal impulse (N s) on a ball at or
    into the ground moving down, with restitution ``e`` above ``rest_speed_mps`` (seed §3,
    §4 with the ground's infinite mass: ``J_n = -(1 + e) m v_z``) and ``e = 0`` below it."""
    r, m = p.radius_m, p.mass_kg
    touching = (s.z <= r) & (s.vz <= 0.0)
    bounce = touching & (-s.vz > p.rest_speed_mps)
    e = xp.where(bounce, p.restitution, xp.zeros_like(s.vz))
    normal_impulse = xp.where(touching, -(1.0 + e) * m * s.vz, 0.0)
    vz = xp.where(touching, -e * s.vz, s.vz)
    z = xp.where(s.z <= r, r + e * (r - s.z), s.z)
    return touching, bounce, normal_impulse, z, vz


def contact_slip(p: BallParams, vx: Array, vy: Array, wx: Array, wy: Array) -> tuple[Array, Array]:
    """Velocity of the ball's lowest point, ``v + omega x (0, 0, -r)`` (m/s): zero when it
    rolls (seed §5, "Kinematic rotations")."""
    return vx - p.radius_m * wy, vy + p.radius_m * wx


def rolling_velocity(
    p: BallParams, vx: Array, vy: Array, wx: Array, wy: Array
) -> tuple[Array, Array]:
    """The velocity ``u`` (m/s) the ball rolls at once friction has stopped its slip: the
    angular momentum about the contact point, ``L = I omega + m r z x v``, is kept by
    friction, and a rolling ball has ``|L| = (m r + I / r) |u|``, so
    ``u = (m r^2 v + I r (omega_y, -omega_x)) / (m r^2 + I)`` (seed §5, §6)."""
    r, m, inertia = p.radius_m, p.mass_kg, p.inertia_kgm2
    share = inertia / (m * r * r + inertia)
    return (1.0 - share) * vx + share * r * wy, (1.0 - share) * vy - share * r * wx


def friction_impulse(
    p: BallParams, slip_x: Array, slip_y: Array, normal_impulse: Array, xp: Any = np
) -> tuple[Array, Array]:
    """Coulomb friction on the contact point (seed §6) as an impulse ``J`` (N s): against
    the slip, at most ``friction * J_n``, and never more than the impulse that stops the slip,
    ``|slip| / (1/m + r^2/I)`` (the effective mass of the contact point): the slip stops
    exactly at zero and never reverses (the sliding block's zero-crossing check, §6)."""
    r, m, inertia = p.radius_m, p.mass_kg, p.inertia_kgm2
    slip = xp.sqrt(slip_x * slip_x + slip_y * slip_y)
    stopping = slip / (1.0 / m + r * r / inertia)
    size = xp.minimum(p.friction * normal_impulse, stopping)
    per_slip = size / xp.maximum(slip, TINY)
    return -per_slip * slip_x, -per_slip * slip_y


def _apply_contact_impulse(
    p: BallParams, vx: Array, vy: Array, wx: Array, wy: Array, jx: Array, jy: Array
) -> tuple[Array, Array, Array, Array]:
    """A horizontal impulse ``J`` at the contact point ``(0, 0, -r)``: ``dv = J / m``,
    ``d omega = (0, 0, -r) x J / I = (r J_y, -r J_x, 0) / I`` (seed §5 "Rotations with physics
    in 3D": ``T = r x F``, ``omega = I^-1 L``). It keeps the angular momentum about the
    contact point."""
    r, m, inertia = p.radius_m, p.mass_kg, p.inertia_kgm2
    return vx + jx / m, vy + jy / m, wx + r * jy / inertia, wy - r * jx / inertia


def rolling_resistance(
    p: BallParams,
    vx: Array,
    vy: Array,
    wx: Array,
    wy: Array,
    normal_impulse: Array,
    xp: Any = np,
) -> tuple[Array, Array, Array, Array]:
    """Rolling resistance (seed §6) as the ground's couple on the flattened contact patch: a
    pure torque (no horizontal force, so the ground's horizontal impulse stays within
    Coulomb's ``friction * J_n``) against the horizontal spin. Its angular impulse
    ``c J_n (r + I / (m r))`` takes ``c J_n / m`` off the rolling velocity of
    :func:`rolling_velocity` (deceleration ``c g`` of a rolling ball on flat ground, kept
    rolling by friction while ``c <= friction``); it never reverses the spin.

    With ``rolling_stop`` (the zero-crossing rule of the sliding block, §6): where the
    rolling velocity is within ``c J_n / m`` of zero, so that the couple would carry it
    through zero in this step, and the ground's friction can take the ball's momentum
    (``m |v| <= friction * J_n``), the ball stops: velocity and horizontal spin exactly 0.
    Without it the couple only zeroes the spin there, and friction spins the ball up again
    at the rolling share of its speed: the speed shrinks geometrically, never to 0.

    Returns the new ``(v_x, v_y, omega_x, omega_y)`` (m/s, rad/s)."""
    m, inertia, r = p.mass_kg, p.inertia_kgm2, p.radius_m
    spin = xp.sqrt(wx * wx + wy * wy)
    slowing = xp.minimum(
        p.rolling_resistance * normal_impulse * (r + inertia / (m * r)) / inertia, spin
    )
    per_spin = slowing / xp.maximum(spin, TINY)
    # the spin's change, then its sum: the arithmetic of every version before rolling_stop
    dwx, dwy = -per_spin * wx, -per_spin * wy
    new_wx, new_wy = wx + dwx, wy + dwy
    if not p.rolling_stop:  # a parameter, not an array value: every version before it
        return vx, vy, new_wx, new_wy
    ux, uy = rolling_velocity(p, vx, vy, wx, wy)
    rolling_speed = xp.sqrt(ux * ux + uy * uy)
    speed = xp.sqrt(vx * vx + vy * vy)
    stops = (
        (normal_impulse > 0.0)
        & (m * rolling_speed <= p.rolling_resistance * normal_impulse)
        & (m * speed <= p.friction * normal_impulse)
    )
    return (
        xp.where(stops, 0.0, vx),
        xp.where(stops, 0.0, vy),
        xp.where(stops, 0.0, new_wx),
        xp.where(stops, 0.0, new_wy),
    )


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
    if skippable(hit):  # no ball touching the panel
        return s, hit
    side = xp.where(offset >= 0.0, 1.0, xp.zeros_like(offset) - 1.0)
    bounced = panel_bounce(
        s, radius_m, normal_x, normal_y, offset, side, approach, restitution, hit, xp
    )
    return bounced, hit


def panel_bounce(
    s: BallState,
    radius_m: float,
    normal_x: Array,
    normal_y: Array,
    offset: Array,
    side: Array,
    approach: Array,
    restitution: float,
    hit: Array,
    xp: Any = np,
) -> BallState:
    """The bounce off a panel where ``hit``: the velocity along the panel's unit normal,
    ``approach``, reverses times ``restitution``, and the ball, ``offset`` along the normal
    from the panel's plane, is put back one radius from it on ``side`` (+1 or -1: the
    side it came from)."""
    change = xp.where(hit, -(1.0 + restitution) * approach, 0.0)
    push = xp.where(hit, side * radius_m - offset, 0.0)
    return BallState(
        s.x + push * normal_x,
        s.y + push * normal_y,
        s.z,
        s.vx + change * normal_x,
        s.vy + change * normal_y,
        s.vz,
        s.wx,
        s.wy,
        s.wz,
        s.qw,
        s.qx,
        s.qy,
        s.qz,
    )


def spin_decay(p: BallParams, elapsed_s: Array, xp: Any = np) -> Array:
    """The factor a ball's spin has decayed by after ``elapsed_s`` in the air,
    ``exp(-t / spin_decay_s)``: air friction's exponential decay, exact over any time."""
    return xp.exp(-elapsed_s / p.spin_decay_s)


def substep(
    p: BallParams, s: BallState, wind_x: Array, wind_y: Array, dt_s: float, xp: Any = np
) -> BallState:
    """One semi-implicit Euler step in the air: velocity first, then position (seed §1, §3).

    The forces are those of :func:`air_force`; gravity is explicit, while drag (damping at
    the rate ``c`` of :func:`drag_rate_per_s`) and the Magnus force (a turn of the relative
    velocity at ``k omega / m``, :func:`magnus_coefficient`) are linearly implicit with their
    coefficients frozen at the start of the step (:func:`_implicit_velocity`): a light,
    large ball's ``dt c`` may exceed 2, where explicit Euler overshoots and diverges. The
    terminal speed is unchanged (``c v = g`` is the fixed point). The spin decays
    exponentially (exact over the step) and turns the orientation quaternion,
    ``dq/dt = 1/2 (0, omega) q``.
    """
    rel_x, rel_y, rel_z = s.vx - wind_x, s.vy - wind_y, s.vz
    speed = xp.sqrt(rel_x * rel_x + rel_y * rel_y + rel_z * rel_z)
    spin = xp.sqrt(s.wx * s.wx + s.wy * s.wy + s.wz * s.wz)
    k, _ = magnus_coefficient(p, speed, spin, xp)
    turn = k * (dt_s / p.mass_kg)  # rad per (rad/s) of spin: dt Omega = turn * omega
    rel_x, rel_y, rel_z = _implicit_velocity(
        1.0 + dt_s * drag_rate_per_s(p, speed),
        rel_x,
        rel_y,
        rel_z - GRAVITY_MPS2 * dt_s,
        turn * s.wx,
        turn * s.wy,
        turn * s.wz,
    )
    vx, vy, vz = rel_x + wind_x, rel_y + wind_y, rel_z
    decay = spin_decay(p, dt_s, math)
    wx, wy, wz = s.wx * decay, s.wy * decay, s.wz * decay
    h = 0.5 * dt_s
    qw = s.qw - h * (wx * s.qx + wy * s.qy + wz * s.qz)
    qx = s.qx + h * (wx * s.qw + wy * s.qz - wz * s.qy)
    qy = s.qy + h * (wy * s.qw + wz * s.qx - wx * s.qz)
    qz = s.qz + h * (wz * s.qw + wx * s.qy - wy * s.qx)
    norm = xp.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    return BallState(
        s.x + vx * dt_s,
        s.y + vy * dt_s,
        s.z + vz * dt_s,
        vx,
        vy,
        vz,
        wx,
        wy,
        wz,
        qw / norm,
        qx / norm,
        qy / norm,
        qz / norm,
    )


def collide_balls(
    m1: float,
    v1: tuple,
    p1: tuple,
    m2: float,
    v2: tuple,
    p2: tuple,
    restitution: float,
    xp: Any = np,
) -> tuple[tuple, tuple]:
    """Two balls touching at positions ``p1``, ``p2`` (3-tuples of components) collide.

    Along the line of centres the seed's restitution formula (§4, after Palmer) gives

    ``u1' = (u1 (m1 - e m2) + (1 + e) u2 m2) / (m1 + m2)``,
    ``u2' = ((1 + e) u1 m1 + u2 (m2 - e m1)) / (m1 + m2)``;

    ``e = 1`` is elastic, ``e = 0`` plastic (common velocity). Across the line of centres
    the velocities are unchanged. Balls moving apart are left alone. Returns ``(v1', v2')``.
    """
    nx, ny, nz = [b - a for a, b in zip(p1, p2, strict=True)]
    # Concentric balls have no line of centres: n = 0 leaves them alone.
    inv_dist = 1.0 / xp.maximum(xp.sqrt(nx * nx + ny * ny + nz * nz), TINY)
    nx, ny, nz = nx * inv_dist, ny * inv_dist, nz * inv_dist
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


REST_SPEED_SQ = 0.01
"""Squared speed (m^2/s^2), and squared rim speed of the horizontal spin, below which a
ball on the ground is at rest (0.1 m/s)."""


def ball_at_rest(p: BallParams, s: BallState, check_spin: bool = True) -> Array:
    """Whether a ball is at rest: on the ground (its centre within 0.1% of a radius of it)
    and slow (``|v| < 0.1 m/s``), and, with ``check_spin``, not spinning about a horizontal
    axis (rim speed ``r |omega_h| < 0.1 m/s``): a ball whose backspin has just stopped it is
    about to come back, so a throw's flight (:func:`simulate_throw`) waits for it.

    BeachballTopple (:mod:`bbgym.physics.toppling`) stops its ball on speed alone
    (``check_spin=False``): that is its rule since v0, and a version never changes
    behaviour (its golden replays pin it).
    """
    speed_sq = s.vx * s.vx + s.vy * s.vy + s.vz * s.vz
    resting = (s.z <= p.radius_m * 1.001) & (speed_sq < REST_SPEED_SQ)
    if not check_spin:
        return resting
    spin_speed_sq = p.radius_m * p.radius_m * (s.wx * s.wx + s.wy * s.wy)
    return resting & (spin_speed_sq < REST_SPEED_SQ)
