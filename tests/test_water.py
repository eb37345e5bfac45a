"""Water that moves (bbgym.physics.water): the current's field, Gerstner waves' dispersion,
closed orbits and self-intersection limit, and the same numbers on every namespace."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import floats
from bbgym.physics.water import (
    MAX_WAVE_STEEPNESS,
    Sea,
    WaterParams,
    current_velocity,
    orbital_velocity,
    particle_label,
    particle_position,
    sea_at_start,
    water_velocity,
)

SEA = WaterParams(
    wave_amplitude_m=0.36, wavelength_m=10.0, wave_direction_rad=0.4,
    wave_components=3, wave_spread_rad=0.6, current_mps=0.3, current_set_rad=-1.0,
    current_variation=0.5, current_variation_length_m=60.0,
)  # fmt: skip
"""A steep sea (steepness near the limit) with a sheared current."""


def _phases(p: WaterParams, batch: int, seed: int = 0) -> tuple[np.ndarray, ...]:
    uniform = np.random.default_rng(seed).random((len(p.components), batch))
    return sea_at_start(p, uniform).phases


def _rk4(velocity: Any, x: np.ndarray, y: np.ndarray, t0: float, t1: float, steps: int):
    h = (t1 - t0) / steps
    t = t0
    for _ in range(steps):
        k1 = velocity(x, y, t)
        k2 = velocity(x + 0.5 * h * k1[0], y + 0.5 * h * k1[1], t + 0.5 * h)
        k3 = velocity(x + 0.5 * h * k2[0], y + 0.5 * h * k2[1], t + 0.5 * h)
        k4 = velocity(x + h * k3[0], y + h * k3[1], t + h)
        x = x + h / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        y = y + h / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        t += h
    return x, y


def test_still_water_by_default() -> None:
    p = WaterParams()
    assert p.still and p.components == () and p.label_iterations == 0
    x = np.linspace(-50.0, 50.0, 7)
    vx, vy = water_velocity(p, x, -x, Sea(3.0, ()))
    assert np.array_equal(vx, np.zeros(7)) and np.array_equal(vy, np.zeros(7))


def test_deep_water_dispersion_crest_speed() -> None:
    """A single wave's crest travels at c = sqrt(g L / 2 pi) (omega^2 = g k)."""
    p = WaterParams(wave_amplitude_m=0.3, wavelength_m=12.0)
    x = np.linspace(0.0, 12.0, 120_001)
    phase = (np.zeros_like(x),)

    def crest(t: float) -> float:
        _, _, _, z = orbital_velocity(p, x, 0.0 * x, Sea(t, phase))
        return float(x[np.argmax(z)])

    c = math.sqrt(GRAVITY_MPS2 * 12.0 / (2.0 * math.pi))
    assert c == pytest.approx(4.328, abs=1e-3)
    t = 0.8
    assert crest(t) - crest(0.0) == pytest.approx(c * t, abs=2e-4)


def test_label_inverts_the_gerstner_map() -> None:
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-40, 40, 500), rng.uniform(-40, 40, 500)
    t = rng.uniform(0, 30, 500)
    phases = _phases(SEA, 500)
    assert SEA.steepness == pytest.approx(0.57, abs=0.01)
    a_x, a_y = particle_label(SEA, x, y, Sea(t, phases))
    back_x, back_y, _ = particle_position(SEA, a_x, a_y, Sea(t, phases))
    amplitudes = sum(c.amplitude_m for c in SEA.components)
    assert np.max(np.hypot(back_x - x, back_y - y)) < 1e-4 * amplitudes


@pytest.mark.parametrize("components", [1, 3])
def test_surface_particles_follow_closed_orbits(components: int) -> None:
    """Integrating the water's velocity at fixed points (Euler's view) moves a particle
    exactly as the Gerstner map says (Lagrange's): a single wave's orbit is a circle of
    radius A that closes after one period, with no drift (Gerstner waves carry no water)."""
    p = WaterParams(
        wave_amplitude_m=0.3, wavelength_m=9.0, wave_direction_rad=2.0,
        wave_components=components, wave_spread_rad=0.5,
    )  # fmt: skip
    phases = _phases(p, 16, seed=components)
    a_x, a_y = np.linspace(-20, 20, 16), np.linspace(5, -5, 16)
    x0, y0, _ = particle_position(p, a_x, a_y, Sea(0.0, phases))

    def velocity(x: np.ndarray, y: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        return water_velocity(p, x, y, Sea(t, phases))

    k = p.components[0].wavenumber_rad_per_m
    period = 2.0 * math.pi / math.sqrt(GRAVITY_MPS2 * k)
    x1, y1 = _rk4(velocity, x0, y0, 0.0, 1.7 * period, 500)
    x_ref, y_ref, _ = particle_position(p, a_x, a_y, Sea(1.7 * period, phases))
    assert np.max(np.hypot(x1 - x_ref, y1 - y_ref)) < 1e-5
    if components == 1:
        x2, y2 = _rk4(velocity, x0, y0, 0.0, period, 300)
        assert np.max(np.hypot(x2 - x0, y2 - y0)) < 1e-5
        # the orbit is a circle of radius A about the label a, in the vertical plane of
        # the wave's direction: seen from above, a line of length 2 A across the crests
        _, _, z1 = particle_position(p, a_x, a_y, Sea(1.7 * period, phases))
        radius = np.hypot(np.hypot(x1 - a_x, y1 - a_y), z1)
        assert np.allclose(radius, 0.3, atol=1e-5)
        d = p.components[0]
        assert np.allclose((x1 - a_x) * d.direction_y - (y1 - a_y) * d.direction_x, 0.0, atol=1e-5)


def test_uniform_current_and_divergence_free_shear() -> None:
    uniform = WaterParams(current_mps=0.8, current_set_rad=math.radians(30.0))
    vx, vy = water_velocity(uniform, np.array([0.0, 100.0]), np.array([5.0, -70.0]), Sea(2.0, ()))
    assert np.allclose(vx, 0.8 * math.cos(math.radians(30.0)), atol=1e-15)
    assert np.allclose(vy, 0.4, atol=1e-15)

    shear = WaterParams(
        current_mps=1.0, current_set_rad=0.7, current_variation=0.6,
        current_variation_length_m=50.0,
    )  # fmt: skip
    rng = np.random.default_rng(2)
    x, y = rng.uniform(-200, 200, 400), rng.uniform(-200, 200, 400)
    vx, vy = current_velocity(shear, x, y)
    speed = np.hypot(vx, vy)
    assert speed.min() == pytest.approx(0.4, abs=0.01) and speed.max() == pytest.approx(
        1.6, abs=0.01
    )
    # direction is always the set, and the field has no divergence (central differences)
    assert np.allclose(np.arctan2(vy, vx), 0.7, atol=1e-12)
    h = 1e-4
    div = (current_velocity(shear, x + h, y)[0] - current_velocity(shear, x - h, y)[0]) / (2 * h)
    div += (current_velocity(shear, x, y + h)[1] - current_velocity(shear, x, y - h)[1]) / (2 * h)
    assert np.max(np.abs(div)) < 1e-7
    # and it does vary: the speed's gradient across the flow reaches 2 pi * 0.6 / 50
    grad = (np.hypot(*current_velocity(shear, x - h * math.sin(0.7), y + h * math.cos(0.7)))
            - speed) / h  # fmt: skip
    assert np.max(np.abs(grad)) == pytest.approx(2 * math.pi * 0.6 / 50.0, rel=0.01)


def test_waves_too_steep_are_refused_naming_the_argument() -> None:
    # one wave: k A = 2 pi * 1.2 / 12 = 0.63 > 0.6
    with pytest.raises(ValueError, match=r"WaterParams\.wave_amplitude_m must be at most 1\.146"):
        WaterParams(wave_amplitude_m=1.2, wavelength_m=12.0)
    # the steepest accepted sea runs finite, its labels converged
    most = MAX_WAVE_STEEPNESS * 12.0 / (2 * math.pi)
    p = WaterParams(wave_amplitude_m=most, wavelength_m=12.0)
    assert p.steepness == pytest.approx(MAX_WAVE_STEEPNESS) and p.label_iterations == 19
    x = np.linspace(-30, 30, 2001)
    phases = (np.zeros_like(x),)
    a_x, a_y = particle_label(p, x, 0 * x, Sea(1.3, phases))
    back_x, _, _ = particle_position(p, a_x, a_y, Sea(1.3, phases))
    assert np.max(np.abs(back_x - x)) < 1e-4 * most
    with pytest.raises(ValueError, match=r"WaterParams\.current_mps"):
        WaterParams(current_mps=-0.1)
    with pytest.raises(TypeError, match=r"WaterParams\.wave_components"):
        WaterParams(wave_components=2.5)


def _strict() -> Any:
    return pytest.importorskip("array_api_strict")


def _torch() -> Any:
    torch = pytest.importorskip("torch")
    compat = pytest.importorskip("array_api_compat.torch")
    return compat, torch


def test_same_numbers_on_every_namespace() -> None:
    rng = np.random.default_rng(3)
    x, y, t = rng.uniform(-30, 30, 9), rng.uniform(-30, 30, 9), rng.uniform(0, 20, 9)
    phases = _phases(SEA, 9)
    reference = np.stack(water_velocity(SEA, x, y, Sea(t, phases)))
    heights = orbital_velocity(SEA, x, y, Sea(t, phases))
    # one env on Python floats
    one = water_velocity(SEA, float(x[4]), float(y[4]), Sea(float(t[4]),
                         tuple(float(ph[4]) for ph in phases)), floats)  # fmt: skip
    assert np.allclose(one, reference[:, 4], atol=1e-12, rtol=0)
    strict = _strict()
    to = lambda a: strict.asarray(a)  # noqa: E731
    got = water_velocity(SEA, to(x), to(y), Sea(to(t), tuple(map(to, phases))), strict)
    assert np.allclose(np.stack([np.asarray(g) for g in got]), reference, atol=1e-12, rtol=0)
    compat, torch = _torch()
    tt = lambda a: torch.as_tensor(a, dtype=torch.float64)  # noqa: E731
    got = orbital_velocity(SEA, tt(x), tt(y), Sea(tt(t), tuple(map(tt, phases))), compat)
    assert np.allclose(np.stack([g.numpy() for g in got]), np.stack(heights), atol=1e-12, rtol=0)
