"""Far-away and extreme objects in every view (issue 10): never an error, and an edge marker.

Renderer-level tests build the scene objects directly (no env layer), as the other render
tests do; the env-level tests at the end go through ``gym.make``. Headless, via SDL's dummy
video driver.
"""

import os

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

pytest.importorskip("pygame")

import pygame  # noqa: E402

from bbgym.envs.sail.view import MARK_COLOR, SailRenderer, SailScene  # noqa: E402
from bbgym.envs.throw.view import (  # noqa: E402
    TARGET_COLOR,
    ThrowRenderer,
    ThrowScene,
    ThrowScreen,
    panel_rects,
    side_view_map,
    top_view_map,
)
from bbgym.envs.topple.frame import ToppleScene  # noqa: E402
from bbgym.envs.topple.frame import panel_rects as topple_panel_rects  # noqa: E402
from bbgym.envs.topple.view import WALL_COLOR, ToppleRenderer  # noqa: E402
from bbgym.render.annotations import EDGE_MARKER_MARGIN_PX  # noqa: E402
from bbgym.render.beach import BALL_MARKER_COLOR  # noqa: E402
from bbgym.render.geometry import clip_polygon, clip_segment, safe_box  # noqa: E402
from bbgym.render.safe_draw import SafeDraw  # noqa: E402

W, H = 640, 480
# Hypothesis runs a renderer many times: one per module, no per-example fixture.
FAR = settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
ANY_SCENE = settings(FAR, max_examples=60)  # the "never raises" properties: more examples


@pytest.fixture(scope="module")
def sail() -> SailRenderer:
    r = SailRenderer("rgb_array", width=W, height=H, pixels_per_meter=12.0)
    yield r
    r.close()


@pytest.fixture(scope="module")
def throw() -> ThrowRenderer:
    r = ThrowRenderer("rgb_array", width=W, height=H)
    yield r
    r.close()


@pytest.fixture(scope="module")
def topple() -> ToppleRenderer:
    r = ToppleRenderer("rgb_array", width=W, height=H)
    yield r
    r.close()


def color_mask(img: np.ndarray, color: tuple[int, int, int], tol: int = 6) -> np.ndarray:
    diff = np.abs(img.astype(np.int16) - np.array(color, dtype=np.int16))
    return np.all(diff <= tol, axis=-1)


def crop(img: np.ndarray, rect: tuple[int, int, int, int]) -> np.ndarray:
    x, y, w, h = rect
    return img[y : y + h, x : x + w]


def assert_frame(img: np.ndarray) -> None:
    assert isinstance(img, np.ndarray)
    assert img.shape == (H, W, 3)
    assert img.dtype == np.uint8
    packed = img.astype(np.int32)
    packed = (packed[..., 0] << 16) | (packed[..., 1] << 8) | packed[..., 2]  # fast np.unique
    assert len(np.unique(packed)) > 5  # the text panels at least


def bearing_row(rect: tuple[int, int, int, int], bearing_rad: float) -> float:
    """Row where a ray from the rect's centre at ``bearing_rad`` (north of east, screen y down)
    meets the right edge inset by the marker margin: where an eastern marker's tip goes."""
    x, y, w, h = rect
    return y + h / 2 - math.tan(bearing_rad) * (w / 2 - EDGE_MARKER_MARGIN_PX)


# --- strategies ------------------------------------------------------------------------------

magnitudes = st.floats(-6.0, 9.0).map(lambda e: 10.0**e)  # 1e-6 m .. 1e9 m
angles = st.floats(-math.pi, math.pi)


@st.composite
def points(draw: st.DrawFn, lo: float = -6.0, hi: float = 9.0) -> tuple[float, float]:
    r = 10.0 ** draw(st.floats(lo, hi))
    a = draw(angles)
    return (r * math.cos(a), r * math.sin(a))


def sizes(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi).map(lambda e: 10.0**e)


def flight(end_xy: tuple[float, float], apex_m: float, k: int = 20) -> np.ndarray:
    """A lob of k points from the hand to ``end_xy`` on the ground, ``apex_m`` high."""
    t = np.linspace(0.0, 1.0, k)
    return np.stack([end_xy[0] * t, end_xy[1] * t, 1.5 * (1 - t) + 4 * apex_m * t * (1 - t)], 1)


@st.composite
def sail_scenes(draw: st.DrawFn) -> SailScene:
    return SailScene(
        time_s=draw(st.floats(0.0, 1e6)),
        position_m=draw(points()),
        heading_rad=draw(st.floats(-100.0, 100.0)),
        heel_rad=draw(st.floats(-100.0, 100.0)),
        boom_angle_rad=draw(st.floats(-100.0, 100.0)),
        rudder_angle_rad=draw(st.floats(-100.0, 100.0)),
        sail_force_n=draw(st.floats(0.0, 1e9)),
        sail_luffing=draw(st.booleans()),
        mark_m=draw(points()),
        mark_radius_m=draw(sizes(-3.0, 8.0)),
        true_wind_mps=draw(st.one_of(st.just((0.0, 0.0)), points(-6.0, 3.0))),
        apparent_wind_speed_mps=draw(st.floats(0.0, 1e3)),
        apparent_wind_angle_rad=draw(st.floats(-math.pi, math.pi)),
        boat_speed_mps=draw(st.floats(0.0, 1e3)),
        wake_m=tuple(draw(st.lists(points(), max_size=6))),
        capsized=draw(st.booleans()),
        hull_length_m=draw(sizes(-2.0, 3.0)),
        hull_beam_m=draw(sizes(-2.0, 3.0)),
        boom_length_m=draw(sizes(-2.0, 3.0)),
    )


@st.composite
def throw_scenes(draw: st.DrawFn) -> ThrowScene:
    traj = flight(draw(points()), draw(magnitudes))
    k = len(traj)
    screen = None
    if draw(st.booleans()):
        a = draw(angles)
        screen = ThrowScreen(
            center_m=draw(points()),
            along_m=(math.cos(a), math.sin(a)),
            half_width_m=draw(sizes(-3.0, 8.0)),
            height_m=draw(sizes(-3.0, 8.0)),
        )
    return ThrowScene(
        trajectory_m=traj,
        orientations=np.tile([1.0, 0.0, 0.0, 0.0], (k, 1)),
        ball_radius_m=draw(sizes(-3.0, 4.0)),
        target_m=draw(points()),
        target_radius_m=draw(sizes(-3.0, 7.0)),
        wind_mps=draw(st.one_of(st.just((0.0, 0.0)), points(-6.0, 3.0))),
        windsock_mps=draw(points(-6.0, 3.0)),
        screen=screen,
        landing_m=(float(traj[-1, 0]), float(traj[-1, 1])),
        previous_landings_m=tuple(draw(st.lists(points(), max_size=3))),
        hit=draw(st.booleans()),
        frame_index=draw(st.one_of(st.none(), st.integers(0, k - 1))),
    )


@st.composite
def topple_scenes(draw: st.DrawFn) -> ToppleScene:
    end = draw(points())
    traj = flight(end, draw(magnitudes), k=16)
    k2 = 40
    state = draw(st.sampled_from(["standing", "fallen_away", "fallen_toward", "loose"]))
    loose = np.full((k2, 3), np.nan)
    panel = None
    if state == "loose":
        x, z = draw(points())
        panel = (x, abs(z), draw(st.floats(-10.0, 10.0)))
        loose[20:] = np.linspace((5.0, 1.0, 0.0), panel, k2 - 20)
    angle = draw(st.floats(-math.pi / 2, math.pi / 2))
    hit = None
    if draw(st.booleans()):
        hit = tuple(float(v) for v in traj[-1])
    return ToppleScene(
        wall_distance_m=draw(magnitudes),
        wall_height_m=draw(sizes(-3.0, 4.0)),
        wall_width_m=draw(sizes(-3.0, 4.0)),
        wall_thickness_m=draw(sizes(-5.0, 1.0)),
        base_depth_m=draw(sizes(-5.0, 2.0)),
        wall_angle_rad=angle,
        pivot_side=draw(st.sampled_from([-1, 0, 1])),
        wall_state=state,
        loose_panel=panel,
        ball_trajectory_m=traj,
        ball_orientations=np.tile([1.0, 0.0, 0.0, 0.0], (len(traj), 1)),
        ball_radius_m=draw(sizes(-3.0, 4.0)),
        wall_angle_samples=np.linspace(0.0, angle, k2),
        loose_samples=loose,
        hit_point_m=hit,
        wind_mps=draw(st.one_of(st.just((0.0, 0.0)), points(-6.0, 3.0))),
        windsock_mps=draw(points(-6.0, 3.0)),
        frame_index=draw(st.one_of(st.none(), st.integers(0, k2 + 5))),
    )


# --- nothing raises, whatever the scene holds ------------------------------------------------


@ANY_SCENE
@given(scene=sail_scenes())
def test_sail_view_renders_any_far_or_extreme_scene(sail: SailRenderer, scene: SailScene) -> None:
    assert_frame(sail.render(scene))


@ANY_SCENE
@given(scene=throw_scenes())
def test_throw_view_renders_any_far_or_extreme_scene(
    throw: ThrowRenderer, scene: ThrowScene
) -> None:
    assert_frame(throw.render(scene))


@ANY_SCENE
@given(scene=topple_scenes())
def test_topple_view_renders_any_far_or_extreme_scene(
    topple: ToppleRenderer, scene: ToppleScene
) -> None:
    assert_frame(topple.render(scene))


def test_human_mode_renders_far_scenes_too() -> None:
    scene = sail_scene(mark_m=(1e9, 0.0))
    renderers = [SailRenderer("human", render_fps=1000), ThrowRenderer("human", render_fps=1000)]
    try:
        assert renderers[0].render(scene) is None
        assert renderers[1].render(throw_scene(target_m=(1e9, 0.0))) is None
    finally:
        for r in renderers:
            r.close()


# --- the edge marker -------------------------------------------------------------------------


def sail_scene(**overrides: object) -> SailScene:
    base = SailScene(
        time_s=1.0,
        position_m=(0.0, 0.0),
        heading_rad=0.0,
        heel_rad=0.0,
        boom_angle_rad=-0.5,
        rudder_angle_rad=0.0,
        sail_force_n=200.0,
        sail_luffing=False,
        mark_m=(10.0, 5.0),
        mark_radius_m=3.0,
        true_wind_mps=(0.0, -5.0),
        apparent_wind_speed_mps=5.0,
        apparent_wind_angle_rad=1.2,
        boat_speed_mps=2.0,
        wake_m=(),
        capsized=False,
    )
    return dataclasses.replace(base, **overrides)


@FAR
@given(bearing=st.floats(-0.5, 0.3), distance=sizes(3.0, 9.0), boat=points(-6.0, 9.0))
def test_sail_far_mark_gets_a_marker_on_the_right_edge_at_its_bearing(
    sail: SailRenderer, bearing: float, distance: float, boat: tuple[float, float]
) -> None:
    # Bearings up to 0.3 rad north of east: the wind compass covers the corner above that.
    mark = (boat[0] + distance * math.cos(bearing), boat[1] + distance * math.sin(bearing))
    img = sail.render(sail_scene(position_m=boat, mark_m=mark))
    mask = color_mask(img, MARK_COLOR, tol=30)
    rows, cols = np.nonzero(mask)
    assert rows.size > 30
    assert cols.min() >= W - 60  # only the arrow, at the right edge...
    assert abs(rows.mean() - bearing_row((0, 0, W, H), bearing)) < 10  # ...at its bearing


@pytest.mark.parametrize(
    ("mark", "edge"),
    [((0.0, 1e9), "top"), ((0.0, -1e9), "bottom"), ((-1e9, 0.0), "left"), ((-1e4, -1e4), "sw")],
)
def test_sail_far_mark_marker_is_on_the_edge_facing_it(
    sail: SailRenderer, mark: tuple[float, float], edge: str
) -> None:
    rows, cols = np.nonzero(color_mask(sail.render(sail_scene(mark_m=mark)), MARK_COLOR, tol=30))
    assert rows.size > 30
    m = EDGE_MARKER_MARGIN_PX + 20
    expected = {
        "top": rows.max() < m and abs(cols.mean() - W / 2) < 6,
        "bottom": rows.min() > H - m and abs(cols.mean() - W / 2) < 6,
        "left": cols.max() < m and abs(rows.mean() - H / 2) < 6,
        # South-west at 45 deg from the boat: the ray leaves through the bottom edge first.
        "sw": rows.min() > H - m and cols.mean() < W / 2 - 150,
    }
    assert expected[edge]


@FAR
@given(dx=st.floats(-20.0, 20.0), dy=st.floats(-13.0, 13.0))
def test_sail_mark_in_view_draws_no_marker(sail: SailRenderer, dx: float, dy: float) -> None:
    img = sail.render(sail_scene(position_m=(3.0, -2.0), mark_m=(3.0 + dx, -2.0 + dy)))
    mask = color_mask(img, MARK_COLOR, tol=30)
    # The buoy is at most 247 px from the centre across and 163 px up or down; an edge arrow
    # would lie 26-44 px inside the border.
    border = np.ones_like(mask)
    border[50 : H - 50, 50 : W - 50] = False
    assert np.count_nonzero(mask & border) == 0


def throw_scene(**overrides: object) -> ThrowScene:
    traj = flight((7.8, 1.0), 1.5)
    base = ThrowScene(
        trajectory_m=traj,
        orientations=np.tile([1.0, 0.0, 0.0, 0.0], (len(traj), 1)),
        ball_radius_m=0.2,
        target_m=(8.0, 1.0),
        target_radius_m=0.75,
        wind_mps=(1.5, -0.5),
        windsock_mps=(1.7, -0.4),
        screen=None,
        landing_m=(7.8, 1.0),
        throws_left=2,
    )
    return dataclasses.replace(base, **overrides)


@FAR
@given(bearing=st.floats(-0.3, 0.3), distance=sizes(4.0, 9.0))  # past 0.36: the top edge
def test_throw_far_target_gets_markers_in_both_views(
    throw: ThrowRenderer, bearing: float, distance: float
) -> None:
    target = (distance * math.cos(bearing), distance * math.sin(bearing))
    img = throw.render(throw_scene(target_m=target))
    side, _, top = panel_rects(W, H)
    # Top view: at the right edge, at the bearing (the thrower's view is tiny next to 10 km).
    rows, cols = np.nonzero(color_mask(crop(img, top), TARGET_COLOR, tol=20))
    assert rows.size > 30
    assert cols.min() >= top[2] - 60
    assert abs(rows.mean() + top[1] - bearing_row(top, bearing)) < 10
    # Side view (along the bearing): at the right edge, level with the panel's middle.
    rows, cols = np.nonzero(color_mask(crop(img, side), TARGET_COLOR, tol=20))
    assert rows.size > 30
    assert cols.min() >= side[2] - 60
    assert abs(rows.mean() - side[3] / 2) < 10


@FAR
@given(distance=st.floats(3.0, 10.0), bearing=st.floats(-math.pi / 4, math.pi / 4))
def test_throw_target_in_view_draws_only_the_ring(
    throw: ThrowRenderer, distance: float, bearing: float
) -> None:
    scene = throw_scene(target_m=(distance * math.cos(bearing), distance * math.sin(bearing)))
    img = throw.render(scene)
    side, _, top = panel_rects(W, H)
    view = top_view_map(scene, W, H)
    tx, ty = view.to_px(*scene.target_m)
    r = max(scene.target_radius_m * view.pixels_per_meter, 6.0) + 2
    mask = color_mask(img, TARGET_COLOR, tol=20)
    rows, cols = np.nonzero(crop(mask, top))
    assert rows.size > 30
    assert np.all(np.hypot(cols - tx, rows + top[1] - ty) <= r)  # no magenta but the ring
    sview = side_view_map(scene, W, H)
    sx, sy = sview.to_px(distance, 0.0)
    rows, cols = np.nonzero(crop(mask, side))
    assert rows.size > 5
    assert np.all(np.abs(cols - sx) <= 0.75 * sview.pixels_per_meter + 2)
    assert np.all(np.abs(rows - sy) <= 6)


def test_throw_ball_far_out_of_the_field_gets_a_marker(throw: ThrowRenderer) -> None:
    side, _, top = panel_rects(W, H)
    strip = (top[0] + top[2] - 60, top[1], 60, top[3])
    far = throw.render(throw_scene(trajectory_m=flight((1e6, 0.0), 1.0), landing_m=(1e6, 0.0)))
    rows, _ = np.nonzero(color_mask(crop(far, strip), BALL_MARKER_COLOR, tol=12))
    assert rows.size > 30
    assert abs(rows.mean() + top[1] - (top[1] + top[3] / 2)) < 10  # due east: mid-height
    side_strip = (side[0] + side[2] - 60, side[1], 60, side[3])
    assert np.count_nonzero(color_mask(crop(far, side_strip), BALL_MARKER_COLOR, tol=12)) > 30
    # The ball of a normal throw is in view: nothing red at the edges.
    near = throw.render(throw_scene())
    assert np.count_nonzero(color_mask(crop(near, strip), BALL_MARKER_COLOR, tol=12)) == 0
    assert np.count_nonzero(color_mask(crop(near, side_strip), BALL_MARKER_COLOR, tol=12)) == 0


def topple_scene(**overrides: object) -> ToppleScene:
    traj = flight((5.7, 0.1), 1.2, k=16)
    base = ToppleScene(
        wall_distance_m=6.0,
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
        wall_angle_samples=np.zeros(40),
        loose_samples=np.full((40, 3), np.nan),
        hit_point_m=None,
        wind_mps=(3.0, -1.0),
        windsock_mps=(3.2, -0.8),
    )
    return dataclasses.replace(base, **overrides)


def strips(rect: tuple[int, int, int, int], px: int = 50) -> tuple[tuple, tuple]:
    x, y, w, h = rect
    return (x, y, px, h), (x + w - px, y, px, h)


def test_topple_far_wall_gets_markers_and_a_near_one_none(topple: ToppleRenderer) -> None:
    side, _, inset = topple_panel_rects(W, H)
    far = topple.render(topple_scene(wall_distance_m=1e7))
    left, right = strips(side)
    rows, _ = np.nonzero(color_mask(crop(far, right), WALL_COLOR))
    assert rows.size > 30
    assert abs(rows.mean() - side[3] / 2) < 10  # due east, 1.2 m up: mid-height
    assert np.count_nonzero(color_mask(crop(far, (0, 0, side[2] // 2, side[3])), WALL_COLOR)) == 0
    inset_left, inset_right = strips(inset, 40)
    assert np.count_nonzero(color_mask(crop(far, inset_right), WALL_COLOR)) > 30
    near = topple.render(topple_scene())
    for rect in (left, right, inset_left, inset_right):
        assert np.count_nonzero(color_mask(crop(near, rect), WALL_COLOR)) == 0


def test_topple_loose_panel_blown_far_away_gets_a_marker(topple: ToppleRenderer) -> None:
    side, _, inset = topple_panel_rects(W, H)
    panel = (-1e5, 2.0, 0.7)  # blown far back over the thrower's head
    loose = np.full((40, 3), np.nan)
    loose[20:] = np.linspace((6.5, 1.2, 0.1), panel, 20)
    img = topple.render(topple_scene(wall_state="loose", loose_panel=panel, loose_samples=loose))
    left, right = strips(side)
    rows, _ = np.nonzero(color_mask(crop(img, left), WALL_COLOR))
    assert rows.size > 30
    assert np.count_nonzero(color_mask(crop(img, right), WALL_COLOR)) == 0
    inset_left, _ = strips(inset, 40)
    assert np.count_nonzero(color_mask(crop(img, inset_left), WALL_COLOR)) > 30


# --- the drawing helper itself ---------------------------------------------------------------


def test_safe_draw_passes_shapes_in_range_to_pygame_unchanged() -> None:
    a, b = pygame.Surface((120, 90)), pygame.Surface((120, 90))
    safe = SafeDraw(pygame)
    for draw, surf in ((pygame.draw, a), (safe, b)):
        surf.fill((0, 0, 0))
        draw.line(surf, (255, 0, 0), (-300.5, 10.2), (700.0, 80.7), 3)
        draw.lines(surf, (0, 255, 0), True, [(5, 5), (100, 20), (60, 85), (-50, 40)], 2)
        draw.polygon(surf, (0, 0, 255), [(30, 30), (90, 35), (70, 80)])
        draw.circle(surf, (255, 255, 0), (60.4, 45.6), 30.2, 4)
        draw.ellipse(surf, (0, 255, 255), (10, 50, 80, 20))
        draw.rect(surf, (255, 0, 255), (20, 10, 50, 25), 2, border_radius=4)
    np.testing.assert_array_equal(pygame.surfarray.array3d(a), pygame.surfarray.array3d(b))


@settings(max_examples=30, deadline=None)
@given(slope=st.floats(-0.4, 0.4), reach=sizes(4.0, 100.0))
def test_a_line_to_a_far_point_keeps_its_direction(slope: float, reach: float) -> None:
    # Clamping each axis would bend the visible part towards 45 deg; clipping keeps it exact.
    expected = H / 2 + slope * (W - 20 - 20.0)
    # (A line that leaves through the top or bottom edge first never reaches that column.)
    assume(reach > W - 20 and 2.0 <= expected <= H - 3.0)
    surf = pygame.Surface((W, H))
    surf.fill((0, 0, 0))
    start = (20.0, H / 2)
    SafeDraw(pygame).line(surf, (255, 255, 255), start, (reach, H / 2 + slope * reach), 1)
    column = pygame.surfarray.array3d(surf)[W - 20, :, 0]
    lit = np.nonzero(column)[0]
    assert lit.size > 0
    assert abs(lit.mean() - expected) <= 1.5


@settings(max_examples=200, deadline=None)
@given(a=points(-3.0, 12.0), b=points(-3.0, 12.0))
@example(a=(-1e12, 0.00012246467991473532), b=(562341325190.3491, 0.0))  # found by CI
def test_clipped_segment_lies_on_the_segment_inside_the_box(
    a: tuple[float, float], b: tuple[float, float]
) -> None:
    box = safe_box((W, H))
    seg = clip_segment(a, b, box)
    # Every point of the segment inside the box shrunk by a pixel is in the clipped one.
    mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    inner = box[0] + 1 <= mid[0] <= box[2] - 1 and box[1] + 1 <= mid[1] <= box[3] - 1
    if seg is None:
        assert not inner
        return
    length = math.dist(a, b)
    for p in seg:
        assert box[0] - 1e-6 <= p[0] <= box[2] + 1e-6 and box[1] - 1e-6 <= p[1] <= box[3] + 1e-6
        # On the line through a and b (relative to the segment's length).
        cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        assert abs(cross) <= 1e-9 * length * max(length, 1.0) + 1e-6
    polygon = clip_polygon([a, b, (a[0], b[1])], box)
    assert all(box[0] - 1e-6 <= p[0] <= box[2] + 1e-6 for p in polygon)


# --- through the envs ------------------------------------------------------------------------


def test_throw_env_renders_a_far_target() -> None:
    gym = pytest.importorskip("gymnasium")
    import bbgym  # noqa: F401  (registers the ids)

    # The env takes targets within its field, at most 1000 m across (field_radius).
    env = gym.make("BeachballThrow-v0", render_mode="rgb_array", field_radius=1000.0)
    try:
        env.reset(seed=0, options={"target": (999.0, 0.0)})
        frame = env.render()
        assert frame.shape == (H, W, 3) and frame.dtype == np.uint8
        _, _, top = panel_rects(W, H)
        rows, cols = np.nonzero(color_mask(crop(frame, top), TARGET_COLOR, tol=20))
        assert rows.size > 30 and cols.min() >= top[2] - 60  # the marker, at the right edge
        env.step(np.array([0.6, 0.0, 0.6, 0.0, 0.0, 0.0], dtype=np.float32))
        assert env.render().shape == (H, W, 3)
        flight_frames = env.unwrapped.render_flight()
        assert len(flight_frames) > 0
        assert all(f.shape == (H, W, 3) for f in flight_frames)
    finally:
        env.close()


def test_sail_env_renders_a_far_mark() -> None:
    gym = pytest.importorskip("gymnasium")
    import bbgym  # noqa: F401

    env = gym.make("BeachballSail-v0", render_mode="rgb_array")
    try:
        env.reset(seed=0, options={"mark": (5000.0, 0.0)})
        frame = env.render()
        assert frame.shape == (H, W, 3)
        _, cols = np.nonzero(color_mask(frame, MARK_COLOR, tol=30))
        assert cols.size > 30 and cols.min() >= W - 60
        env.step(np.zeros(2, dtype=np.float32))
        assert env.render().shape == (H, W, 3)
    finally:
        env.close()


def test_topple_env_renders_after_a_throw() -> None:
    gym = pytest.importorskip("gymnasium")
    import bbgym  # noqa: F401

    env = gym.make("BeachballTopple-v0", render_mode="rgb_array")
    try:
        env.reset(seed=0)
        env.step(np.array([1.0, 0.0, 0.4, 0.0, 0.0, 0.0], dtype=np.float32))
        assert env.render().shape == (H, W, 3)
        assert all(f.shape == (H, W, 3) for f in env.unwrapped.render_flight())
    finally:
        env.close()
