"""Tests for the two-panel beach-ball throw renderer (headless, via SDL's dummy video driver)."""

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

from bbgym.envs.throw.view import (  # noqa: E402
    SCREEN_COLOR,
    TARGET_COLOR,
    ThrowRenderer,
    ThrowScene,
    ThrowScreen,
    panel_rects,
    side_view_map,
    top_view_map,
    view_axes,
)
from bbgym.render.beach import (  # noqa: E402
    GORE_COLORS,
    beach_ball_image,
    quat_from_axis_angle,
    quat_rotate,
    quat_to_matrix,
)

WIDTH, HEIGHT = 640, 480
REPO_ROOT = Path(__file__).resolve().parents[2]
IDENTITY = (1.0, 0.0, 0.0, 0.0)


def arc(n: int = 60) -> np.ndarray:
    """A lob from the hand towards (8, 1) that bends left on the way."""
    t = np.linspace(0.0, 1.3, n)
    return np.stack([6.0 * t, 0.8 * t**2, 1.9 + 6.0 * t - 4.9 * t**2], axis=1)


def make_scene(q: tuple[float, ...] | np.ndarray = IDENTITY, **overrides: object) -> ThrowScene:
    traj = arc()
    base = ThrowScene(
        trajectory_m=traj,
        orientations=np.tile(np.asarray(q, dtype=float), (len(traj), 1)),
        ball_radius_m=0.2,
        target_m=(8.0, 1.0),
        target_radius_m=0.75,
        wind_mps=(1.5, -0.5),
        windsock_mps=(1.7, -0.4),
        screen=None,
        landing_m=(7.8, 1.35),
        previous_landings_m=((6.5, -0.5),),
        throws_left=1,
        throws_total=3,
        miss_distance_m=0.4,
        spin_parameter=0.12,
        flight_time_s=1.3,
        apex_height_m=3.7,
    )
    return dataclasses.replace(base, **overrides)


def color_mask(img: np.ndarray, color: tuple[int, int, int], tol: int = 12) -> np.ndarray:
    diff = np.abs(img.astype(np.int16) - np.array(color, dtype=np.int16))
    return np.all(diff <= tol, axis=-1)


def changed_pixels(a: np.ndarray, b: np.ndarray) -> int:
    return int(np.count_nonzero(np.any(a != b, axis=-1)))


@pytest.fixture
def renderer():
    r = ThrowRenderer("rgb_array", width=WIDTH, height=HEIGHT)
    yield r
    r.close()


def test_rgb_array_shape_dtype_and_determinism(renderer: ThrowRenderer) -> None:
    scene = make_scene()
    a = renderer.render(scene)
    assert isinstance(a, np.ndarray)
    assert a.shape == (HEIGHT, WIDTH, 3)
    assert a.dtype == np.uint8
    assert len(np.unique(a.reshape(-1, 3), axis=0)) > 20  # not a blank frame
    b = renderer.render(scene)
    np.testing.assert_array_equal(a, b)


def test_ball_stripes_rotate_with_orientation(renderer: ThrowRenderer) -> None:
    plain = renderer.render(make_scene(IDENTITY))
    quarter = renderer.render(make_scene(quat_from_axis_angle((1, 0, 0), math.pi / 2)))
    full = renderer.render(make_scene(quat_from_axis_angle((1, 0, 0), 2 * math.pi)))
    # Only the balls change (the trace and everything else are the same)...
    assert changed_pixels(plain, quarter) > 100
    # ...and a full turn is the same orientation, so the same picture.
    np.testing.assert_array_equal(plain, full)
    # Turning about the poles (body z) also turns the gores.
    spun = renderer.render(make_scene(quat_from_axis_angle((0, 0, 1), math.pi / 6)))
    assert changed_pixels(plain, spun) > 50


def gore_counts(pixels: np.ndarray) -> np.ndarray:
    """Pixels per gore colour, matched by hue (brightness divided out: the ball is shaded)."""
    p = pixels.reshape(-1, 3).astype(float)
    palette = np.array(GORE_COLORS, dtype=float)
    p_norm = p / np.maximum(p.max(axis=1, keepdims=True), 1.0)
    pal_norm = palette / palette.max(axis=1, keepdims=True)
    dist = np.linalg.norm(p_norm[:, None, :] - pal_norm[None, :, :], axis=-1)
    close = dist.min(axis=1) < 0.12
    return np.bincount(dist.argmin(axis=1)[close], minlength=len(GORE_COLORS))


def test_side_view_ball_shows_all_six_gores_when_a_pole_faces_the_viewer(
    renderer: ThrowRenderer,
) -> None:
    # The side-view camera looks along -(bearing x up); turning the body z axis about the
    # bearing by +90 deg points it at the camera, so all six gores show around the polar cap.
    bearing = np.array([8.0, 1.0, 0.0]) / math.hypot(8.0, 1.0)
    scene = make_scene(quat_from_axis_angle(bearing, math.pi / 2))
    img = renderer.render(scene)
    end = scene.trajectory_m[-1]
    cx, cy = side_view_map(scene, WIDTH, HEIGHT).to_px(float(end[:2] @ bearing[:2]), end[2])
    patch = img[round(cy) - 9 : round(cy) + 10, round(cx) - 9 : round(cx) + 10]
    assert np.all(gore_counts(patch) >= 8)
    # Without a throw there is no ball there: only sky.
    empty = renderer.render(
        make_scene(trajectory_m=np.zeros((0, 3)), orientations=np.zeros((0, 4)))
    )
    patch = empty[round(cy) - 9 : round(cy) + 10, round(cx) - 9 : round(cx) + 10]
    assert gore_counts(patch).sum() == 0


def test_beach_ball_image_gores_follow_the_rotation() -> None:
    right, up = view_axes("top", (1.0, 0.0))
    _, _, rgb0, cov0 = beach_ball_image(np.eye(3), right, up, (20.0, 20.0), 12.0)
    assert cov0[cov0.shape[0] // 2, cov0.shape[1] // 2] == 1.0  # centre is fully covered
    assert cov0[0, 0] == 0.0  # corner is outside the disc
    # Half a gore-turn about the poles moves every gore edge: most of the disc changes colour.
    rot = quat_to_matrix(quat_from_axis_angle((0, 0, 1), math.pi / 6))
    _, _, rgb1, _ = beach_ball_image(rot, right, up, (20.0, 20.0), 12.0)
    inside = cov0 == 1.0
    assert np.mean(np.any(rgb0 != rgb1, axis=-1)[inside]) > 0.5
    # A full gore-turn (60 deg) maps each gore onto the next one: same outline, other colours.
    rot = quat_to_matrix(quat_from_axis_angle((0, 0, 1), math.pi / 3))
    _, _, rgb2, cov2 = beach_ball_image(rot, right, up, (20.0, 20.0), 12.0)
    np.testing.assert_array_equal(cov0, cov2)
    assert not np.array_equal(rgb0, rgb2)


def test_target_ring_drawn_at_expected_top_view_position(renderer: ThrowRenderer) -> None:
    scene = make_scene(target_m=(5.0, -4.0), landing_m=None, previous_landings_m=())
    img = renderer.render(scene)
    top = top_view_map(scene, WIDTH, HEIGHT)
    tx, ty = top.to_px(*scene.target_m)
    _, _, top_rect = panel_rects(WIDTH, HEIGHT)
    assert top_rect[1] <= ty < top_rect[1] + top_rect[3]
    r_px = scene.target_radius_m * top.pixels_per_meter
    mask = color_mask(img, TARGET_COLOR, tol=20)
    window = mask[
        round(ty - r_px) : round(ty + r_px) + 1,
        round(tx - r_px) : round(tx + r_px) + 1,
    ]
    # Outer and middle magenta rings cover well over a third of the box around the target.
    assert np.count_nonzero(window) > 0.3 * window.size
    # The ring's centre of mass in the top panel is at the target.
    rows, cols = np.nonzero(mask[top_rect[1] :, :])
    assert abs(cols.mean() - tx) < 2.0
    assert abs(rows.mean() + top_rect[1] - ty) < 2.0


def test_screen_changes_both_views(renderer: ThrowRenderer) -> None:
    no_screen = renderer.render(make_scene())
    screen = ThrowScreen(center_m=(4.0, 0.5), along_m=(0.0, 1.0), half_width_m=1.0, height_m=2.0)
    with_screen = renderer.render(make_scene(screen=screen))
    assert changed_pixels(no_screen, with_screen) > 200
    side_rect, _, top_rect = panel_rects(WIDTH, HEIGHT)
    mask = color_mask(with_screen, SCREEN_COLOR, tol=6)
    assert np.count_nonzero(mask[: side_rect[3], : side_rect[2]]) > 50  # side view: a rectangle
    assert np.count_nonzero(mask[top_rect[1] :, :]) > 50  # top view: a thick segment
    assert np.count_nonzero(color_mask(no_screen, SCREEN_COLOR, tol=6)) == 0


def test_empty_trajectory_renders(renderer: ThrowRenderer) -> None:
    scene = make_scene(
        trajectory_m=np.zeros((0, 3)),
        orientations=np.zeros((0, 4)),
        landing_m=None,
        previous_landings_m=(),
        miss_distance_m=None,
        flight_time_s=None,
        apex_height_m=None,
        throws_left=3,
    )
    img = renderer.render(scene)
    assert img.shape == (HEIGHT, WIDTH, 3)
    assert changed_pixels(img, renderer.render(make_scene())) > 200


def test_hit_changes_the_readout(renderer: ThrowRenderer) -> None:
    miss = renderer.render(make_scene(hit=False))
    hit = renderer.render(make_scene(hit=True, miss_distance_m=0.0))
    _, readout, _ = panel_rects(WIDTH, HEIGHT)
    x, y, w, h = readout
    assert changed_pixels(miss[y : y + h, x : x + w], hit[y : y + h, x : x + w]) > 100


def test_frame_index_moves_the_ball(renderer: ThrowRenderer) -> None:
    last = renderer.render(make_scene())
    early = renderer.render(make_scene(frame_index=10))
    assert changed_pixels(last, early) > 200
    np.testing.assert_array_equal(last, renderer.render(make_scene(frame_index=59)))


def test_bad_render_mode_raises() -> None:
    with pytest.raises(ValueError, match="render_mode"):
        ThrowRenderer("ansi")


def test_human_mode_with_dummy_display() -> None:
    r = ThrowRenderer("human", render_fps=1000)
    try:
        assert r.render(make_scene()) is None
    finally:
        r.close()


def test_module_import_does_not_import_pygame() -> None:
    code = (
        "import sys, bbgym.envs.throw.view as m; "
        "assert m.ThrowScene; sys.exit(1 if 'pygame' in sys.modules else 0)"
    )
    env = {**os.environ, "PYTHONPATH": str(REPO_ROOT)}
    result = subprocess.run([sys.executable, "-c", code], cwd=REPO_ROOT, env=env)
    assert result.returncode == 0


def test_quaternion_helpers() -> None:
    q = quat_from_axis_angle((0, 0, 1), math.pi / 2)
    np.testing.assert_allclose(quat_rotate(q, (1.0, 0.0, 0.0)), (0.0, 1.0, 0.0), atol=1e-12)
    q = quat_from_axis_angle((1, 0, 0), math.pi / 2)
    np.testing.assert_allclose(quat_rotate(q, (0.0, 0.0, 1.0)), (0.0, -1.0, 0.0), atol=1e-12)
    # Batches, sign invariance (q and -q are the same rotation) and a zero quaternion.
    v = np.array([[1.0, 2.0, 3.0], [-1.0, 0.5, 0.0]])
    np.testing.assert_allclose(quat_rotate(q, v), quat_rotate(-q, v))
    np.testing.assert_allclose(quat_rotate((0, 0, 0, 0), v), v)
    np.testing.assert_allclose(quat_to_matrix(q) @ quat_to_matrix(q).T, np.eye(3), atol=1e-12)


# -- the readout during a flight, the scale bar ------------------------------------------------


def test_flying_ball_readout_shows_elapsed_time_not_the_final_results() -> None:
    from bbgym.envs.throw.view import in_flight, readout_text

    scene = make_scene(flight_time_s=1.37, apex_height_m=3.81, miss_distance_m=0.42, hit=True)
    k = 10  # of 60 points, 0.05 s apart
    flying = dataclasses.replace(scene, frame_index=k)
    assert in_flight(flying)
    text = readout_text(flying)
    shown = " | ".join([text.header, text.result, *text.lines])
    for final in ("1.37", "3.81", "0.42", "HIT"):
        assert final not in shown, (final, shown)
    assert "miss dist --" in text.lines
    assert f"time {k * 0.05:.2f} s" in text.lines
    height = scene.trajectory_m[k, 2]
    assert f"height {height:.2f} m" in text.lines
    assert text.result == "in flight"
    # Elapsed time follows the frame, at the scene's sampling interval.
    later = readout_text(dataclasses.replace(scene, frame_index=40, sample_dt_s=0.1))
    assert "time 4.00 s" in later.lines


@pytest.mark.parametrize("frame_index", [None, 59, 500])
def test_landing_frame_readout_shows_the_final_results(frame_index: int | None) -> None:
    from bbgym.envs.throw.view import in_flight, readout_text

    scene = make_scene(flight_time_s=1.37, apex_height_m=3.81, frame_index=frame_index)
    assert not in_flight(scene)
    text = readout_text(scene)
    assert "flight 1.37 s" in text.lines and "apex 3.81 m" in text.lines
    assert "miss dist 0.40 m" in text.lines and text.result == "miss"
    assert readout_text(dataclasses.replace(scene, hit=True)).result == "HIT!"


def test_flight_frame_hides_the_landing_the_env_left_in(renderer: ThrowRenderer) -> None:
    # A flight frame of a scene that still carries its landing and result draws like one
    # without them: nothing of the outcome shows before the landing frame.
    scene = make_scene(hit=True, frame_index=20)
    bare = dataclasses.replace(scene, landing_m=None, hit=False, miss_distance_m=None)
    np.testing.assert_array_equal(renderer.render(scene), renderer.render(bare))
    assert changed_pixels(renderer.render(make_scene(hit=True)), renderer.render(scene)) > 0


def test_readout_text_is_what_the_panel_draws(renderer: ThrowRenderer) -> None:
    # Frames differ only where the panel text differs: the final flight time is not drawn
    # in a flight frame (same frame drawn with a different final time: same pixels).
    a = renderer.render(make_scene(frame_index=10, flight_time_s=1.3, apex_height_m=3.7))
    b = renderer.render(make_scene(frame_index=10, flight_time_s=2.9, apex_height_m=1.1))
    np.testing.assert_array_equal(a, b)
    c = renderer.render(make_scene(flight_time_s=1.3, apex_height_m=3.7))
    d = renderer.render(make_scene(flight_time_s=2.9, apex_height_m=1.1))
    _, readout, _ = panel_rects(WIDTH, HEIGHT)
    x, y, w, h = readout
    changed = np.argwhere(np.any(c != d, axis=-1))
    assert len(changed) and np.all((changed[:, 1] >= x) & (changed[:, 0] < y + h))


@pytest.mark.parametrize("target", [(8.0, 1.0), (30.0, -12.0), (3.0, 0.5)])
def test_top_view_scale_bar_is_metres_times_pixels_per_metre(
    renderer: ThrowRenderer, target: tuple[float, float]
) -> None:
    from bbgym.envs.throw.view import TOP_SCALE_BAR_MAX_PX
    from bbgym.render.annotations import SCALE_BAR_COLOR, scale_bar, scale_bar_origin

    scene = make_scene(target_m=target, landing_m=None, previous_landings_m=())
    img = renderer.render(scene)
    view = top_view_map(scene, WIDTH, HEIGHT)
    bar = scale_bar(view.pixels_per_meter, TOP_SCALE_BAR_MAX_PX)
    assert bar is not None
    x0, y0 = scale_bar_origin(view.rect, HEIGHT)
    row = img[y0, x0 - 3 : x0 + round(bar.length_px) + 3]
    run = int(np.count_nonzero(np.all(row == np.array(SCALE_BAR_COLOR), axis=-1)))
    assert run == round(bar.metres * view.pixels_per_meter)


@pytest.mark.parametrize("speed", [0.0, 0.4, 3.0, 9.0])
def test_the_windsock_label_never_covers_the_sock(speed: float) -> None:
    # Every wind direction, the sock near the middle and near each edge of the panel: the
    # label stands clear of the sock and the pole, and inside the panel.
    import pygame

    from bbgym.render.beach import ViewMap, draw_top_windsock

    pygame.font.init()
    font = pygame.font.Font(None, 16)
    surface = pygame.Surface((640, 280))
    view = ViewMap(rect=(0, 0, 640, 280), origin_px=(320.0, 140.0), pixels_per_meter=24.0)
    for pole in ((0.0, 0.0), (-12.5, 4.5), (12.5, -5.2), (0.0, 5.0), (0.0, -5.5)):
        for k in range(24):
            angle = 2 * math.pi * k / 24
            wind = (speed * math.cos(angle), speed * math.sin(angle))
            label, sock = draw_top_windsock(pygame, surface, font, view, pole, wind)
            assert not pygame.Rect(label).colliderect(pygame.Rect(sock)), (pole, k, label, sock)
            assert pygame.Rect(0, 0, 640, 280).contains(pygame.Rect(label))
