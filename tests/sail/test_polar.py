"""The default preset's polar matches a real dinghy's (DESIGN §6)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.polar import compute_polar


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


# -- the plot ----------------------------------------------------------------------------------


def test_polar_plot_has_speed_units_and_readable_tick_labels(polar):
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from bbgym.cli.polar import RADIAL_LABEL_CLEARANCE_PX, label_layout, polar_figure

    fig = polar_figure(polar, "lift")
    try:
        ax = fig.axes[0]
        radial = [t.get_text() for t in ax.get_yticklabels() if t.get_text()]
        assert len(radial) >= 3 and all(t.endswith(" m/s") for t in radial)
        values = [float(t.removesuffix(" m/s")) for t in radial]
        assert values == sorted(values) and values[-1] <= ax.get_rmax()
        # Angular labels: true wind angles in degrees, 0 at the top, mirrored on both tacks.
        angular = [t.get_text() for t in ax.get_xticklabels()]
        assert angular[:7] == [f"{a}\N{DEGREE SIGN}" for a in range(0, 181, 30)]
        assert angular[7:] == [f"{a}\N{DEGREE SIGN}" for a in range(150, 0, -30)]
        assert "true wind angle" in ax.get_xlabel()
        layout = label_layout(fig, ax)
        # No label overlaps another, and the speed labels clear every plotted curve.
        assert not layout["overlap"]
        assert layout["clearance_px"] >= RADIAL_LABEL_CLEARANCE_PX
        assert len(layout["points"]) > 100
    finally:
        plt.close(fig)


def test_polar_plot_writes_a_png(polar, tmp_path):
    pytest.importorskip("matplotlib")
    from PIL import Image

    from bbgym.cli.polar import plot_polar

    out = tmp_path / "polar.png"
    plot_polar(out, polar, "lift")
    with Image.open(out) as png:
        assert min(png.size) > 500
