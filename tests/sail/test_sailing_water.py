"""The dinghy in moving water (bbgym.physics.sailing_step with bbgym.physics.water): still
water keeps the first versions' bits, a current carries a boat, a floating boat rides a
Gerstner wave's closed orbit, and the rudder needs speed through the water."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from bbgym.physics.common import AIR_DENSITY_KGM3, GRAVITY_MPS2, WATER_DENSITY_KGM3
from bbgym.physics.dinghy import DinghyParams, DinghyState, dinghy_at_rest
from bbgym.physics.sailing_step import step
from bbgym.physics.water import Sea, WaterParams, sea_at_start, water_velocity

P = DinghyParams()
N = 6


def _sea(
    p: WaterParams,
    batch: int,
    current_mps: float = 0.0,
    current_set_rad: float = 0.0,
    wave_direction_rad: float = 0.3,
    seed: int = 0,
) -> Sea:
    full = np.ones(batch)
    uniform = np.random.default_rng(seed).random((len(p.components), batch))
    return sea_at_start(
        p, current_mps * full, current_set_rad * full, wave_direction_rad * full, uniform
    )


def _sail(
    p: DinghyParams,
    boat: DinghyState,
    water: WaterParams | None,
    sea: Sea | None,
    seconds: float,
    dt_s: float = 0.05,
    rudder_rad: float = 0.0,
    wind: tuple = (0.0, 0.0),
    substeps: int = 5,
) -> tuple[DinghyState, list[DinghyState]]:
    """Steps of ``substeps`` substeps with the controls held, the sea's clock running."""
    n = boat.x_m.shape[0]
    zero = np.zeros(n)
    track = [boat]
    for k in range(round(seconds / (dt_s * substeps))):
        if sea is not None:
            sea = sea._replace(time_s=zero + k * dt_s * substeps)
        boat, _ = step(
            p,
            boat,
            zero + rudder_rad,
            zero + 1.0,
            zero + wind[0],
            zero + wind[1],
            dt_s,
            substeps,
            np,
            water,
            sea,
        )
        track.append(boat)
    return boat, track


def test_still_water_keeps_the_bits_of_no_water() -> None:
    """A sea with no current and no waves changes no bit of the first versions' step."""
    rng = np.random.default_rng(0)
    boat = dinghy_at_rest(
        N,
        heading_rad=rng.uniform(-3, 3, N),
        speed_mps=rng.uniform(0, 4, N),
        boom_rad=rng.uniform(-1, 1, N),
    )
    boat = boat._replace(x_m=rng.uniform(-50, 50, N), heel_rad=rng.uniform(-0.5, 0.5, N))
    controls = (
        rng.uniform(-0.5, 0.5, N),
        rng.uniform(0, 1, N),
        rng.uniform(-8, 8, N),
        rng.uniform(-8, 8, N),
    )
    still = WaterParams()
    plain = step(P, boat, *controls, 0.05, 5, np)
    watered = step(P, boat, *controls, 0.05, 5, np, still, _sea(still, N))
    for a, b in zip(plain[0], watered[0], strict=True):
        assert np.array_equal(a, b)


def test_a_current_carries_a_boat() -> None:
    water = WaterParams()
    # Without windage nothing holds a boat back from the water: one drifting with the
    # current stays with it exactly, one at rest across it is soon carried (the centreboard
    # grips the water sideways).
    bare = P.replace(windage=0.0)
    sea = _sea(water, 2, current_mps=1.0, current_set_rad=math.pi / 2)
    drifting = dinghy_at_rest(2, speed_mps=[1.0, 0.0], heading_rad=math.pi / 2)
    boat, _ = _sail(bare, drifting, water, sea, 30.0)
    assert boat.vy_mps[0] == pytest.approx(1.0, abs=1e-12)
    assert boat.vx_mps[0] == pytest.approx(0.0, abs=1e-12)
    assert boat.y_m[0] == pytest.approx(30.0, abs=1e-9)
    beam_on = dinghy_at_rest(1, heading_rad=0.0)
    boat, _ = _sail(bare, beam_on, water, _sea(water, 1, 1.0, math.pi / 2), 30.0)
    assert boat.vy_mps[0] == pytest.approx(1.0, abs=0.02)

    # With windage and no wind the boat meets a headwind as fast as it moves over the
    # ground: it lags the current, going astern through the water at u = c - v, and
    # settles where the air's drag equals the water's on the hull moving astern,
    # 1/2 rho_air C_w v^2 = 1/2 rho_water C_astern (1 + u^2 / u_w^2) u^2.
    def balance(v: float) -> float:
        u = 1.0 - v
        wave = 1.0 + (u / P.hull_wave_speed_mps) ** 2
        hull = WATER_DENSITY_KGM3 * P.hull_drag_backward * wave
        return AIR_DENSITY_KGM3 * P.windage * v * v - hull * u * u

    settled = brentq(balance, 0.0, 1.0)
    boat, _ = _sail(P, dinghy_at_rest(1), water, _sea(water, 1, 1.0, 0.0), 240.0)
    assert settled == pytest.approx(0.892, abs=0.001)
    assert boat.vx_mps[0] == pytest.approx(settled, abs=0.002)


def test_a_floating_boat_rides_a_closed_gerstner_orbit() -> None:
    """No wind, no current, one wave: a hull moving with the water follows its particle's
    circle and comes back after each period (Gerstner waves carry no water), at the env's
    0.05 s substep; with its sail and windage in the still air it strays by centimetres."""
    water = WaterParams(wave_amplitude_m=0.3, wavelength_m=12.0)
    period = 2.0 * math.pi / math.sqrt(GRAVITY_MPS2 * 2.0 * math.pi / 12.0)
    substeps = 55
    dt = period / substeps  # about 0.05 s
    sea = _sea(water, N)
    boat = dinghy_at_rest(N, x_m=np.linspace(-20, 20, N), heading_rad=np.linspace(0, 3, N))
    vx, vy = water_velocity(water, sea, boat.x_m, boat.y_m)
    boat = boat._replace(vx_mps=vx, vy_mps=vy)
    # a capsized boat without windage: a hull alone, nothing but the water on it
    hull_only = boat._replace(capsized=np.ones(N, dtype=bool))
    ten_periods = [hull_only]
    for k in range(10):
        now = sea._replace(time_s=sea.time_s + k * period)
        after, _ = step(
            P.replace(windage=0.0),
            ten_periods[-1],
            0 * vx,
            0 * vx + 1,
            0 * vx,
            0 * vx,
            dt,
            substeps,
            np,
            water,
            now,
        )
        ten_periods.append(after)
    # within the accuracy of the particle labels: less than a micrometre a period (the
    # water's flow held over each substep instead strayed by 0.1 m a period at 0.05 s)
    for k, after in enumerate(ten_periods[1:], start=1):
        tolerance = 1e-6 * k
        assert np.max(np.hypot(after.x_m - boat.x_m, after.y_m - boat.y_m)) < tolerance
        assert np.max(np.hypot(after.vx_mps - vx, after.vy_mps - vy)) < tolerance
    # the whole boat, its sail and hull in the still air
    after, track = _sail(P, boat, water, sea, period, dt_s=dt, substeps=1)
    assert np.max(np.hypot(after.x_m - boat.x_m, after.y_m - boat.y_m)) < 0.02
    xs = np.array([b.x_m for b in track])
    # it did move: along the wave's direction the orbit spans 2 A cos(0.3)
    assert np.ptp(xs, axis=0) == pytest.approx(np.full(N, 0.6 * math.cos(0.3)), abs=0.01)


def test_the_rudder_needs_speed_through_the_water() -> None:
    """1.5 m/s over the ground with full rudder for 10 s: drifting with a current the boat
    barely turns; through still water it turns most of the way round."""
    water = WaterParams()
    boat = dinghy_at_rest(1, speed_mps=1.5)
    drifting, _ = _sail(P, boat, water, _sea(water, 1, 1.5, 0.0), 10.0, rudder_rad=0.5)
    moving, _ = _sail(P, boat, None, None, 10.0, rudder_rad=0.5)
    assert abs(math.degrees(drifting.heading_rad[0])) < 3.0
    assert math.degrees(moving.heading_rad[0]) > 90.0
    # the same speed through the water against a current: it turns as in still water
    against, _ = _sail(P, boat, water, _sea(water, 1, 0.0, 0.0), 10.0, rudder_rad=0.5)
    assert against.heading_rad[0] == moving.heading_rad[0]
