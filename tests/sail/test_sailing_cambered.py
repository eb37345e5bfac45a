"""The cambered sail (lift and drag, a force that leans forward of the sail's normal) and the
planing hull, with numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.common import AIR_DENSITY_KGM3, WATER_DENSITY_KGM3
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.sailing import (
    cambered_sail_coefficients,
    hull_force_linearised,
    sail_force_linearised,
    sail_normal_coefficient,
)

P = DinghyParams(sail_model="cambered")
ALPHA = np.radians(np.linspace(0.2, 89.8, 400))


def coefficients(p: DinghyParams, alpha: np.ndarray):
    return cambered_sail_coefficients(p, np.sin(alpha), np.cos(alpha))


def lift_and_drag(p: DinghyParams, alpha: np.ndarray):
    """C_L and C_D back from the sail-axis coefficients."""
    secant, _, chord, _ = coefficients(p, alpha)
    normal = np.sin(alpha) * secant
    return (
        normal * np.cos(alpha) + chord * np.sin(alpha),
        normal * np.sin(alpha) - chord * np.cos(alpha),
    )


def test_lift_and_drag_are_the_polar_it_states():
    # Well below the stall the flow is attached: C_L = a sin(alpha), C_D = C_D0 + k C_L^2.
    # (a sharp stall, so that the blend is all attached flow there)
    sharp = P.replace(sail_stall_width_rad=math.radians(0.5))
    alpha = np.radians(np.array([2.0, 5.0, 8.0]))
    lift, drag = lift_and_drag(sharp, alpha)
    slope = P.sail_cl_peak / math.sin(P.sail_stall_rad)
    attached = 0.5 * (1.0 - np.tanh((alpha - P.sail_stall_rad) / math.radians(1.0)))
    assert attached.min() > 1.0 - 1e-6
    np.testing.assert_allclose(lift, slope * np.sin(alpha), rtol=1e-6)
    np.testing.assert_allclose(
        drag, P.sail_drag_parasitic + P.sail_drag_induced * lift**2, rtol=1e-6
    )
    # Broadside the sail is a flat plate: no lift, drag C_D0 + cn_flat, all of it normal.
    secant, _, chord, _ = coefficients(P, np.array([math.pi / 2]))
    assert chord[0] == pytest.approx(0.0, abs=1e-9)
    assert secant[0] == pytest.approx(P.sail_cn_flat + P.sail_drag_parasitic, rel=1e-9, abs=1e-9)
    # Luffing (alpha = 0): no normal force, the parasitic drag pulls aft along the chord.
    secant, _, chord, _ = cambered_sail_coefficients(P, np.array([0.0]), np.array([1.0]))
    assert 0.0 * secant[0] == 0.0 and chord[0] == pytest.approx(-P.sail_drag_parasitic)


def test_derivatives_match_finite_differences():
    h = 1e-6
    secant, sin_d_secant, chord, d_chord = coefficients(P, ALPHA)
    up, down = coefficients(P, ALPHA + h), coefficients(P, ALPHA - h)
    np.testing.assert_allclose(
        sin_d_secant, np.sin(ALPHA) * (up[0] - down[0]) / (2 * h), rtol=1e-5, atol=1e-8
    )
    np.testing.assert_allclose(d_chord, (up[2] - down[2]) / (2 * h), rtol=1e-5, atol=1e-8)


def test_the_force_leans_forward_where_lift_beats_drag():
    # Attached flow at a beating angle of attack: L/D well above cot(alpha), so the chord
    # force pulls toward the luff; a flat sail's force (the "lift" model) is normal only.
    alpha = np.radians(np.array([8.0, 12.0, 16.0]))
    lift, drag = lift_and_drag(P, alpha)
    assert (lift / drag > 4.0).all()
    assert (coefficients(P, alpha)[2] > 0.0).all()
    # ... and the normal force is the one a flat sail of the same normal coefficient has.
    np.testing.assert_allclose(
        sail_normal_coefficient(P, np.sin(alpha)),
        np.sin(alpha) * coefficients(P, alpha)[0],
        rtol=1e-12,
    )


def test_sail_force_is_normal_plus_chord_and_only_the_normal_turns_the_boom():
    # Boom 15 deg out to starboard, apparent wind from 35 deg off the port bow at 5 m/s.
    boom = np.array([-math.radians(15.0)])
    aw_angle = math.radians(35.0)
    aw_u, aw_v = np.array([-5.0 * math.cos(aw_angle)]), np.array([-5.0 * math.sin(aw_angle)])
    one, upright = np.array([1.0]), np.array([True])
    drive, side, normal, _, _, speed = sail_force_linearised(P, boom, one, upright, aw_u, aw_v)
    alpha = aw_angle - math.radians(15.0)
    secant, _, chord, _ = coefficients(P, np.array([alpha]))
    q = 0.5 * AIR_DENSITY_KGM3 * P.sail_area_m2 * 25.0
    # The boom is pushed to leeward (starboard) by the normal force alone.
    assert normal[0] == pytest.approx(-q * math.sin(alpha) * secant[0], rel=1e-9)
    # The boat gets the normal force and the chord force toward the luff (forward).
    n = np.array([math.sin(boom[0]), math.cos(boom[0])])
    luffward = np.array([math.cos(boom[0]), -math.sin(boom[0])])
    expected = normal[0] * n + q * chord[0] * luffward
    np.testing.assert_allclose([drive[0], side[0]], expected, rtol=1e-9)
    assert drive[0] > 0.0 and side[0] < 0.0 and speed[0] == pytest.approx(5.0)
    # The flat "lift" sail gets less drive from the same wind and the same normal coefficient.
    flat = P.replace(sail_model="lift")
    flat_drive = sail_force_linearised(flat, boom, one, upright, aw_u, aw_v)[0]
    assert drive[0] > flat_drive[0] + q * chord[0] * math.cos(boom[0]) * 0.5


def test_mirror_wind_mirrors_the_force():
    boom = np.array([-0.3, 0.3])
    aw_u, aw_v = np.array([-3.0, -3.0]), np.array([-4.0, 4.0])
    one, upright = np.ones(2), np.ones(2, dtype=bool)
    drive, side, normal, c_n, k_boom, _ = sail_force_linearised(P, boom, one, upright, aw_u, aw_v)
    assert drive[0] == pytest.approx(drive[1], rel=1e-12)
    assert side[0] == pytest.approx(-side[1], rel=1e-12)
    assert normal[0] == pytest.approx(-normal[1], rel=1e-12)
    assert c_n[0] == pytest.approx(c_n[1]) and k_boom[0] == pytest.approx(k_boom[1])


def test_planing_hull_levels_its_wave_drag_off():
    p = DinghyParams(hull_planing_speed_mps=3.0)
    surge = np.linspace(0.1, 12.0, 200)
    zero = np.zeros_like(surge)
    along, _, rate, _ = hull_force_linearised(p, surge, zero)
    skin = 0.5 * WATER_DENSITY_KGM3 * p.hull_drag_forward * surge**2
    wave = (surge / p.hull_wave_speed_mps) ** 2 / (1.0 + (surge / 3.0) ** 2)
    np.testing.assert_allclose(-along, skin * (1.0 + wave), rtol=1e-12)
    # The rate the implicit step uses is the slope of the drag.
    h = 1e-6
    slope = -(
        hull_force_linearised(p, surge + h, zero)[0] - hull_force_linearised(p, surge - h, zero)[0]
    ) / (2 * h)
    np.testing.assert_allclose(rate, slope, rtol=1e-6)
    # Far past u_p the wave part tends to (u_p / u_w)^2 of the skin drag.
    assert wave[-1] == pytest.approx((3.0 / p.hull_wave_speed_mps) ** 2, rel=0.07)
    # A displacement hull (the default, u_p = 0) has the first versions' drag, to the bit.
    displacement = hull_force_linearised(DinghyParams(), surge, zero)
    u_w2 = DinghyParams().hull_wave_speed_mps ** 2
    np.testing.assert_allclose(-displacement[0], skin * (1.0 + surge**2 / u_w2), rtol=1e-12)
    assert (-along <= -displacement[0] + 1e-9).all()


@pytest.mark.parametrize("planing_mps", [1e-200, 1e-7, 1e-3])
def test_a_hull_that_planes_at_once_has_only_skin_drag_and_stays_finite(planing_mps):
    """u_p -> 0: the wave drag levels off at (u_p / u_w)^2 of the skin drag, nothing. Tiny
    u_p once divided by zero (found by the fuzzer); float32 must not make inf * 0 at rest."""
    torch = pytest.importorskip("torch")
    p = DinghyParams(hull_planing_speed_mps=planing_mps)
    surge = np.array([0.0, 0.5, 3.0, 12.0])
    along, _, rate, _ = hull_force_linearised(p, surge, 0.0 * surge)
    skin = 0.5 * WATER_DENSITY_KGM3 * p.hull_drag_forward * surge**2
    # W <= (u_p / u_w)^2: 2e-7 of the skin drag at u_p = 1 mm/s, below 1e-11 under 1e-6 m/s
    np.testing.assert_allclose(
        -along, skin, rtol=(planing_mps / p.hull_wave_speed_mps) ** 2 + 1e-11
    )
    assert np.isfinite(rate).all()
    from array_api_compat import torch as xp

    t = torch.tensor(surge, dtype=torch.float32)
    along32, _, rate32, _ = hull_force_linearised(p, t, 0.0 * t, xp)
    assert torch.isfinite(along32).all() and torch.isfinite(rate32).all()
    np.testing.assert_allclose(-along32.numpy(), skin, rtol=1e-5)
