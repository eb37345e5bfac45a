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
    LABEL_TOLERANCE,
    MAX_WAVE_STEEPNESS,
    Sea,
    WaterParams,
    current_velocity,
    max_wave_amplitude,
    particle_label,
    particle_position,
    sea_at_start,
    water_over,
    water_velocity,
    waves_at,
)

SEA_PARAMS = WaterParams(
    wave_amplitude_m=0.36,
    wavelength_m=10.0,
    wave_components=3,
    wave_spread_rad=0.6,
    current_variation=0.5,
    current_variation_length_m=60.0,
)
"""A steep sea (steepness near the limit) with a sheared current."""


def _sea(
    p: WaterParams,
    batch: int,
    seed: int = 0,
    current_mps: float = 0.0,
    current_set_rad: float = 0.0,
    wave_direction_rad: float = 0.4,
) -> Sea:
    """A batch of seas with the same current and wave direction and random phases."""
    rng = np.random.default_rng(seed)
    full = np.ones(batch)
    uniform = rng.random((len(p.components), batch))
    return sea_at_start(
        p, current_mps * full, current_set_rad * full, wave_direction_rad * full, uniform
    )


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
    assert p.components == () and p.label_iterations == 0 and p.steepness == 0.0
    x = np.linspace(-50.0, 50.0, 7)
    flow = water_over(p, _sea(p, 7), x, -x, 0.05)
    for value in flow:
        assert np.array_equal(value, np.zeros(7))
    assert np.array_equal(water_velocity(p, _sea(p, 7), x, -x)[0], np.zeros(7))


def test_deep_water_dispersion_crest_speed() -> None:
    """A single wave's crest travels at c = sqrt(g L / 2 pi) (omega^2 = g k)."""
    p = WaterParams(wave_amplitude_m=0.3, wavelength_m=12.0)
    x = np.linspace(0.0, 12.0, 120_001)
    sea = _sea(p, x.size, wave_direction_rad=0.0)._replace(phases=(np.zeros_like(x),))

    def crest(t: float) -> float:
        z = waves_at(p, sea._replace(time_s=t + 0 * x), x, 0.0 * x)[-1]
        return float(x[np.argmax(z)])

    c = math.sqrt(GRAVITY_MPS2 * 12.0 / (2.0 * math.pi))
    assert c == pytest.approx(4.328, abs=1e-3)
    t = 0.8
    assert crest(t) - crest(0.0) == pytest.approx(c * t, abs=2e-4)


def test_label_inverts_the_gerstner_map() -> None:
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-40, 40, 500), rng.uniform(-40, 40, 500)
    sea = _sea(SEA_PARAMS, 500)._replace(time_s=rng.uniform(0, 30, 500))
    assert SEA_PARAMS.steepness == pytest.approx(0.57, abs=0.01)
    a_x, a_y = particle_label(SEA_PARAMS, sea, x, y)
    back_x, back_y, _ = particle_position(SEA_PARAMS, sea, a_x, a_y)
    amplitudes = sum(c.amplitude_m for c in SEA_PARAMS.components)
    assert np.max(np.hypot(back_x - x, back_y - y)) < LABEL_TOLERANCE * amplitudes


@pytest.mark.parametrize("components", [1, 3])
def test_surface_particles_follow_closed_orbits(components: int) -> None:
    """Integrating the water's velocity at fixed points (Euler's view) moves a particle
    exactly as the Gerstner map says (Lagrange's): a single wave's orbit is a circle of
    radius A that closes after one period, with no drift (Gerstner waves carry no water);
    the acceleration given is the velocity's rate of change along the particle's path."""
    p = WaterParams(
        wave_amplitude_m=0.3, wavelength_m=9.0, wave_components=components, wave_spread_rad=0.5
    )
    sea0 = _sea(p, 16, seed=components, wave_direction_rad=2.0)
    a_x, a_y = np.linspace(-20, 20, 16), np.linspace(5, -5, 16)
    x0, y0, _ = particle_position(p, sea0, a_x, a_y)

    def at(t: float) -> Sea:
        return sea0._replace(time_s=t + 0.0 * a_x)

    def velocity(x: np.ndarray, y: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        return water_velocity(p, at(t), x, y)

    k = p.components[0].wavenumber_rad_per_m
    period = 2.0 * math.pi / math.sqrt(GRAVITY_MPS2 * k)
    t1 = 1.7 * period
    x1, y1 = _rk4(velocity, x0, y0, 0.0, t1, 500)
    x_ref, y_ref, z1 = particle_position(p, at(t1), a_x, a_y)
    assert np.max(np.hypot(x1 - x_ref, y1 - y_ref)) < 1e-5
    # over a substep the particle at a point moves as the map says, and ends with the
    # velocity of the water where it ends
    flow = water_over(p, at(t1), x_ref, y_ref, 0.05)
    x2, y2, _ = particle_position(p, at(t1 + 0.05), a_x, a_y)
    assert np.allclose(flow.shift_x_m, x2 - x_ref, atol=1e-6 * 0.3)
    assert np.allclose(flow.shift_y_m, y2 - y_ref, atol=1e-6 * 0.3)
    assert np.allclose(flow.vx_mps, water_velocity(p, at(t1), x_ref, y_ref)[0], atol=1e-12)
    end_x, end_y = water_velocity(p, at(t1 + 0.05), x2, y2)
    assert np.allclose(flow.next_vx_mps, end_x, atol=1e-6)
    assert np.allclose(flow.next_vy_mps, end_y, atol=1e-6)
    if components == 1:
        x2, y2 = _rk4(velocity, x0, y0, 0.0, period, 300)
        assert np.max(np.hypot(x2 - x0, y2 - y0)) < 1e-5
        # the orbit is a circle of radius A about the label a, in the vertical plane of
        # the wave's direction: seen from above, a line of length 2 A across the crests
        radius = np.hypot(np.hypot(x1 - a_x, y1 - a_y), z1)
        assert np.allclose(radius, 0.3, atol=1e-5)
        across = (x1 - a_x) * sea0.wave_y[0] - (y1 - a_y) * sea0.wave_x[0]
        assert np.allclose(across, 0.0, atol=1e-5)


def test_uniform_current_and_divergence_free_shear() -> None:
    uniform = WaterParams()
    sea = _sea(uniform, 2, current_mps=0.8, current_set_rad=math.radians(30.0))
    flow = water_over(uniform, sea, np.array([0.0, 100.0]), np.array([5.0, -70.0]), 0.1)
    assert np.allclose(flow.vx_mps, 0.8 * math.cos(math.radians(30.0)), atol=1e-15)
    assert np.allclose(flow.vy_mps, 0.4, atol=1e-15)
    assert np.array_equal(flow.next_vy_mps, flow.vy_mps)
    assert np.allclose(flow.shift_y_m, 0.04, atol=1e-15)

    shear = WaterParams(current_variation=0.6, current_variation_length_m=50.0)
    sea = _sea(shear, 400, current_mps=1.0, current_set_rad=0.7)
    rng = np.random.default_rng(2)
    x, y = rng.uniform(-200, 200, 400), rng.uniform(-200, 200, 400)
    vx, vy = current_velocity(shear, sea, x, y)
    speed = np.hypot(vx, vy)
    assert speed.min() == pytest.approx(0.4, abs=0.01)
    assert speed.max() == pytest.approx(1.6, abs=0.01)
    # direction is always the set, and the field has no divergence (central differences)
    assert np.allclose(np.arctan2(vy, vx), 0.7, atol=1e-12)
    h = 1e-4
    div = current_velocity(shear, sea, x + h, y)[0] - current_velocity(shear, sea, x - h, y)[0]
    div += current_velocity(shear, sea, x, y + h)[1] - current_velocity(shear, sea, x, y - h)[1]
    assert np.max(np.abs(div / (2 * h))) < 1e-7
    # and it does vary: the speed's gradient across the flow reaches 2 pi * 0.6 / 50
    step_x, step_y = -h * math.sin(0.7), h * math.cos(0.7)
    grad = (np.hypot(*current_velocity(shear, sea, x + step_x, y + step_y)) - speed) / h
    assert np.max(np.abs(grad)) == pytest.approx(2 * math.pi * 0.6 / 50.0, rel=0.01)
    # no current: the variation changes nothing and stays finite
    still = water_velocity(shear, _sea(shear, 400), x, y)
    assert np.array_equal(still[0], np.zeros(400))


def test_waves_too_steep_are_refused_naming_the_argument() -> None:
    # one wave: k A = 2 pi * 1.2 / 12 = 0.63 > 0.6
    with pytest.raises(ValueError, match=r"WaterParams\.wave_amplitude_m must be at most 1\.146"):
        WaterParams(wave_amplitude_m=1.2, wavelength_m=12.0)
    # the steepest accepted sea runs finite, its labels converged
    most = MAX_WAVE_STEEPNESS * 12.0 / (2 * math.pi)
    p = WaterParams(wave_amplitude_m=most, wavelength_m=12.0)
    assert p.steepness == pytest.approx(MAX_WAVE_STEEPNESS) and p.label_iterations == 28
    x = np.linspace(-30, 30, 2001)
    sea = _sea(p, x.size)._replace(time_s=1.3 + 0 * x)
    a_x, a_y = particle_label(p, sea, x, 0 * x)
    back_x, _, _ = particle_position(p, sea, a_x, a_y)
    assert np.max(np.abs(back_x - x)) < LABEL_TOLERANCE * most
    assert all(np.all(np.isfinite(v)) for v in water_over(p, sea, x, 0 * x, 0.25))
    with pytest.raises(ValueError, match=r"WaterParams\.current_variation"):
        WaterParams(current_variation=-0.1)
    with pytest.raises(TypeError, match=r"WaterParams\.wave_components"):
        WaterParams(wave_components=2.5)


def test_same_numbers_on_every_namespace() -> None:
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-30, 30, 9), rng.uniform(-30, 30, 9)
    sea = _sea(SEA_PARAMS, 9, current_mps=0.5, current_set_rad=2.0)
    sea = sea._replace(time_s=rng.uniform(0, 20, 9))
    reference = np.stack(water_over(SEA_PARAMS, sea, x, y, 0.05))
    # one env on Python floats
    one = Sea(
        *(tuple(float(v[4]) for v in f) if isinstance(f, tuple) else float(f[4]) for f in sea)
    )
    got = water_over(SEA_PARAMS, one, float(x[4]), float(y[4]), 0.05, floats)
    assert np.allclose(got, reference[:, 4], atol=1e-12, rtol=0)
    strict = pytest.importorskip("array_api_strict")
    torch = pytest.importorskip("torch")
    compat = pytest.importorskip("array_api_compat.torch")
    for xp, convert in ((strict, strict.asarray), (compat, torch.as_tensor)):

        def to(tree: Any, convert: Any = convert) -> Any:
            return tuple(map(to, tree)) if isinstance(tree, tuple) else convert(tree)

        got = water_over(SEA_PARAMS, Sea(*to(tuple(sea))), to(x), to(y), 0.05, xp)
        assert np.allclose(np.stack([np.asarray(g) for g in got]), reference, atol=1e-12, rtol=0)


@pytest.mark.parametrize("wave_components", [1, 3, 8])
@pytest.mark.parametrize("wavelength_m", [1.0, 1.6487212707001282, 12.0, 500.0])
def test_the_largest_amplitude_is_accepted_and_a_hair_more_is_not(wavelength_m, wave_components):
    """max_wave_amplitude is the edge of the accepted set, to the last bit (the fuzzer
    once drew the rounded-up quotient: 8 components of 1.65 m waves)."""
    most = max_wave_amplitude(wavelength_m, wave_components)
    water = WaterParams(
        wave_amplitude_m=most, wavelength_m=wavelength_m, wave_components=wave_components
    )
    assert water.steepness <= MAX_WAVE_STEEPNESS
    if most < 5.0:  # below the field's own cap the steepness is the limit
        assert water.steepness == pytest.approx(MAX_WAVE_STEEPNESS, rel=1e-12)
        with pytest.raises(ValueError, match="water|WaterParams.wave_amplitude_m"):
            WaterParams(
                wave_amplitude_m=most * (1 + 1e-9),
                wavelength_m=wavelength_m,
                wave_components=wave_components,
            )
