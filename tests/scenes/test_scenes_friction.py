"""§6, friction on a ball: the golf ball's bounce with friction and the envs' rolling ball
with and without the zero-crossing rule (``bbgym.scenes.friction``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.ball import BallParams, rolling_resistance, rolling_velocity
from bbgym.physics.common import GRAVITY_MPS2
from bbgym.scenes import get_scene, simulate
from bbgym.scenes.friction import golf_air, golf_contact

BACK, NONE, TOP = 0, 1, 2  # the golf ball's rows


def contacts(params: dict, steps: int) -> list[tuple]:
    """Each step of the golf scene split at the ground: ``(before, after)`` the contact,
    for the steps where the ground pushed some ball."""
    scene = get_scene("golf-ball")
    p = scene.make_params(params)
    s, found = scene.initial(p, np), []
    for _ in range(steps):
        flown = golf_air(p, s, np)
        s = golf_contact(p, flown, np)
        if np.any(s.vz != flown.vz):
            found.append((flown, s))
    return p, found


def expected_bounce(p, before, after) -> np.ndarray:
    """Coulomb's answer for the forward velocity after one contact: rolling (the angular
    momentum about the contact point kept) where friction's most, ``mu J_n``, can stop the
    slip, else the slip braked by exactly ``mu J_n``."""
    ball = p.ball
    m, r, inertia = ball.mass_kg, ball.radius_m, ball.inertia_kgm2
    normal = m * (after.vz - before.vz)
    slip = before.vx - r * before.wy
    stopping = np.abs(slip) / (1.0 / m + r * r / inertia)
    rolls = stopping <= ball.friction * normal
    rolled, _ = rolling_velocity(ball, before.vx, before.vy, before.wx, before.wy)
    slid = before.vx - np.sign(slip) * ball.friction * normal / m
    return np.where(rolls, rolled, slid), rolls


def test_golf_ball_backspin_checks_topspin_kicks_within_coulomb() -> None:
    """§6, the golf ball: at the first bounce the forward velocity is Coulomb's (to 1e-12):
    backspin slows the ball more than no spin (from 4.24 to 0.51 m/s at the defaults, a
    slide friction cannot stop; no spin rolls on at 5/7 of it, 3.03 m/s), topspin kicks it
    on (6.68 m/s, faster than it came); the backspun ball comes back at the next bounce,
    and at 1000 rad/s and mu = 1 at the first. Where friction suffices the contact rolls
    (slip 0 to 1e-12, all three at the end); with mu = 0.05 none does at the first bounce.
    Over spins and frictions no contact's tangential impulse exceeds mu J_n, no contact
    adds kinetic energy and the total energy never grows."""
    p, found = contacts({}, 60)
    before, after = found[0]
    forward, rolls = expected_bounce(p, before, after)
    np.testing.assert_allclose(after.vx, forward, rtol=1e-12, atol=1e-12)
    assert list(rolls) == [False, True, True]
    assert after.vx[BACK] < after.vx[NONE] < before.vx[NONE]
    assert np.all(after.vx[TOP] > before.vx)  # faster than any came down
    assert after.vx[NONE] == pytest.approx(5.0 / 7.0 * before.vx[NONE], rel=1e-12)
    assert after.vx[BACK] == pytest.approx(0.509, abs=1e-3)
    assert after.vx[TOP] == pytest.approx(6.681, abs=1e-3)
    r = p.ball.radius_m
    np.testing.assert_allclose((after.vx - r * after.wy)[rolls], 0.0, atol=1e-12)
    assert abs(after.vx[BACK] - r * after.wy[BACK]) > 1.0  # still sliding
    run = simulate(get_scene("golf-ball"))
    velocity, slip = run.measures["velocity_mps"], run.measures["slip_mps"]
    assert velocity[:, BACK].min() < -0.5  # it comes back
    np.testing.assert_allclose(slip[-1], 0.0, atol=1e-9)  # all three end rolling
    _, hard = contacts({"spin_radps": 1000.0, "friction": 1.0}, 60)
    assert hard[0][1].vx[BACK] < 0.0 < hard[0][0].vx[BACK]  # back at once
    q, icy = contacts({"friction": 0.05}, 60)
    forward, rolls = expected_bounce(q, *icy[0])
    assert not rolls.any()
    np.testing.assert_allclose(icy[0][1].vx, forward, rtol=1e-12)
    for spin in (0.0, 300.0, 1200.0):
        for mu in (0.1, 0.5, 1.5):
            q, found = contacts({"spin_radps": spin, "friction": mu}, 400)
            ball = q.ball
            for before, after in found:
                normal = ball.mass_kg * (after.vz - before.vz)
                tangential = ball.mass_kg * np.abs(after.vx - before.vx)
                assert np.all(tangential <= mu * normal * (1.0 + 1e-12) + 1e-15)
                kinetic = [
                    0.5 * ball.mass_kg * (s.vx**2 + s.vz**2) + 0.5 * ball.inertia_kgm2 * s.wy**2
                    for s in (before, after)
                ]
                assert np.all(kinetic[1] <= kinetic[0] * (1.0 + 1e-12))
            energy = simulate(
                get_scene("golf-ball"), {"spin_radps": spin, "friction": mu}, steps=400
            ).measures["energy_j"]
            assert np.all(np.diff(energy, axis=0) <= 1e-12)


OFF, ON = 0, 1  # the rolling ball's rows


def test_rolling_ball_stops_exactly_with_the_zero_crossing_rule_and_creeps_without() -> None:
    """§6, the zero crossing in the envs' rolling ball (a 2 m/s beach ball on grass,
    c = 0.1, substeps of 0.01 s): with ``rolling_stop`` it stops, speed and spin exactly 0,
    within v0 / (c g) = 2.04 s (at 1.62 s: drag helps) and stays; without it the speed is
    still above 0 three times as long after, falling by 3/5 a step (the shell's rolling
    share; 0.6 to 1e-3) once resistance would carry it through zero. Until the stop the two
    laws are the same, bit for bit."""
    scene = get_scene("rolling-ball")
    p = scene.make_params(None)
    bound = p.speed_mps / (p.rolling_resistance * GRAVITY_MPS2)
    assert bound == pytest.approx(2.0387, abs=1e-4)
    steps = math.ceil(bound / p.dt_s) + 1
    run = simulate(scene, steps=3 * steps)
    speed, spin = run.measures["speed_mps"], run.measures["rim_speed_mps"]
    moving = run.measures["moving_s"]
    stopped = np.flatnonzero((speed[:, ON] == 0.0) & (spin[:, ON] == 0.0))
    first = int(stopped[0])
    assert first <= steps and first * p.dt_s == pytest.approx(1.62, abs=0.005)
    assert np.all(speed[first:, ON] == 0.0) and np.all(spin[first:, ON] == 0.0)
    # moving_s counts the steps it ended moving: all before the stop
    assert moving[-1, ON] == pytest.approx((first - 1) * p.dt_s, abs=1e-9)
    np.testing.assert_array_equal(speed[:first, OFF], speed[:first, ON])
    assert np.all(speed[:, OFF] > 0.0)  # never 0, even at three times the bound
    assert moving[-1, OFF] == pytest.approx(3 * steps * p.dt_s)
    creeping = speed[:, OFF]
    window = (creeping[:-1] > 1e-9) & (creeping[:-1] < 1e-4)
    ratios = creeping[1:][window] / creeping[:-1][window]
    assert window.sum() >= 10
    np.testing.assert_allclose(ratios, 0.6, atol=1e-3)


def test_rolling_stop_needs_friction_to_hold_the_ball_and_is_off_by_default() -> None:
    """The rule stops a ball only where the ground's friction can take its momentum: on
    ice (mu = 0) a ball sliding with just the backspin that makes its rolling velocity 0
    slides on; with friction it stops. Off by default: every env version keeps its law."""
    assert BallParams().rolling_stop is False
    normal = 0.1  # N s, in resting contact
    for mu, stops in ((0.0, False), (0.6, True)):
        ball = BallParams(friction=mu, rolling_stop=True)
        r, m, inertia = ball.radius_m, ball.mass_kg, ball.inertia_kgm2
        vx = 0.05
        wy = -m * r * vx / inertia  # rolling velocity 0
        assert rolling_velocity(ball, vx, 0.0, 0.0, wy)[0] == pytest.approx(0.0, abs=1e-15)
        out = rolling_resistance(
            ball,
            np.array([vx]),
            np.array([0.0]),
            np.array([0.0]),
            np.array([wy]),
            np.array([normal]),
            np,
        )
        assert bool(out[0][0] == 0.0 and out[3][0] == 0.0) is stops


def test_the_envs_throws_end_before_the_rolling_ball_creeps() -> None:
    """A throw's flight ends once the ball rests (below 0.1 m/s, ``ball_at_rest``), before
    the creep that ``rolling_stop`` removes: over 500 random throws in wind, with and
    without the rule (most rolling to rest), every landing, flight time, step count and
    final state is the same bit for bit, so no env version changes by it (it waits for a
    version that changes its dynamics anyway)."""
    from dataclasses import replace

    from bbgym.physics.ball import ball_at
    from bbgym.physics.flight import simulate_throw

    rng = np.random.default_rng(28)
    n = 500
    v = rng.uniform((-2.0, -8.0, 0.0), (12.0, 8.0, 10.0), (n, 3))
    w = rng.uniform(-30.0, 30.0, (n, 3))
    wind = rng.uniform(-4.0, 4.0, (2, n))
    start = ball_at(0.0, 0.0, 1.5, *v.T, *w.T, xp=np)
    results = [
        simulate_throw(
            replace(BallParams(), rolling_stop=stop),
            start,
            wind[0],
            wind[1],
            max_time_s=30.0,
            field_radius_m=100.0,
            record=False,
        )
        for stop in (False, True)
    ]
    rested = results[0].final
    assert np.sum(np.hypot(rested.vx, rested.vy) < 0.1) > n // 2  # rolled to rest, most
    for field, value in results[0]._asdict().items():
        if field == "trajectory":
            continue
        for got, want in zip(
            np.atleast_1d(results[1]._asdict()[field]), np.atleast_1d(value), strict=True
        ):
            np.testing.assert_array_equal(got, want, err_msg=field)
