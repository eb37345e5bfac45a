"""Gusts and shifts: a smooth, seeded, stationary random process."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.wind import GustParams, gust_init, gust_step, wind_vector


def simulate(seed: int, batch: int = 2000, steps: int = 400, dt: float = 0.25):
    params = GustParams()
    rng = np.random.default_rng(seed)
    on = np.ones(batch, dtype=bool)
    g = gust_init(params, rng.standard_normal((2, batch)), on)
    speeds = []
    for _ in range(steps):
        g = gust_step(g, params, dt, rng.standard_normal((2, batch)), on)
        speeds.append(g.speed.copy())
    return params, g, np.array(speeds)


def test_gusts_are_seeded():
    _, a, _ = simulate(3, batch=10, steps=50)
    _, b, _ = simulate(3, batch=10, steps=50)
    _, c, _ = simulate(4, batch=10, steps=50)
    np.testing.assert_array_equal(a.speed, b.speed)
    assert not np.allclose(a.speed, c.speed)


def test_gust_statistics_and_smoothness():
    params, g, speeds = simulate(0)
    # The raw process is stationary with the configured std; smoothing shrinks it a little.
    assert np.std(g.speed_raw) == pytest.approx(params.speed_std, rel=0.1)
    assert 0.6 * params.speed_std < np.std(g.speed) < params.speed_std
    assert np.std(g.shift) < params.shift_std_rad
    # Smooth: a quarter-second change is tiny compared with the spread.
    step_change = np.abs(np.diff(speeds, axis=0)).mean()
    assert step_change < 0.05 * params.speed_std


def test_disabled_gusts_give_steady_wind():
    params = GustParams()
    off = np.zeros(3, dtype=bool)
    g = gust_init(params, np.ones((2, 3)), off)
    g = gust_step(g, params, 0.25, np.ones((2, 3)), off)
    wx, wy, speed, wind_from = wind_vector(np.full(3, 5.0), np.full(3, math.pi / 2), g)
    np.testing.assert_allclose(speed, 5.0)
    # From the north: the air moves south.
    np.testing.assert_allclose(wy, -5.0)
    np.testing.assert_allclose(wx, 0.0, atol=1e-12)


def test_gust_params_validation():
    with pytest.raises(ValueError, match="speed_std"):
        GustParams(speed_std=-0.1)
    with pytest.raises(ValueError, match="time_constant_s"):
        GustParams(time_constant_s=0.0)
