"""Tests for the wall-topple renderer (headless, via SDL's dummy video driver)."""

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

from bbgym.envs.topple.frame import (  # noqa: E402
    attached_pose,
)
from bbgym.envs.topple.view import (  # noqa: E402
    WALL_COLOR,
    ToppleRenderer,
    ToppleScene,
    frame_state,
    loose_pose,
    panel_rects,
    side_view_map,
    wrap_angle,
)

WIDTH, HEIGHT = 640, 480
REPO_ROOT = Path(__file__).resolve().parents[2]
D = 6.0
K2 = 60


def lob(n: int = 16) -> np.ndarray:
    """A lob from the hand that reaches the wall's face (x = D - 0.02 - r) high up."""
    t = np.linspace(0.0, 0.77, n)
    return np.stack([(D - 0.22) / 0.77 * t, 0.15 * t, 1.9 + 4.2 * t - 4.9 * t**2], axis=1)


def make_scene(**overrides: object) -> ToppleScene:
    traj = lob()
    angles = np.concatenate([np.zeros(len(traj)), np.linspace(0.0, 0.5, K2 - len(traj))])
    hit = traj[-1]
    base = ToppleScene(
        wall_distance_m=D,
        wall_height_m=2.4,
        wall_width_m=1.2,
        wall_thickness_m=0.04,
        base_depth_m=0.5,
        wall_angle_rad=0.0,
        pivot_side=0,
        wall_state="standing",
        loose_panel=None,
        ball_trajectory_m=traj,
        ball_orientations=np.tile([1.0, 0.0, 0.0, 0.0], (len(traj), 1)),
        ball_radius_m=0.2,
        wall_angle_samples=angles,
        loose_samples=np.full((K2, 3), np.nan),
        hit_point_m=(D - 0.02, float(hit[1]), float(hit[2])),
        wind_mps=(3.0, -1.0),
        windsock_mps=(3.2, -0.8),
        throws_left=5,
        throws_total=8,
        hits=2,
    )
    return dataclasses.replace(base, **overrides)


def loose_scene(**overrides: object) -> ToppleScene:
    angles = np.concatenate([np.linspace(0.0, 0.35, 25), np.full(K2 - 25, np.nan)])
    loose = np.full((K2, 3), np.nan)
    for i in range(25, K2):
        t = (i - 25) * 0.05
        loose[i] = (D + 0.6 + 1.6 * t, 1.4 + 2.6 * t - 1.6 * t * t, 0.35 + 2.2 * t)
    base = make_scene(
        wall_state="loose",
        loose_panel=tuple(float(v) for v in loose[-1]),
        wall_angle_rad=0.35,
        wall_angle_samples=angles,
        loose_samples=loose,
        wind_mps=(9.0, 1.0),
    )
    return dataclasses.replace(base, **overrides)


def color_mask(img: np.ndarray, color: tuple[int, int, int], tol: int = 6) -> np.ndarray:
    diff = np.abs(img.astype(np.int16) - np.array(color, dtype=np.int16))
    return np.all(diff <= tol, axis=-1)


def changed_pixels(a: np.ndarray, b: np.ndarray) -> int:
    return int(np.count_nonzero(np.any(a != b, axis=-1)))


def crop(img: np.ndarray, rect: tuple[int, int, int, int]) -> np.ndarray:
    x, y, w, h = rect
    return img[y : y + h, x : x + w]


@pytest.fixture
def renderer():
    r = ToppleRenderer("rgb_array", width=WIDTH, height=HEIGHT)
    yield r
    r.close()


def test_rgb_array_shape_dtype_and_determinism(renderer: ToppleRenderer) -> None:
    scene = make_scene()
    a = renderer.render(scene)
    assert isinstance(a, np.ndarray)
    assert a.shape == (HEIGHT, WIDTH, 3)
    assert a.dtype == np.uint8
    assert len(np.unique(a.reshape(-1, 3), axis=0)) > 20  # not a blank frame
    np.testing.assert_array_equal(a, renderer.render(scene))
    # A fresh renderer draws the same picture.
    other = ToppleRenderer("rgb_array")
    try:
        np.testing.assert_array_equal(a, other.render(scene))
    finally:
        other.close()


def wall_columns_at(img: np.ndarray, scene: ToppleScene, z_m: float) -> np.ndarray:
    """Columns of wall-coloured pixels in the side-view row at height ``z_m``."""
    row = round(side_view_map(scene, WIDTH, HEIGHT).to_px(0.0, z_m)[1])
    return np.nonzero(color_mask(img[row - 2 : row + 3], WALL_COLOR).any(axis=0))[0]


def test_leaning_wall_top_moves_away_from_the_thrower(renderer: ToppleRenderer) -> None:
    upright = make_scene()
    leaning = make_scene(wall_angle_rad=0.5, pivot_side=1)
    a = renderer.render(upright)
    b = renderer.render(leaning)
    assert changed_pixels(a, b) > 300
    view = side_view_map(upright, WIDTH, HEIGHT)
    wall_x = view.to_px(D, 0.0)[0]
    # Near the top of the upright wall (z = 1.9 m), the panel is at x = D...
    cols_up = wall_columns_at(a, upright, 1.9)
    assert len(cols_up) > 0
    assert abs(cols_up.mean() - wall_x) < 4
    # ...leaning 0.5 rad about the far foot edge it is at d + b/2 + (z - ...) tan: well to the
    # right; the top is at x = d + 0.25 + 2.4 sin(0.5) - 0.25 cos(0.5) ~ d + 1.18 m.
    cols_lean = wall_columns_at(b, leaning, 1.9)
    assert len(cols_lean) > 0
    assert cols_lean.mean() > cols_up.mean() + 0.6 * view.pixels_per_meter
    # Leaning toward the thrower moves it left instead.
    toward = make_scene(wall_angle_rad=-0.5, pivot_side=-1)
    cols_toward = wall_columns_at(renderer.render(toward), toward, 1.9)
    assert cols_toward.mean() < cols_up.mean() - 0.6 * view.pixels_per_meter


def test_pose_pivots_about_the_foot_edges() -> None:
    scene = make_scene()
    far = attached_pose(scene, 0.5)
    # The far bottom edge of the foot stays put, the near one lifts off the ground.
    np.testing.assert_allclose(far.to_world(0.25, 0.0), (D + 0.25, 0.0), atol=1e-12)
    assert far.to_world(-0.25, 0.0)[1] > 0.1
    near = attached_pose(scene, -0.5)
    np.testing.assert_allclose(near.to_world(-0.25, 0.0), (D - 0.25, 0.0), atol=1e-12)
    # Lying flat away from the thrower: the top is beyond the foot, low down.
    flat = attached_pose(scene, math.pi / 2)
    top_x, top_z = flat.to_world(0.0, 2.4)
    assert top_x > D + 2.4 and top_z < 0.5
    # A loose panel's (x, z) is the panel centre; the pose round-trips.
    pose = loose_pose(scene, (9.0, 1.5, 1.0))
    np.testing.assert_allclose(pose.to_world(0.0, 1.2), (9.0, 1.5), atol=1e-12)
    np.testing.assert_allclose(pose.to_body(*pose.to_world(0.3, 0.7)), (0.3, 0.7), atol=1e-12)
    assert wrap_angle(math.radians(312.0)) == pytest.approx(math.radians(-48.0))


def test_loose_state_shows_a_banner(renderer: ToppleRenderer) -> None:
    standing = renderer.render(make_scene(wall_angle_rad=0.35, pivot_side=1))
    loose = renderer.render(loose_scene())
    assert changed_pixels(standing, loose) > 1000
    side, readout, _ = panel_rects(WIDTH, HEIGHT)
    # The readout's state line changes ("BROKE LOOSE!" in orange)...
    assert changed_pixels(crop(standing, readout), crop(loose, readout)) > 300
    orange = (255, 150, 20)
    assert np.count_nonzero(color_mask(crop(loose, readout), orange, tol=30)) > 100
    # ...and a big banner goes across the top of the side view.
    x, y, w, _ = side
    top_band = (x, y, w, 100)
    assert np.count_nonzero(color_mask(crop(loose, top_band), orange, tol=10)) > 3000
    assert np.count_nonzero(color_mask(crop(standing, top_band), orange, tol=10)) == 0


def test_animation_shows_the_moment_it_breaks(renderer: ToppleRenderer) -> None:
    scene = loose_scene()
    before = frame_state(dataclasses.replace(scene, frame_index=24))
    after = frame_state(dataclasses.replace(scene, frame_index=25))
    assert not before.loose and before.state == "standing"
    assert after.loose and after.state == "loose"
    side, _, _ = panel_rects(WIDTH, HEIGHT)
    x, y, w, _ = side
    a = renderer.render(dataclasses.replace(scene, frame_index=24))
    b = renderer.render(dataclasses.replace(scene, frame_index=25))
    orange = (255, 150, 20)
    assert np.count_nonzero(color_mask(crop(a, (x, y, w, 100)), orange, tol=10)) == 0
    assert np.count_nonzero(color_mask(crop(b, (x, y, w, 100)), orange, tol=10)) > 3000


def test_fallen_away_and_toward_differ(renderer: ToppleRenderer) -> None:
    away = make_scene(wall_angle_rad=math.pi / 2, pivot_side=1, wall_state="fallen_away")
    toward = make_scene(wall_angle_rad=-math.pi / 2, pivot_side=-1, wall_state="fallen_toward")
    a = renderer.render(away)
    b = renderer.render(toward)
    assert changed_pixels(a, b) > 1000
    side, readout, _ = panel_rects(WIDTH, HEIGHT)
    assert side[0] == 0  # the side view's columns are the image's
    green, red = (46, 204, 84), (236, 64, 52)
    # "FELL AWAY" in green vs "FELL TOWARD YOU" in red.
    assert np.count_nonzero(color_mask(crop(a, readout), green, tol=30)) > 100
    assert np.count_nonzero(color_mask(crop(b, readout), red, tol=30)) > 100
    # The panel lies beyond the foot in one and towards the thrower in the other.
    view = side_view_map(away, WIDTH, HEIGHT)
    cols_a = np.nonzero(color_mask(crop(a, view.rect), WALL_COLOR).any(axis=0))[0]
    cols_b = np.nonzero(color_mask(crop(b, view.rect), WALL_COLOR).any(axis=0))[0]
    assert cols_a.mean() > view.to_px(D + 1.0, 0.0)[0]
    assert cols_b.mean() < view.to_px(D - 1.0, 0.0)[0]


def test_empty_trajectory_renders(renderer: ToppleRenderer) -> None:
    scene = make_scene(
        ball_trajectory_m=np.zeros((0, 3)),
        ball_orientations=np.zeros((0, 4)),
        wall_angle_samples=np.zeros(0),
        loose_samples=np.zeros((0, 3)),
        hit_point_m=None,
    )
    img = renderer.render(scene)
    assert img.shape == (HEIGHT, WIDTH, 3)
    assert changed_pixels(img, renderer.render(make_scene())) > 200
    # An animation frame of a step without a throw also renders.
    assert renderer.render(dataclasses.replace(scene, frame_index=3)).shape == (HEIGHT, WIDTH, 3)


def test_frame_index_animates(renderer: ToppleRenderer) -> None:
    scene = make_scene(wall_angle_rad=0.5, pivot_side=1)
    first = renderer.render(dataclasses.replace(scene, frame_index=0))
    last = renderer.render(dataclasses.replace(scene, frame_index=K2 - 1))
    assert changed_pixels(first, last) > 300
    # The ball moves along, then stays at its last point while the wall keeps leaning.
    mid = renderer.render(dataclasses.replace(scene, frame_index=8))
    assert changed_pixels(first, mid) > 100
    cols_first = wall_columns_at(first, scene, 1.9)
    cols_last = wall_columns_at(last, scene, 1.9)
    assert cols_last.mean() > cols_first.mean() + 10
    # The last sample equals the final state here; past the end it stays there.
    np.testing.assert_array_equal(last, renderer.render(scene))
    np.testing.assert_array_equal(
        last, renderer.render(dataclasses.replace(scene, frame_index=K2 + 20))
    )


def test_hit_mark_appears_when_the_ball_arrives(renderer: ToppleRenderer) -> None:
    scene = make_scene()
    star = (255, 226, 0)
    early = renderer.render(dataclasses.replace(scene, frame_index=3))
    final = renderer.render(scene)
    side, _, _ = panel_rects(WIDTH, HEIGHT)
    assert np.count_nonzero(color_mask(crop(early, side), star, tol=4)) == 0
    assert np.count_nonzero(color_mask(crop(final, side), star, tol=4)) > 20
    missed = renderer.render(make_scene(hit_point_m=None))
    assert np.count_nonzero(color_mask(crop(missed, side), star, tol=4)) == 0


def test_bad_render_mode_raises() -> None:
    with pytest.raises(ValueError, match="render_mode"):
        ToppleRenderer("ansi")


def test_human_mode_with_dummy_display() -> None:
    r = ToppleRenderer("human", render_fps=1000)
    try:
        assert r.render(make_scene()) is None
    finally:
        r.close()


def test_module_import_does_not_import_pygame() -> None:
    code = (
        "import sys, bbgym.envs.topple.view as m; "
        "assert m.ToppleScene; sys.exit(1 if 'pygame' in sys.modules else 0)"
    )
    env = {**os.environ, "PYTHONPATH": str(REPO_ROOT)}
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO_ROOT, env=env)
    assert result.returncode == 0


# -- the end-of-episode banner, the scale bar --------------------------------------------------


def banner_band(img: np.ndarray) -> np.ndarray:
    """Where the banners go: the top of the side view."""
    from bbgym.envs.topple.view import BANNER_TOP_PX

    side, _, _ = panel_rects(WIDTH, HEIGHT)
    x, y, w, _ = side
    return crop(img, (x, y + BANNER_TOP_PX, w, 90))


def failed_scene(**overrides: object) -> ToppleScene:
    """The last throw's end: the wall still stands, no throws left."""
    return make_scene(throws_left=0, **overrides)


def fallen_away_scene(**overrides: object) -> ToppleScene:
    fields: dict[str, object] = {
        "wall_angle_rad": math.pi / 2,
        "pivot_side": 1,
        "wall_state": "fallen_away",
        "throws_left": 3,
    }
    return make_scene(**{**fields, **overrides})


def test_banner_says_the_wall_still_stands_when_out_of_throws() -> None:
    from bbgym.envs.topple.view import banner

    shown = banner(failed_scene())
    assert shown is not None and not shown.success
    assert shown.text == "FAILED: out of throws"
    assert shown.detail == "wall still standing after 8 throws"
    # Also on the step's last sample, not while the ball of the last throw still flies.
    assert banner(failed_scene(frame_index=K2 - 1)) == shown
    assert banner(failed_scene(frame_index=10)) is None
    # Throws left: the episode goes on, no banner.
    assert banner(make_scene(throws_left=1)) is None


def test_banner_for_each_way_the_episode_ends() -> None:
    from bbgym.envs.topple.view import banner

    away = banner(fallen_away_scene())
    assert away is not None and away.success and away.text == "WALL DOWN!"
    assert away.detail == "it fell away after 5 throws"
    toward = banner(
        make_scene(
            wall_angle_rad=-math.pi / 2, pivot_side=-1, wall_state="fallen_toward", throws_left=7
        )
    )
    assert toward is not None and not toward.success
    assert toward.text.startswith("FAILED") and toward.detail == "after 1 throw"
    loose = banner(loose_scene())
    assert loose is not None and loose.success and loose.text == "BROKE LOOSE!"
    # Falling away on the very last throw is a success, not "out of throws".
    assert banner(fallen_away_scene(throws_left=0)).success  # type: ignore[union-attr]


def test_failed_final_frame_has_a_red_banner_where_a_success_has_a_green_one(
    renderer: ToppleRenderer,
) -> None:
    from bbgym.envs.topple.frame import (
        FAILURE_BANNER_COLOR,
        SUCCESS_BANNER_COLOR,
    )

    failed = renderer.render(failed_scene())
    going_on = renderer.render(make_scene(throws_left=1))
    success = renderer.render(fallen_away_scene())
    red = [
        np.count_nonzero(color_mask(banner_band(f), FAILURE_BANNER_COLOR))
        for f in (failed, going_on, success)
    ]
    green = [
        np.count_nonzero(color_mask(banner_band(f), SUCCESS_BANNER_COLOR))
        for f in (failed, going_on, success)
    ]
    assert red[0] > 3000 and red[1] == 0 and red[2] == 0
    assert green[2] > 3000 and green[0] == 0 and green[1] == 0
    # The failed frame differs from the one that goes on where the banner is.
    assert changed_pixels(banner_band(failed), banner_band(going_on)) > 3000
    assert changed_pixels(banner_band(failed), banner_band(success)) > 3000
    # A flight frame of the last throw has no banner yet.
    flying = renderer.render(failed_scene(frame_index=10))
    assert np.count_nonzero(color_mask(banner_band(flying), FAILURE_BANNER_COLOR)) == 0


@pytest.mark.parametrize("distance", [D, 2.5, 30.0])
def test_inset_scale_bar_is_metres_times_pixels_per_metre(
    renderer: ToppleRenderer, distance: float
) -> None:
    from bbgym.envs.topple.view import INSET_SCALE_BAR_MAX_PX, top_view_map
    from bbgym.render.annotations import SCALE_BAR_COLOR, scale_bar, scale_bar_origin

    scene = make_scene(wall_distance_m=distance, hit_point_m=None)
    img = renderer.render(scene)
    view = top_view_map(scene, WIDTH, HEIGHT)
    bar = scale_bar(view.pixels_per_meter, min(INSET_SCALE_BAR_MAX_PX, 0.4 * view.rect[2]))
    assert bar is not None
    x0, y0 = scale_bar_origin(view.rect, HEIGHT)
    row = img[y0, x0 - 3 : x0 + round(bar.length_px) + 3]
    run = int(np.count_nonzero(np.all(row == np.array(SCALE_BAR_COLOR), axis=-1)))
    assert run == round(bar.metres * view.pixels_per_meter)
