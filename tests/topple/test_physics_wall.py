"""The falling wall, one behaviour per test, with numbers (seed §8 "Buster Keaton", §5)."""

from __future__ import annotations

import math
from dataclasses import fields

import numpy as np
import pytest

from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2
from bbgym.physics.namespace import floats
from bbgym.physics.wall import (
    FALLEN_AWAY,
    FALLEN_TOWARD,
    LOOSE,
    STANDING,
    WallParams,
    ball_hits_wall,
    loose_step,
    wall_at,
    wall_step,
    wall_torques,
)

P = WallParams()


def run(p, wind, seconds, dt=0.005, state=None):
    s = state or wall_at(6.0)
    for _ in range(int(round(seconds / dt))):
        s = wall_step(p, s, wind, dt, floats)
    return s


def test_torques_follow_the_seed():
    # Wind: h/2 F_w cos(phi); gravity m g x_cm about the far edge.
    u, phi = 3.0, 0.3
    tau_wind, tau_gravity, face = wall_torques(P, phi, 1.0, u, floats)
    assert face == pytest.approx(P.wind_force_n(u) * math.cos(phi))
    assert tau_wind == pytest.approx(P.height_m / 2 * P.wind_force_n(u) * math.cos(phi))
    x_cm = -P.half_base_m * math.cos(phi) + P.height_m / 2 * math.sin(phi)
    assert tau_gravity == pytest.approx(P.mass_kg * GRAVITY_MPS2 * x_cm)
    # Restoring while the centre of mass is over the foot, overturning past it.
    tip = math.atan(P.half_base_m / (P.height_m / 2))
    assert wall_torques(P, 0.9 * tip, 1.0, 0.0, floats)[1] < 0.0
    assert wall_torques(P, 1.1 * tip, 1.0, 0.0, floats)[1] > 0.0


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
    state = state._replace(angle=phi0, pivot=1.0)
    dt, t = 1e-4, 0.0
    while state.status == STANDING:
        state = wall_step(thin, state, 0.0, dt, floats)
        t += dt
    assert state.status == FALLEN_AWAY
    assert t == pytest.approx(t_analytic, rel=5e-3)


def hit(z, restitution=0.6, speed=10.0, p=P):
    q = WallParams(ball_restitution=restitution, **{k: getattr(p, k) for k in ("mass_kg",)})
    s = wall_at(6.0)
    x = 6.0 - q.thickness_m / 2 - 0.15  # ball centre 0.15 m before the face, touching
    return q, s, ball_hits_wall(q, s, 0.25, 0.2, x, 0.0, z, speed, 0.0, floats), x


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
    s = s._replace(rate=0.2, pivot=1.0)
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
    with pytest.raises(ValueError, match=r"^WallParams\.mass_kg must be in \[0.1, 1000\]"):
        WallParams(mass_kg=0.0)
    with pytest.raises(ValueError, match=r"^WallParams\.base_depth_m must be >= thickness_m"):
        WallParams(base_depth_m=0.01, thickness_m=0.05)
    with pytest.raises(ValueError, match=r"^WallParams\.ball_restitution must be in \[0, 1\]"):
        WallParams(ball_restitution=2.0)


def test_a_250_m_wall_is_refused_and_the_largest_lightest_accepted_runs_finite():
    # A 250 m wall used to end in "math domain error": its tumbling damping, explicit,
    # flipped and grew the loose panel's spin until cos(inf). No stage-set panel is 250 m.
    with pytest.raises(ValueError, match=r"^WallParams\.height_m must be in \[0.2, 20\]"):
        WallParams(height_m=250.0)
    for p in (
        WallParams(height_m=20.0, width_m=20.0, mass_kg=0.1, base_depth_m=5.0),
        WallParams(height_m=20.0, width_m=0.1, mass_kg=0.1, base_depth_m=1e-4, thickness_m=1e-4),
        WallParams(height_m=20.0, mass_kg=1000.0, anchor_n=0.0, base_friction=0.0),
    ):
        for wind in (20.0, -20.0, 3.0):
            s = run(p, wind, 10.0, dt=0.01)
            assert all(np.isfinite(float(v)) for v in s)
            assert s.status != STANDING or abs(wind) < 20.0


def test_stiff_loose_panel_air_terms_slow_it_and_never_reverse_it():
    # A 20 m x 20 m panel of 100 g: dt * damping rate is in the hundreds for both its face
    # drag and its tumbling; explicit Euler would throw it backward, faster each step.
    p = WallParams(height_m=20.0, width_m=20.0, mass_kg=0.1)
    dt, wind = 0.01, 20.0
    face_rate = 0.5 * AIR_DENSITY_KGM3 * p.drag_coefficient * p.area_m2 * wind / p.mass_kg
    half = 0.5 * p.height_m
    tumble = 0.25 * AIR_DENSITY_KGM3 * p.drag_coefficient * p.width_m * half**4
    inertia_cm = p.mass_kg * (p.height_m**2 + p.thickness_m**2) / 12.0
    assert dt * face_rate > 100.0 and dt * tumble * 50.0 / inertia_cm > 100.0
    # Upright (face normal along x), high in the air, at rest in a 20 m/s wind, tumbling.
    x, z, angle, vx, vz, rate, landed = loose_step(
        p, 0.0, 100.0, 0.0, 0.0, 0.0, 50.0, wind, dt, floats
    )
    assert not landed
    # Implicit: w_n' = w_n / (1 + dt c), the panel pulled toward the wind's speed, not past.
    assert vx == pytest.approx(wind * (1.0 - 1.0 / (1.0 + dt * face_rate)), rel=1e-9)
    assert 0.0 < vx < wind
    assert 0.0 < rate < 50.0  # slowed, same sense
    assert rate == pytest.approx(50.0 / (1.0 + dt * tumble * 50.0 / inertia_cm), rel=1e-9)


def test_without_drag_the_wind_cannot_tip_or_tear_the_wall():
    p = WallParams(drag_coefficient=0.0)
    assert p.tipping_wind_speed_mps() == math.inf and p.breakaway_wind_speed_mps() == math.inf
    s = run(p, 20.0, 5.0)
    assert s.status == STANDING and s.angle == 0.0 and s.stress == 0.0


def test_a_foot_that_holds_nothing_stands_in_calm_air_and_slides_off_in_any_wind():
    p = WallParams(base_friction=0.0, anchor_n=0.0)
    assert p.hold_n == 0.0
    calm = run(p, 0.0, 5.0)
    assert calm.status == STANDING and calm.stress == 0.0
    blown = run(p, 0.5, 0.01)
    assert blown.status == LOOSE and math.isfinite(blown.stress) and blown.stress > 1.0


def test_every_field_has_its_documented_interval():
    import ast
    import inspect

    from bbgym.physics.validation import accepted_interval

    docs = {}
    body = ast.parse(inspect.getsource(WallParams)).body[0].body
    for node, after in zip(body, body[1:], strict=False):
        if isinstance(node, ast.AnnAssign) and isinstance(after, ast.Expr):
            docs[node.target.id] = " ".join(after.value.value.split())
    for f in fields(WallParams):
        accepted = accepted_interval(WallParams, f.name)
        assert f"Accepted {accepted}" in docs[f.name]
        # Both ends accepted (the foot at least as deep as the panel is thick).
        low = {"thickness_m": accepted.low} if f.name == "base_depth_m" else {}
        high = {"base_depth_m": accepted.high} if f.name == "thickness_m" else {}
        WallParams(**{f.name: accepted.low}, **low)
        WallParams(**{f.name: accepted.high}, **high)
        for bad in (accepted.low - 1e-3, accepted.high * 1.01 + 1e-3, math.inf):
            with pytest.raises(ValueError, match=rf"^WallParams\.{f.name} "):
                WallParams(**{f.name: bad})
        with pytest.raises(TypeError, match=rf"^WallParams\.{f.name} "):
            WallParams(**{f.name: None})
