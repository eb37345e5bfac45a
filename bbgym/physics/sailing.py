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
sheet stop and jibes        :func:`apply_sheet_stop`        boom jolt (§9 "jibing")
integration                 :func:`substep`, :func:`step`   semi-implicit Euler (§1, §3)
==========================  ============================================================

Frames: world x east, y north, angles counterclockwise from +x. Body frame x forward
(surge ``u``), y to port (sway ``v``). Heel ``> 0``: port side down. Boom angle is measured
from the aft-pointing centerline, ``> 0``: boom swung out to port; the boom then points
along ``(-cos(boom), sin(boom))`` in the body frame and the sail's normal (to port) is
``(sin(boom), cos(boom))``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from bbgym.physics.backend import Array
from bbgym.physics.common import AIR_DENSITY_KGM3, WATER_DENSITY_KGM3, quadratic_drag, split_along

SAIL_MODELS = ("lift", "seed")


@dataclass(frozen=True)
class DinghyParams:
    """Physical constants of a Laser-like single-handed dinghy, SI units.

    The defaults are the default preset (``configs/beachball_sail.yaml``), calibrated so the
    polar matches a real dinghy's (see ``scripts/polar.py`` and ``tests/test_polar.py``).
    """

    sail_model: str = "lift"
    """``"lift"``: flat-plate normal coefficient with stall; ``"seed"``: drag formula (§9)."""
    mass_kg: float = 135.0
    """Hull (59 kg) plus helmsman (76 kg)."""
    yaw_inertia_kgm2: float = 180.0
    heel_inertia_kgm2: float = 120.0
    hull_length_m: float = 4.2
    hull_beam_m: float = 1.4

    sail_area_m2: float = 7.06
    sail_cn_peak: float = 1.5
    """Lift model: normal-force coefficient at the stall angle (attached flow)."""
    sail_stall_rad: float = math.radians(16.0)
    """Lift model: angle of attack where the flow separates."""
    sail_stall_width_rad: float = math.radians(3.0)
    """Lift model: how abruptly the attached flow gives way to separated flow."""
    sail_cn_flat: float = 1.3
    """Lift model: normal coefficient of separated flow at 90 deg (a flat plate's drag)."""
    sail_drag_coefficient: float = 1.1
    """Seed model: drag coefficient of a flat surface facing the wind (§8: about 1.1)."""
    sail_ce_height_m: float = 2.9
    """Height of the sail's centre of effort above the heel axis."""
    sail_ce_aft_m: float = 1.0
    """Distance of the centre of effort from the mast along the boom."""

    boom_length_m: float = 2.7
    boom_impact_heel_arm_m: float = 2.9
    """Height above the heel axis where a jibing sail's momentum is stopped.

    Most of the swinging mass and air is the cloth, high on the mast; when the sheet stops
    the boom the mast stops the sail, so the roll impulse is the sail's angular momentum
    times this height over ``sail_ce_aft_m``."""
    boom_inertia_kgm2: float = 15.0
    """Boom and sail about the mast."""
    boom_air_damping: float = 25.0
    """Quadratic air damping of a swinging sail, torque = -k * rate * |rate| (N m s^2)."""
    by_the_lee_rad: float = math.radians(10.0)
    """How far by the lee (wind from aft, on the boom's side) the sail holds before it is
    blown across in a jibe."""
    sheet_min_rad: float = math.radians(4.0)
    """Boom angle with the sheet fully in."""
    sheet_max_rad: float = math.radians(85.0)
    """Boom angle with the sheet fully out (free to swing to the shroudless stop)."""

    hull_drag_forward: float = 0.007
    """C_d * A (m^2) of the hull moving ahead: small."""
    hull_wave_speed_mps: float = 2.4
    """Speed where wave-making doubles the forward drag: ``drag * (1 + (u / u_w)^2)``.

    A 4 m hull makes a bow wave as long as itself near ``sqrt(g L / 2 pi)`` ~ 2.6 m/s;
    past it the boat climbs its own wave and the drag grows much faster than ``u^2``."""
    hull_drag_backward: float = 0.08
    """C_d * A (m^2) moving astern: larger (transom first)."""
    hull_drag_sideways: float = 1.2
    """C_d * A (m^2) of hull and foils moving straight sideways: large."""
    keel_lift_slope: float = 600.0
    """Side force of the centreboard per (forward speed * sideways speed), N s^2/m^2.

    The centreboard is a foil: its side force is ``1/2 rho A C_L_alpha * u * v``
    (``A`` 0.35 m^2, ``C_L_alpha`` about 5 /rad plus the hull's share), so leeway is
    small and almost independent of speed."""
    windage: float = 1.0
    """C_d * A (m^2) of hull, mast and crew in the apparent wind."""

    rudder_max_rad: float = math.radians(30.0)
    rudder_moment_coeff: float = 200.0
    """Yaw moment per rudder angle and forward speed squared, N m / (rad m^2/s^2)."""
    yaw_damping_linear: float = 500.0
    """Hydrodynamic yaw damping per forward speed, N m s / (rad m/s)."""
    yaw_damping_quadratic: float = 400.0
    """Yaw damping at any speed (the hull's end plates), N m s^2/rad^2."""

    crew_righting_nm: float = 600.0
    """Helmsman fully hiked: 76 kg * g * 0.94 m."""
    crew_response_rad: float = math.radians(8.0)
    """Heel at which the helmsman is about 3/4 hiked out."""
    crew_time_s: float = 1.0
    """Time constant of the helmsman moving across the boat."""
    hull_righting_nm: float = 150.0
    """Form stability, moment = -k sin(heel)."""
    heel_damping: float = 350.0
    """N m s/rad."""
    capsize_heel_rad: float = math.radians(60.0)

    def __post_init__(self) -> None:
        if self.sail_model not in SAIL_MODELS:
            raise ValueError(f"sail_model must be one of {SAIL_MODELS}, got {self.sail_model!r}")
        for f in fields(self):
            if f.name == "sail_model":
                continue
            value = getattr(self, f.name)
            if not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
                raise ValueError(f"{f.name} must be a finite number > 0, got {value!r}")
        if self.sheet_min_rad >= self.sheet_max_rad or self.sheet_max_rad > math.pi / 2:
            raise ValueError(
                "sheet_min_rad must be < sheet_max_rad <= pi/2, got "
                f"{self.sheet_min_rad!r}, {self.sheet_max_rad!r}"
            )
        if self.capsize_heel_rad >= math.pi / 2:
            raise ValueError(f"capsize_heel_rad must be < pi/2, got {self.capsize_heel_rad!r}")

    def replace(self, **changes: object) -> DinghyParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


@dataclass
class DinghyState:
    """State of a batch of dinghies; every field has shape ``(batch,)``."""

    x_m: np.ndarray
    y_m: np.ndarray
    heading_rad: np.ndarray
    vx_mps: np.ndarray
    vy_mps: np.ndarray
    yaw_rate_rps: np.ndarray
    heel_rad: np.ndarray
    heel_rate_rps: np.ndarray
    boom_rad: np.ndarray
    boom_rate_rps: np.ndarray
    crew_out: np.ndarray
    """Helmsman's position, -1 (hiked to port) .. +1 (hiked to starboard)."""
    capsized: np.ndarray
    """Bool; once capsized the boat stays down (the sail lies in the water)."""

    def copy(self) -> DinghyState:
        return DinghyState(**{f.name: getattr(self, f.name).copy() for f in fields(self)})

    def select(self, mask: np.ndarray, other: DinghyState) -> DinghyState:
        """Elementwise: ``other`` where ``mask`` else ``self`` (used by vector resets)."""
        return DinghyState(
            **{
                f.name: np.where(mask, getattr(other, f.name), getattr(self, f.name))
                for f in fields(self)
            }
        )


@dataclass
class StepEvents:
    """What happened during one :func:`step`, per boat."""

    jibes: np.ndarray
    """Boom crossings of the centerline with the apparent wind from aft."""
    jibe_severity_rps: np.ndarray
    """Largest boom angular speed at such a crossing (0 if none)."""
    tacks: np.ndarray
    """Bow crossings of the true wind direction."""


def dinghy_at_rest(
    batch: int, x_m=0.0, y_m=0.0, heading_rad=0.0, speed_mps=0.0, boom_rad=0.0
) -> DinghyState:
    """A batch of upright boats moving straight ahead at ``speed_mps``."""

    def full(v: object) -> np.ndarray:
        return np.broadcast_to(np.asarray(v, dtype=np.float64), (batch,)).copy()

    heading = full(heading_rad)
    speed = full(speed_mps)
    zeros = np.zeros(batch)
    return DinghyState(
        x_m=full(x_m),
        y_m=full(y_m),
        heading_rad=heading,
        vx_mps=speed * np.cos(heading),
        vy_mps=speed * np.sin(heading),
        yaw_rate_rps=zeros.copy(),
        heel_rad=zeros.copy(),
        heel_rate_rps=zeros.copy(),
        boom_rad=full(boom_rad),
        boom_rate_rps=zeros.copy(),
        crew_out=zeros.copy(),
        capsized=np.zeros(batch, dtype=bool),
    )


def apparent_wind_body(
    state: DinghyState, wind_x: Array, wind_y: Array, cos_h: Array, sin_h: Array
) -> tuple[Array, Array]:
    """Apparent wind ``v_a = v_w - v_s`` (seed §9) in the body frame: (ahead, to port).

    The vector points where the air moves relative to the boat.
    """
    return split_along(wind_x - state.vx_mps, wind_y - state.vy_mps, cos_h, sin_h)


def sail_normal_coefficient(p: DinghyParams, sin_attack: Array, xp: Any = np) -> Array:
    """Normal-force coefficient ``C_N`` of the flat sail at angle of attack ``alpha``.

    ``F_N = 1/2 rho A C_N |v_a|^2``, perpendicular to the sail.

    * ``"seed"``: the drag formula applied to the wind component perpendicular to the sail
      (§9): ``F_N = 1/2 rho A C_d v_perp^2`` with ``v_perp = |v_a| sin(alpha)``, i.e.
      ``C_N = C_d sin^2(alpha)``.
    * ``"lift"``: a flat plate. Attached flow at small angles gives a normal coefficient
      that grows like ``sin(alpha)`` up to ``sail_cn_peak`` at ``sail_stall_rad``; past the
      stall the flow separates and ``C_N = sail_cn_flat * sin(alpha)`` (Hoerner's flat
      plate). A logistic blend in ``alpha`` joins the two, so the force is smooth.
    """
    if p.sail_model == "seed":
        return p.sail_drag_coefficient * sin_attack * sin_attack
    attack = xp.arcsin(xp.clip(sin_attack, 0.0, 1.0))
    attached = p.sail_cn_peak * sin_attack / math.sin(p.sail_stall_rad)
    separated = p.sail_cn_flat * sin_attack
    attached_share = 1.0 / (1.0 + xp.exp((attack - p.sail_stall_rad) / p.sail_stall_width_rad))
    return attached_share * attached + (1.0 - attached_share) * separated


def sail_force(
    p: DinghyParams, state: DinghyState, aw_u: Array, aw_v: Array, xp: Any = np
) -> tuple[Array, Array, Array]:
    """Force of the planar, friction-free sail (seed §9): ``(drive, side, normal)``.

    Only the apparent-wind component perpendicular to the sail pushes it, so the force is
    along the sail's normal; it pushes the sail (and the boat) to the side the air flows
    to. Heel tilts the sail out of the wind: the effective area is ``A cos(heel)`` (§9
    "tilt"). Returns the body-frame components ``drive`` (ahead) and ``side`` (to port),
    and the signed normal force (``> 0`` pushes the boom to port).
    """
    normal_x, normal_y = xp.sin(state.boom_rad), xp.cos(state.boom_rad)
    wind_normal = aw_u * normal_x + aw_v * normal_y
    speed_sq = aw_u * aw_u + aw_v * aw_v
    sin_attack = xp.abs(wind_normal) / xp.sqrt(xp.maximum(speed_sq, 1e-12))
    area = p.sail_area_m2 * xp.cos(state.heel_rad) * xp.logical_not(state.capsized)
    magnitude = (
        0.5 * AIR_DENSITY_KGM3 * area * sail_normal_coefficient(p, sin_attack, xp) * speed_sq
    )
    # By the lee (wind from aft and from the side the boom is on) the air runs over the sail
    # from leech to luff; a soft sail cannot hold its shape that way and is blown across:
    # the force points to the side the air flows to, and the boom jibes.
    by_the_lee = (aw_u > 0.0) & (
        aw_v * xp.sign(state.boom_rad) < -math.sin(p.by_the_lee_rad) * xp.sqrt(speed_sq)
    )
    direction = xp.where(by_the_lee, -xp.sign(state.boom_rad), xp.sign(wind_normal))
    normal = direction * magnitude
    return normal * normal_x, normal * normal_y, normal


def hull_force(p: DinghyParams, surge: Array, sway: Array, xp: Any = np) -> tuple[Array, Array]:
    """Water force on hull and keel in the body frame, from the velocity split (§9).

    Ahead the hull is slippery, astern less so; sideways the centreboard resists strongly
    (foil lift ~ ``u * v`` while moving ahead, plus quadratic drag of the hull), so the boat
    drifts (leeway) only a little.
    """
    forward_area = xp.where(surge >= 0.0, p.hull_drag_forward, p.hull_drag_backward)
    half_rho = 0.5 * WATER_DENSITY_KGM3
    wave_factor = 1.0 + (surge / p.hull_wave_speed_mps) ** 2
    along = -half_rho * forward_area * wave_factor * surge * xp.abs(surge)
    across = -(p.keel_lift_slope * xp.abs(surge) + half_rho * p.hull_drag_sideways * xp.abs(sway))
    return along, across * sway


def yaw_moment(
    p: DinghyParams, surge: Array, yaw_rate: Array, rudder_rad: Array, xp: Any = np
) -> Array:
    """Rudder moment minus yaw damping.

    The rudder is a foil: its moment grows with forward speed squared, so a boat at rest
    cannot steer (seed §9: "no steering speed"). Moving astern the rudder acts reversed.
    """
    rudder = p.rudder_moment_coeff * surge * xp.abs(surge) * rudder_rad
    damping = p.yaw_damping_linear * xp.abs(surge) + p.yaw_damping_quadratic * xp.abs(yaw_rate)
    return rudder - damping * yaw_rate


def heel_moment(p: DinghyParams, state: DinghyState, sail_side: Array, xp: Any = np) -> Array:
    """Heeling moment of the sail's side force against crew, hull and damping (§9 "tilt").

    The side force acts at the centre of effort, whose height above the heel axis shrinks
    as ``cos(heel)``. The helmsman's weight (``crew_out``) and the hull's form stability
    right the boat.
    """
    cos_heel = xp.cos(state.heel_rad)
    heeling = sail_side * p.sail_ce_height_m * cos_heel
    crew = -p.crew_righting_nm * state.crew_out * cos_heel
    hull = -p.hull_righting_nm * xp.sin(state.heel_rad)
    return heeling + crew + hull - p.heel_damping * state.heel_rate_rps


def boom_limit_from_sheet(p: DinghyParams, sheet: Array, xp: Any = np) -> Array:
    """Largest boom angle the sheet allows: ``sheet`` 0 = fully in, 1 = fully out."""
    return p.sheet_min_rad + xp.clip(sheet, 0.0, 1.0) * (p.sheet_max_rad - p.sheet_min_rad)


def apply_sheet_stop(
    boom: Array, boom_rate: Array, arrival_rate: Array, limit: Array, xp: Any = np
) -> tuple[Array, Array, Array]:
    """The sheet caps the boom angle at ``+-limit``; returns ``(boom, rate, impact_rate)``.

    A boom that reaches the cap while swinging out is stopped dead by the sheet (an
    inelastic stop). ``impact_rate`` is the signed angular speed it arrived with
    (``arrival_rate``, the rate before this substep's push), whose angular momentum the
    sheet hands to the hull (see :func:`substep`): the jolt of a jibe. The further the
    sheet is eased, the longer the boom accelerates and the harder it hits. A sail pressing
    steadily on the sheet arrives with rate 0 each substep and gives no jolt: the sheet load
    is then an internal force.
    """
    over = xp.abs(boom) > limit
    outward = over & (boom * boom_rate > 0.0)
    impact_rate = xp.where(outward & (boom * arrival_rate > 0.0), arrival_rate, 0.0)
    boom = xp.clip(boom, -limit, limit)
    boom_rate = xp.where(outward, 0.0, boom_rate)
    return boom, boom_rate, impact_rate


def substep(
    p: DinghyParams,
    state: DinghyState,
    rudder_rad: Array,
    boom_limit_rad: Array,
    wind_x: Array,
    wind_y: Array,
    dt_s: float,
    xp: Any = np,
) -> tuple[DinghyState, Array]:
    """One semi-implicit Euler step (seed §1, §3): velocities first, then positions.

    Returns the new state and the signed boom angular speed at a sheet-stop impact.
    """
    cos_h, sin_h = xp.cos(state.heading_rad), xp.sin(state.heading_rad)
    surge, sway = split_along(state.vx_mps, state.vy_mps, cos_h, sin_h)
    aw_u, aw_v = apparent_wind_body(state, wind_x, wind_y, cos_h, sin_h)

    drive, side, normal = sail_force(p, state, aw_u, aw_v, xp)
    hull_along, hull_across = hull_force(p, surge, sway, xp)
    # Windage of hull, mast and crew: the only force that pushes a boat in irons astern.
    windage_u, windage_v = quadratic_drag(p.windage, AIR_DENSITY_KGM3, -aw_u, -aw_v, xp=xp)
    force_u = drive + hull_along + windage_u
    force_v = side + hull_across + windage_v
    down = state.capsized
    force_x = cos_h * force_u - sin_h * force_v
    force_y = sin_h * force_u + cos_h * force_v

    yaw_acc = yaw_moment(p, surge, state.yaw_rate_rps, rudder_rad, xp) / p.yaw_inertia_kgm2
    heel_acc = xp.where(down, 0.0, heel_moment(p, state, side, xp) / p.heel_inertia_kgm2)
    boom_torque = p.sail_ce_aft_m * normal - p.boom_air_damping * state.boom_rate_rps * xp.abs(
        state.boom_rate_rps
    )

    vx = state.vx_mps + force_x / p.mass_kg * dt_s
    vy = state.vy_mps + force_y / p.mass_kg * dt_s
    yaw_rate = state.yaw_rate_rps + yaw_acc * dt_s
    heel_rate = xp.where(down, 0.0, state.heel_rate_rps + heel_acc * dt_s)
    boom_rate = state.boom_rate_rps + boom_torque / p.boom_inertia_kgm2 * dt_s

    boom, boom_rate, impact = apply_sheet_stop(
        state.boom_rad + boom_rate * dt_s, boom_rate, state.boom_rate_rps, boom_limit_rad, xp
    )
    # The sheet hands the sail's angular momentum to the hull: all of it to yaw, and a roll
    # impulse from the height where the mast stops the swinging cloth (the jibe's jolt).
    impulse = p.boom_inertia_kgm2 * impact
    yaw_rate = yaw_rate - impulse / p.yaw_inertia_kgm2
    roll_arm = p.boom_impact_heel_arm_m / p.sail_ce_aft_m
    heel_rate = heel_rate + xp.where(down, 0.0, impulse * roll_arm / p.heel_inertia_kgm2)

    heel = state.heel_rad + heel_rate * dt_s
    capsized = down | (xp.abs(heel) > p.capsize_heel_rad)
    # The helmsman reacts to the heel and to how fast it grows (a sailor feels the gust
    # before the boat lies over); the lead term offsets the time it takes to move.
    crew_target = xp.tanh((heel + p.crew_time_s * heel_rate) / p.crew_response_rad)
    crew_out = state.crew_out + (crew_target - state.crew_out) * (dt_s / p.crew_time_s)

    new_state = DinghyState(
        x_m=state.x_m + vx * dt_s,
        y_m=state.y_m + vy * dt_s,
        heading_rad=state.heading_rad + yaw_rate * dt_s,
        vx_mps=vx,
        vy_mps=vy,
        yaw_rate_rps=yaw_rate,
        heel_rad=heel,
        heel_rate_rps=heel_rate,
        boom_rad=boom,
        boom_rate_rps=boom_rate,
        crew_out=xp.where(down, state.crew_out, crew_out),
        capsized=capsized,
    )
    return new_state, impact


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
    """Advance ``n_substeps`` substeps of ``dt_s`` with the controls held.

    ``rudder_rad`` is clipped to ``+-rudder_max_rad``; ``sheet`` in [0, 1] is how far the
    sheet is eased (0 fully in). Counts jibes (the boom crosses the centerline while the
    apparent wind comes from aft, checked every substep: a boom crosses in a fraction of a
    second) and tacks (the bow crosses the true wind between the start and the end of the
    step: a boat turns far less than half a circle in one control step).
    """
    rudder = xp.clip(rudder_rad, -p.rudder_max_rad, p.rudder_max_rad)
    limit = boom_limit_from_sheet(p, sheet, xp)
    wind_from = xp.arctan2(-wind_y, -wind_x)
    jibes = xp.zeros_like(state.x_m, dtype=int)
    severity = xp.zeros_like(state.x_m)
    wind_off_bow = xp.sin(wind_from - state.heading_rad)
    for _ in range(n_substeps):
        previous_boom = state.boom_rad
        state, _impact = substep(p, state, rudder, limit, wind_x, wind_y, dt_s, xp)
        crossed = previous_boom * state.boom_rad < 0.0
        if xp.any(crossed):
            cos_h, sin_h = xp.cos(state.heading_rad), xp.sin(state.heading_rad)
            aw_u, _ = apparent_wind_body(state, wind_x, wind_y, cos_h, sin_h)
            # Air moving forward over the boat (aw_u > 0) means the wind comes from aft.
            jibe = crossed & (aw_u > 0.0)
            jibes = jibes + jibe
            severity = xp.maximum(severity, xp.where(jibe, xp.abs(state.boom_rate_rps), 0.0))
    off_bow = xp.sin(wind_from - state.heading_rad)
    tacks = (off_bow * wind_off_bow < 0.0) & (xp.cos(wind_from - state.heading_rad) > 0.0)
    return state, StepEvents(jibes=jibes, jibe_severity_rps=severity, tacks=tacks + 0)
