"""A sailing dinghy driven by apparent wind through a sheet-controlled sail (seed §9).

Top view in 2D plus heel. Every function is pure and batched: state arrays have a leading
batch axis, parameters live in the frozen :class:`~bbgym.physics.dinghy.DinghyParams`
(:mod:`bbgym.physics.dinghy`). One physical law, one
function:

==========================  ============================================================
law                         function
==========================  ============================================================
apparent wind               :func:`apparent_wind_body`      ``v_a = v_w - v_s`` (§9)
sail normal coefficient     :func:`sail_normal_coefficient` ``"seed"`` / ``"lift"``
cambered sail lift, drag    :func:`cambered_sail_coefficients` ``"cambered"``
sail force and boom torque  :func:`sail_force`              planar, friction-free (§9)
the whole rig's force       :func:`rig_force`               main and jib (wind shadow)
the jib's angle             :func:`jib_angle`               two sheets; backed (§9)
sails that steer            :func:`sail_yaw_moment`         force at the centre of effort
hull and keel drag          :func:`hull_force`              split along/across hull (§9)
rudder and yaw damping      :func:`yaw_moment`              moment ~ forward speed^2
heel and capsize            :func:`heel_moment`             cos(heel) area, hiking (§9)
crew hiking and its lag     :func:`crew_step`               exact first-order lag
sheet stop and jibes        :func:`apply_sheet_stop`        boom jolt (§9 "jibing")
integration                 :mod:`bbgym.physics.sailing_step` semi-implicit Euler (§1, §3)
moving water                :mod:`bbgym.physics.water`        current, Gerstner waves (§10)
energy of a passive boat    :func:`mechanical_energy`       (for tests)
==========================  ============================================================

(Each force function has a ``*_linearised`` twin that also returns the derivative the
integration needs; the plain one returns the force alone.) The integration, which puts the
laws together into a step, is :mod:`bbgym.physics.sailing_step`.


Frames: world x east, y north, angles counterclockwise from +x. Body frame x forward
(surge ``u``), y to port (sway ``v``). Heel ``> 0``: port side down. Boom angle is measured
from the aft-pointing centerline, ``> 0``: boom swung out to port; the boom then points
along ``(-cos(boom), sin(boom))`` in the body frame and the sail's normal (to port) is
``(sin(boom), cos(boom))``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bbgym.physics.common import (
    NORM_FLOOR,
    split_along,
)
from bbgym.physics.dinghy import DinghyParams, DinghyState
from bbgym.physics.namespace import Array


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
    if p.sail_model == "cambered":
        secant, sin_d_secant, _, _ = cambered_sail_coefficients(p, sin_attack, cos_attack, xp)
        return secant, sin_d_secant
    stall, half_inv_width, flat, half_excess, d_coefficient = p._lift
    # (sin_attack may round past 1: clip, or arcsin has a domain error)
    half_x = xp.tanh((xp.asin(xp.clip(sin_attack, 0.0, 1.0)) - stall) * half_inv_width)
    # C_N / sin(alpha): the attached slope (sail_cn_peak / sin(stall)) below the stall, the
    # flat plate's (sail_cn_flat) above it.
    secant = flat + half_excess * (1.0 - half_x)
    return secant, sin_attack * d_coefficient * (1.0 - half_x * half_x)


def cambered_sail_coefficients(
    p: DinghyParams, sin_attack: Array, cos_attack: Array, xp: Any = np
) -> tuple[Array, Array, Array, Array]:
    """A cambered sail's force as normal and chordwise coefficients, from its lift and
    drag: ``(S, sin(alpha) dS/dalpha, C_T, dC_T/dalpha)`` with ``S = C_N / sin(alpha)`` (see
    :func:`sail_normal_coefficients`) and ``C_T`` the force along the chord toward the luff
    (the leading edge).

    Lift is across the apparent wind, drag along it. Attached flow (below
    ``sail_stall_rad``): ``C_L = a sin(alpha)`` with ``a = sail_cl_peak / sin(stall)``, and
    ``C_D = C_D0 + k C_L^2`` (parasitic plus induced drag). Separated flow: a flat plate,
    whose force ``sail_cn_flat sin(alpha)`` is normal to it (``C_L = cn sin cos``,
    ``C_D = C_D0 + cn sin^2``). The same logistic blend as the ``"lift"`` model joins them.
    In the sail's axes ``C_N = C_L cos + C_D sin`` and ``C_T = C_L sin - C_D cos``: where
    the lift-to-drag ratio beats ``cot(alpha)`` the force leans forward of the normal and
    pulls the sail (and the boat) along its chord, which a flat sail's cannot. Both
    coefficients are symmetric in the side the wind is on, as a soft sail's camber flips
    with it; at ``alpha = 0`` the sail luffs (``C_N = 0``) and only the parasitic drag pulls.
    """
    stall, half_inv_width = p._lift[0], p._lift[1]
    slope, induced = p._cambered
    flat, parasitic = p.sail_cn_flat, p.sail_drag_parasitic
    s, c = sin_attack, cos_attack
    t = xp.tanh((xp.asin(xp.clip(s, 0.0, 1.0)) - stall) * half_inv_width)
    attached = 0.5 * (1.0 - t)
    d_attached = (-0.5 * half_inv_width) * (1.0 - t * t)
    # C_L = s L, C_D = C_D0 + s^2 D; their derivatives in alpha dL, dD
    lift = attached * slope + (1.0 - attached) * flat * c
    drag = attached * induced + (1.0 - attached) * flat
    d_lift = d_attached * (slope - flat * c) - (1.0 - attached) * flat * s
    d_drag = d_attached * (induced - flat)
    s2 = s * s
    drag_coefficient = parasitic + s2 * drag
    secant = lift * c + drag_coefficient
    d_secant = d_lift * c - lift * s + 2.0 * s * c * drag + s2 * d_drag
    chord = s2 * lift - c * drag_coefficient
    d_chord = (
        2.0 * s * c * lift
        + s2 * d_lift
        + s * drag_coefficient
        - c * (2.0 * s * c * drag + s2 * d_drag)
    )
    return secant, s * d_secant, chord, d_chord


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
    sail_q: float | None = None,
) -> tuple[Array, Array, Array, Array, Array, Array]:
    """Force of the planar, friction-free sail (seed §9) and its stiffnesses.

    ``boom_rad`` is the sail's angle off the aft-pointing centreline (the main's boom, or
    the jib's foot with ``sail_q`` its ``1/2 rho A``; the main's by default).

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

    A cambered sail (``sail_model="cambered"``) adds the chordwise part of its lift and
    drag (:func:`cambered_sail_coefficients`), toward the leading edge where lift beats
    drag: it drives the boat but passes through the mast, so it does not turn the boom, and
    its rate of change bounds ``c_n`` from above as well.

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
    inv_speed = 1.0 / xp.maximum(speed, NORM_FLOOR)  # finite in a calm (components 0)
    wind_normal_abs = xp.abs(wind_normal)
    sin_attack = wind_normal_abs * inv_speed
    cos_attack = xp.abs(wind_chord) * inv_speed
    secant, sin_d_secant = sail_normal_coefficients(p, sin_attack, cos_attack, xp)
    q = p._sail_q if sail_q is None else sail_q
    q_speed = xp.where(upright, q * cos_heel * speed, 0.0)
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
    drive, side = pressure * normal_u, pressure * normal_v
    if p.sail_model == "cambered":
        # The chordwise force (toward the leading edge, upwind along the chord) acts
        # through the mast and does not turn the boom. Its rate of change with the boat's
        # velocity is at most q |v_a| (2 |C_T| + |dC_T/dalpha|): added to the damping
        # bound, so the step stays linearly implicit.
        _, _, chord, d_chord = cambered_sail_coefficients(p, sin_attack, cos_attack, xp)
        pull = (q_speed * speed) * chord * xp.sign(wind_chord)
        drive, side = drive + pull * normal_v, side - pull * normal_u
        c_n = c_n + q_speed * (2.0 * xp.abs(chord) + xp.abs(d_chord))
    return drive, side, normal, c_n, k_boom, speed


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


def jib_angle(p: DinghyParams, jib_sheet: Array, aw_u: Array, aw_v: Array, xp: Any = np) -> Array:
    """The jib's angle off the aft-pointing centreline (``> 0``: clew to port) for its
    sheets and the apparent wind (body frame).

    A jib has two sheets, one to each side, and no boom. ``jib_sheet`` in [-1, 1] pulls the
    port sheet (``> 0``) or the starboard one (``< 0``), ``|jib_sheet|`` how hard: 1 holds
    the clew at ``jib_sheet_min_rad`` on that side, 0 lets it out to ``jib_sheet_max_rad``.
    The sheet is a rope from a fairlead on its side: the more it is eased, the further the
    clew can swing out on that side and across to the other, to ``2 min - limit`` (the
    angles it reaches are symmetric about the fairlead's). Within that range the light
    cloth takes its place at once (no state), along the flow to leeward, where it luffs
    unless the range stops it.

    Pulled on the leeward side, the sheet trims the jib. Pulled on the windward side, it
    holds the jib against the wind: backed. The wind then pushes the jib, and the bow, to
    leeward: seed §9's trick for a boat stopped head to wind, and what a jib kept on the
    old sheet does in a tack as the bow passes through the wind.
    """
    leeward = xp.where(aw_v >= 0.0, 1.0 + 0.0 * aw_v, -1.0)  # where the air flows (+ port)
    free = leeward * xp.atan2(xp.abs(aw_v), -aw_u)  # the foot along the flow: luffing
    pull = xp.abs(jib_sheet)
    limit = p.jib_sheet_max_rad - pull * (p.jib_sheet_max_rad - p.jib_sheet_min_rad)
    across = 2.0 * p.jib_sheet_min_rad - limit  # how far it reaches on the other side
    port = jib_sheet >= 0.0
    high = xp.where(port, limit, -across)
    low = xp.where(port, across, -limit)
    return xp.minimum(xp.maximum(free, low), high)


def rig_force(
    p: DinghyParams,
    state: DinghyState,
    jib_sheet: Array | None,
    aw_u: Array,
    aw_v: Array,
    xp: Any = np,
) -> tuple[Array, Array]:
    """The force of all the boat's sails in the apparent wind ``(aw_u, aw_v)``, body frame
    (``drive`` ahead, ``side`` to port): the main's (:func:`sail_force`) and a sloop's
    jib's at its angle for ``jib_sheet`` (:func:`jib_angle`; None: its sheets eased).
    What the rig takes from the air (:mod:`bbgym.physics.shadow`)."""
    drive, side, _ = sail_force(p, state, aw_u, aw_v, xp)
    if p.rig == "sloop":
        jib = jib_angle(p, 0.0 * aw_u if jib_sheet is None else jib_sheet, aw_u, aw_v, xp)
        upright = xp.logical_not(state.capsized)
        jib_drive, jib_side = sail_force_linearised(
            p, jib, xp.cos(state.heel_rad), upright, aw_u, aw_v, xp, p._jib_q
        )[:2]
        drive, side = drive + jib_drive, side + jib_side
    return drive, side


def sail_yaw_moment(
    ahead_m: float,
    along_m: float,
    height_m: float,
    angle_rad: Array,
    sin_heel: Array,
    drive: Array,
    side: Array,
    xp: Any = np,
) -> Array:
    """Yaw moment about the hull's centre of lateral resistance of a sail's force
    (``drive`` ahead, ``side`` to port) acting at its centre of effort: ``along_m`` from
    the sail's foot end (mast or tack, ``ahead_m`` ahead of the centre) along a foot at
    ``angle_rad``, and ``height_m`` up the mast, which heel leans to the low side:
    ``x = ahead - along cos(angle)``, ``y = along sin(angle) + height sin(heel)``,
    ``M = x side - y drive`` (counterclockwise: the bow to port).

    A sail sheeted in, its centre aft of the centreboard, turns the bow into the wind
    (weather helm); the jib, ahead of it, turns it away; eased, the main's drive acts out
    to leeward; heeled, both act further to leeward: more weather helm (seed §9, "Controlling
    the sail").
    """
    x = ahead_m - along_m * xp.cos(angle_rad)
    y = along_m * xp.sin(angle_rad) + height_m * sin_heel
    return x * side - y * drive


def hull_force_linearised(
    p: DinghyParams, surge: Array, sway: Array, xp: Any = np
) -> tuple[Array, Array, Array, Array]:
    """Water force on hull and keel in the body frame, from the velocity split (§9), and
    its derivatives ``(along, across, -d along/d surge, -d across/d sway)``.

    Ahead the hull is slippery, astern less so, with wave making past ``u_w``:
    ``along = -1/2 rho CdA (1 + W) u |u|``, ``W = u^2/u_w^2``; a planing hull
    (``hull_planing_speed_mps`` ``u_p > 0``) rises out of its wave, ``W = (u/u_w)^2 /
    (1 + (u/u_p)^2)``, which levels off at ``(u_p/u_w)^2``. Sideways the centreboard resists
    strongly (foil lift ~ ``u * v`` while moving ahead, plus quadratic drag of the hull):
    ``across = -(k |u| + 1/2 rho CdA_side |v|) v``, so the boat drifts (leeway) only a
    little. The derivatives (>= 0) are the damping rates :func:`substep` integrates
    implicitly.
    """
    ahead_minus_astern, astern, inv_wave_speed_sq, side = p._hull
    speed_u = xp.abs(surge)
    drag_u = (astern + xp.where(surge >= 0.0, ahead_minus_astern, 0.0 * surge)) * speed_u
    surge_sq = surge * surge
    wave = surge_sq * inv_wave_speed_sq
    keel = p.keel_lift_slope * speed_u
    drag_v = side * xp.abs(sway)
    across = -(keel + drag_v) * sway
    if not p._inv_planing_sq:  # a displacement hull: d(u^2 (1 + W))/du = u (2 + 4 W)
        return (
            -drag_u * (1.0 + wave) * surge,
            across,
            drag_u * (2.0 + 4.0 * wave),
            keel + 2.0 * drag_v,
        )
    # Planing: W = (u/u_w)^2 / (1 + (u/u_p)^2) levels off, and
    # d(u^2 (1 + W))/du = u (2 + 2 W + 2 W / (1 + (u/u_p)^2)).
    inv_rise = 1.0 / (1.0 + surge_sq * p._inv_planing_sq)
    wave = wave * inv_rise
    rate = drag_u * (2.0 + 2.0 * wave * (1.0 + inv_rise))
    return -drag_u * (1.0 + wave) * surge, across, rate, keel + 2.0 * drag_v


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
