"""A sailing dinghy driven by apparent wind through a sheet-controlled sail (seed §9).

Top view in 2D plus heel. Every function is pure and batched: state arrays have a leading
batch axis, parameters live in the frozen :class:`DinghyParams`. One physical law, one
function:

==========================  ============================================================
law                         function
==========================  ============================================================
apparent wind               :func:`apparent_wind_body`      ``v_a = v_w - v_s`` (§9)
sail normal coefficient     :func:`sail_normal_coefficient` ``"seed"`` / ``"lift"``
sail force and boom torque  :func:`sail_force`              planar, friction-free (§9)
hull and keel drag          :func:`hull_force`              split along/across hull (§9)
rudder and yaw damping      :func:`yaw_moment`              moment ~ forward speed^2
heel and capsize            :func:`heel_moment`             cos(heel) area, hiking (§9)
crew hiking and its lag     :func:`crew_step`               exact first-order lag
sheet stop and jibes        :func:`apply_sheet_stop`        boom jolt (§9 "jibing")
integration                 :func:`substep`, :func:`step`   semi-implicit Euler (§1, §3)
energy of a passive boat    :func:`mechanical_energy`       (for tests)
==========================  ============================================================

(Each force function has a ``*_linearised`` twin that also returns the derivative the
integration needs; the plain one returns the force alone.)

Integration (:func:`substep`): semi-implicit Euler (seed §1 "discrete time", §3),
velocities first, then positions from the new velocities. Several forces grow steeply with
the velocity they oppose, at a rate ``c = -dF/dv`` that an explicit update overshoots
once ``dt * c / m > 2``: at the default 0.05 s a 34 kg hull, a 45 kg m^2 yaw inertia or a
4x stiffer centreboard went NaN (issue 10). Each such term is linearised about the start
of the substep and integrated implicitly, which is unconditionally stable, keeps every
steady state exactly (the polar is unchanged) and never reverses a decaying velocity:

=====================================  =================================  ====================
stiff term                             force / moment                     integrated
=====================================  =================================  ====================
hull drag with wave making             ``-1/2 rho CdA (1 + u^2/u_w^2)     linearly implicit
                                       u |u|``                            Euler: ``v + dt F /
centreboard lift, sideways hull drag   ``-(k |u| + 1/2 rho CdA |v|) v``   (m + dt c)``, ``c``
sail and windage against the boat's    ``~ rho A C_N |v_a| v_a``          the derivative (the
velocity (the apparent wind)                                              secant ``F / v``
yaw damping                            ``-(c_1 |u| + c_2 |r|) r``         overshoots quartic
                                                                          wave drag)
heel: form stability, crew's reaction  ``-k sin(heel)``, ``-M crew``,     implicit Euler on
to heel and rate, damping              ``-c rate``                        the linearised
                                                                          oscillator
crew lag toward its target             ``(target - crew) / T``            exact exponential
boom: the sail's weathervane torque,   ``~ -k_b (boom - wind)``,          trapezoidal rule
quadratic air damping                  ``-c w |w|``                       (spring), implicit
                                                                          (damping)
=====================================  =================================  ====================

A stiffness or damping rate may be overestimated, never underestimated (a linearly
implicit step stays stable for any rate at least about the true one, and only damps more
for more): where a slope is negative (a stalling sail, a lever that shrinks as the boat
heels), its magnitude is used; the form stability's ``sin`` counts with its largest slope
``k``. The boom takes the trapezoidal rule, not implicit Euler: it keeps the energy of a
free swing, whose speed at the sheet stop is the jolt of a jibe, and the stop itself finds
the speed the boom meets it with from the substep's uniform acceleration, so the jolt does
not depend on the step. Explicit (semi-implicit Euler): the forces' values at the start of
the substep, the cross-couplings (keel lift ~ ``|u|`` acting on ``v``, the sail's moment on
the heel), the positions, and the jibing boom (a real instability). Every boat inside the
intervals of :class:`DinghyParams` stays finite at any ``dt`` up to 0.25 s in any true wind
(``tests/test_sailing_stability.py``); the error is first order in ``dt`` (a course sailed
40 s at 0.05 s ends within a metre of a 20x finer integration).

Frames: world x east, y north, angles counterclockwise from +x. Body frame x forward
(surge ``u``), y to port (sway ``v``). Heel ``> 0``: port side down. Boom angle is measured
from the aft-pointing centerline, ``> 0``: boom swung out to port; the boom then points
along ``(-cos(boom), sin(boom))`` in the body frame and the sail's normal (to port) is
``(sin(boom), cos(boom))``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import (
    AIR_DENSITY_KGM3,
    WATER_DENSITY_KGM3,
    quadratic_drag_rate,
    split_along,
)
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_choice, check_fields, interval, param

SAIL_MODELS = ("lift", "seed")


@dataclass(frozen=True)
class DinghyParams:
    """Physical constants of a Laser-like single-handed dinghy, SI units.

    The defaults are the default preset (``configs/beachball_sail.yaml``), calibrated so the
    polar matches a real dinghy's (see ``bbgym polar`` and ``tests/test_polar.py``).

    Accepted intervals (checked on construction by :func:`check_fields`; errors name
    ``DinghyParams.<field>``). They span a 20 kg sailboard-like hull to a few-tonne 15 m
    keelboat; bounds are where the model stops meaning anything, and 0 is allowed where it
    is a meaningful degenerate boat (no windage, no centreboard, no damping: the implicit
    integration needs no damping to stay stable). Every combination is stable at any
    ``dt <= 0.25 s`` (``tests/test_sailing_stability.py``). Cross-field rules:
    ``sheet_min_rad < sheet_max_rad <= pi/2``, ``capsize_heel_rad < pi/2``.

    ======================  ================  =============================================
    field                   interval          why the bounds
    ======================  ================  =============================================
    mass_kg                 [20, 5000]        sailboard with sailor .. few-tonne keelboat
    yaw_inertia_kgm2        [1, 1e5]          ``m k^2``, k 0.2 m .. 4.5 m
    heel_inertia_kgm2       [1, 1e5]          same span about the roll axis
    hull_length_m           [1, 15]           dinghy .. 15 m keelboat (drawing only)
    hull_beam_m             [0.3, 6]          (drawing only)
    sail_area_m2            [0.5, 150]        kite-sized .. keelboat main and jib
    sail_cn_peak            [0.1, 3]          normal coefficients of real sails: 0.5 .. 2
    sail_stall_rad          [2, 45] deg       where attached flow can separate
    sail_stall_width_rad    [1e-4, 0.5]       abrupt (a step) .. very gradual stall
    sail_cn_flat            [0.1, 3]          flat plate broadside: about 1.2
    sail_drag_coefficient   [0.1, 3]          (seed model) flat plate: about 1.1
    sail_ce_height_m        [0.1, 25]         centre of effort above the heel axis
    sail_ce_aft_m           [0.05, 10]        centre of effort aft of the mast
    boom_length_m           [0.3, 10]         (drawing only)
    boom_impact_heel_arm_m  [0, 25]           0: a jibe gives no roll jolt
    boom_inertia_kgm2       [0.05, 1e4]       a sailboard rig .. a keelboat's main
    boom_air_damping        [0, 1e4]          0: no air damping of the swing
    by_the_lee_rad          [0, 45] deg       0: the sail is blown across at once
    sheet_min_rad           [0, 90] deg       boom on the centreline .. square
    sheet_max_rad           (0, 90] deg       (past 90 deg the boom would point forward)
    hull_drag_forward       [1e-3, 2]         skin of a 0.5 m^2 board .. a keelboat's hull
    hull_wave_speed_mps     [0.5, 20]         ``sqrt(g L / 2 pi)`` of 0.2 m .. a planing hull
    hull_drag_backward      [1e-3, 5]         as forward (0 would sail astern without limit)
    hull_drag_sideways      [1e-3, 30]        hull and foils broadside
    keel_lift_slope         [0, 2e4]          0: no centreboard (a raft)
    windage                 [0, 20]           0: no windage
    rudder_max_rad          [1, 60] deg       past 60 deg a rudder only brakes
    rudder_moment_coeff     [0, 1e5]          0: no rudder
    yaw_damping_linear      [0, 1e5]          0: no damping
    yaw_damping_quadratic   [0, 1e5]          0: no damping
    crew_righting_nm        [0, 5e4]          0: no crew hiking .. a keelboat's rail crew
    crew_response_rad       [0.005, 1]        heel that hikes the crew out
    crew_time_s             [0.01, 30]        reaction time of the crew
    hull_righting_nm        [0, 5e5]          0: no form stability .. a ballasted keel
    heel_damping            [0, 1e5]          0: no damping
    capsize_heel_rad        [3 deg, 90 deg)   a boat on its side has capsized
    ======================  ================  =============================================
    """

    sail_model: str = "lift"
    """``"lift"``: flat-plate normal coefficient with stall; ``"seed"``: drag formula (§9)."""
    mass_kg: float = param(135.0, interval(20.0, 5000.0))
    """Hull (59 kg) plus helmsman (76 kg). Accepted: [20, 5000]."""
    yaw_inertia_kgm2: float = param(180.0, interval(1.0, 1e5))
    """Moment of inertia about the vertical axis. Accepted: [1, 1e5]."""
    heel_inertia_kgm2: float = param(120.0, interval(1.0, 1e5))
    """Moment of inertia about the heel (roll) axis. Accepted: [1, 1e5]."""
    hull_length_m: float = param(4.2, interval(1.0, 15.0))
    """Drawing only. Accepted: [1, 15]."""
    hull_beam_m: float = param(1.4, interval(0.3, 6.0))
    """Drawing only. Accepted: [0.3, 6]."""

    sail_area_m2: float = param(7.06, interval(0.5, 150.0))
    """Accepted: [0.5, 150]."""
    sail_cn_peak: float = param(1.5, interval(0.1, 3.0))
    """Lift model: normal-force coefficient at the stall angle (attached flow). Accepted:
    [0.1, 3]."""
    sail_stall_rad: float = param(math.radians(16.0), interval(math.radians(2.0), math.pi / 4))
    """Lift model: angle of attack where the flow separates. Accepted: [2, 45] deg."""
    sail_stall_width_rad: float = param(math.radians(3.0), interval(1e-4, 0.5))
    """Lift model: how abruptly the attached flow gives way to separated flow. Accepted:
    [1e-4, 0.5]."""
    sail_cn_flat: float = param(1.3, interval(0.1, 3.0))
    """Lift model: normal coefficient of separated flow at 90 deg (a flat plate's drag).
    Accepted: [0.1, 3]."""
    sail_drag_coefficient: float = param(1.1, interval(0.1, 3.0))
    """Seed model: drag coefficient of a flat surface facing the wind (§8: about 1.1).
    Accepted: [0.1, 3]."""
    sail_ce_height_m: float = param(2.9, interval(0.1, 25.0))
    """Height of the sail's centre of effort above the heel axis. Accepted: [0.1, 25]."""
    sail_ce_aft_m: float = param(1.0, interval(0.05, 10.0))
    """Distance of the centre of effort from the mast along the boom. Accepted: [0.05, 10]."""

    boom_length_m: float = param(2.7, interval(0.3, 10.0))
    """Drawing only. Accepted: [0.3, 10]."""
    boom_impact_heel_arm_m: float = param(2.9, interval(0.0, 25.0))
    """Height above the heel axis where a jibing sail's momentum is stopped. Accepted:
    [0, 25].

    Most of the swinging mass and air is the cloth, high on the mast; when the sheet stops
    the boom the mast stops the sail, so the roll impulse is the sail's angular momentum
    times this height over ``sail_ce_aft_m``."""
    boom_inertia_kgm2: float = param(15.0, interval(0.05, 1e4))
    """Boom and sail about the mast. Accepted: [0.05, 1e4]."""
    boom_air_damping: float = param(25.0, interval(0.0, 1e4))
    """Quadratic air damping of a swinging sail, torque = -k * rate * |rate| (N m s^2).
    Accepted: [0, 1e4]."""
    by_the_lee_rad: float = param(math.radians(10.0), interval(0.0, math.pi / 4))
    """How far by the lee (wind from aft, on the boom's side) the sail holds before it is
    blown across in a jibe. Accepted: [0, 45] deg."""
    sheet_min_rad: float = param(math.radians(4.0), interval(0.0, math.pi / 2))
    """Boom angle with the sheet fully in. Accepted: [0, 90] deg, below sheet_max_rad."""
    sheet_max_rad: float = param(math.radians(85.0), interval(0.0, math.pi / 2, low_open=True))
    """Boom angle with the sheet fully out (free to swing to the shroudless stop). Accepted:
    (0, 90] deg."""

    hull_drag_forward: float = param(0.007, interval(1e-3, 2.0))
    """C_d * A (m^2) of the hull moving ahead: small. Accepted: [1e-3, 2]."""
    hull_wave_speed_mps: float = param(2.4, interval(0.5, 20.0))
    """Speed where wave-making doubles the forward drag: ``drag * (1 + (u / u_w)^2)``.
    Accepted: [0.5, 20].

    A 4 m hull makes a bow wave as long as itself near ``sqrt(g L / 2 pi)`` ~ 2.6 m/s;
    past it the boat climbs its own wave and the drag grows much faster than ``u^2``."""
    hull_drag_backward: float = param(0.08, interval(1e-3, 5.0))
    """C_d * A (m^2) moving astern: larger (transom first). Accepted: [1e-3, 5]."""
    hull_drag_sideways: float = param(1.2, interval(1e-3, 30.0))
    """C_d * A (m^2) of hull and foils moving straight sideways: large. Accepted:
    [1e-3, 30]."""
    keel_lift_slope: float = param(600.0, interval(0.0, 2e4))
    """Side force of the centreboard per (forward speed * sideways speed), N s^2/m^2.
    Accepted: [0, 2e4].

    The centreboard is a foil: its side force is ``1/2 rho A C_L_alpha * u * v``
    (``A`` 0.35 m^2, ``C_L_alpha`` about 5 /rad plus the hull's share), so leeway is
    small and almost independent of speed."""
    windage: float = param(1.0, interval(0.0, 20.0))
    """C_d * A (m^2) of hull, mast and crew in the apparent wind. Accepted: [0, 20]."""

    rudder_max_rad: float = param(math.radians(30.0), interval(math.radians(1.0), math.pi / 3))
    """Accepted: [1, 60] deg."""
    rudder_moment_coeff: float = param(200.0, interval(0.0, 1e5))
    """Yaw moment per rudder angle and forward speed squared, N m / (rad m^2/s^2).
    Accepted: [0, 1e5]."""
    yaw_damping_linear: float = param(500.0, interval(0.0, 1e5))
    """Hydrodynamic yaw damping per forward speed, N m s / (rad m/s). Accepted: [0, 1e5]."""
    yaw_damping_quadratic: float = param(400.0, interval(0.0, 1e5))
    """Yaw damping at any speed (the hull's end plates), N m s^2/rad^2. Accepted:
    [0, 1e5]."""

    crew_righting_nm: float = param(600.0, interval(0.0, 5e4))
    """Helmsman fully hiked: 76 kg * g * 0.94 m. Accepted: [0, 5e4]."""
    crew_response_rad: float = param(math.radians(8.0), interval(0.005, 1.0))
    """Heel at which the helmsman is about 3/4 hiked out. Accepted: [0.005, 1]."""
    crew_time_s: float = param(1.0, interval(0.01, 30.0))
    """Time constant of the helmsman moving across the boat. Accepted: [0.01, 30]."""
    hull_righting_nm: float = param(150.0, interval(0.0, 5e5))
    """Form stability, moment = -k sin(heel). Accepted: [0, 5e5]."""
    heel_damping: float = param(350.0, interval(0.0, 1e5))
    """N m s/rad. Accepted: [0, 1e5]."""
    capsize_heel_rad: float = param(
        math.radians(60.0), interval(math.radians(3.0), math.pi / 2, high_open=True)
    )
    """Heel past which the boat capsizes. Accepted: [3, 90) deg."""

    def __post_init__(self) -> None:
        check_fields(self)
        check_choice("DinghyParams.sail_model", self.sail_model, SAIL_MODELS)
        if not self.sheet_min_rad < self.sheet_max_rad <= math.pi / 2:
            raise ValueError(
                "DinghyParams.sheet_min_rad must be < sheet_max_rad <= pi/2, got "
                f"{self.sheet_min_rad!r}, {self.sheet_max_rad!r}"
            )
        if self.capsize_heel_rad >= math.pi / 2:
            raise ValueError(
                f"DinghyParams.capsize_heel_rad must be < pi/2, got {self.capsize_heel_rad!r}"
            )
        # Products of parameters the physics needs every substep, computed once (the single
        # env runs on Python floats, where each multiplication costs as much as a sin).
        # Not fields: equality, hashing and repr see the parameters only.
        excess = self.sail_cn_peak / math.sin(self.sail_stall_rad) - self.sail_cn_flat
        half_rho = 0.5 * WATER_DENSITY_KGM3
        derived = {
            "_sail_q": 0.5 * AIR_DENSITY_KGM3 * self.sail_area_m2,
            "_minus_sin_by_the_lee": -math.sin(self.by_the_lee_rad),
            # Lift model: C_N / sin(alpha) = flat + half_excess * (1 - tanh(x / 2)).
            "_lift": (
                self.sail_stall_rad,
                0.5 / self.sail_stall_width_rad,
                self.sail_cn_flat,
                0.5 * excess,
                -0.25 * excess / self.sail_stall_width_rad,
            ),
            "_hull": (
                half_rho * (self.hull_drag_forward - self.hull_drag_backward),
                half_rho * self.hull_drag_backward,
                1.0 / (self.hull_wave_speed_mps * self.hull_wave_speed_mps),
                half_rho * self.hull_drag_sideways,
            ),
            "_roll_arm": self.boom_impact_heel_arm_m / self.sail_ce_aft_m,
        }
        for name, value in derived.items():
            object.__setattr__(self, name, value)

    def replace(self, **changes: object) -> DinghyParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


class DinghyState(NamedTuple):
    """State of a batch of dinghies; every field has shape ``(batch,)`` (or is a Python
    float for one boat). Immutable: a step makes a new state."""

    x_m: Array
    y_m: Array
    heading_rad: Array
    vx_mps: Array
    vy_mps: Array
    yaw_rate_rps: Array
    heel_rad: Array
    heel_rate_rps: Array
    boom_rad: Array
    boom_rate_rps: Array
    crew_out: Array
    """Helmsman's position, -1 (hiked to port) .. +1 (hiked to starboard)."""
    capsized: Array
    """Bool; once capsized the boat stays down (the sail lies in the water)."""


class StepEvents(NamedTuple):
    """What happened during one :func:`step`, per boat."""

    jibes: Array
    """Boom crossings of the centerline with the apparent wind from aft (int)."""
    jibe_severity_rps: Array
    """Largest boom angular speed at such a crossing (0 if none)."""
    tacks: Array
    """Bow crossings of the true wind direction (int, 0 or 1)."""


def dinghy_moving(
    heading_rad: Array, speed_mps: Array, boom_rad: Array, xp: Any = np
) -> DinghyState:
    """Upright boats at the origin moving straight ahead at ``speed_mps``, the boom at
    ``boom_rad`` (arrays of one shape, any namespace)."""
    zeros = 0.0 * heading_rad
    return DinghyState(
        x_m=zeros,
        y_m=zeros,
        heading_rad=heading_rad,
        vx_mps=speed_mps * xp.cos(heading_rad),
        vy_mps=speed_mps * xp.sin(heading_rad),
        yaw_rate_rps=zeros,
        heel_rad=zeros,
        heel_rate_rps=zeros,
        boom_rad=boom_rad,
        boom_rate_rps=zeros,
        crew_out=zeros,
        capsized=zeros > 0.0,
    )


def dinghy_at_rest(
    batch: int,
    x_m: Any = 0.0,
    y_m: Any = 0.0,
    heading_rad: Any = 0.0,
    speed_mps: Any = 0.0,
    boom_rad: Any = 0.0,
) -> DinghyState:
    """A NumPy batch of upright boats moving straight ahead at ``speed_mps``."""

    def full(v: object) -> np.ndarray:
        return np.broadcast_to(np.asarray(v, dtype=np.float64), (batch,)).copy()

    boat = dinghy_moving(full(heading_rad), full(speed_mps), full(boom_rad))
    return boat._replace(x_m=full(x_m), y_m=full(y_m))


def apparent_wind_body(
    state: DinghyState, wind_x: Array, wind_y: Array, cos_h: Array, sin_h: Array
) -> tuple[Array, Array]:
    """Apparent wind ``v_a = v_w - v_s`` (seed §9) in the body frame: (ahead, to port).

    The vector points where the air moves relative to the boat.
    """
    return split_along(wind_x - state.vx_mps, wind_y - state.vy_mps, cos_h, sin_h)


def sail_normal_coefficients(
    p: DinghyParams, sin_attack: Array, cos_attack: Array, xp: Any = np
) -> tuple[Array, Array]:
    """Normal-force coefficient of the flat sail at angle of attack ``alpha``, as
    ``(S, sin(alpha) dS/dalpha)`` with the secant ``S = C_N / sin(alpha)`` (finite at
    ``alpha = 0``): the slope the implicit integration needs (see
    :func:`sail_force_linearised`) is ``dC_N/dalpha = cos(alpha) S + sin(alpha) dS/dalpha``.

    ``F_N = 1/2 rho A C_N |v_a|^2``, perpendicular to the sail.

    * ``"seed"``: the drag formula applied to the wind component perpendicular to the sail
      (§9): ``F_N = 1/2 rho A C_d v_perp^2`` with ``v_perp = |v_a| sin(alpha)``, i.e.
      ``C_N = C_d sin^2(alpha)``.
    * ``"lift"``: a flat plate. Attached flow at small angles gives a normal coefficient
      that grows like ``sin(alpha)`` up to ``sail_cn_peak`` at ``sail_stall_rad``; past the
      stall the flow separates and ``C_N = sail_cn_flat * sin(alpha)`` (Hoerner's flat
      plate). A logistic blend in ``alpha`` joins the two, so the force is smooth; it is
      written ``(1 - tanh(x / 2)) / 2``, equal to ``1 / (1 + exp(x))`` but free of overflow
      however abrupt the stall (``sail_stall_width_rad``).
    """
    if p.sail_model == "seed":
        secant = p.sail_drag_coefficient * sin_attack
        return secant, secant * cos_attack
    stall, half_inv_width, flat, half_excess, d_coefficient = p._lift
    # (sin_attack may round past 1: clip, or arcsin has a domain error)
    half_x = xp.tanh((xp.asin(xp.clip(sin_attack, 0.0, 1.0)) - stall) * half_inv_width)
    # C_N / sin(alpha): the attached slope (sail_cn_peak / sin(stall)) below the stall, the
    # flat plate's (sail_cn_flat) above it.
    secant = flat + half_excess * (1.0 - half_x)
    return secant, sin_attack * d_coefficient * (1.0 - half_x * half_x)


def sail_normal_coefficient(p: DinghyParams, sin_attack: Array, xp: Any = np) -> Array:
    """Normal-force coefficient ``C_N`` alone (see :func:`sail_normal_coefficients`)."""
    cos_attack = xp.sqrt(xp.maximum(1.0 - sin_attack * sin_attack, 0.0))
    return sin_attack * sail_normal_coefficients(p, sin_attack, cos_attack, xp)[0]


def sail_force_linearised(
    p: DinghyParams,
    boom_rad: Array,
    cos_heel: Array,
    upright: Array,
    aw_u: Array,
    aw_v: Array,
    xp: Any = np,
) -> tuple[Array, Array, Array, Array, Array, Array]:
    """Force of the planar, friction-free sail (seed §9) and its stiffnesses.

    Only the apparent-wind component perpendicular to the sail, ``w_n = v_a . n``, pushes
    it, so the force is along the sail's normal ``n``; it pushes the sail (and the boat) to
    the side the air flows to. Heel tilts the sail out of the wind: the effective area is
    ``A cos(heel)`` (§9 "tilt"); a capsized boat (``upright`` false) has none. The normal force
    is ``F_N = q |v_a|^2 C_N(alpha)`` with ``q = 1/2 rho A cos(heel)`` and
    ``sin(alpha) = |w_n| / |v_a|``.

    By the lee (wind from aft and from the side the boom is on) the air runs over the sail
    from leech to luff; a soft sail cannot hold its shape that way and is blown across:
    the boom is pushed toward the other side (``-sign(boom)``) and jibes. The air's
    pressure on the boat still acts along ``sign(w_n)``, with the air: a force against it
    would drive the boat upwind, creating energy (with a large sail on a light hull it ran
    away to 1500 m/s within a second).

    Returns ``(drive, side, normal, c_n, k_boom, |v_a|)``: the body-frame components
    (ahead, to port) of the force on the boat, the signed normal force on the boom
    (``> 0`` pushes it to port), and the two derivatives the integration treats
    implicitly:

    * ``c_n = dF_N/dw_n = q |v_a| (2 sin(alpha) C_N + cos(alpha) dC_N/dalpha)``: how fast
      the force falls as the boat's velocity along ``n`` catches up with the air (the
      sail's aerodynamic damping of the boat);
    * ``k_boom = ce_aft q |v_a|^2 (S + sin(alpha) |dS/dalpha|)``, ``S = C_N / sin(alpha)``,
      while the air runs from luff to leech: the weathervane stiffness that swings the
      boom into the wind. It bounds both the torque curve's secant and its slope
      ``dC_N/dalpha = cos(alpha) S + sin(alpha) dS/dalpha`` and equals the slope at small
      angles: the trapezoidal boom update keeps a swing's energy with the exact stiffness,
      damps it with a larger one, and would feed it with a smaller one.

    ``k_boom`` is 0 by the lee (the jibing boom is left explicit). Where the slope is negative
    (in the stall) the physics itself destabilises; the implicit update then counts the
    slope's magnitude as damping, which only slows that divergence: a linearly implicit
    step stays stable whenever its coefficient is at least the true damping rate.
    """
    normal_u, normal_v = xp.sin(boom_rad), xp.cos(boom_rad)
    wind_normal = aw_u * normal_u + aw_v * normal_v
    # Along the boom, from the mast (-cos(boom), sin(boom)): > 0 when the air runs aft.
    wind_chord = aw_v * normal_u - aw_u * normal_v
    speed = xp.sqrt(aw_u * aw_u + aw_v * aw_v)
    inv_speed = 1.0 / (speed + 1e-300)  # finite in a calm, where both components are 0
    wind_normal_abs = xp.abs(wind_normal)
    sin_attack = wind_normal_abs * inv_speed
    cos_attack = xp.abs(wind_chord) * inv_speed
    secant, sin_d_secant = sail_normal_coefficients(p, sin_attack, cos_attack, xp)
    q_speed = xp.where(upright, p._sail_q * cos_heel * speed, 0.0)
    # |F_N| = q |v_a|^2 C_N = q |v_a| (C_N / sin(alpha)) |w_n|, along sign(w_n).
    pressure = (q_speed * secant) * wind_normal
    # By the lee the boom is blown across, toward -sign(boom).
    boom_side = xp.sign(boom_rad)
    by_the_lee = (aw_u > 0.0) & (aw_v * boom_side < p._minus_sin_by_the_lee * speed)
    normal = xp.where(by_the_lee, -boom_side * xp.abs(pressure), pressure)
    # 2 sin C_N + cos dC_N/dalpha = (1 + sin^2) S + cos sin dS/dalpha
    c_n = q_speed * xp.abs((1.0 + sin_attack * sin_attack) * secant + cos_attack * sin_d_secant)
    # The weathervane stiffness holds while the air runs aft along the boom (luff to leech).
    luff_to_leech = (wind_chord > 0.0) & xp.logical_not(by_the_lee)  # air running aft
    k_boom = xp.where(luff_to_leech, p.sail_ce_aft_m * q_speed * speed, 0.0) * (
        secant + xp.abs(sin_d_secant)
    )
    return pressure * normal_u, pressure * normal_v, normal, c_n, k_boom, speed


def sail_force(
    p: DinghyParams, state: DinghyState, aw_u: Array, aw_v: Array, xp: Any = np
) -> tuple[Array, Array, Array]:
    """Force of the planar, friction-free sail (seed §9): ``(drive, side, normal)``.

    The body-frame components ``drive`` (ahead) and ``side`` (to port), and the signed
    normal force (``> 0`` pushes the boom to port); see :func:`sail_force_linearised`.
    """
    upright = xp.logical_not(state.capsized)
    forces = sail_force_linearised(
        p, state.boom_rad, xp.cos(state.heel_rad), upright, aw_u, aw_v, xp
    )
    return forces[0], forces[1], forces[2]


def hull_force_linearised(
    p: DinghyParams, surge: Array, sway: Array, xp: Any = np
) -> tuple[Array, Array, Array, Array]:
    """Water force on hull and keel in the body frame, from the velocity split (§9), and
    its derivatives ``(along, across, -d along/d surge, -d across/d sway)``.

    Ahead the hull is slippery, astern less so, with wave making past ``u_w``:
    ``along = -1/2 rho CdA (1 + u^2/u_w^2) u |u|``. Sideways the centreboard resists
    strongly (foil lift ~ ``u * v`` while moving ahead, plus quadratic drag of the hull):
    ``across = -(k |u| + 1/2 rho CdA_side |v|) v``, so the boat drifts (leeway) only a
    little. The derivatives (>= 0) are the damping rates :func:`substep` integrates
    implicitly.
    """
    ahead_minus_astern, astern, inv_wave_speed_sq, side = p._hull
    speed_u = xp.abs(surge)
    drag_u = (astern + xp.where(surge >= 0.0, ahead_minus_astern, 0.0 * surge)) * speed_u
    wave = surge * surge * inv_wave_speed_sq
    keel = p.keel_lift_slope * speed_u
    drag_v = side * xp.abs(sway)
    along = -drag_u * (1.0 + wave) * surge
    across = -(keel + drag_v) * sway
    return along, across, drag_u * (2.0 + 4.0 * wave), keel + 2.0 * drag_v


def hull_force(p: DinghyParams, surge: Array, sway: Array, xp: Any = np) -> tuple[Array, Array]:
    """Water force on hull and keel in the body frame: ``(along, across)``; see
    :func:`hull_force_linearised`."""
    along, across, _, _ = hull_force_linearised(p, surge, sway, xp)
    return along, across


def yaw_moment_linearised(
    p: DinghyParams, surge: Array, yaw_rate: Array, rudder_rad: Array, xp: Any = np
) -> tuple[Array, Array]:
    """Rudder moment minus yaw damping, and the damping rate ``-dM/d(yaw rate) >= 0``.

    The rudder is a foil: its moment grows with forward speed squared, so a boat at rest
    cannot steer (seed §9: "no steering speed"). Moving astern the rudder acts reversed.
    Damping: ``-(c_1 |u| + c_2 |r|) r``.
    """
    rudder = p.rudder_moment_coeff * surge * xp.abs(surge) * rudder_rad
    linear = p.yaw_damping_linear * xp.abs(surge)
    quadratic = p.yaw_damping_quadratic * xp.abs(yaw_rate)
    return rudder - (linear + quadratic) * yaw_rate, linear + 2.0 * quadratic


def yaw_moment(
    p: DinghyParams, surge: Array, yaw_rate: Array, rudder_rad: Array, xp: Any = np
) -> Array:
    """Rudder moment minus yaw damping; see :func:`yaw_moment_linearised`."""
    return yaw_moment_linearised(p, surge, yaw_rate, rudder_rad, xp)[0]


def heel_moment_linearised(
    p: DinghyParams,
    cos_heel: Array,
    sin_heel: Array,
    heel_rate: Array,
    crew_out: Array,
    sail_side: Array,
    xp: Any = np,
) -> tuple[Array, Array]:
    """Heeling moment of the sail's side force against crew, hull and damping (§9 "tilt"),
    and a bound on its stiffness ``-dM/d(heel)`` for the implicit update.

    The side force acts at the centre of effort, whose height above the heel axis shrinks
    as ``cos(heel)``; the helmsman's weight (``crew_out``) rights the boat with a lever
    that shrinks the same way, and the hull's form stability with ``-k sin(heel)``:
    ``M = F_side h_ce cos(heel) - M_crew crew cos(heel) - k sin(heel) - c rate``. The side
    force itself scales with the area ``cos(heel)``, so its moment goes as ``cos^2``.

    The stiffness is ``k + |(2 F_side h_ce - M_crew crew) sin(heel)|``: for the form
    stability ``k``, not its slope ``k cos(heel)``. ``sin`` bends over, so near 90 deg
    its slope is far below ``sin(heel) / heel``; a linearly implicit step with a stiffness
    below that secant overshoots a stiff boat across to the other side, one at or above it
    never does (implicit Euler on a linear spring stays stable for any stiffness at least
    about half the true one, and damps more for more).
    """
    heeling = sail_side * p.sail_ce_height_m
    crew = p.crew_righting_nm * crew_out
    moment = (
        (heeling - crew) * cos_heel - p.hull_righting_nm * sin_heel - p.heel_damping * heel_rate
    )
    # The levers' part in magnitude: where it destabilises (crew or sail lever winning) the
    # implicit update only slows the motion down.
    return moment, p.hull_righting_nm + xp.abs((2.0 * heeling - crew) * sin_heel)


def heel_moment(p: DinghyParams, state: DinghyState, sail_side: Array, xp: Any = np) -> Array:
    """Heeling moment with the crew where it is now; see :func:`heel_moment_linearised`."""
    return heel_moment_linearised(
        p,
        xp.cos(state.heel_rad),
        xp.sin(state.heel_rad),
        state.heel_rate_rps,
        state.crew_out,
        sail_side,
        xp,
    )[0]


def crew_step(
    p: DinghyParams,
    crew_out: Array,
    heel_rad: Array,
    heel_rate_rps: Array,
    dt_s: float,
    xp: Any = np,
) -> tuple[Array, Array]:
    """The helmsman hikes toward ``tanh((heel + T rate) / crew_response_rad)`` with the lag
    ``T = crew_time_s``, integrated exactly over ``dt_s``:
    ``crew += (target - crew) (1 - exp(-dt / T))``.

    The helmsman reacts to the heel and to how fast it grows (a sailor feels the gust before
    the boat lies over); the lead term offsets the time it takes to move. Returns the new
    position and its gain ``d crew / d(heel + T rate)`` (for the implicit heel update).
    """
    lag = 1.0 - math.exp(-dt_s / p.crew_time_s)  # Python floats: a constant when compiled
    target = xp.tanh((heel_rad + p.crew_time_s * heel_rate_rps) * (1.0 / p.crew_response_rad))
    gain = (lag / p.crew_response_rad) * (1.0 - target * target)
    return crew_out + (target - crew_out) * lag, gain


def boom_limit_from_sheet(p: DinghyParams, sheet: Array, xp: Any = np) -> Array:
    """Largest boom angle the sheet allows: ``sheet`` 0 = fully in, 1 = fully out."""
    return p.sheet_min_rad + xp.clip(sheet, 0.0, 1.0) * (p.sheet_max_rad - p.sheet_min_rad)


def apply_sheet_stop(
    boom: Array,
    boom_rate: Array,
    previous_boom: Array,
    previous_rate: Array,
    limit: Array,
    dt_s: float,
    xp: Any = np,
) -> tuple[Array, Array, Array]:
    """The sheet caps the boom angle at ``+-limit``; returns ``(boom, rate, impact_rate)``.

    A boom that reaches the cap while swinging out is stopped dead by the sheet (an
    inelastic stop). ``impact_rate`` is the signed angular speed it arrives with, whose
    angular momentum the sheet hands to the hull (see :func:`substep`): the jolt of a jibe.
    Within the substep the boom turns with uniform angular acceleration ``a`` from
    ``previous_rate`` (``w_0``) to ``boom_rate`` (as the trapezoidal boom update of
    :func:`substep` assumes), so it meets the stop, ``gap`` beyond ``previous_boom``, at
    ``w^2 = w_0^2 + 2 a gap``: the same jolt at any step size. The further the sheet is
    eased, the longer the boom accelerates and the harder it hits. A sail pressing steadily
    on the sheet starts each substep at the stop at rest and gives no jolt: the sheet load
    is then an internal force.
    """
    side = xp.sign(boom)
    outward_rate = side * boom_rate
    start_rate = side * previous_rate
    gap = limit - side * previous_boom
    short_of_stop = gap > 0.0
    gap = xp.where(short_of_stop, gap, 0.0)
    # A boom already at (or, the sheet just hauled in, beyond) the stop (gap 0) hits it
    # only if it was moving out at the start. w^2 lies between the two rates' squares, so
    # it is >= 0 but for rounding.
    outward = (xp.abs(boom) > limit) & (outward_rate > 0.0)
    hits = outward & (short_of_stop | (start_rate > 0.0))
    contact_sq = start_rate * start_rate + (2.0 / dt_s) * (outward_rate - start_rate) * gap
    impact_rate = xp.where(hits, side, 0.0) * xp.sqrt(xp.abs(contact_sq))
    boom = xp.clip(boom, -limit, limit)
    return boom, xp.where(outward, 0.0, boom_rate), impact_rate  # stopped dead if outward


def substep(
    p: DinghyParams,
    state: DinghyState,
    rudder_rad: Array,
    boom_limit_rad: Array,
    wind_x: Array,
    wind_y: Array,
    dt_s: float,
    xp: Any = np,
) -> tuple[DinghyState, Array, Array]:
    """One semi-implicit Euler step (seed §1, §3): velocities first, then positions, with
    the stiff terms linearised and integrated implicitly (see the module docstring).

    The forces come from the state at the start of the substep; then each velocity takes
    its implicit update, one law each: the hull (:func:`_hull_velocity`), the boom and its
    sheet stop (:func:`_boom_update`), yaw (:func:`_yaw_rate`), heel with the crew
    (:func:`_heel_update`). Returns the new state, the signed boom angular speed at a
    sheet-stop impact, and whether the boom jibed (crossed the centreline with the air
    moving forward over the boat: the wind from aft).
    """
    h = dt_s
    cos_h, sin_h = xp.cos(state.heading_rad), xp.sin(state.heading_rad)
    surge, sway = split_along(state.vx_mps, state.vy_mps, cos_h, sin_h)
    aw_u, aw_v = apparent_wind_body(state, wind_x, wind_y, cos_h, sin_h)
    cos_heel, sin_heel = xp.cos(state.heel_rad), xp.sin(state.heel_rad)
    upright = xp.logical_not(state.capsized)

    drive, side, normal, c_sail, k_boom, aw_speed = sail_force_linearised(
        p, state.boom_rad, cos_heel, upright, aw_u, aw_v, xp
    )
    vx, vy = _hull_velocity(
        p, state, cos_h, sin_h, surge, sway, aw_u, aw_v, aw_speed, drive, side, c_sail, h, xp
    )
    boom, boom_rate, impact = _boom_update(p, state, normal, k_boom, boom_limit_rad, h, xp)
    # The sheet hands the sail's angular momentum to the hull: all of it to yaw, and a roll
    # impulse from the height where the mast stops the swinging cloth (the jibe's jolt).
    # Both enter the implicit updates below as part of the substep's angular impulse, so
    # the damping acts on them as on any moment (added after the damping, a jolt would
    # turn the boat by h * its rate more than the continuous motion does).
    impulse = p.boom_inertia_kgm2 * impact
    yaw_rate = _yaw_rate(p, state, surge, rudder_rad, impulse, h, xp)
    heel, heel_rate, crew, capsized = _heel_update(
        p, state, cos_heel, sin_heel, upright, side, impulse, h, xp
    )
    new_state = DinghyState(
        state.x_m + h * vx, state.y_m + h * vy, state.heading_rad + h * yaw_rate, vx, vy,
        yaw_rate, heel, heel_rate, boom, boom_rate, crew, capsized,
    )  # fmt: skip
    jibe = (state.boom_rad * boom < 0.0) & (aw_u > 0.0)
    return new_state, impact, jibe


def _hull_velocity(
    p: DinghyParams, state: DinghyState, cos_h: Array, sin_h: Array, surge: Array,
    sway: Array, aw_u: Array, aw_v: Array, aw_speed: Array, drive: Array, side: Array,
    c_sail: Array, h: float, xp: Any,
) -> tuple[Array, Array]:  # fmt: skip
    """The boat's new world velocity: sail, hull and windage forces, linearly implicit in
    the body frame (module docstring)."""
    hull_u, hull_v, c_u, c_v = hull_force_linearised(p, surge, sway, xp)
    # Windage of hull, mast and crew, quadratic drag against the air (-k v_rel with v_rel =
    # -v_a): the only force that pushes a boat in irons astern. Its derivative is at most
    # 2 k (isotropic bound).
    windage = quadratic_drag_rate(p.windage, AIR_DENSITY_KGM3, aw_speed)

    # Linearly implicit Euler for the boat's velocity in the body frame:
    # (m I + h C) dV = h F with the damping rates C = diag(c_u, c_v) + (2 k_air + c_sail) I.
    # The sail's rate acts along its normal n only (c_sail n n^T); counted in every
    # direction it is an upper bound (n n^T <= I), which keeps the step stable (a linearly
    # implicit step may overestimate a damping, never underestimate it much) and the matrix
    # diagonal: two divisions instead of a 2x2 solve.
    force_u = drive + hull_u + windage * aw_u
    force_v = side + hull_v + windage * aw_v
    c_iso = 2.0 * windage + c_sail
    du = h * force_u / (p.mass_kg + h * (c_u + c_iso))
    dv = h * force_v / (p.mass_kg + h * (c_v + c_iso))
    return state.vx_mps + cos_h * du - sin_h * dv, state.vy_mps + sin_h * du + cos_h * dv


def _boom_update(
    p: DinghyParams, state: DinghyState, normal: Array, k_boom: Array, boom_limit_rad: Array,
    h: float, xp: Any,
) -> tuple[Array, Array, Array]:  # fmt: skip
    """The boom's new ``(angle, rate, impact rate)``: the trapezoidal rule on its
    oscillator (the sail's weathervane stiffness ``k_boom``), air damping implicit, then the
    sheet stop (:func:`apply_sheet_stop`).

    The trapezoidal rule is unconditionally stable like implicit Euler, but it keeps the
    energy of a free swing, whose speed at the sheet stop is the jibe's jolt (implicit Euler
    would damp it by ``(h w_0)^2`` per substep: at 0.05 s a 10% weaker jolt). The air damps
    a swinging sail with ``-k rate |rate|``; with the coefficient ``k |rate|`` frozen over
    the substep, implicit Euler is exact for pure quadratic decay, ``w / (1 + k w dt / I)``.
    """
    omega = state.boom_rate_rps
    c_boom = p.boom_air_damping * xp.abs(omega)
    half_h = 0.5 * h
    hk_boom = half_h * k_boom
    boom_rate = omega + h * (p.sail_ce_aft_m * normal - (c_boom + hk_boom) * omega) / (
        p.boom_inertia_kgm2 + h * c_boom + half_h * hk_boom
    )
    return apply_sheet_stop(
        state.boom_rad + half_h * (omega + boom_rate),
        boom_rate,
        state.boom_rad,
        omega,
        boom_limit_rad,
        h,
        xp,
    )


def _yaw_rate(
    p: DinghyParams, state: DinghyState, surge: Array, rudder_rad: Array, impulse: Array,
    h: float, xp: Any,
) -> Array:  # fmt: skip
    """The new yaw rate: rudder and damping (:func:`yaw_moment_linearised`), implicit, with
    the sheet's angular ``impulse``."""
    yaw, c_yaw = yaw_moment_linearised(p, surge, state.yaw_rate_rps, rudder_rad, xp)
    return state.yaw_rate_rps + (h * yaw - impulse) / (p.yaw_inertia_kgm2 + h * c_yaw)


def _heel_update(
    p: DinghyParams, state: DinghyState, cos_heel: Array, sin_heel: Array, upright: Array,
    side: Array, impulse: Array, h: float, xp: Any,
) -> tuple[Array, Array, Array, Array]:  # fmt: skip
    """The new ``(heel, heel rate, crew, capsized)``: implicit Euler on the oscillator
    linearised about the start of the substep, the crew included.

    The crew moves toward its target (exact lag, :func:`crew_step`), and its reaction to the
    heel and rate reached in this substep (its gain) is part of the implicit stiffness
    (``k_crew``) and damping (``k_crew * T``, the lead term). The sheet's roll impulse acts
    at ``boom_impact_heel_arm_m``. A capsized boat stays as it lies.
    """
    heel = state.heel_rad
    rate = state.heel_rate_rps
    crew, gain = crew_step(p, state.crew_out, heel, rate, h, xp)
    heel_m, k_heel = heel_moment_linearised(p, cos_heel, sin_heel, rate, crew, side, xp)
    k_crew = (p.crew_righting_nm * cos_heel) * gain
    k_heel = k_heel + k_crew
    heel_rate = xp.where(
        upright,
        rate
        + (h * (heel_m - h * k_heel * rate) + p._roll_arm * impulse)
        / (p.heel_inertia_kgm2 + h * (p.heel_damping + p.crew_time_s * k_crew + h * k_heel)),
        0.0,
    )
    new_heel = heel + h * heel_rate
    capsized = state.capsized | (xp.abs(new_heel) > p.capsize_heel_rad)
    # The crew's reaction to this substep's heel and rate, to first order (its gain): the
    # same as crew_step from the new state up to O(dt^2), without a second tanh.
    crew = crew + gain * (new_heel - heel + p.crew_time_s * (heel_rate - rate))
    crew = xp.where(
        upright, state.crew_out + (xp.clip(crew, -1.0, 1.0) - state.crew_out), state.crew_out
    )
    return new_heel, heel_rate, crew, capsized


class StepCarry(NamedTuple):
    """What :func:`step` carries from substep to substep: the boat, the held controls and
    wind, and the jibes so far."""

    boat: DinghyState
    rudder_rad: Array
    boom_limit_rad: Array
    wind_x: Array
    wind_y: Array
    jibes: Array
    jibe_severity_rps: Array


def step_begin(
    p: DinghyParams, state: DinghyState, rudder_rad: Array, sheet: Array, wind_x: Array,
    wind_y: Array, xp: Any = np,
) -> StepCarry:  # fmt: skip
    """Start a :func:`step`: clip the controls and hold them, with the wind."""
    rudder = xp.clip(rudder_rad, -p.rudder_max_rad, p.rudder_max_rad)
    limit = boom_limit_from_sheet(p, sheet, xp)
    jibes = xp.zeros_like(state.x_m, dtype=xp.int64)
    return StepCarry(state, rudder, limit, wind_x, wind_y, jibes, xp.zeros_like(state.x_m))


def step_substep(p: DinghyParams, carry: StepCarry, dt_s: float, xp: Any = np) -> StepCarry:
    """One substep of a :func:`step`, counting jibes (the boom crosses the centerline while
    the apparent wind comes from aft, checked every substep: a boom crosses in a fraction
    of a second) and keeping the fastest boom speed at one."""
    state, _impact, jibe = substep(
        p, carry.boat, carry.rudder_rad, carry.boom_limit_rad, carry.wind_x, carry.wind_y,
        dt_s, xp,
    )  # fmt: skip
    jibes = carry.jibes + xp.astype(jibe, xp.int64)
    severity = xp.maximum(carry.jibe_severity_rps, xp.where(jibe, xp.abs(state.boom_rate_rps), 0.0))
    return carry._replace(boat=state, jibes=jibes, jibe_severity_rps=severity)


def step_end(
    p: DinghyParams, start: DinghyState, carry: StepCarry, xp: Any = np
) -> tuple[DinghyState, StepEvents]:
    """Finish a :func:`step` begun at ``start``: a tack is the bow crossing the true wind
    between the start and the end of the step (a boat turns far less than half a circle
    in one control step)."""
    wind_from = xp.atan2(-carry.wind_y, -carry.wind_x)
    state = carry.boat
    wind_off_bow = xp.sin(wind_from - start.heading_rad)
    off_bow = xp.sin(wind_from - state.heading_rad)
    tacks = (off_bow * wind_off_bow < 0.0) & (xp.cos(wind_from - state.heading_rad) > 0.0)
    return state, StepEvents(carry.jibes, carry.jibe_severity_rps, xp.astype(tacks, xp.int64))


def step(
    p: DinghyParams,
    state: DinghyState,
    rudder_rad: Array,
    sheet: Array,
    wind_x: Array,
    wind_y: Array,
    dt_s: float,
    n_substeps: int,
    xp: Any = np,
) -> tuple[DinghyState, StepEvents]:
    """Advance ``n_substeps`` substeps of ``dt_s`` (:func:`substep`) with the controls held.

    ``rudder_rad`` is clipped to ``+-rudder_max_rad``; ``sheet`` in [0, 1] is how far the
    sheet is eased (0 fully in). Counts jibes and tacks (:func:`step_substep`,
    :func:`step_end`). A compiled backend runs the same three parts, compiling the substep
    once rather than unrolling the loop.
    """
    carry = step_begin(p, state, rudder_rad, sheet, wind_x, wind_y, xp)
    for _ in range(n_substeps):
        carry = step_substep(p, carry, dt_s, xp)
    return step_end(p, state, carry, xp)


def mechanical_energy(p: DinghyParams, state: DinghyState, xp: Any = np) -> Array:
    """Kinetic energy of hull, yaw, heel and boom plus the hull's righting potential:
    ``1/2 m |v|^2 + 1/2 I_yaw r^2 + 1/2 I_heel p^2 + 1/2 I_boom w^2 + k (1 - cos(heel))``.

    With no wind, the rudder centred and no hiking crew (an actuator: ``crew_righting_nm``
    0), every force left (drag, damping, righting) is passive, so this can only fall:
    the tests check that the implicit integration dissipates and never creates energy.
    The sheet stop (an inelastic collision that hands the boom's momentum to the hull) and
    a sail blown across by the lee are not passive and can add energy.
    """
    return (
        0.5 * p.mass_kg * (state.vx_mps * state.vx_mps + state.vy_mps * state.vy_mps)
        + 0.5 * p.yaw_inertia_kgm2 * state.yaw_rate_rps * state.yaw_rate_rps
        + 0.5 * p.heel_inertia_kgm2 * state.heel_rate_rps * state.heel_rate_rps
        + 0.5 * p.boom_inertia_kgm2 * state.boom_rate_rps * state.boom_rate_rps
        # 1 - cos(heel) = 2 sin^2(heel / 2), without the cancellation at small heel
        + (2.0 * p.hull_righting_nm) * xp.sin(0.5 * state.heel_rad) ** 2
    )
