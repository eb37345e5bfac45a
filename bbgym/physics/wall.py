"""The falling wall: a panel on a foot, toppled by wind and beach-ball hits (seed §8, §5).

Seed §8, "Buster Keaton": a wall of height ``h`` turns about the bottom edge it tips
over. The wind force on its face, reduced by ``cos(phi)`` as less area faces the wind,
acts at half height (torque ``h/2 F_w cos(phi)``); gravity on the centre of mass rights
it while that is over the foot and overturns it past. The force along the ground at the
edge is held by friction and fixings up to a limit; past it the wall breaks loose and
flies as a free panel, pushed by the wind normal to its face (seed §8, loose panels).

2D in the vertical x-z plane: the thrower is at x = 0, the wall's foot is centred on
``base_x``, its face toward the thrower. ``angle`` (phi) > 0 leans the top away (+x).
Pure functions over :class:`WallParams` and :class:`WallState`, on the array namespace
``xp`` (Python floats, NumPy, ``array_api_strict``, torch: :mod:`bbgym.physics.namespace`),
with the standard's names only, like the rest of the physics. The status code is a float
of the batch's dtype (``STANDING`` ... ``LOOSE`` compare equal to it).

==========================  ============================================================
law                         function
==========================  ============================================================
wind and gravity torques    :func:`wall_torques`
rocking, toppling, landing  :func:`wall_step` (semi-implicit Euler about the pivot edge),
                            :func:`wall_rk4_step` (RK4, Topple-v2); both end in the same
                            events (:func:`_wall_events`)
breaking loose              :func:`_edge_shear` against ``hold_n`` (:func:`_wall_events`)
loose panel flight          :func:`loose_step`
ball hits                   :func:`ball_hits_wall` (restitution formula of §4, ``r x J``;
                            the face's place: :func:`face_frame`)
==========================  ============================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2
from bbgym.physics.namespace import Array, namespace_of, skippable
from bbgym.physics.validation import check_at_least, check_fields, interval, param

STANDING, FALLEN_AWAY, FALLEN_TOWARD, LOOSE = 0, 1, 2, 3
STATE_NAMES = ("standing", "fallen_away", "fallen_toward", "loose")
HOLD_FLOOR_N = 1e-3
"""What the stress of a foot that holds nothing (no friction, no pegs) is measured against:
it breaks loose at the first shear, and its stress reads that shear per mN, finite."""


@dataclass(frozen=True)
class WallParams:
    """A light stage-set panel on a foot (defaults: 2.4 m x 0.7 m, 8 kg, foot 0.4 m deep:
    the wind alone tips it at 3.3 m/s and tears it loose at 11 m/s).

    Every field's accepted interval is in its docstring (checked on construction, errors
    naming ``WallParams.<field>``); the model stops meaning anything past them (a wall of
    more than 20 m is no stage-set panel, nor one of more than a tonne)."""

    height_m: float = param(2.4, interval(0.2, 20.0))
    """Accepted [0.2, 20] m."""
    width_m: float = param(0.7, interval(0.1, 20.0))
    """Accepted [0.1, 20] m."""
    thickness_m: float = param(0.03, interval(1e-4, 0.5))
    """Accepted [0.0001, 0.5] m, and at most ``base_depth_m``."""
    base_depth_m: float = param(0.4, interval(1e-4, 5.0))
    """Depth of the foot along x; the panel stands in its middle and tips about its edges.
    Accepted [0.0001, 5] m, and at least ``thickness_m``."""
    mass_kg: float = param(8.0, interval(0.1, 1000.0))
    """Accepted [0.1, 1000] kg: from a sheet of card to a tonne of timber."""
    drag_coefficient: float = param(1.2, interval(0.0, 2.0))
    """Flat plate facing the wind (seed §8: about 1.1 for a flat surface). Accepted [0, 2]
    (0: no wind force)."""
    base_friction: float = param(0.6, interval(0.0, 2.0))
    """Coulomb friction coefficient between the foot (or a loose panel) and the ground
    (seed §6). Accepted [0, 2]."""
    anchor_n: float = param(100.0, interval(0.0, 1e5))
    """What the foot's pegs hold beyond friction. Accepted [0, 100000] N."""
    ball_restitution: float = param(0.6, interval(0.0, 1.0))
    """Ball on the wall's face (seed §4: 0 plastic, 1 elastic). Accepted [0, 1]."""

    def __post_init__(self) -> None:
        check_fields(self)
        check_at_least(self, "base_depth_m", "thickness_m")

    @property
    def half_base_m(self) -> float:
        return 0.5 * self.base_depth_m

    @property
    def area_m2(self) -> float:
        return self.height_m * self.width_m

    @property
    def face_drag_kg_m(self) -> float:
        """``1/2 rho C_d A`` of the face: the wind's force on it per squared normal speed,
        the quadratic drag of :func:`~bbgym.physics.common.quadratic_drag_rate` (seed §8)
        per unit speed. Every drag on the face goes through here (written in the product
        order the wall always used, so the v0 replays keep their bits)."""
        return 0.5 * AIR_DENSITY_KGM3 * self.drag_coefficient * self.area_m2

    @property
    def inertia_kgm2(self) -> float:
        """About the foot's edge: the slab's own ``m (h^2 + t^2) / 12`` plus ``m d^2``
        (parallel axes, ``d`` from the edge to the centre of mass). A thin slab standing
        on its own edge gives the seed's rod about its end, ``m h^2 / 3`` (§5)."""
        h, t, b, m = self.height_m, self.thickness_m, self.half_base_m, self.mass_kg
        return m * (h * h + t * t) / 12.0 + m * (h * h / 4.0 + b * b)

    @property
    def hold_n(self) -> float:
        """Largest force along the ground the foot's edge takes before breaking loose."""
        return self.base_friction * self.mass_kg * GRAVITY_MPS2 + self.anchor_n

    def wind_force_n(self, wind_speed_mps: float) -> float:
        """Drag on the upright face, ``1/2 rho C_d A u^2`` (seed §8)."""
        return self.face_drag_kg_m * wind_speed_mps**2

    def tipping_wind_speed_mps(self) -> float:
        """Wind normal to the face that just tips the upright wall over its foot's edge:
        ``h/2 F_w = m g b`` (``inf`` without drag)."""
        k = self.face_drag_kg_m
        if k == 0.0:
            return math.inf
        return math.sqrt(self.mass_kg * GRAVITY_MPS2 * self.half_base_m / (0.5 * self.height_m * k))

    def breakaway_wind_speed_mps(self) -> float:
        """Wind whose force on the upright face exceeds what the foot holds, ``F_w = hold_n``
        (``inf`` without drag)."""
        k = self.face_drag_kg_m
        if k == 0.0:
            return math.inf
        return math.sqrt(self.hold_n / k)


class WallState(NamedTuple):
    """Per wall: lean and rate about the pivot edge, which edge (+1 far, -1 near, 0 resting
    on the foot), status code (:data:`STATE_NAMES`, as a float), the foot's position, the
    largest edge shear as a fraction of what holds it, the loose panel's centre, angle,
    velocity, and whether it has landed (bool). Immutable: ``_replace`` makes a new one."""

    angle: Array
    rate: Array
    pivot: Array
    status: Array
    base_x: Array
    stress: Array
    loose_x: Array
    loose_z: Array
    loose_angle: Array
    loose_vx: Array
    loose_vz: Array
    loose_rate: Array
    landed: Array


def wall_at(base_x: Array, xp: Any = None) -> WallState:
    """An upright wall resting on its foot at ``base_x`` (``xp``: NumPy for a NumPy array,
    else :data:`~bbgym.physics.namespace.floats`, unless given)."""
    xp = namespace_of(base_x) if xp is None else xp
    zero = 0.0 * base_x
    return WallState(
        zero,
        zero,
        zero,
        zero + float(STANDING),
        base_x,
        zero,
        zero,
        zero,
        zero,
        zero,
        zero,
        zero,
        xp.zeros_like(base_x, dtype=xp.bool),
    )


def _lever(p: WallParams, angle: Array, side: Array, xp: Any) -> tuple[Array, Array]:
    """Centre of mass relative to the pivot edge: the foot's edge is ``side * b`` from the
    panel, the centre is ``h/2`` up it; rotated by the lean."""
    return _lever_at(p, xp.cos(angle), xp.sin(angle), side)


def _lever_at(p: WallParams, c: Array, s: Array, side: Array) -> tuple[Array, Array]:
    """:func:`_lever` from the lean's cosine and sine (each computed once a stage)."""
    b, half_h = p.half_base_m, 0.5 * p.height_m
    return -side * b * c + half_h * s, side * b * s + half_h * c


def wall_torques(p: WallParams, angle: Array, side: Array, wind_x: Array, xp: Any = np) -> tuple:
    """``(wind torque, gravity torque, face force)`` about the pivot edge on ``side``.

    The face force is the drag of the wind component along +x on the area facing it,
    ``F_w cos(phi)``, at half height: torque ``h/2 F_w cos(phi)`` (seed §8). Gravity acts
    at the centre of mass: its torque ``m g x_cm`` rights the wall while the centre is
    over the foot and overturns it past.
    """
    return _torques_at(p, xp.cos(angle), xp.sin(angle), side, wind_x, xp)


def _torques_at(p: WallParams, c: Array, s: Array, side: Array, wind_x: Array, xp: Any) -> tuple:
    """:func:`wall_torques` from the lean's cosine and sine."""
    face = p.face_drag_kg_m * wind_x * xp.abs(wind_x) * c
    x_cm, _ = _lever_at(p, c, s, side)
    return 0.5 * p.height_m * face, p.mass_kg * GRAVITY_MPS2 * x_cm, face


def _tipping_pivot(p: WallParams, s: WallState, standing: Array, wind_x: Array, xp: Any) -> Array:
    """The edge the wall turns about: a wall resting on its foot starts to tip only when
    the wind's torque beats the righting moment of its weight about an edge, ``m g b``."""
    limit = p.mass_kg * GRAVITY_MPS2 * p.half_base_m
    # The wind's torque on the upright wall: wall_torques' at phi = 0, its cos exactly 1.
    tau_rest, _, _ = _torques_at(p, 1.0, 0.0, 0.0, wind_x, xp)
    start = (s.pivot == 0) & standing
    pivot = xp.where(start & (tau_rest > limit), 1.0, s.pivot)
    return xp.where(start & (tau_rest < -limit), -1.0, pivot)


def _angular_acceleration(
    p: WallParams, c: Array, sn: Array, pivot: Array, wind_x: Array, xp: Any
) -> tuple[Array, Array]:
    """``(angular acceleration, face force)`` of a wall leaning by the angle of cosine
    ``c`` and sine ``sn`` about the edge ``pivot`` (none on its foot, ``pivot == 0``)."""
    tau_wind, tau_gravity, face = _torques_at(p, c, sn, pivot, wind_x, xp)
    return xp.where(pivot == 0, 0.0, (tau_wind + tau_gravity) / p.inertia_kgm2), face


def _edge_shear(
    p: WallParams,
    c: Array,
    sn: Array,
    rate: Array,
    acc: Array,
    pivot: Array,
    face: Array,
    xp: Any,
) -> Array:
    """The force along the ground the pivot edge must give to hold the wall from sliding:
    ``m a_cm`` minus the face force's horizontal part (the lean's cosine ``c``, sine
    ``sn``)."""
    b, half_h = p.half_base_m, 0.5 * p.height_m
    a_cm_x = (pivot * b * sn + half_h * c) * acc + (pivot * b * c - half_h * sn) * rate * rate
    return xp.abs(p.mass_kg * a_cm_x - face * c)


def wall_step(p: WallParams, s: WallState, wind_x: Array, dt_s: float, xp: Any = np) -> WallState:
    """Advance a wall by ``dt_s`` in one semi-implicit Euler step: standing walls rock or
    topple, loose panels fly."""
    standing = s.status == STANDING
    pivot = _tipping_pivot(p, s, standing, wind_x, xp)
    c, sn = xp.cos(s.angle), xp.sin(s.angle)
    acc, face = _angular_acceleration(p, c, sn, pivot, wind_x, xp)
    rate = s.rate + acc * dt_s
    angle = s.angle + rate * dt_s
    shear = _edge_shear(p, c, sn, s.rate, acc, pivot, face, xp)
    return _wall_events(p, s, standing, pivot, angle, rate, shear, wind_x, dt_s, xp)


def wall_rk4_step(
    p: WallParams, s: WallState, wind_x: Array, dt_s: Array, xp: Any = np, fly_loose: bool = True
) -> WallState:
    """Advance a wall by ``dt_s`` (a float, or an array of one step per wall) in one
    classical Runge-Kutta step of its rocking, ``phi'' = tau(phi) / I`` about the edge
    chosen at the step's start; the events after it as :func:`wall_step`'s. The edge's
    shear is the largest of the four stages'. Without ``fly_loose`` a loose panel stays
    where it is (a caller whose step has no time for it)."""
    standing = s.status == STANDING
    pivot = _tipping_pivot(p, s, standing, wind_x, xp)
    half = 0.5 * dt_s
    angle, rate = s.angle, s.rate
    rates, accs, shear = [], [], None
    # On the host, with no wall of the batch turning (all on their feet: no rate, no
    # torque), the later stages repeat the first: it stands for them (the same values).
    stages = 1 if skippable(pivot != 0) else 4
    for k in range(stages):
        if k:  # the stage's point: from the start along the previous stage's rates
            step = half if k < 3 else dt_s
            angle, rate = s.angle + step * rates[-1], s.rate + step * accs[-1]
        c, sn = xp.cos(angle), xp.sin(angle)
        acc, face = _angular_acceleration(p, c, sn, pivot, wind_x, xp)
        stage_shear = _edge_shear(p, c, sn, rate, acc, pivot, face, xp)
        shear = stage_shear if shear is None else xp.maximum(shear, stage_shear)
        rates.append(rate)
        accs.append(acc)
    rates, accs = rates * (4 // stages), accs * (4 // stages)
    sixth = dt_s / 6.0
    new_angle = s.angle + sixth * (rates[0] + 2.0 * (rates[1] + rates[2]) + rates[3])
    new_rate = s.rate + sixth * (accs[0] + 2.0 * (accs[1] + accs[2]) + accs[3])
    return _wall_events(
        p, s, standing, pivot, new_angle, new_rate, shear, wind_x, dt_s, xp, fly_loose
    )


def _wall_events(
    p: WallParams,
    s: WallState,
    standing: Array,
    pivot: Array,
    angle: Array,
    rate: Array,
    shear: Array,
    wind_x: Array,
    dt_s: Array,
    xp: Any,
    fly_loose: bool = True,
) -> WallState:
    """What follows a step of the rocking from ``s`` to ``(angle, rate)``: breaking loose
    (``shear`` past ``hold_n``: the panel leaves with the motion it had at the step's
    start), landing back on the foot (plastic) or flat on the ground, and a loose panel's
    flight over the step."""
    b = p.half_base_m
    breaks = standing & (shear > p.hold_n)

    # Back onto the foot (a plastic landing), or down flat on the ground.
    back = (pivot != 0) & (angle * pivot < 0.0)
    angle, rate = xp.where(back, 0.0, angle), xp.where(back, 0.0, rate)
    pivot = xp.where(back, 0.0, pivot)
    away, toward = angle >= 0.5 * math.pi, angle <= -0.5 * math.pi
    status = xp.where(standing & away, float(FALLEN_AWAY), s.status)
    status = xp.where(standing & toward, float(FALLEN_TOWARD), status)
    angle = xp.clip(angle, -0.5 * math.pi, 0.5 * math.pi)
    rate = xp.where(away | toward, 0.0, rate)

    # Breaking loose: the panel leaves with the motion it had.
    loose = (s.loose_x, s.loose_z, s.loose_angle, s.loose_vx, s.loose_vz, s.loose_rate)
    if not skippable(breaks):
        x_rel, z_rel = _lever(p, s.angle, pivot, xp)
        pivot_x = s.base_x + pivot * b
        status = xp.where(breaks, float(LOOSE), status)
        leaving = (pivot_x + x_rel, z_rel, s.angle, s.rate * z_rel, -s.rate * x_rel, s.rate)
        loose = _freeze_select(breaks, leaving, loose, xp)
    flying = (s.status == LOOSE) & xp.logical_not(s.landed)
    landed = s.landed
    if fly_loose and not skippable(flying):
        flown = loose_step(p, *loose, wind_x, dt_s, xp)
        loose = _freeze_select(flying, flown[:6], loose, xp)
        landed = landed | (flying & flown[6])

    keep = xp.logical_not(standing)
    stress = xp.maximum(s.stress, xp.where(standing, shear / max(p.hold_n, HOLD_FLOOR_N), 0.0))
    return WallState(
        xp.where(keep, s.angle, angle),
        xp.where(keep, s.rate, rate),
        xp.where(keep, s.pivot, pivot),
        status,
        s.base_x,
        stress,
        *loose,
        landed,
    )


def _freeze_select(mask: Array, new: tuple, old: tuple, xp: Any) -> tuple:
    return tuple(xp.where(mask, a, b) for a, b in zip(new, old, strict=True))


def loose_step(
    p: WallParams,
    x: Array,
    z: Array,
    angle: Array,
    vx: Array,
    vz: Array,
    rate: Array,
    wind_x: Array,
    dt_s: float,
    xp: Any = np,
) -> tuple:
    """A free panel in the wind (seed §8): the air pushes it along its face normal, in
    proportion to the area seen by the relative wind, ``-1/2 rho C_d A w_n |w_n| n``;
    gravity pulls it down; air damps its tumbling. On the ground it rests on its lower end,
    slides with friction and tips over that end. Returns the new ``(x, z, angle, vx, vz,
    rate, landed)``; it has landed when it lies (nearly) flat.

    Both air terms are quadratic dampers, stiff for a light, large panel (``dt c`` far above
    2: explicit Euler would flip and grow the velocity until ``cos`` of an infinite angle
    fails): they are linearly implicit, ``u_new = (u + dt a_other) / (1 + dt c)`` with the
    rate ``c >= 0`` taken at the start of the step, so they slow the panel and never
    reverse it, at any step."""
    nx, nz = xp.cos(angle), -xp.sin(angle)
    w_n = (vx - wind_x) * nx + vz * nz
    # Face drag -1/2 rho C_d A w_n |w_n| n = -m c w_n n, implicit along n; gravity explicit.
    c_face = p.face_drag_kg_m / p.mass_kg * xp.abs(w_n)
    vz = vz - GRAVITY_MPS2 * dt_s
    w_n_free = (vx - wind_x) * nx + vz * nz
    braked = w_n_free / (1.0 + dt_s * c_face) - w_n_free
    vx, vz = vx + braked * nx, vz + braked * nz
    # Drag on a plate spinning about its centre: 2 * int_0^{h/2} 1/2 rho C_d w (w r)^2 r dr,
    # a torque -tumble * rate |rate|, implicit as above.
    half = 0.5 * p.height_m
    tumble = 0.25 * AIR_DENSITY_KGM3 * p.drag_coefficient * p.width_m * half**4
    inertia_cm = p.mass_kg * (p.height_m**2 + p.thickness_m**2) / 12.0
    rate = rate / (1.0 + dt_s * tumble / inertia_cm * xp.abs(rate))
    x, z, angle = x + vx * dt_s, z + vz * dt_s, angle + rate * dt_s
    # On the ground the panel stands on its lower end: the ground holds it up, friction
    # drags its foot, and its weight tips it over that end until it lies flat.
    ca, sa = xp.cos(angle), xp.sin(angle)
    lowest = z - half * xp.abs(ca) - 0.5 * p.thickness_m * xp.abs(sa)
    touching = lowest <= 0.0
    z = xp.where(touching, z - lowest, z)
    vz = xp.where(touching & (vz < 0.0), 0.0, vz)
    friction = p.base_friction * p.mass_kg * GRAVITY_MPS2
    sliding = xp.maximum(xp.abs(vx) - friction / p.mass_kg * dt_s, 0.0)
    drag_foot = xp.where(touching & (vx != 0.0), -xp.sign(vx) * friction, 0.0)
    vx = xp.where(touching, xp.sign(vx) * sliding, vx)
    lever = half * sa * xp.sign(ca)  # centre of mass beyond the lower end, along x
    inertia_end = inertia_cm + p.mass_kg * half * half
    # Weight about the lower end, and the friction dragging that end (half below the
    # centre): a panel pushed along the ground trips over its foot.
    tip = (
        p.mass_kg * GRAVITY_MPS2 * lever / inertia_end - drag_foot * half * xp.abs(ca) / inertia_cm
    )
    rate = xp.where(touching, rate + tip * dt_s, rate)
    landed = touching & (xp.abs(sa) >= math.sin(0.45 * math.pi))
    zero = 0.0 * x
    flat = xp.where(sa >= 0.0, zero + 0.5 * math.pi, -0.5 * math.pi)
    return (
        x,
        xp.where(landed, zero + 0.5 * p.thickness_m, z),
        xp.where(landed, flat, angle),
        xp.where(landed, zero, vx),
        xp.where(landed, zero, vz),
        xp.where(landed, zero, rate),
        landed,
    )


def face_frame(p: WallParams, s: WallState, xp: Any = np) -> tuple:
    """Where the panel is: ``(side, cos, sin, pivot_x, foot_x, foot_z)``, the edge it
    turns about (+1 far, -1 near; a wall on its foot is pushed about its far edge), the
    cosine and sine of its lean, that edge's x, and the panel's foot point (the middle of
    its bottom). A point ``(x, z)`` is ``(x - foot_x) sin + (z - foot_z) cos`` up the
    panel and ``(x - foot_x) cos - (z - foot_z) sin + thickness / 2`` behind its near
    face (the one toward the thrower)."""
    side = xp.where(s.pivot == 0, 1.0, s.pivot)
    b = p.half_base_m
    c, sn = xp.cos(s.angle), xp.sin(s.angle)
    pivot_x = s.base_x + side * b
    return side, c, sn, pivot_x, pivot_x - side * b * c, side * b * sn


def ball_hits_wall(
    p: WallParams,
    s: WallState,
    ball_mass_kg: float,
    ball_radius_m: float,
    bx: Array,
    by: Array,
    bz: Array,
    bvx: Array,
    bvz: Array,
    xp: Any = np,
    located: Array | None = None,
    frame: tuple | None = None,
) -> tuple[WallState, Array, Array, Array]:
    """A ball striking the face of a standing wall.

    Along the face normal ``n`` the seed's restitution formula (§4) acts between the ball
    and the wall's effective mass at the hit point, ``I / (k . n)^2`` with ``k`` the
    point's velocity per unit lean rate about the pivot edge. The wall gains the angular
    momentum ``r x J`` of the impulse, so a high hit turns it more than a low one, and the
    ball rebounds. A wall resting on its foot is pushed about its far edge.

    A ball touches the face when its centre is less than a radius from the face's plane,
    over the face; ``located``, where given, says per ball whether it is in contact (a
    contact its caller located in time, where the centre is one radius from the plane
    up to rounding) in place of the test of its distance. ``frame``: the wall's
    :func:`face_frame`, where the caller has it already.

    Returns ``(wall, new ball vx, new ball vz, hit height along the face or -1)``.
    """
    standing = s.status == STANDING
    t = p.thickness_m
    side, c, sn, pivot_x, foot_x, foot_z = face_frame(p, s, xp) if frame is None else frame
    along = (bx - foot_x) * sn + (bz - foot_z) * c
    offset = (bx - foot_x) * c - (bz - foot_z) * sn + 0.5 * t  # > 0 behind the near face
    # k = velocity of the contact point per unit rate: (r_z, -r_x) about the pivot edge.
    rx = foot_x + along * sn - 0.5 * t * c - pivot_x
    rz = foot_z + along * c + 0.5 * t * sn
    k_n = rz * c + rx * sn
    wall_speed = s.rate * k_n
    ball_speed = bvx * c - bvz * sn
    if located is None:
        touching = (offset > -ball_radius_m) & (offset < ball_radius_m)
    else:
        touching = located
    over_face = (xp.abs(by) <= 0.5 * p.width_m) & (along >= 0.0) & (along <= p.height_m)
    hit = standing & over_face & touching & (ball_speed > wall_speed)
    # The §4 formula with the wall's effective mass m_w = I / k_n^2, as the impulse it
    # implies: u_b' = u_b - J / m_b, J = (1 + e) (u_b - u_w) / (1 / m_b + k_n^2 / I), and the
    # wall's angular impulse k_n J. Written so, it never divides by k_n (a hit level with
    # the pivot edge has k_n = 0: an infinite m_w, a rigid stop) and it keeps the angular
    # momentum about the edge and, at e = 1, the energy exactly.
    if skippable(hit):  # no ball strikes a wall
        return s, bvx, bvz, xp.where(hit, along, -1.0)
    e = p.ball_restitution
    impulse = (
        (1.0 + e) * (ball_speed - wall_speed) / (1.0 / ball_mass_kg + k_n * k_n / p.inertia_kgm2)
    )
    d_ball = xp.where(hit, -impulse / ball_mass_kg, 0.0)
    new_rate = xp.where(hit, s.rate + impulse * k_n / p.inertia_kgm2, s.rate)
    wall = WallState(s.angle, new_rate, xp.where(hit, side, s.pivot), *s[3:])
    return wall, bvx + d_ball * c, bvz - d_ball * sn, xp.where(hit, along, -1.0)
