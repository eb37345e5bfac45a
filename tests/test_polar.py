"""The default preset's polar matches a real dinghy's (DESIGN §6)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.polar import compute_polar
from bbgym.physics.sailing import DinghyParams


@pytest.fixture(scope="module")
def polar():
    return compute_polar(DinghyParams(), wind_speed_mps=5.0)


def test_best_upwind_vmg_between_38_and_48_degrees(polar):
    angle, vmg = polar.best_upwind()
    assert 38.0 <= math.degrees(angle) <= 48.0
    assert vmg > 0.2 * 5.0


def test_no_progress_straight_upwind(polar):
    assert polar.true_wind_angle_rad[0] == 0.0
    assert polar.vmg_mps[0] <= 0.0


def test_fastest_between_90_and_135_degrees_at_055_to_085_of_wind(polar):
    angle, speed = polar.fastest()
    assert 90.0 <= math.degrees(angle) <= 135.0
    assert 0.55 <= speed / 5.0 <= 0.85


def test_upwind_leeway_between_2_and_8_degrees(polar):
    i = int(np.argmax(polar.vmg_mps))
    assert 2.0 <= math.degrees(polar.leeway_rad[i]) <= 8.0
    assert not polar.capsized.any()


def test_seed_sail_model_sails_off_the_wind_but_points_worse():
    # The seed's drag-on-the-perpendicular model (C_N = C_d sin^2) drives the boat well
    # off the wind but gives little force at the small angles of attack of beating.
    angles = np.radians([50.0, 90.0, 150.0])
    seed = compute_polar(DinghyParams(sail_model="seed"), 5.0, angles)
    lift = compute_polar(DinghyParams(sail_model="lift"), 5.0, angles)
    assert (seed.boat_speed_mps[1:] > 1.5).all()
    assert lift.vmg_mps[0] > 2.0 * seed.vmg_mps[0]
