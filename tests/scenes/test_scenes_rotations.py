"""§5, rotations: each scene's claim measured (bbgym/scenes/rotations.py)."""

from __future__ import annotations

import numpy as np
import pytest

from bbgym.physics.ball import collide_balls
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.scenes import get_scene, simulate
from bbgym.scenes import rotations as rot


def run_states(name: str, params: dict | None = None, steps: int | None = None) -> tuple:
    states: list = []
    run = simulate(get_scene(name), params, steps=steps, on_step=lambda p, s: states.append(s))
    return run, states


@pytest.mark.parametrize("restitution", [1.0, 0.6])
def test_rotation_box_spin_is_set_by_the_contact_and_only_there(restitution: float) -> None:
    """§5, kinematic rotation: a step whose floor bounce changed a ball's vertical velocity
    leaves its spin at -v_x / r, a wall bounce at +-v_y / r (left, right wall): the contact
    point's velocity along the surface, v . (z x n) - omega r, is zero (to 1e-12); rolling
    right on the floor is clockwise. A step without a contact changes no spin (exactly) and
    turns the angle by omega dt. Every ball meets the floor and the walls are met."""
    run, states = run_states("rotation-box", {"restitution": restitution})
    p = run.params
    r, dt = p.radius_m, p.dt_s
    floors = walls = 0
    for before, after in zip(states[:-1], states[1:], strict=True):
        floor = after.vy_mps != before.vy_mps - GRAVITY_MPS2 * dt
        wall = after.vx_mps != before.vx_mps
        w, vx, vy = after.angular_velocity_radps, after.vx_mps, after.vy_mps
        # the floor's normal (0, 1): z x n = (-1, 0); the walls' (+-1, 0): z x n = (0, +-1)
        np.testing.assert_allclose((-vx - r * w)[floor], 0.0, atol=1e-12)
        assert np.all(w[floor & (vx > 0.0)] < 0.0)
        side = np.where(after.x_m < 0.0, 1.0, -1.0)
        only_wall = wall & ~floor
        np.testing.assert_allclose((side * vy - r * w)[only_wall], 0.0, atol=1e-12)
        none = ~(floor | wall)
        assert np.array_equal(w[none], before.angular_velocity_radps[none])
        turned = before.angle_rad + dt * before.angular_velocity_radps
        np.testing.assert_array_equal(after.angle_rad, turned)
        floors, walls = floors + int(floor.sum()), walls + int(only_wall.sum())
    assert floors >= 3 * p.balls and walls >= 2
    assert np.ptp(run.measures["spin_radps"]) > 5.0  # spins do change, at the contacts


@pytest.mark.parametrize("restitution", [1.0, 0.5])
def test_double_bounce_2_spins_by_the_contact_and_keeps_the_formula(restitution: float) -> None:
    """§5, double bounce 2: at the balls' collision (found where the step's collision part
    changed anything) the momentum along the line of centres is kept and the approach speed
    along it reverses times e (to 1e-12), the velocities across it are unchanged, and each
    ball's spin is -t . (v_bottom - v_top) / r_i (t = z x u, u from the bottom ball to the
    top one): both clockwise (the top ball sits to the right), the half-size one twice as
    fast. Upright (no offset), the same bounce gives no spin."""
    scene = get_scene("double-bounce-2")
    run, states = run_states("double-bounce-2", {"restitution": restitution})
    p = run.params
    m1, m2 = p.masses()
    hits = []
    for k, (before, after) in enumerate(zip(states[:-1], states[1:], strict=True)):
        pre = rot.double2_fall(p, rot.Spinning(*before), np)
        if not np.array_equal(pre.vx_mps, after.vx_mps) or not np.array_equal(
            pre.vy_mps, after.vy_mps
        ):
            hits.append((k, pre, after))
    assert hits and hits[0][0] < 0.5 / p.dt_s  # the first soon after the floor bounce
    _, pre, after = hits[0]
    ux, uy = after.x_m[1] - after.x_m[0], after.y_m[1] - after.y_m[0]
    norm = np.hypot(ux, uy)
    ux, uy = ux / norm, uy / norm
    tx, ty = -uy, ux
    along_pre, along_post = (s.vx_mps * ux + s.vy_mps * uy for s in (pre, after))
    across_pre, across_post = (s.vx_mps * tx + s.vy_mps * ty for s in (pre, after))
    assert m1 * along_post[0] + m2 * along_post[1] == pytest.approx(
        m1 * along_pre[0] + m2 * along_pre[1], rel=1e-12, abs=1e-12
    )
    closing = along_pre[0] - along_pre[1]
    assert closing > 0.0
    assert along_post[0] - along_post[1] == pytest.approx(-restitution * closing, abs=1e-12)
    np.testing.assert_allclose(across_post, across_pre, rtol=1e-12, atol=1e-12)
    slide = tx * (pre.vx_mps[0] - pre.vx_mps[1]) + ty * (pre.vy_mps[0] - pre.vy_mps[1])
    radii = np.array([p.bottom_radius_m, p.top_radius_m])
    np.testing.assert_allclose(after.angular_velocity_radps, -slide / radii, rtol=1e-12)
    assert np.all(after.angular_velocity_radps < -1.0)
    assert after.angular_velocity_radps[1] == pytest.approx(2.0 * after.angular_velocity_radps[0])
    assert after.vx_mps[1] > 0.0 > after.vx_mps[0]  # pushed apart sideways
    upright = simulate(scene, {"restitution": restitution, "offset_share": 0.0}, steps=400)
    np.testing.assert_array_equal(upright.measures["spin_radps"], 0.0)
    np.testing.assert_array_equal(upright.measures["vx_mps"], 0.0)


def first_impact(run) -> int:
    """The first row after the ball's velocity changed (the plank's impulse)."""
    vy = run.measures["momentum_y_ns"][:, 0]
    return int(np.argmax(vy != vy[0]))


def check_conservation(run, linear: bool) -> None:
    m = run.measures
    p = run.params
    scale = p.ball_mass_kg * p.speed_mps
    keys = (
        ("momentum_x_ns", "momentum_y_ns", "angular_momentum_js")
        if linear
        else ("angular_momentum_js",)
    )
    for key in keys:
        total = m[key].sum(axis=1)
        np.testing.assert_allclose(total, total[0], atol=1e-12 * scale * p.plank_length_m)
    energy = m["kinetic_energy_j"].sum(axis=1)
    if p.restitution == 1.0:
        np.testing.assert_allclose(energy, energy[0], rtol=1e-12)
    assert np.all(np.diff(energy) <= 1e-12 * energy[0])


@pytest.mark.parametrize(
    ("restitution", "hit_share"), [(1.0, 0.6), (0.5, -1.0), (0.0, 0.0), (0.3, 0.9)]
)
def test_plank_free_moves_and_turns_by_the_impulse_and_keeps_momentum(
    restitution: float, hit_share: float
) -> None:
    """§5, the plank: the ball (m_b, v) hits the plank at rest at d from its centre; with
    the plank's effective mass 1 / (1/m + d^2/I), I = m l^2 / 12, the impulse is
    J = (1 + e) m_b m_eff v / (m_b + m_eff): the plank moves at J / m and turns at
    -J d / I (clockwise for a hit right of the centre), the ball leaves at
    v (m_b - e m_eff) / (m_b + m_eff) (all to 1e-12) and the kinetic energy loses
    (1 - e^2) m_b m_eff v^2 / (2 (m_b + m_eff)). Over the run momentum and angular momentum
    (about the start's centre) are kept to 1e-12, the energy too when elastic, never
    gained otherwise."""
    run = simulate(get_scene("plank-free"), {"restitution": restitution, "hit_share": hit_share})
    p, m = run.params, run.measures
    mb, big, v, d = p.ball_mass_kg, p.plank_mass_kg, p.speed_mps, p.hit_m()
    inertia = big * p.plank_length_m**2 / 12.0
    assert p.centre_inertia_kgm2() == pytest.approx(inertia, rel=1e-15)
    m_eff = 1.0 / (1.0 / big + d * d / inertia)
    impulse = (1.0 + restitution) * mb * m_eff * v / (mb + m_eff)
    k = first_impact(run)
    assert 0 < k < len(run.times_s) - 1
    rebound = -v * (mb - restitution * m_eff) / (mb + m_eff)
    assert m["momentum_y_ns"][k, 0] / mb == pytest.approx(rebound, rel=1e-12, abs=1e-12)
    assert m["momentum_y_ns"][k, 1] / big == pytest.approx(-impulse / big, rel=1e-12)
    assert m["spin_radps"][k, 1] == pytest.approx(-impulse * d / inertia, rel=1e-12, abs=1e-12)
    loss = (1.0 - restitution**2) * mb * m_eff * v * v / (2.0 * (mb + m_eff))
    energy = m["kinetic_energy_j"].sum(axis=1)
    assert energy[k - 1] - energy[k] == pytest.approx(loss, rel=1e-9, abs=1e-12)
    check_conservation(run, linear=True)


@pytest.mark.parametrize(("restitution", "axis_share"), [(1.0, -1.0), (0.5, 0.0), (0.0, 0.5)])
def test_plank_anchored_turns_about_its_axis_and_keeps_angular_momentum_there(
    restitution: float, axis_share: float
) -> None:
    """§5, the plank on an axis: the text's split into two rods d1, d2 about their ends,
    each with its share of the mass, gives m l^2 / 3 at an end, m l^2 / 12 at the centre,
    m l^2 / 12 + m s^2 anywhere (the text's code, the whole mass each side, agrees at an
    end and is twice as much at the centre). The ball's impulse at a from the axis turns
    the plank at -J a / I_axis, J by the restitution formula with m_eff = I_axis / a^2 (to
    1e-12); the centre stays on its circle about the axis; the angular momentum about the
    axis is kept (1e-12) while the axis's push changes the momentum."""
    params = {"restitution": restitution, "axis_share": axis_share}
    run = simulate(get_scene("plank-anchored"), params)
    p, m = run.params, run.measures
    big, length, s = p.plank_mass_kg, p.plank_length_m, p.pivot_m()
    inertia = p.axis_inertia_kgm2()
    assert inertia == pytest.approx(big * length**2 / 12.0 + big * s * s, rel=1e-12)
    half = 0.5 * length
    text = big * ((half - s) ** 2 + (half + s) ** 2) / 3.0
    if axis_share == -1.0:
        assert inertia == pytest.approx(big * length**2 / 3.0, rel=1e-12)
        assert text == pytest.approx(inertia, rel=1e-12)
    if axis_share == 0.0:
        assert text == pytest.approx(2.0 * inertia, rel=1e-12)
    mb, v = p.ball_mass_kg, p.speed_mps
    lever = p.hit_m() - s
    m_eff = inertia / lever**2
    impulse = (1.0 + restitution) * mb * m_eff * v / (mb + m_eff)
    k = first_impact(run)
    assert 0 < k < len(run.times_s) - 1
    rebound = -v * (mb - restitution * m_eff) / (mb + m_eff)
    assert m["momentum_y_ns"][k, 0] / mb == pytest.approx(rebound, rel=1e-12, abs=1e-12)
    assert m["spin_radps"][k, 1] == pytest.approx(-impulse * lever / inertia, rel=1e-12)
    states: list = []
    simulate(get_scene("plank-anchored"), params, on_step=lambda q, st: states.append(st))
    for st in states:
        assert np.hypot(st.x_m[1] - s, st.y_m[1]) == pytest.approx(abs(s), abs=1e-12)
    check_conservation(run, linear=False)
    momentum = m["momentum_y_ns"].sum(axis=1)
    assert abs(momentum[-1] - momentum[0]) > 0.1 * mb * v  # the axis pushed


def test_many_beachballs_match_spins_where_they_collide_the_bad_ones_do_not() -> None:
    """§5, many beachballs: two balls colliding head-on with spins 3 and -1 rad/s leave
    with velocities by the envs' collide_balls and spins (3 - -1) / 2 = 2 and -2 (meshed
    gears: no spin slip at the contact); the bad variant leaves the spins as they were.
    Over a run of 12 balls (the same motion in both: spin never acts back) the spins'
    slip r |omega_i + omega_j| between touching balls averages under a tenth of the
    unmatched one (measured 0.05 against 0.69 m/s)."""
    p = get_scene("many-beachballs").make_params({"balls": 2, "restitution": 0.7})
    r = p.radius_m
    rows = ([0.0, 1.99 * r], [1.0, 1.0], [1.5, -0.5], [0.2, 0.0], [0.0, 0.0], [3.0, -1.0])
    two = rot.Spinning(*(np.array(a, dtype=np.float64) for a in rows))
    m = p.mass_kg()
    zero = np.zeros(1)
    v1, v2 = collide_balls(
        m,
        (two.vx_mps[0:1], two.vy_mps[0:1], zero),
        (zero, zero, zero),
        m,
        (two.vx_mps[1:2], two.vy_mps[1:2], zero),
        (1.0 + zero, zero, zero),
        0.7,
        np,
    )
    for match, spins in ((True, [2.0, -2.0]), (False, [3.0, -1.0])):
        out = rot.many_collide(p, two, match, np)
        np.testing.assert_array_equal(out.angular_velocity_radps, spins)
        np.testing.assert_allclose(out.vx_mps, [v1[0][0], v2[0][0]], rtol=1e-15)
        np.testing.assert_allclose(out.vy_mps, [0.2, 0.0], rtol=1e-15)
        assert out.x_m[1] - out.x_m[0] == pytest.approx(2.0 * r)  # the overlap pushed out
    good, bad = simulate(get_scene("many-beachballs")), simulate(get_scene("many-beachballs-bad"))
    np.testing.assert_array_equal(good.measures["height_m"], bad.measures["height_m"])
    touching = good.measures["contacts"] > 0
    assert touching.mean() > 0.3  # the balls pile up: most are touching another
    matched = good.measures["gear_slip_mps"][touching].mean()
    unmatched = bad.measures["gear_slip_mps"][touching].mean()
    assert unmatched > 0.3 and matched < 0.1 * unmatched
