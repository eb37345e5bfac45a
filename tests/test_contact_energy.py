"""Contacts are impulses that never add energy (DESIGN §2 "Stability", §3.2, §3.3).

The ball on the ground (seed §3 bounces, §5 "Kinematic rotations", §6 friction and the
sliding block's zero crossing), on a screen, on the falling wall (§5 "the plank", §8) and on
another ball (§4): analytic results of the rolling condition, and properties checked with
hypothesis over every accepted parameter set and a wide range of states.
"""

from __future__ import annotations

import math
from dataclasses import fields, replace

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from bbgym.physics.ball import (
    TINY,
    BallParams,
    BallState,
    ball_at,
    collide_balls,
    contact_slip,
    ground_contact,
    panel_contact,
    rolling_velocity,
)
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.flight import simulate_throw
from bbgym.physics.namespace import floats
from bbgym.physics.wall import STANDING, WallParams, ball_hits_wall, wall_at

G = GRAVITY_MPS2
DT = 0.01
FAST = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def params(draw, cls):
    """Any accepted ``cls``: every field drawn over its whole documented interval."""
    values = {}
    for f in fields(cls):
        accepted = f.metadata.get("interval")
        if isinstance(f.default, bool):
            values[f.name] = draw(st.booleans())
        elif accepted is not None:
            values[f.name] = draw(
                st.floats(
                    accepted.low,
                    accepted.high,
                    exclude_min=accepted.low_open,
                    exclude_max=accepted.high_open,
                )
            )
    if cls is WallParams:
        values["thickness_m"], values["base_depth_m"] = sorted(
            (values["thickness_m"], values["base_depth_m"])
        )
    return cls(**values)


def kinetic_energy(p: BallParams, s: BallState) -> float:
    """Translational plus rotational kinetic energy (J)."""
    v_sq = s.vx * s.vx + s.vy * s.vy + s.vz * s.vz
    w_sq = s.wx * s.wx + s.wy * s.wy + s.wz * s.wz
    return 0.5 * p.mass_kg * v_sq + 0.5 * p.inertia_kgm2 * w_sq


def contact_angular_momentum(p: BallParams, s: BallState) -> tuple[float, float]:
    """Horizontal angular momentum about the contact point, ``I omega + m r z x v``."""
    m, r, inertia = p.mass_kg, p.radius_m, p.inertia_kgm2
    return inertia * s.wx - m * r * s.vy, inertia * s.wy + m * r * s.vx


def rest_on_ground(p: BallParams, s: BallState) -> BallState:
    """One substep of gravity alone (semi-implicit Euler), then the ground: no air, so the
    contact's numbers are the analytic ones (the normal impulse is exactly m g dt)."""
    vz = s.vz - G * DT
    s = s._replace(x=s.x + s.vx * DT, y=s.y + s.vy * DT, z=s.z + vz * DT, vz=vz)
    return ground_contact(p, s, DT, floats)[0]


def slide(p: BallParams, vx: float, wy: float, max_steps: int = 3000) -> tuple[list, int]:
    """A ball set on the ground at ``vx`` with spin ``wy``; the states after each substep and
    the substep in which the slip stopped."""
    s = ball_at(0.0, 0.0, p.radius_m, vx, 0.0, 0.0, 0.0, wy, 0.0)
    states, stopped = [s], None
    for n in range(1, max_steps + 1):
        s = rest_on_ground(p, s)
        states.append(s)
        if stopped is None and abs(contact_slip(p, s.vx, s.vy, s.wx, s.wy)[0]) < 1e-12:
            stopped = n
    return states, stopped


@pytest.mark.parametrize("solid, share", [(False, 3 / 5), (True, 5 / 7)])
@pytest.mark.parametrize("rolling_resistance", [0.0, 0.1])
def test_sliding_ball_without_spin_rolls_on_at_its_rolling_share(solid, share, rolling_resistance):
    # Angular momentum about the contact point is kept by friction: m r v0 = (m r + I / r) u,
    # so u = v0 / (1 + I / m r^2): 3/5 for a thin shell (I = 2/3 m r^2), 5/7 for a solid ball.
    p = BallParams(solid=solid, friction=0.6, rolling_resistance=rolling_resistance)
    assert 1.0 / (1.0 + p.inertia_kgm2 / (p.mass_kg * p.radius_m**2)) == pytest.approx(share)
    v0, mu, c = 5.0, p.friction, p.rolling_resistance
    states, n = slide(p, v0, 0.0)
    assert n is not None
    # The slip falls at (1 + m r^2 / I)(mu - c) g: friction drives it, the rolling-resistance
    # couple (from the second substep on, once there is spin to brake) works against it.
    gain = 1.0 + p.mass_kg * p.radius_m**2 / p.inertia_kgm2
    t_slide = v0 / (gain * (mu - c) * G)
    assert n * DT == pytest.approx(t_slide - c / (mu - c) * DT, abs=DT)
    end = states[n]
    # What rolling resistance took during the slide: c g per second after the first step.
    assert end.vx == pytest.approx(share * v0 - c * G * (n - 1) * DT, rel=1e-12)
    assert end.vx == pytest.approx(share * v0 - c * G * t_slide, abs=2 * c * G * DT + 1e-12)
    assert end.wy == pytest.approx(end.vx / p.radius_m, rel=1e-12)  # rolling: omega = v / r
    energies = [kinetic_energy(p, s) for s in states]
    assert all(b <= a * (1 + 1e-12) for a, b in zip(energies, energies[1:], strict=False))
    assert energies[n] < 0.5 * p.mass_kg * v0 * v0
    if c == 0.0:
        assert end.vx == pytest.approx(share * v0, rel=1e-12)
        assert states[-1].vx == pytest.approx(end.vx, rel=1e-12)  # rolls on forever
        return
    # Then it rolls without slipping at c g, and stops without turning back.
    for a, b in zip(states[n : n + 100], states[n + 1 : n + 101], strict=True):
        assert a.vx - b.vx == pytest.approx(c * G * DT, rel=1e-9)
        assert abs(contact_slip(p, b.vx, b.vy, b.wx, b.wy)[0]) < 1e-12
    assert min(s.vx for s in states) >= 0.0 and min(s.wy for s in states) >= 0.0
    t_stop = n * DT + end.vx / (c * G)
    assert states[int(t_stop / DT) + 50].vx < 1e-6


@pytest.mark.parametrize("solid, threshold", [(False, 3 / 2), (True, 5 / 2)])
def test_backspin_beyond_the_angular_momentum_threshold_brings_the_ball_back(solid, threshold):
    # u = (m r^2 v + I r omega_y) / (m r^2 + I) < 0 when backspin -omega_y r > (m r^2 / I) v:
    # 3/2 v for a thin shell, 5/2 v for a solid ball. Without rolling resistance, exactly.
    p = BallParams(solid=solid, rolling_resistance=0.0)
    assert p.mass_kg * p.radius_m**2 / p.inertia_kgm2 == pytest.approx(threshold)
    v0 = 4.0
    for factor in (0.97, 1.03):
        wy = -factor * threshold * v0 / p.radius_m
        states, n = slide(p, v0, wy)
        expected = rolling_velocity(p, v0, 0.0, 0.0, wy)[0]
        assert states[n].vx == pytest.approx(expected, rel=1e-12)
        assert (states[n].vx < 0.0) == (factor > 1.0)
        assert states[n].vx == pytest.approx(v0 * (1 - factor) * threshold / (1 + threshold))


def test_strong_backspin_comes_back_with_rolling_resistance_and_stops_once():
    p = BallParams()  # default grass: rolling resistance 0.1, whose couple brakes backspin
    v0 = 4.0
    states, n = slide(p, v0, -3.0 * v0 / p.radius_m)
    assert states[n].vx < -0.5  # rolling back toward the thrower
    vx = np.array([s.vx for s in states])
    turned = int(np.argmax(vx < 0.0))
    assert np.all(vx[turned:] <= 0.0)  # it comes back once and stops, no rocking
    assert abs(vx[-1]) < 1e-6


def test_topspin_kicks_the_ball_forward():
    p = BallParams(rolling_resistance=0.0)
    v0 = 4.0
    states, n = slide(p, v0, 2.0 * v0 / p.radius_m)  # spinning faster than it rolls
    assert states[n].vx == pytest.approx(3 / 5 * v0 + 2 / 5 * 2.0 * v0, rel=1e-12)
    assert states[n].vx > v0
    energies = [kinetic_energy(p, s) for s in states[: n + 1]]
    assert energies[-1] < energies[0]  # the spin paid for the kick, and then some


def test_friction_zero_is_ice():
    # No friction: the ground gives no horizontal impulse, so the ball slides on at its speed
    # and only the rolling-resistance couple brakes its spin (never past zero).
    p = BallParams(friction=0.0)
    states, _ = slide(p, 3.0, 10.0, max_steps=400)
    assert all(s.vx == 3.0 for s in states)
    assert states[-1].wy == 0.0 and min(s.wy for s in states) >= 0.0


@FAST
@given(
    p=params(BallParams),
    depth=st.floats(0.0, 0.5),
    v=st.tuples(*[st.floats(-40.0, 40.0)] * 2, st.floats(-40.0, 2.0)),
    w=st.tuples(*[st.floats(-500.0, 500.0)] * 3),
)
@example(  # a spin far below TINY: braked in proportion, not stopped
    p=BallParams(
        radius_m=1.0,
        shell_areal_density_kgm2=1.0,
        density_kgm3=10.0,
        drag_coefficient=0.0,
        lift_coefficient_max=0.0,
        spin_decay_s=1.0,
        restitution=0.0,
        friction=0.0,
        rolling_resistance=1.0,
        rest_speed_mps=1.0,
    ),
    depth=0.0,
    v=(0.0, 0.0, -4.772778792939452e-18),
    w=(4.772778792939452e-18, 0.0, 0.0),
)
def test_one_ground_contact_never_adds_energy_and_keeps_contact_angular_momentum(p, depth, v, w):
    r, m, inertia = p.radius_m, p.mass_kg, p.inertia_kgm2
    s = ball_at(0.0, 0.0, r * (1.0 - depth), *v, *w)
    after, touching = ground_contact(p, s, DT, floats)
    values = list(after)
    assert all(math.isfinite(x) for x in values)
    before_e, after_e = kinetic_energy(p, s), kinetic_energy(p, after)
    assert after_e <= before_e * (1.0 + 1e-9) + 1e-12
    assert touching == (v[2] <= 0.0)
    # The ground's horizontal impulse stays inside Coulomb's cone, friction * J_n.
    bounce = touching and -v[2] > p.rest_speed_mps
    e = p.restitution if bounce else 0.0
    normal_impulse = -(1.0 + e) * m * v[2] if touching else 0.0
    horizontal = m * math.hypot(after.vx - s.vx, after.vy - s.vy)
    # The velocity change is read as a difference of velocities: it carries their rounding
    # (a few ulp of |v|), which matters when friction is tiny.
    rounding = m * 1e-15 * (abs(v[0]) + abs(v[1]) + r * (abs(w[0]) + abs(w[1])))
    assert horizontal <= p.friction * normal_impulse * (1.0 + 1e-9) + 1e-12 + rounding
    # Angular momentum about the contact point: friction and the normal impulse keep it;
    # only the rolling-resistance couple (resting contact) takes some, against the spin.
    spin = math.hypot(s.wx, s.wy)
    couple = 0.0
    if touching and not bounce:
        couple = min(
            p.rolling_resistance * normal_impulse * (r + inertia / (m * r)), inertia * spin
        )
    lx, ly = contact_angular_momentum(p, s)
    # A spin below TINY (rad/s) is braked in proportion (no division by a vanishing norm).
    per_spin = couple / max(spin, TINY)
    expected = (lx - per_spin * s.wx, ly - per_spin * s.wy)
    scale = m * r * math.hypot(*v) + inertia * math.hypot(*w) + 1e-12
    got = contact_angular_momentum(p, after)
    assert got[0] == pytest.approx(expected[0], abs=1e-9 * scale)
    assert got[1] == pytest.approx(expected[1], abs=1e-9 * scale)
    # Friction never reverses the slip (the sliding block's zero crossing, seed §6).
    mid_wx, mid_wy = s.wx - per_spin * s.wx / inertia, s.wy - per_spin * s.wy / inertia
    mid = contact_slip(p, s.vx, s.vy, mid_wx, mid_wy)
    end = contact_slip(p, after.vx, after.vy, after.wx, after.wy)
    assert end[0] * mid[0] + end[1] * mid[1] >= -1e-9 * scale / m * math.hypot(*mid)
    # The batched (NumPy) contact is the same computation.
    batch, _ = ground_contact(p, BallState(*(np.array([x]) for x in s)), DT)
    np.testing.assert_allclose([x[0] for x in batch], values, rtol=1e-12, atol=1e-12)


@FAST
@given(
    angle=st.floats(-math.pi, math.pi),
    offset=st.floats(0.01, 0.99),
    side=st.sampled_from([-1.0, 1.0]),
    lateral=st.floats(-1.0, 1.0),
    v=st.tuples(*[st.floats(-40.0, 40.0)] * 3),
    restitution=st.one_of(st.just(0.0), st.just(1.0), st.floats(0.0, 1.0)),
)
def test_panel_contact_reflects_the_normal_velocity_and_never_adds_energy(
    angle, offset, side, lateral, v, restitution
):
    p = BallParams()
    offset = side * offset  # which side of the panel, in radii off its plane
    ax, ay = math.cos(angle), math.sin(angle)  # the panel runs along (ax, ay) through 0
    nx, ny = -ay, ax
    r = p.radius_m
    x, y = offset * r * nx + lateral * ax, offset * r * ny + lateral * ay
    s = ball_at(x, y, 1.0, *v, 3.0, -2.0, 1.0)
    after, hit = panel_contact(s, r, 0.0, 0.0, ax, ay, 1.5, 2.0, restitution, True, floats)
    approach = v[0] * nx + v[1] * ny
    assert hit == (abs(lateral) <= 1.5 and approach * offset < 0.0)
    assert kinetic_energy(p, after) <= kinetic_energy(p, s) * (1.0 + 1e-12)
    normal_after = after.vx * nx + after.vy * ny
    tangential = (v[0] * ax + v[1] * ay, after.vx * ax + after.vy * ay)
    assert tangential[1] == pytest.approx(tangential[0], abs=1e-9)
    assert normal_after == pytest.approx(-restitution * approach if hit else approach, abs=1e-9)
    if hit:  # pushed back out to touch the panel on its own side
        assert (after.x * nx + after.y * ny) == pytest.approx(math.copysign(r, offset))
    if restitution == 1.0:
        assert kinetic_energy(p, after) == pytest.approx(kinetic_energy(p, s), rel=1e-12)


@FAST
@given(
    wall=params(WallParams),
    ball=params(BallParams),
    pivot=st.sampled_from([-1.0, 0.0, 1.0]),
    lean=st.floats(0.0, 0.6),
    rate=st.floats(-3.0, 3.0),
    along=st.floats(0.0, 1.0),
    offset=st.floats(-0.99, 0.99),
    v=st.tuples(*[st.floats(-40.0, 40.0)] * 2),
    restitution=st.one_of(st.just(0.0), st.just(1.0), st.floats(0.0, 1.0)),
)
def test_ball_hitting_the_wall_keeps_angular_momentum_and_never_adds_energy(
    wall, ball, pivot, lean, rate, along, offset, v, restitution
):
    p = replace(wall, ball_restitution=restitution)
    s = wall_at(6.0)
    side = pivot if pivot != 0.0 else 1.0
    s = s._replace(pivot=pivot, angle=pivot * lean, rate=rate if pivot != 0.0 else 0.0)
    b, t, c, sn = p.half_base_m, p.thickness_m, math.cos(s.angle), math.sin(s.angle)
    pivot_x = s.base_x + side * b
    foot_x, foot_z = pivot_x - side * b * c, side * b * sn
    # A point on the near face at that height, and the ball's centre `offset` radii off it.
    h, q = along * p.height_m, offset * ball.radius_m - 0.5 * t
    bx, bz = foot_x + h * sn + q * c, foot_z + h * c - q * sn
    m = ball.mass_kg
    after, vx, vz, height = ball_hits_wall(p, s, m, ball.radius_m, bx, 0.0, bz, *v, floats)
    assume(height >= 0.0)
    assert after.status == STANDING and after.pivot == side
    assert all(math.isfinite(x) for x in (after.rate, vx, vz))
    inertia = p.inertia_kgm2
    energy = (
        0.5 * m * (v[0] ** 2 + v[1] ** 2) + 0.5 * inertia * s.rate**2,
        0.5 * m * (vx * vx + vz * vz) + 0.5 * inertia * after.rate**2,
    )
    assert energy[1] <= energy[0] * (1.0 + 1e-9)
    # About the pivot edge: I rate + m (v_x r_z - v_z r_x), r from the edge to the ball.
    rx, rz = bx - pivot_x, bz
    momentum = (
        inertia * s.rate + m * (v[0] * rz - v[1] * rx),
        inertia * after.rate + m * (vx * rz - vz * rx),
    )
    # (rounding: the terms' sizes, with the wall's whole extent as the lever)
    lever = p.height_m + p.base_depth_m + ball.radius_m
    speeds = math.hypot(*v) + math.hypot(vx, vz)
    scale = inertia * (abs(s.rate) + abs(after.rate)) + m * speeds * lever
    assert momentum[1] == pytest.approx(momentum[0], abs=1e-9 * scale)
    if restitution == 1.0:
        assert energy[1] == pytest.approx(energy[0], rel=1e-9)
    if restitution == 0.0:  # plastic: the ball moves on with the face it hit
        # (the face's speed along its normal is the same anywhere on the ball's normal line)
        point_normal = after.rate * (bz * c + (bx - pivot_x) * sn)
        assert vx * c - vz * sn == pytest.approx(point_normal, abs=1e-9 * (1 + math.hypot(*v)))


@FAST
@given(
    m=st.tuples(*[st.floats(1e-3, 1e3)] * 2),
    p2=st.one_of(
        st.just((0.0, 0.0, 0.0)),
        st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda p: np.dot(p, p) > 1e-6),
    ),
    v1=st.tuples(*[st.floats(-40.0, 40.0)] * 3),
    v2=st.tuples(*[st.floats(-40.0, 40.0)] * 3),
    restitution=st.one_of(st.just(0.0), st.just(1.0), st.floats(0.0, 1.0)),
)
def test_ball_collisions_keep_momentum_and_never_add_energy(m, p2, v1, v2, restitution):
    a1, a2 = collide_balls(m[0], v1, (0.0, 0.0, 0.0), m[1], v2, p2, restitution, floats)
    assert all(math.isfinite(x) for x in (*a1, *a2))
    for k in range(3):
        before = m[0] * v1[k] + m[1] * v2[k]
        after = m[0] * a1[k] + m[1] * a2[k]
        assert after == pytest.approx(before, abs=1e-9 * (m[0] + m[1]) * 40.0)
    energy = (
        0.5 * (m[0] * np.dot(v1, v1) + m[1] * np.dot(v2, v2)),
        0.5 * (m[0] * np.dot(a1, a1) + m[1] * np.dot(a2, a2)),
    )
    assert energy[1] <= energy[0] * (1.0 + 1e-9) + 1e-12
    dist = math.sqrt(np.dot(p2, p2))
    if dist == 0.0:  # concentric: no line of centres, nothing happens
        assert a1 == tuple(v1) and a2 == tuple(v2)
        return
    n = np.array(p2) / dist
    u1, u2 = np.dot(v1, n), np.dot(v2, n)
    if u1 > u2 and restitution == 0.0:  # plastic: a common velocity along the centre line
        assert np.dot(a1, n) == pytest.approx(np.dot(a2, n), abs=1e-9 * 80.0)
    if restitution == 1.0:
        assert energy[1] == pytest.approx(energy[0], rel=1e-9, abs=1e-12)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    p=params(BallParams),
    direction=st.tuples(*[st.floats(-1.0, 1.0)] * 3),
    speed=st.floats(0.1, 60.0),
    spin=st.tuples(*[st.floats(-280.0, 280.0)] * 3),
    wind=st.tuples(*[st.floats(-14.0, 14.0)] * 2),
)
def test_random_throw_with_any_ball_is_finite_on_numpy_and_python_floats(
    p, direction, speed, spin, wind
):
    norm = math.sqrt(sum(d * d for d in direction))
    assume(norm > 1e-3)
    v = [speed * d / norm for d in direction]
    start = (0.0, 0.0, p.radius_m + 1.5, *v, *spin)
    one = simulate_throw(p, ball_at(*start), *wind, max_time_s=4.0, max_roll_s=1.0, xp=floats)
    batch = simulate_throw(
        p,
        ball_at(*(np.array([x]) for x in start)),
        np.array([wind[0]]),
        np.array([wind[1]]),
        max_time_s=4.0,
        max_roll_s=1.0,
    )
    got = [one.landing_x, one.landing_y, one.flight_time_s, one.apex_height_m]
    got += list(one.final)
    assert all(math.isfinite(x) for x in got)
    want = [batch.landing_x, batch.landing_y, batch.flight_time_s, batch.apex_height_m]
    want += list(batch.final)
    np.testing.assert_allclose(got, np.concatenate(want), rtol=1e-9, atol=1e-9)
    assert one.steps == batch.steps[0]
