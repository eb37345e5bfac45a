"""Tests for the top-view sailing renderer (headless, via SDL's dummy video driver)."""

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

import dataclasses
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pygame")

from gymnasium.error import DependencyNotInstalled  # noqa: E402

from bbgym.envs.sail import view as sail_view  # noqa: E402
from bbgym.envs.sail.view import (  # noqa: E402
    CREST_BAND_COLOR,
    CREW_COLOR,
    CURRENT_COLOR,
    JIB_FILL_COLOR,
    MARK_COLOR,
    SAIL_FILL_COLOR,
    WATER_COLOR,
    SailRenderer,
    SailScene,
    body_to_world,
    world_to_screen,
)

WIDTH, HEIGHT, PPM = 640, 480, 12.0
REPO_ROOT = Path(__file__).resolve().parents[2]


def make_scene(**overrides: object) -> SailScene:
    """Boat at the origin heading east, wind from the north, boom out to starboard."""
    base = SailScene(
        time_s=12.5,
        position_m=(0.0, 0.0),
        heading_rad=0.0,
        heel_rad=-0.2,
        boom_angle_rad=-0.6,
        rudder_angle_rad=0.1,
        sail_force_n=300.0,
        sail_luffing=False,
        mark_m=(10.0, 5.0),
        mark_radius_m=3.0,
        true_wind_mps=(0.0, -5.0),
        apparent_wind_speed_mps=5.8,
        apparent_wind_angle_rad=math.radians(70.0),
        boat_speed_mps=2.0,
        wake_m=tuple((-1.0 * k, 0.0) for k in range(20, 0, -1)),
        capsized=False,
        jibes=1,
        tacks=2,
    )
    return dataclasses.replace(base, **overrides)


def color_mask(img: np.ndarray, color: tuple[int, int, int], tol: int = 12) -> np.ndarray:
    diff = np.abs(img.astype(np.int16) - np.array(color, dtype=np.int16))
    return np.all(diff <= tol, axis=-1)


@pytest.fixture
def renderer():
    r = SailRenderer("rgb_array", width=WIDTH, height=HEIGHT, pixels_per_meter=PPM)
    yield r
    r.close()


def test_rgb_array_shape_and_dtype(renderer: SailRenderer) -> None:
    img = renderer.render(make_scene())
    assert isinstance(img, np.ndarray)
    assert img.shape == (HEIGHT, WIDTH, 3)
    assert img.dtype == np.uint8
    # Not a blank frame: many distinct colours are drawn.
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 10


def test_same_scene_is_deterministic_and_heading_changes_image(renderer: SailRenderer) -> None:
    scene = make_scene()
    a = renderer.render(scene)
    b = renderer.render(scene)
    np.testing.assert_array_equal(a, b)
    turned = renderer.render(make_scene(heading_rad=math.pi / 2))
    assert np.count_nonzero(np.any(a != turned, axis=-1)) > 100


def test_orange_crew_on_windward_side(renderer: SailRenderer) -> None:
    # Heading east, boom out to starboard (south): crew hikes on the port side = north = up.
    img = renderer.render(make_scene(boom_angle_rad=-0.6))
    rows, _ = np.nonzero(color_mask(img, CREW_COLOR, tol=30))
    assert rows.size > 20
    assert rows.mean() < HEIGHT / 2
    # Boom out to port (north): crew on the starboard side = down.
    img = renderer.render(
        make_scene(boom_angle_rad=0.6, apparent_wind_angle_rad=math.radians(-70.0))
    )
    rows, _ = np.nonzero(color_mask(img, CREW_COLOR, tol=30))
    assert rows.size > 20
    assert rows.mean() > HEIGHT / 2


def test_sail_is_on_the_boom_side_and_bellied_to_leeward(renderer: SailRenderer) -> None:
    boom = -0.8  # heading east, boom out to starboard
    img = renderer.render(make_scene(boom_angle_rad=boom, sail_force_n=600.0))
    # Only look around the boat (screen centre): the HUD text antialiasing has similar greys.
    box = 60
    top, left = HEIGHT // 2 - box, WIDTH // 2 - box
    mask = color_mask(img, SAIL_FILL_COLOR, tol=6)[top : top + 2 * box, left : left + 2 * box]
    rows, cols = np.nonzero(mask)
    assert rows.size > 10
    # Back to world metres (boat at the origin, heading east = body frame).
    x = (cols + left - WIDTH / 2) / PPM
    y = (HEIGHT / 2 - (rows + top)) / PPM
    assert y.mean() < 0  # the sail is on the starboard (south) side
    # The belly is on the far side of the boom from the hull's stern, i.e. to leeward.
    mast = np.array([4.2 / 6, 0.0])
    boom_dir = np.array([-math.cos(boom), math.sin(boom)])
    normal = np.array([-boom_dir[1], boom_dir[0]])
    stern_side = np.sign(np.dot(np.array([-2.1, 0.0]) - mast, normal))
    sides = np.sign((x - mast[0]) * normal[0] + (y - mast[1]) * normal[1])
    assert np.mean(sides == -stern_side) > 0.8


def test_mark_drawn_at_expected_screen_position(renderer: SailRenderer) -> None:
    mark = (10.0, 5.0)
    img = renderer.render(make_scene(mark_m=mark))
    sx, sy = world_to_screen(mark, (0.0, 0.0), PPM, (WIDTH, HEIGHT))
    assert (round(sx), round(sy)) == (440, 180)
    mask = color_mask(img, MARK_COLOR, tol=30)
    window = mask[round(sy) - 8 : round(sy) + 9, round(sx) - 8 : round(sx) + 9]
    assert np.count_nonzero(window) > 30
    # No edge arrow when the mark is on screen: nothing mark-coloured near the border.
    assert np.count_nonzero(mask[:, WIDTH - 40 :]) == 0


def test_far_mark_gives_edge_arrow(renderer: SailRenderer) -> None:
    img = renderer.render(make_scene(mark_m=(500.0, 0.0)))
    mask = color_mask(img, MARK_COLOR, tol=30)
    assert np.count_nonzero(mask[:, WIDTH - 50 :]) > 30
    rows, _ = np.nonzero(mask)
    assert abs(rows.mean() - HEIGHT / 2) < 15  # the mark is due east: arrow at mid-height
    assert np.count_nonzero(mask[:, : WIDTH - 50]) == 0

    img = renderer.render(make_scene(mark_m=(0.0, -500.0)))
    mask = color_mask(img, MARK_COLOR, tol=30)
    assert np.count_nonzero(mask[HEIGHT - 50 :, :]) > 30


def test_capsized_renders_and_differs(renderer: SailRenderer) -> None:
    upright = renderer.render(make_scene())
    capsized = renderer.render(make_scene(capsized=True, heel_rad=1.5))
    assert capsized.shape == (HEIGHT, WIDTH, 3)
    assert np.count_nonzero(np.any(upright != capsized, axis=-1)) > 200


def test_luffing_sail_and_empty_wake_render(renderer: SailRenderer) -> None:
    full = renderer.render(make_scene())
    luffing = renderer.render(make_scene(sail_luffing=True, sail_force_n=0.0, wake_m=()))
    assert luffing.shape == (HEIGHT, WIDTH, 3)
    assert not np.array_equal(full, luffing)


def test_bad_render_mode_raises() -> None:
    with pytest.raises(ValueError, match="render_mode"):
        SailRenderer("ansi")


def test_human_mode_with_dummy_display() -> None:
    r = SailRenderer("human", render_fps=1000)
    try:
        assert r.render(make_scene()) is None
    finally:
        r.close()


def test_missing_pygame_raises_dependency_not_installed(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pygame", None)  # makes `import pygame` fail
    with pytest.raises(DependencyNotInstalled, match="pip install"):
        SailRenderer("rgb_array")


def test_module_import_does_not_import_pygame() -> None:
    code = (
        "import sys, bbgym.envs.sail.view as m; "
        "assert m.SailScene; sys.exit(1 if 'pygame' in sys.modules else 0)"
    )
    env = {**os.environ, "PYTHONPATH": str(REPO_ROOT)}
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO_ROOT, env=env)
    assert result.returncode == 0


def test_frames_and_geometry_helpers() -> None:
    # World y is up on screen.
    assert world_to_screen((0.0, 1.0), (0.0, 0.0), 10.0, (100, 100)) == (50.0, 40.0)
    # Body +y is port: for a boat heading north, port is west.
    wx, wy = body_to_world((0.0, 1.0), (5.0, 5.0), math.pi / 2)
    assert wx == pytest.approx(4.0)
    assert wy == pytest.approx(5.0)
    assert sail_view.leeward_sign(0.5, 1.0) == 1.0
    assert sail_view.leeward_sign(0.0, 1.0) == -1.0


# -- scale bar ---------------------------------------------------------------------------------


@pytest.mark.parametrize("ppm", [0.01, 0.37, 1.0, 3.0, 7.5, 12.0, 16.0, 45.0, 1000.0, 2.5e5])
def test_scale_bar_is_a_round_number_of_metres_as_long_as_it_should_be(ppm: float) -> None:
    from bbgym.render.annotations import SCALE_BAR_MAX_PX, scale_bar

    bar = scale_bar(ppm)
    assert bar is not None
    assert bar.length_px == pytest.approx(bar.metres * ppm, rel=1e-12)
    assert SCALE_BAR_MAX_PX / 2.5 - 1e-9 <= bar.length_px <= SCALE_BAR_MAX_PX + 1e-9
    mantissa = bar.metres / 10.0 ** math.floor(math.log10(bar.metres) + 1e-12)
    assert min(abs(mantissa - m) for m in (1.0, 2.0, 5.0)) < 1e-9


@pytest.mark.parametrize(
    ("ppm", "metres", "label"),
    [
        (12.0, 10.0, "10 m"),
        (16.0, 5.0, "5 m"),
        (3.0, 20.0, "20 m"),
        (0.1, 1000.0, "1 km"),
        (0.01, 10000.0, "10 km"),
        (400.0, 0.2, "20 cm"),
        (1e5, 0.001, "1 mm"),
    ],
)
def test_scale_bar_choice_and_label(ppm: float, metres: float, label: str) -> None:
    from bbgym.render.annotations import scale_bar

    bar = scale_bar(ppm)
    assert bar is not None and bar.metres == pytest.approx(metres) and bar.label == label


@pytest.mark.parametrize("ppm", [0.0, -3.0, math.nan, math.inf])
def test_no_scale_bar_without_a_scale(ppm: float) -> None:
    from bbgym.render.annotations import scale_bar

    assert scale_bar(ppm) is None


def bar_run_px(img: np.ndarray, origin: tuple[int, int], length_px: float) -> int:
    """Pixels of the scale bar's colour on its row, from just before to just after it."""
    from bbgym.render.annotations import SCALE_BAR_COLOR

    x0, y0 = origin
    row = img[y0, max(x0 - 3, 0) : x0 + round(length_px) + 3]
    return int(np.count_nonzero(np.all(row == np.array(SCALE_BAR_COLOR), axis=-1)))


@pytest.mark.parametrize("ppm", [12.0, 3.0, 40.0])
def test_sail_scale_bar_is_metres_times_pixels_per_metre(ppm: float) -> None:
    from bbgym.render.annotations import CAPTION_BAND_PX, scale_bar, scale_bar_origin

    r = SailRenderer("rgb_array", width=WIDTH, height=HEIGHT, pixels_per_meter=ppm)
    try:
        img = r.render(make_scene())
    finally:
        r.close()
    bar = scale_bar(ppm)
    assert bar is not None
    origin = scale_bar_origin((0, 0, WIDTH, HEIGHT), HEIGHT)
    assert origin[1] < HEIGHT - CAPTION_BAND_PX  # above the strip a recording's caption covers
    assert bar_run_px(img, origin, bar.length_px) == round(bar.metres * ppm)


def test_the_wind_label_stays_legible_over_the_marks_ring(renderer: SailRenderer) -> None:
    # A mark whose dashed ring crosses the wind dial's label: the label sits on its own
    # panel, so no dash runs through its text.
    cx = WIDTH - sail_view.WIND_ARROW_CENTER_FROM_CORNER_PX
    top = sail_view.WIND_ARROW_CENTER_FROM_CORNER_PX + int(sail_view.WIND_ARROW_MAX_PX) // 2 + 10
    label_x, label_y = cx, top + 7  # the middle of the label's line of text
    mark = ((label_x - WIDTH / 2) / PPM, -(label_y - HEIGHT / 2) / PPM)
    ring = renderer.render(make_scene(mark_m=mark, mark_radius_m=36.0 / PPM))
    clear = renderer.render(make_scene(mark_m=(0.0, -10.0), mark_radius_m=36.0 / PPM))
    box = np.s_[top : top + 11, cx - 36 : cx + 36]  # inside the label's line
    assert np.array_equal(ring[box], clear[box])  # not a dash in the label
    # The ring is there, just not over the label: it differs from the clear water next to it.
    assert not np.array_equal(ring[top + 30 : top + 60], clear[top + 30 : top + 60])


def test_the_jib_is_drawn_on_its_side_of_the_bow(renderer: SailRenderer) -> None:
    """Heading east, wind from the south-east quarter (from starboard): the jib trimmed to
    port lies north of the centreline, backed to starboard south of it; a cat rig has none."""
    box = 60
    top, left = HEIGHT // 2 - box, WIDTH // 2 - box
    centre_rows = []
    for angle in (0.25, -0.25):
        scene = make_scene(
            jib_angle_rad=angle, apparent_wind_angle_rad=math.radians(-40.0), boom_angle_rad=0.3
        )
        img = renderer.render(scene)
        mask = color_mask(img, JIB_FILL_COLOR, tol=8)[top : top + 2 * box, left : left + 2 * box]
        rows, cols = np.nonzero(mask)
        assert rows.size > 5
        assert (cols + left - WIDTH / 2).mean() / PPM > 0.8  # ahead of the mast, by the bow
        centre_rows.append((rows + top).mean())
    assert centre_rows[0] < HEIGHT / 2 < centre_rows[1]  # port is up on the screen
    assert not color_mask(renderer.render(make_scene()), JIB_FILL_COLOR, tol=8).any()


PANEL_ROWS, PANEL_COLS = 160, 240
"""The readout panel's corner of the frame (top left)."""


def test_current_arrows_are_fixed_to_the_world(renderer: SailRenderer) -> None:
    arrows = tuple(((x, y), (0.5, 0.0)) for x in (-16.0, 0.0, 16.0) for y in (-12.0, 12.0))
    img = renderer.render(make_scene(current_arrows=arrows, current_mps=0.5))
    teal = color_mask(img, CURRENT_COLOR, tol=10)
    # the readout's last line, "current 0.50 m/s (arrows)", is the arrows' legend, in teal
    panel = (slice(0, PANEL_ROWS), slice(0, PANEL_COLS))
    assert teal[panel].sum() > 30
    teal[panel] = False
    assert teal.sum() > 6 * 20  # six arrows, each 3 m long (0.5 m/s for 6 s)
    # the boat moves 4 m east: the arrows move 4 m west on the screen
    moved = color_mask(
        renderer.render(make_scene(current_arrows=arrows, current_mps=0.5, position_m=(4.0, 0.0))),
        CURRENT_COLOR,
        tol=10,
    )
    moved[panel] = False
    shift = np.nonzero(teal)[1].mean() - np.nonzero(moved)[1].mean()
    assert shift == pytest.approx(4.0 * PPM, abs=2.0)
    assert not color_mask(renderer.render(make_scene()), CURRENT_COLOR, tol=10).any()


@pytest.mark.parametrize(
    ("height", "color"), [(1.0, CREST_BAND_COLOR), (0.2, WATER_COLOR), (-1.0, WATER_COLOR)]
)
def test_wave_crests_are_a_light_band_on_plain_water(renderer: SailRenderer, height, color) -> None:
    """Flat bands (a GIF of them stays small): crests lighter than the water, the rest the
    plain water."""
    assert sum(CREST_BAND_COLOR) > sum(WATER_COLOR)
    rows = tuple(tuple(height for _ in range(60)) for _ in range(50))
    img = renderer.render(make_scene(wave_cells=((-30.0, -25.0), rows), mark_m=(500.0, 0.0)))
    # a patch of open water, clear of the boat and the panels
    patch = img[HEIGHT // 2 + 60 : HEIGHT // 2 + 90, WIDTH // 2 - 200 : WIDTH // 2 - 150]
    assert color_mask(patch, color, tol=3).mean() > 0.9


def test_the_v2_scene_carries_the_jib_current_and_waves() -> None:
    from bbgym.envs.sail import BeachballSailEnv
    from bbgym.envs.sail.scene import describe_scene
    from bbgym.physics.calibration import calibrated_sloop

    water = {"wave_amplitude_m": 0.2, "wavelength_m": 12.0}
    env = BeachballSailEnv(dinghy=calibrated_sloop(), water=water, current_speed_range=(0.3, 0.3))
    env.reset(seed=0, options={"wave_direction": 0.0, "wave_phase": 0.0})
    scene = describe_scene(env.task, env.state, (), np.zeros(3))
    assert scene.jib_angle_rad is not None and scene.current_mps == pytest.approx(0.3)
    assert all(math.hypot(*v) == pytest.approx(0.3) for _, v in scene.current_arrows)
    (x0, _), rows = scene.wave_cells
    # One wave travelling east with a crest at x = 0 at t = 0, the same in every row: a
    # trochoid, the particle from a at x = a - A sin(k a) and as high as A cos(k a) (sharper
    # crests and flatter troughs than cos(k x)).
    k, amplitude = 2 * math.pi / 12.0, 0.2
    xs = x0 + np.arange(len(rows[0]))
    a = xs.copy()
    for _ in range(60):
        a = xs + amplitude * np.sin(k * a)
    np.testing.assert_allclose(rows[0], np.cos(k * a), atol=1e-6)
    assert np.abs(np.asarray(rows[0]) - np.cos(k * xs)).max() > 0.05
    np.testing.assert_allclose(rows[-1], rows[0], atol=1e-12)
    still = BeachballSailEnv()
    still.reset(seed=0)
    scene = describe_scene(still.task, still.state, (), np.zeros(2))
    assert scene.jib_angle_rad is None and scene.wave_cells is None and scene.current_arrows == ()
