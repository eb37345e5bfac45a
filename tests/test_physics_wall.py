"""The falling wall, one behaviour per test, with numbers (seed §8 "Buster Keaton", §5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.backend import scalar
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.wall import (
    FALLEN_AWAY,
    FALLEN_TOWARD,
    LOOSE,
    STANDING,
    WallParams,
    ball_hits_wall,
    wall_at,
    wall_step,
    wall_torques,
)

P = WallParams()


def run(p, wind, seconds, dt=0.005, state=None):
    s = state or wall_at(6.0)
    for _ in range(int(round(seconds / dt))):
        s = wall_step(p, s, wind, dt, scalar)
    return s


def test_torques_follow_the_seed():
    # Wind: h/2 F_w cos(phi); gravity m g x_cm about the far edge.
    u, phi = 3.0, 0.3
    tau_wind, tau_gravity, face = wall_torques(P, phi, 1.0, u, scalar)
    assert face == pytest.approx(P.wind_force_n(u) * math.cos(phi))
    assert tau_wind == pytest.approx(P.height_m / 2 * P.wind_force_n(u) * math.cos(phi))
    x_cm = -P.half_base_m * math.cos(phi) + P.height_m / 2 * math.sin(phi)
    assert tau_gravity == pytest.approx(P.mass_kg * GRAVITY_MPS2 * x_cm)
    # Restoring while the centre of mass is over the foot, overturning past it.
    tip = math.atan(P.half_base_m / (P.height_m / 2))
    assert wall_torques(P, 0.9 * tip, 1.0, 0.0, scalar)[1] < 0.0
    assert wall_torques(P, 1.1 * tip, 1.0, 0.0, scalar)[1] > 0.0


def test_stands_below_and_falls_above_the_tipping_wind_speed():
    u_tip = P.tipping_wind_speed_mps()
    assert P.height_m / 2 * P.wind_force_n(u_tip) == pytest.approx(
        P.mass_kg * GRAVITY_MPS2 * P.half_base_m
    )
    below = run(P, 0.97 * u_tip, 20.0)
    assert below.status == STANDING and below.angle == 0.0
    assert run(P, 1.03 * u_tip, 20.0).status == FALLEN_AWAY
    assert run(P, -1.03 * u_tip, 20.0).status == FALLEN_TOWARD


def test_stands_forever_in_calm_air():
    s = run(P, 0.0, 60.0)
    assert s.status == STANDING and s.angle == 0.0 and s.rate == 0.0


def test_moment_of_inertia_about_the_edge():
    thin = WallParams(thickness_m=1e-4, base_depth_m=1e-4)
    assert thin.inertia_kgm2 == pytest.approx(thin.mass_kg * thin.height_m**2 / 3, rel=1e-6)
    h, t, b, m = P.height_m, P.thickness_m, P.half_base_m, P.mass_kg
    assert P.inertia_kgm2 == pytest.approx(m * (h * h + t * t) / 12 + m * (h * h / 4 + b * b))


def test_fall_time_from_a_small_lean_matches_the_thin_slab():
    # Thin slab about its edge: phi'' = (3 g / 2 h) sin(phi), so from rest at phi0 the time
    # to the ground is sqrt(h / 3g) * int_phi0^{pi/2} dphi / sqrt(cos(phi0) - cos(phi)).
    thin = WallParams(thickness_m=1e-4, base_depth_m=1e-4)
    phi0, h = 0.05, thin.height_m
    n = 200000
    s_max = math.sqrt(math.pi / 2 - phi0)
    s = (np.arange(n) + 0.5) * s_max / n  # phi = phi0 + s^2 takes the singularity away
    integrand = 2 * s / np.sqrt(math.cos(phi0) - np.cos(phi0 + s * s))
    t_analytic = math.sqrt(h / (3 * GRAVITY_MPS2)) * integrand.sum() * s_max / n
    state = wall_at(0.0)
    state.angle, state.pivot = phi0, 1.0
    dt, t = 1e-4, 0.0
    while state.status == STANDING:
        state = wall_step(thin, state, 0.0, dt, scalar)
        t += dt
    assert state.status == FALLEN_AWAY
    assert t == pytest.approx(t_analytic, rel=5e-3)


def hit(z, restitution=0.6, speed=10.0, p=P):
    q = WallParams(ball_restitution=restitution, **{k: getattr(p, k) for k in ("mass_kg",)})
    s = wall_at(6.0)
    x = 6.0 - q.thickness_m / 2 - 0.15  # ball centre 0.15 m before the face, touching
    return q, s, ball_hits_wall(q, s, 0.25, 0.2, x, 0.0, z, speed, 0.0, scalar), x


def test_high_hit_turns_the_wall_more_than_a_low_one_and_the_ball_rebounds():
    rates = []
    for z in (0.5, 1.2, 2.2):
        _, _, (wall, vx, vz, height), _ = hit(z)
        assert height == pytest.approx(z) and wall.pivot == 1.0
        assert vx < 0.0 and vz == pytest.approx(0.0)  # bounced back toward the thrower
        rates.append(wall.rate)
    assert 0.0 < rates[0] < rates[1] < rates[2]


@pytest.mark.parametrize("restitution", [0.0, 0.6, 1.0])
def test_hit_conserves_angular_momentum_about_the_edge(restitution):
    q, s, (wall, vx, vz, _), x = hit(1.8, restitution)
    pivot_x = s.base_x + q.half_base_m
    # Angular momentum in the lean's sense: I rate + m (v_x r_z - v_z r_x).
    r_x, r_z = x - pivot_x, 1.8
    before = 0.25 * (10.0 * r_z)
    after = q.inertia_kgm2 * wall.rate + 0.25 * (vx * r_z - vz * r_x)
    assert after == pytest.approx(before, rel=1e-9)
    energy_after = 0.5 * q.inertia_kgm2 * wall.rate**2 + 0.5 * 0.25 * (vx * vx + vz * vz)
    if restitution == 1.0:
        assert energy_after == pytest.approx(0.5 * 0.25 * 100.0, rel=1e-9)
    else:
        assert energy_after < 0.5 * 0.25 * 100.0


def test_a_small_push_rocks_the_wall_back_onto_its_foot():
    s = wall_at(6.0)
    s.rate, s.pivot = 0.2, 1.0
    rocked = run(P, 0.0, 3.0, state=s)
    assert rocked.status == STANDING and rocked.angle == 0.0 and rocked.pivot == 0.0


def test_breaking_loose_and_flying_as_a_panel():
    # On a foot too deep to tip over, the wind's whole force lands on the foot's edge:
    # below the hold it stays put, above it tears loose.
    deep = WallParams(base_depth_m=4.0, anchor_n=0.0)
    u_break = deep.breakaway_wind_speed_mps()
    assert deep.wind_force_n(u_break) == pytest.approx(deep.hold_n)
    assert deep.tipping_wind_speed_mps() > 1.5 * u_break
    held = run(deep, 0.97 * u_break, 1.0)
    assert held.status == STANDING and held.angle == 0.0
    assert held.stress == pytest.approx(0.97**2)
    torn = run(deep, 1.03 * u_break, 0.01)
    assert torn.status == LOOSE and not torn.landed
    flown = run(deep, 1.03 * u_break, 10.0, state=torn)
    assert flown.landed  # blown over downwind, lying flat
    assert flown.loose_angle == pytest.approx(math.pi / 2)
    assert flown.loose_z == pytest.approx(deep.thickness_m / 2)
    assert flown.loose_x > 6.0 + 1.0
    # A wall free to tip needs less from its foot while it accelerates, but a storm still
    # tears it loose on the way down.
    assert run(P, 12.0, 5.0).status == LOOSE


def test_batched_walls_match_single_walls():
    winds = np.array([0.0, 2.0, 3.5, -3.5, 12.0])
    batch = wall_at(np.full(5, 6.0))
    for _ in range(400):
        batch = wall_step(P, batch, winds, 0.005)
    for i, u in enumerate(winds):
        one = run(P, float(u), 2.0)
        assert one.status == batch.status[i]
        assert one.angle == pytest.approx(batch.angle[i], abs=1e-12)
        assert one.loose_x == pytest.approx(batch.loose_x[i], abs=1e-12)


def test_params_validation_names_the_argument():
    with pytest.raises(ValueError, match="mass_kg"):
        WallParams(mass_kg=0.0)
    with pytest.raises(ValueError, match="base_depth_m"):
        WallParams(base_depth_m=0.01, thickness_m=0.05)
    with pytest.raises(ValueError, match="ball_restitution"):
        WallParams(ball_restitution=2.0)
