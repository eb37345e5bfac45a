"""Topple-v2's interval (``interval_integrator="rk4_events"``): RK4 steps of 0.05 s with the
ball's bouncing touchdowns and its hit on the wall located inside a step
(:func:`bbgym.physics.toppling.event_bodies`), against analytic results (a ball in a
vacuum, a wall falling freely) and against a fine integration of v1's substeps."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from bbgym.physics.ball import BallParams, ball_at
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import replaced
from bbgym.physics.toppling import IntervalParams, interval_start, run_interval
from bbgym.physics.wall import WallParams, _lever, wall_at, wall_rk4_step
from bbgym.physics.wind import GustParams, gust_init

sys.path.insert(0, str(Path(__file__).parents[2] / "scripts"))
from topple_accuracy import V2, accuracy_run, errors_against  # noqa: E402

VACUUM = BallParams(drag_coefficient=0.0, lift_coefficient_max=0.0)


def interval_params(ball: BallParams, sim_dt: float, integrator: str) -> IntervalParams:
    """A 3-s interval, gusts every 0.25 s, a sample every 0.05 s."""
    return IntervalParams(
        wall=WallParams(),
        ball=ball,
        gust=GustParams(),
        sim_dt=sim_dt,
        gust_dt=0.25,
        n_substeps=round(3.0 / sim_dt),
        gust_every=round(0.25 / sim_dt),
        record_every=round(0.05 / sim_dt),
        chunk_substeps=round(0.25 / sim_dt),
        integrator=integrator,
    )


def calm_interval(params: IntervalParams, velocity: np.ndarray, wall_x: float):
    """Balls launched from 1.5 m up at ``velocity`` (rows vx, vz) without spin, at walls
    ``wall_x`` away, in still air; the carry at the interval's end (samples kept)."""
    n = velocity.shape[1]
    zero = np.zeros(n)
    ball = ball_at(zero, zero, zero + 1.5, velocity[0], zero, velocity[1], zero, zero, zero)
    wall = wall_at(zero + wall_x, np)
    off = np.zeros(n, dtype=bool)
    gust = gust_init(params.gust, (zero, zero), off, np)
    carry = interval_start(params, ball, wall, gust, zero, zero, ~off, ~off, np, record=True)
    noise = np.zeros((2 * params.n_gust_updates, n))
    return run_interval(params, carry, zero, zero, off, noise, np, stop_early=False)


def test_a_hit_in_a_vacuum_is_located_exactly():
    """Without air the flight is a parabola, which RK4 integrates exactly: the ball's
    centre reaches the upright face (one radius plus half the panel's thickness before
    the foot's centre) at the parabola's height there, to rounding; v1's substeps find it
    up to a substep late."""
    velocity = np.array([[6.0, 8.0, 10.0, 12.0, 14.0], [3.0, 2.0, 1.0, 0.5, 0.0]])
    wall_x = 4.0
    contact_x = wall_x - 0.5 * WallParams().thickness_m - VACUUM.radius_m
    t = contact_x / velocity[0]
    expected = 1.5 + velocity[1] * t - 0.5 * GRAVITY_MPS2 * t * t
    assert np.all((expected > 0.2) & (expected < 2.4))  # every throw meets the face
    v2 = calm_interval(interval_params(VACUUM, 0.05, "rk4_events"), velocity, wall_x)
    np.testing.assert_array_equal(v2.hits, 1)
    np.testing.assert_allclose(v2.hit_height, expected, rtol=0, atol=1e-9)
    v1 = calm_interval(interval_params(VACUUM, 0.01, "semi_implicit_euler"), velocity, wall_x)
    assert np.abs(v1.hit_height - expected).max() > 1e-3


def test_a_bounce_in_a_vacuum_is_located_exactly():
    """A ball thrown at a far wall lands and bounces: sampled every 0.05 s, its height
    follows the parabola to the touchdown at one radius, then the one leaving it at
    ``restitution`` times the impact speed, to rounding (the bounce falls inside a step)."""
    velocity = np.array([[2.0, 3.0, 4.0], [1.0, 2.5, 4.0]])
    r, e, g = VACUUM.radius_m, VACUUM.restitution, GRAVITY_MPS2
    carry = calm_interval(interval_params(VACUUM, 0.05, "rk4_events"), velocity, 40.0)
    heights = np.array([sample[2] for sample in carry.taken])
    times = 0.05 * np.arange(len(heights))[:, None]
    vz = velocity[1]
    landing = (vz + np.sqrt(vz * vz + 2.0 * g * (1.5 - r))) / g
    assert np.all(landing % 0.05 > 1e-3)  # inside a step, not on its end
    rebound = e * g * landing - e * vz  # e times the impact speed
    after = times - landing
    expected = np.where(
        after < 0.0,
        1.5 + vz * times - 0.5 * g * times * times,
        r + rebound * after - 0.5 * g * after * after,
    )
    before_second = after < 2.0 * rebound / g - 0.05
    np.testing.assert_allclose(heights[before_second], expected[before_second], rtol=0, atol=1e-9)


def free_fall(dt_s: float, time_s: float = 0.7):
    """A wall leaning 0.4 rad (past its tipping lean of atan(b / (h / 2)) = 0.165) falls
    about its far edge in still air: (lean, rate) after ``time_s`` in RK4 steps."""
    wall = wall_at(np.array([4.0]), np)
    wall = replaced(wall, angle=wall.angle + 0.4, pivot=wall.pivot + 1.0)
    for _ in range(round(time_s / dt_s)):
        wall = wall_rk4_step(WallParams(), wall, np.zeros(1), dt_s, np)
    return wall


def test_the_walls_rk4_step_keeps_the_energy_and_is_fourth_order():
    p = WallParams()

    def energy(w):
        _, z_cm = _lever(p, w.angle, w.pivot, np)
        return 0.5 * p.inertia_kgm2 * w.rate**2 + p.mass_kg * GRAVITY_MPS2 * z_cm

    start = free_fall(0.05, 0.0)
    coarse = free_fall(0.05)
    assert 0.5 < coarse.angle[0] < 1.4 and coarse.status[0] == 0  # falling, not yet down
    drop = p.mass_kg * GRAVITY_MPS2 * 0.5 * p.height_m
    assert abs(energy(coarse)[0] - energy(start)[0]) < 1e-5 * drop
    reference = free_fall(0.001)
    errors = [abs(free_fall(dt).angle[0] - reference.angle[0]) for dt in (0.05, 0.025)]
    assert errors[0] < 1e-4
    assert errors[0] / errors[1] > 12.0  # 16 for a fourth-order method


@pytest.mark.parametrize("seed", [0, 1])
def test_v2_is_closer_to_a_fine_integration_than_v1(seed: int):
    """Against v1's substeps at 0.001 s (10x finer than v1's): v2's steps of 0.05 s give
    the walls' outcomes and the hits as the reference does (99% and 98% at least; the
    outcomes as often as v1's 0.01 s substeps or more), the wall's lean within 5 mrad
    (p95 of each throw's largest difference over the interval), the hit's height within
    3 cm and the ball's first 0.6 s within 1 cm (p95 both), each several times closer
    than v1's 0.01 s substeps."""
    reference = accuracy_run(seed=seed, sim_dt=0.001)
    assert reference["hit"].mean() > 0.25 and np.abs(reference["lean"]).max() > 0.1
    v1 = errors_against(reference, accuracy_run(seed=seed))
    v2 = errors_against(reference, accuracy_run(seed=seed, **V2))
    assert v2["status"] >= 0.99 and v2["hit"] >= 0.98
    assert v2["lean"] < 0.005 and v2["hit_height"] < 0.03 and v2["flight"] < 0.01
    assert v2["status"] >= v1["status"]
    assert v2["lean"] < v1["lean"] / 3.0, (v1, v2)
    assert v2["hit_height"] < v1["hit_height"] / 2.0, (v1, v2)
    assert v2["flight"] < v1["flight"] / 3.0, (v1, v2)
