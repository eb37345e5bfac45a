"""§8's turbulence and falling-wall scenes: the drag crisis, gusts as randomness, and the
wall that turns about its edge (the claims measured; the generic checks of every scene are
in tests/scenes/test_scenes.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.wall import FALLEN_AWAY, LOOSE, STANDING
from bbgym.scenes import get_scene, simulate
from bbgym.scenes.wind import AIR_VISCOSITY_PAS, MINSTD_MODULUS, next_uniform, reynolds_number

LAMINAR, TURBULENT, BY_REYNOLDS, SMALL, GUSTY = range(5)


def test_turbulence_drag_crisis_switches_at_the_critical_reynolds_number() -> None:
    """§8 (laminar 0.47, turbulent 0.2, after Palmer): the laminar and turbulent large
    balls fall at their terminal speeds sqrt(2 m g / (rho C_d A)) (to 0.01%), 8.34 and
    12.79 m/s, sqrt(0.47 / 0.2) apart; the ball whose Reynolds number decides keeps 0.47
    while Re < 3e5 and 0.2 from the step it passes it (at 4.5 m/s through the air, Re_c
    mu / (rho d)), and ends at the turbulent terminal speed; the small ball's Re stays
    under 3e5 (2.2e5 at 8.34 m/s), it stays laminar; with the critical number raised to
    1e6 the large one stays laminar too."""
    scene = get_scene("turbulence")
    run = simulate(scene)
    p = run.params
    speed, re, cd = (run.measures[k] for k in ("fall_speed_mps", "reynolds", "drag_coefficient"))
    pairs = p.ball_pairs()
    laminar_v, turbulent_v = (pairs[k][0].terminal_speed_mps() for k in (LAMINAR, TURBULENT))
    assert turbulent_v / laminar_v == pytest.approx(math.sqrt(0.47 / 0.2), rel=1e-12)
    assert laminar_v == pytest.approx(8.34, abs=0.01)
    assert turbulent_v == pytest.approx(12.79, abs=0.01)
    for row, terminal in (
        (LAMINAR, laminar_v),
        (TURBULENT, turbulent_v),
        (BY_REYNOLDS, turbulent_v),
        (SMALL, laminar_v),
    ):
        assert speed[-1, row] == pytest.approx(terminal, rel=1e-4), row
    # the crisis: one switch, exactly where Re reaches the critical number
    below = re[:, BY_REYNOLDS] < p.critical_reynolds
    switch = int(np.argmin(below))
    assert 0 < switch and np.all(below[:switch]) and not np.any(below[switch:])
    assert np.all(cd[:switch, BY_REYNOLDS] == 0.47) and np.all(cd[switch:, BY_REYNOLDS] == 0.2)
    crisis_speed = p.critical_reynolds * AIR_VISCOSITY_PAS / (1.2 * 2.0 * p.large_radius_m)
    assert crisis_speed == pytest.approx(4.525, abs=1e-3)
    air_speed = re[switch - 1 : switch + 1, BY_REYNOLDS] * crisis_speed / p.critical_reynolds
    assert air_speed[0] < crisis_speed <= air_speed[1]
    # before the switch it falls exactly as the laminar ball does
    np.testing.assert_array_equal(speed[: switch + 1, BY_REYNOLDS], speed[: switch + 1, LAMINAR])
    assert np.all(speed[switch + 60 :, BY_REYNOLDS] > speed[switch + 60 :, LAMINAR])
    # the small ball never reaches the crisis
    assert re[:, SMALL].max() == pytest.approx(reynolds_number(laminar_v, 0.4), rel=1e-3)
    assert re[:, SMALL].max() < 2.3e5 and np.all(cd[:, SMALL] == 0.47)
    late = simulate(scene, {"critical_reynolds": 1e6}).measures
    assert np.all(late["drag_coefficient"][:, BY_REYNOLDS] == 0.47)
    assert late["fall_speed_mps"][-1, BY_REYNOLDS] == pytest.approx(laminar_v, rel=1e-4)


def test_turbulence_gusts_are_random_with_the_steady_mean_and_repeat_under_a_seed() -> None:
    """§8 ("we can probably model it with randomness"): the gusty ball's run is the same
    for the same seed and another for another seed; over 8 seeds, after 3 s, its drift
    averages the steady ball's drift in the steady wind (within 3 standard errors of the
    seeds' means) with a spread of a tenth of the wind or more, while the steady balls'
    drift is the same on every seed;
    it falls at the laminar terminal speed on average (within 0.5%). The generator is the
    exact Lehmer one: from 1, its 10,000th value is 1043618065 (Park and Miller's check)."""
    x = np.array([1.0])
    for _ in range(10_000):
        x, _ = next_uniform(x, np)
    assert x[0] == 1043618065.0 and 0.0 < x[0] < MINSTD_MODULUS
    scene = get_scene("turbulence")
    steps, settled = 480, 180
    runs = [simulate(scene, {"seed": seed}, steps=steps).measures for seed in range(8)]
    again = simulate(scene, {"seed": 0}, steps=steps).measures
    for key, values in runs[0].items():
        np.testing.assert_array_equal(again[key], values)
    assert (
        np.abs(runs[1]["drift_speed_mps"][:, GUSTY] - runs[0]["drift_speed_mps"][:, GUSTY]).max()
        > 0.1
    )
    for run in runs[1:]:
        np.testing.assert_array_equal(
            run["drift_speed_mps"][:, :GUSTY], runs[0]["drift_speed_mps"][:, :GUSTY]
        )
    wind = scene.make_params(None).wind_mps
    # the steady ball, in the same laminar drag, is still catching up with the wind
    steady = runs[0]["drift_speed_mps"][settled:, LAMINAR]
    assert np.all(np.diff(steady) > 0.0) and 0.94 * wind < steady[0] < steady[-1] < wind
    drift = np.stack([run["drift_speed_mps"][settled:, GUSTY] for run in runs])
    means = drift.mean(axis=1)
    standard_error = means.std(ddof=1) / math.sqrt(len(means))
    assert abs(means.mean() - steady.mean()) < 3.0 * standard_error < 0.15 * wind
    assert drift.std() > 0.1 * wind
    fall = np.stack([run["fall_speed_mps"][settled:, GUSTY] for run in runs])
    laminar_v = scene.make_params(None).ball_pairs()[LAMINAR][0].terminal_speed_mps()
    assert fall.mean() == pytest.approx(laminar_v, rel=0.005)


def fall_time_s(inertia_over_moment_s2: float, start_rad: float, end_rad: float) -> float:
    """The time an inverted pendulum ``phi'' = sin(phi) / T^2`` (``T^2`` the ratio given)
    takes from rest at ``start`` to ``end``: energy gives ``phi'^2 = 2 (cos start -
    cos phi) / T^2``; the substitution ``phi = start + t^2`` takes the square root's
    singularity out of the integral (trapezoids on 200,001 points)."""
    t = np.linspace(0.0, math.sqrt(end_rad - start_rad), 200_001)
    gap = np.cos(start_rad) - np.cos(start_rad + t * t)
    integrand = np.where(
        t > 0,
        2.0 * t / np.sqrt(2.0 * np.maximum(gap, 1e-300)),
        2.0 / math.sqrt(2.0 * math.sin(start_rad)),
    )
    return math.sqrt(inertia_over_moment_s2) * float(np.trapezoid(integrand, t))


def test_falling_wall_falls_by_the_pendulum_law_and_the_wind_tips_or_tears_it() -> None:
    """§8, the Buster Keaton wall (Topple's wall physics): nudged 2 deg past its balance
    in calm air it falls about its edge as I phi'' = m g r sin(phi - phi_b) and lands
    within a step of that law's time (1.80 s); a thin slab (a 1 mm foot) lands within a
    step of phi'' = 3 g / (2 h) sin(phi)'s (1.83 s); turning on its edge, its energy less
    the wind's work h/2 F_w sin(phi) keeps to 1e-5 J until it lands, and drops then; in a
    breeze under the tipping speed (2.5 < 3.3 m/s) a wall stands still; a gale (5 m/s)
    tips an upright wall and it lands sooner than the nudged one; a storm (14 m/s, past
    the 11 m/s whose force the foot holds) tears it loose."""
    scene = get_scene("falling-wall")
    run = simulate(scene)
    p, m = run.params, run.measures
    wall = p.wall()
    status, lean, energy = m["status"], m["lean_deg"], m["energy_j"]
    calm, breeze, gale, storm = range(4)
    landed = [int(np.argmax(status[:, k] == FALLEN_AWAY)) for k in (calm, gale)]
    r = math.hypot(wall.half_base_m, 0.5 * wall.height_m)
    nudge = math.radians(p.nudge_deg)
    expected = fall_time_s(
        wall.inertia_kgm2 / (wall.mass_kg * GRAVITY_MPS2 * r),
        nudge,
        0.5 * math.pi - p.balance_rad(),
    )
    assert expected == pytest.approx(1.80, abs=0.01)
    assert (landed[0] - 1) * p.dt_s < expected <= landed[0] * p.dt_s
    for k, land in zip((calm, gale), landed, strict=True):
        assert np.all(np.abs(energy[:land, k] - energy[0, k]) < 1e-5), k
        assert energy[land, k] < energy[0, k] - 10.0  # the landing takes the rest
    assert p.breeze_mps < wall.tipping_wind_speed_mps() < p.gale_mps
    assert np.all(status[:, breeze] == STANDING) and np.all(lean[:, breeze] == 0.0)
    assert 0 < landed[1] < landed[0]
    assert wall.breakaway_wind_speed_mps() < p.storm_mps and status[-1, storm] == LOOSE
    assert np.all(status[:, gale] != LOOSE)
    thin = simulate(scene, {"base_depth_m": 1e-3, "thickness_m": 1e-3})
    tp = thin.params
    start = tp.balance_rad() + math.radians(tp.nudge_deg)
    slab = fall_time_s(2.0 * tp.height_m / (3.0 * GRAVITY_MPS2), start, 0.5 * math.pi)
    assert slab == pytest.approx(1.834, abs=0.01)
    thin_landed = int(np.argmax(thin.measures["status"][:, calm] == FALLEN_AWAY))
    assert (thin_landed - 1) * tp.dt_s < slab <= thin_landed * tp.dt_s
