"""§8's panels and planes (``bbgym.scenes.flight``): the wind panel's normal force,
terminal speed, glide and tumbling; the aeroplane's trim, turns, the propeller's gyro
effect and gusts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2
from bbgym.scenes import get_scene, simulate
from bbgym.scenes.flight import (
    AIRFRAME,
    body_axes,
    panel_normal_force,
    propeller_gyro_torque,
    turned,
)

FLAT, TILTED, SPINNING, EDGE_ON = 0, 1, 2, 3
LEVEL, LEFT, RIGHT, GUSTS = 0, 1, 2, 3


def rotation_matrix(state, k: int) -> np.ndarray:
    axes = body_axes((state.qw[k], state.qx[k], state.qy[k], state.qz[k]))
    return np.array(axes).T  # columns: the body's axes in the world


def test_confetti_normal_force_terminal_speed_glide_and_rocking() -> None:
    """§8, the wind panel. In still air: the flat panel falls straight at
    sqrt(2 m g / (rho C A)) (1.672 m/s for the card, reached to 1e-6) and never turns; the
    edge-on panel feels nothing and falls as in a vacuum (the semi-implicit step's exact
    sum); the panel tilted +20 deg glides toward its lean (+x) until it first turns
    broadside, the one tilted -20 deg exactly mirrors it, and then they rock over and
    tumble: their tilt swings between broadside (< 2 deg) and upside down (> 170 deg) again
    and again, and their fall speeds up and slows (by more than 1 m/s). The orientation
    stays orthonormal (R^T R = I to 1e-9) for every panel, with the default wind too."""
    scene = get_scene("confetti")
    states: list = []
    run = simulate(scene, {"wind_speed_mps": 0.0}, on_step=lambda p, s: states.append(s))
    p, m = run.params, run.measures
    assert p.terminal_speed_mps() == pytest.approx(
        math.sqrt(2 * 0.2 * 0.01 * GRAVITY_MPS2 / (AIR_DENSITY_KGM3 * 1.17 * 0.01))
    )
    vz, height = m["vertical_velocity_mps"], m["height_m"]
    flying = height[:, FLAT] > 0.0
    assert -vz[flying, FLAT][-1] == pytest.approx(p.terminal_speed_mps(), rel=1e-6)
    assert np.all(m["tilt_deg"][:, FLAT] == 0.0) and np.all(m["drift_m"][:, FLAT] == 0.0)
    n = np.arange(len(run.times_s))
    edge = height[:, EDGE_ON] > 0.0
    np.testing.assert_allclose(vz[edge, EDGE_ON], -GRAVITY_MPS2 * p.dt_s * n[edge], rtol=1e-12)
    np.testing.assert_allclose(m["tilt_deg"][:, EDGE_ON], 90.0, atol=1e-9)
    mirrored = simulate(scene, {"wind_speed_mps": 0.0, "tilt_deg": -20.0}).measures
    tilt = m["tilt_deg"][:, TILTED]
    broadside = int(np.argmax(tilt < 1.0))
    assert 0 < broadside and m["drift_m"][broadside, TILTED] > 0.03
    np.testing.assert_allclose(mirrored["drift_m"][:, TILTED], -m["drift_m"][:, TILTED], atol=1e-12)
    in_air = height[:, TILTED] > 0.0
    swings = np.diff((tilt[in_air] > 90.0).astype(int)) != 0
    assert np.sum(swings) >= 10 and tilt[in_air].min() < 2.0 and tilt[in_air].max() > 170.0
    fall = vz[in_air, TILTED]
    late = fall[len(fall) // 4 :]  # after the first swings
    assert late.max() - late.min() > 1.0
    windy: list = []
    simulate(scene, steps=600, on_step=lambda p, s: windy.append(s))
    for state in (states[-1], windy[-1]):
        for k in range(4):
            r = rotation_matrix(state, k)
            np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-9)


def test_panel_force_is_along_the_normal_and_from_the_normal_wind_only() -> None:
    """The force on a panel is along its normal whatever the wind (its component along the
    panel is zero to rounding), it is -1/2 rho C A |u_n| u_n (at dt -> 0), and a wind along
    the panel pushes nothing."""
    rng = np.random.default_rng(1)
    q = tuple(np.array(v) for v in rng.standard_normal(4))
    q = turned(q, (0.0, 0.0, 0.0), 0.01, np)  # normalised
    ex, ey, ez = (np.array(a, dtype=float) for a in body_axes(q))
    for wind in rng.standard_normal((5, 3)) * 5.0:
        u_n = float(wind @ ez)
        f = float(panel_normal_force(1.17, 0.01, 0.002, u_n, 0.0, 1e-12, np))
        force = f * ez
        scale = 1e-15 * np.linalg.norm(force)
        assert abs(force @ ex) < scale and abs(force @ ey) < scale
        assert f * 0.002 == pytest.approx(
            -0.5 * AIR_DENSITY_KGM3 * 1.17 * 0.01 * abs(u_n) * u_n, rel=1e-9
        )
        along = wind - u_n * ez  # the wind's part along the panel: u_n is 0 to rounding
        f_along = panel_normal_force(1.17, 0.01, 0.002, float(along @ ez), 0.0, 0.01, np)
        assert abs(f_along) < 1e-20


def test_aeroplane_trim_turns_gyro_pitch_and_gusts() -> None:
    """§8, the aeroplane. Trimmed at 40 m/s (alpha 5.79 deg, thrust 1172 N), lift and
    thrust hold the weight exactly and the level plane keeps its altitude (to 1 mm over
    15 s). Banked 30 deg the planes turn left and right at g tan(bank) / V (within 10%, V
    and the bank measured). The propeller (1.5 kg m^2 at 2500 rpm, L = 393 N m s) pitches
    the nose up in the left turn and down in the right, by L |omega_z| (the torque's
    measure against the body rates); the tail holds the nose against it, so the left turn
    flies at a larger angle of attack than the right by twice L r / (C_m q S c) (within
    10%), while without the propeller the two turns mirror each other exactly (to 1e-9)
    and with it they turn at different rates. Gusts make the gusty plane's airspeed and
    altitude wander (by metres), deterministically for a seed."""
    scene = get_scene("aeroplane")
    run = simulate(scene)
    p, m = run.params, run.measures
    alpha, thrust = p.trim()
    weight = AIRFRAME.mass_kg * GRAVITY_MPS2
    q_trim = p.dynamic_pressure_pa() * AIRFRAME.wing_area_m2
    lift = q_trim * AIRFRAME.lift_slope_per_rad * alpha
    assert lift * math.cos(alpha) + thrust * math.sin(alpha) == pytest.approx(weight, rel=1e-12)
    assert lift == pytest.approx(weight, rel=0.02)  # "lift = weight", to the thrust's share
    np.testing.assert_allclose(m["lift_over_weight"][:, LEVEL], 1.0, atol=1e-9)
    assert np.ptp(m["altitude_m"][:, LEVEL]) < 1e-3
    late = slice(-250, None)  # the last 5 s: turning steadily
    for row, sign in ((LEFT, 1.0), (RIGHT, -1.0)):
        bank = np.radians(m["bank_deg"][late, row].mean())
        rate = np.radians(m["turn_rate_degps"][late, row].mean())
        expected = GRAVITY_MPS2 * math.tan(bank) / m["airspeed_mps"][late, row].mean()
        assert sign * bank > 0.0 and rate == pytest.approx(expected, rel=0.1), row
    momentum = p.propeller_momentum_kgm2ps()
    assert momentum == pytest.approx(1.5 * 2500 * 2 * math.pi / 60)
    gyro = m["gyro_nose_up_nm"][late]
    assert gyro[:, LEFT].min() > 30.0 and gyro[:, RIGHT].max() < -30.0
    states: list = []
    simulate(scene, steps=400, on_step=lambda p, s: states.append(s))
    for state in states[::50]:
        torque = propeller_gyro_torque(momentum, (state.wx_radps, state.wy_radps, state.wz_radps))
        np.testing.assert_allclose(-torque[1], momentum * state.wz_radps, rtol=1e-15)
    sin_attack = np.sin(np.radians(m["attack_deg"][late]))
    half_gap = 0.5 * (sin_attack[:, LEFT] - sin_attack[:, RIGHT]).mean()
    q_turns = 0.5 * AIR_DENSITY_KGM3 * (m["airspeed_mps"][late, LEFT:GUSTS] ** 2).mean()
    stiffness = AIRFRAME.pitch_stiffness * q_turns * AIRFRAME.wing_area_m2 * AIRFRAME.chord_m
    predicted = 0.5 * (gyro[:, LEFT] - gyro[:, RIGHT]).mean() / stiffness
    assert half_gap > 0.0 and half_gap == pytest.approx(predicted, rel=0.1)
    rates = m["turn_rate_degps"][late].mean(axis=0)
    assert abs(rates[LEFT] + rates[RIGHT]) > 0.01  # the gyro makes one direction faster
    still = simulate(scene, {"propeller_rpm": 0.0}).measures
    for key in ("attack_deg", "altitude_m", "airspeed_mps"):
        np.testing.assert_allclose(still[key][:, LEFT], still[key][:, RIGHT], rtol=1e-9)
    np.testing.assert_allclose(
        still["turn_rate_degps"][:, LEFT], -still["turn_rate_degps"][:, RIGHT], atol=1e-9
    )
    assert np.ptp(m["airspeed_mps"][:, GUSTS]) > 2.0 and np.ptp(m["altitude_m"][:, GUSTS]) > 2.0
    again = simulate(scene, steps=200).measures["altitude_m"][:, GUSTS]
    np.testing.assert_array_equal(again, m["altitude_m"][:201, GUSTS])
    other = simulate(scene, {"seed": 1}, steps=200).measures["altitude_m"][:, GUSTS]
    assert np.abs(other - again).max() > 0.01
