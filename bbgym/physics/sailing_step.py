"""The dinghy's step: the laws of :mod:`bbgym.physics.sailing` integrated in time.

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
(``tests/sail/test_sailing_stability.py``); the error is first order in ``dt`` (a course sailed
40 s at 0.05 s ends within a metre of a 20x finer integration).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import AIR_DENSITY_KGM3, quadratic_drag_rate, split_along
from bbgym.physics.dinghy import DinghyParams, DinghyState, StepEvents
from bbgym.physics.namespace import Array, replaced
from bbgym.physics.sailing import (
    apparent_wind_body,
    apply_sheet_stop,
    boom_limit_from_sheet,
    crew_step,
    heel_moment_linearised,
    hull_force_linearised,
    jib_angle,
    sail_force_linearised,
    sail_yaw_moment,
    yaw_moment_linearised,
)
from bbgym.physics.water import Sea, WaterFlow, WaterParams, water_over


def substep(
    p: DinghyParams,
    state: DinghyState,
    rudder_rad: Array,
    boom_limit_rad: Array,
    wind_x: Array,
    wind_y: Array,
    dt_s: float,
    xp: Any = np,
    water: WaterFlow | None = None,
    jib_sheet: Array | None = None,
) -> tuple[DinghyState, Array, Array]:
    """One semi-implicit Euler step (seed §1, §3): velocities first, then positions, with
    the stiff terms linearised and integrated implicitly (see the module docstring).

    ``water`` is the water where the boat is over the substep
    (:func:`bbgym.physics.water.water_over`); None is still water (the first versions'
    boat, whose bits it keeps). Hull, centreboard and rudder act on the velocity through
    the water (seed §9: "relative the water, if that moves"), the sail and windage on the
    velocity through the air (the apparent wind), and the pressure that accelerates the
    water in a wave accelerates the boat floating in it by as much (the Froude-Krylov force
    ``m a_water`` of a body whose displaced water weighs what it does). The boat moves with
    the water particle it floats on plus its velocity relative to it: with nothing else
    pushing, it follows the particle's orbit exactly, at any step size.

    A sloop (``p.rig``) has a jib as well, trimmed by ``jib_sheet``
    (:func:`~bbgym.physics.sailing.jib_angle`; None: its sheets eased, 0), and each sail's
    force acts at its centre of
    effort: the sails turn the boat (:func:`~bbgym.physics.sailing.sail_yaw_moment`) and
    the jib heels it from its own height.

    The forces come from the state at the start of the substep; then each velocity takes
    its implicit update, one law each: the hull (:func:`_hull_velocity`), the boom and its
    sheet stop (:func:`_boom_update`), yaw (:func:`_yaw_rate`), heel with the crew
    (:func:`_heel_update`). Returns the new state, the signed boom angular speed at a
    sheet-stop impact, and whether the boom jibed (crossed the centreline with the air
    moving forward over the boat: the wind from aft).
    """
    h = dt_s
    cos_h, sin_h = xp.cos(state.heading_rad), xp.sin(state.heading_rad)
    if water is None:
        surge, sway = split_along(state.vx_mps, state.vy_mps, cos_h, sin_h)
    else:  # through the water
        rel_x, rel_y = state.vx_mps - water.vx_mps, state.vy_mps - water.vy_mps
        surge, sway = split_along(rel_x, rel_y, cos_h, sin_h)
    aw_u, aw_v = apparent_wind_body(state, wind_x, wind_y, cos_h, sin_h)
    cos_heel, sin_heel = xp.cos(state.heel_rad), xp.sin(state.heel_rad)
    upright = xp.logical_not(state.capsized)

    drive, side, normal, c_sail, k_boom, aw_speed = sail_force_linearised(
        p, state.boom_rad, cos_heel, upright, aw_u, aw_v, xp
    )
    heeling_side, sail_moment = side, None
    if p.rig == "sloop":
        jib = jib_angle(p, 0.0 * aw_u if jib_sheet is None else jib_sheet, aw_u, aw_v, xp)
        jib_drive, jib_side, _, c_jib, _, _ = sail_force_linearised(
            p, jib, cos_heel, upright, aw_u, aw_v, xp, p._jib_q
        )
        sail_moment = sail_yaw_moment(
            p.mast_ahead_m,
            p.sail_ce_aft_m,
            p.sail_ce_height_m,
            state.boom_rad,
            sin_heel,
            drive,
            side,
            xp,
        ) + sail_yaw_moment(
            p.jib_tack_ahead_m,
            p.jib_ce_aft_m,
            p.jib_ce_height_m,
            jib,
            sin_heel,
            jib_drive,
            jib_side,
            xp,
        )
        # the heel moment takes the side force at the main's height: the jib's, scaled
        heeling_side = side + p._jib_heel_ratio * jib_side
        drive, side, c_sail = drive + jib_drive, side + jib_side, c_sail + c_jib
    push_u, push_v = drive, side
    if water is not None:  # the Froude-Krylov force (body frame); it does not heel the boat
        accel_x = (water.next_vx_mps - water.vx_mps) * (1.0 / h)
        accel_y = (water.next_vy_mps - water.vy_mps) * (1.0 / h)
        accel_u, accel_v = split_along(accel_x, accel_y, cos_h, sin_h)
        push_u, push_v = drive + p.mass_kg * accel_u, side + p.mass_kg * accel_v
    vx, vy = _hull_velocity(
        p, state, cos_h, sin_h, surge, sway, aw_u, aw_v, aw_speed, push_u, push_v, c_sail, h, xp
    )
    boom, boom_rate, impact = _boom_update(p, state, normal, k_boom, boom_limit_rad, h, xp)
    # The sheet hands the sail's angular momentum to the hull: all of it to yaw, and a roll
    # impulse from the height where the mast stops the swinging cloth (the jibe's jolt).
    # Both enter the implicit updates below as part of the substep's angular impulse, so
    # the damping acts on them as on any moment (added after the damping, a jolt would
    # turn the boat by h * its rate more than the continuous motion does).
    impulse = p.boom_inertia_kgm2 * impact
    yaw_rate = _yaw_rate(p, state, surge, rudder_rad, impulse, h, xp, sail_moment)
    heel, heel_rate, crew, capsized = _heel_update(
        p, state, cos_heel, sin_heel, upright, heeling_side, impulse, h, xp
    )
    if water is None:
        x, y = state.x_m + h * vx, state.y_m + h * vy
    else:  # the water particle's own move, and the boat's relative to it
        x = state.x_m + water.shift_x_m + h * (vx - water.next_vx_mps)
        y = state.y_m + water.shift_y_m + h * (vy - water.next_vy_mps)
    new_state = DinghyState(
        x,
        y,
        state.heading_rad + h * yaw_rate,
        vx,
        vy,
        yaw_rate,
        heel,
        heel_rate,
        boom,
        boom_rate,
        crew,
        capsized,
    )
    jibe = (state.boom_rad * boom < 0.0) & (aw_u > 0.0)
    return new_state, impact, jibe


def _hull_velocity(
    p: DinghyParams,
    state: DinghyState,
    cos_h: Array,
    sin_h: Array,
    surge: Array,
    sway: Array,
    aw_u: Array,
    aw_v: Array,
    aw_speed: Array,
    drive: Array,
    side: Array,
    c_sail: Array,
    h: float,
    xp: Any,
) -> tuple[Array, Array]:
    """The boat's new world velocity: sail (``drive``, ``side``, with any force on the
    boat as a whole), hull and windage forces, linearly implicit in the body frame (module
    docstring); ``surge`` and ``sway`` are through the water."""
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
    p: DinghyParams,
    state: DinghyState,
    normal: Array,
    k_boom: Array,
    boom_limit_rad: Array,
    h: float,
    xp: Any,
) -> tuple[Array, Array, Array]:
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
    p: DinghyParams,
    state: DinghyState,
    surge: Array,
    rudder_rad: Array,
    impulse: Array,
    h: float,
    xp: Any,
    sail_moment: Array | None = None,
) -> Array:
    """The new yaw rate: rudder and damping (:func:`yaw_moment_linearised`), implicit, with
    the sheet's angular ``impulse`` and the sails' moment (a sloop's; explicit)."""
    yaw, c_yaw = yaw_moment_linearised(p, surge, state.yaw_rate_rps, rudder_rad, xp)
    if sail_moment is not None:
        yaw = yaw + sail_moment
    return state.yaw_rate_rps + (h * yaw - impulse) / (p.yaw_inertia_kgm2 + h * c_yaw)


def _heel_update(
    p: DinghyParams,
    state: DinghyState,
    cos_heel: Array,
    sin_heel: Array,
    upright: Array,
    side: Array,
    impulse: Array,
    h: float,
    xp: Any,
) -> tuple[Array, Array, Array, Array]:
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
    sea: Sea | None = None
    """The water's state (its clock runs with the substeps); None for still water."""
    jib_sheet: Array | None = None
    """A sloop's jib sheet, held (None for a cat rig)."""


def step_begin(
    p: DinghyParams,
    state: DinghyState,
    rudder_rad: Array,
    sheet: Array,
    wind_x: Array,
    wind_y: Array,
    xp: Any = np,
    sea: Sea | None = None,
    jib_sheet: Array | None = None,
) -> StepCarry:
    """Start a :func:`step`: clip the controls and hold them, with the wind; ``sea`` is
    the water at the start (None: still water); ``jib_sheet`` in [-1, 1] a sloop's."""
    rudder = xp.clip(rudder_rad, -p.rudder_max_rad, p.rudder_max_rad)
    limit = boom_limit_from_sheet(p, sheet, xp)
    jibes = xp.zeros_like(state.x_m, dtype=xp.int64)
    if p.rig == "sloop" and jib_sheet is not None:
        jib_sheet = xp.clip(jib_sheet, -1.0, 1.0)
    elif p.rig == "cat":
        jib_sheet = None
    return StepCarry(
        state, rudder, limit, wind_x, wind_y, jibes, xp.zeros_like(state.x_m), sea, jib_sheet
    )


def step_substep(
    p: DinghyParams,
    carry: StepCarry,
    dt_s: float,
    xp: Any = np,
    water: WaterParams | None = None,
) -> StepCarry:
    """One substep of a :func:`step`, counting jibes (the boom crosses the centerline while
    the apparent wind comes from aft, checked every substep: a boom crosses in a fraction
    of a second) and keeping the fastest boom speed at one. With a sea, ``water`` says how
    it moves; the water where the boat is holds over the substep."""
    flow, sea = None, carry.sea
    if sea is not None:
        flow = water_over(water, sea, carry.boat.x_m, carry.boat.y_m, dt_s, xp)
        sea = replaced(sea, time_s=sea.time_s + dt_s)
    state, _impact, jibe = substep(
        p,
        carry.boat,
        carry.rudder_rad,
        carry.boom_limit_rad,
        carry.wind_x,
        carry.wind_y,
        dt_s,
        xp,
        flow,
        carry.jib_sheet,
    )
    jibes = carry.jibes + xp.astype(jibe, xp.int64)
    severity = xp.maximum(carry.jibe_severity_rps, xp.where(jibe, xp.abs(state.boom_rate_rps), 0.0))
    return replaced(carry, boat=state, jibes=jibes, jibe_severity_rps=severity, sea=sea)


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
    water: WaterParams | None = None,
    sea: Sea | None = None,
    jib_sheet: Array | None = None,
) -> tuple[DinghyState, StepEvents]:
    """Advance ``n_substeps`` substeps of ``dt_s`` (:func:`substep`) with the controls held;
    in moving water, ``water`` and the ``sea`` at the start (its clock is the caller's); a
    sloop's ``jib_sheet`` in [-1, 1] (the port sheet above 0, the starboard one below,
    :func:`~bbgym.physics.sailing.jib_angle`).

    ``rudder_rad`` is clipped to ``+-rudder_max_rad``; ``sheet`` in [0, 1] is how far the
    sheet is eased (0 fully in). Counts jibes and tacks (:func:`step_substep`,
    :func:`step_end`). A compiled backend runs the same three parts, compiling the substep
    once rather than unrolling the loop.
    """
    carry = step_begin(p, state, rudder_rad, sheet, wind_x, wind_y, xp, sea, jib_sheet)
    for _ in range(n_substeps):
        carry = step_substep(p, carry, dt_s, xp, water)
    return step_end(p, state, carry, xp)
