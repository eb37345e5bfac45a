"""Pictures a person can read (issue 52, item 8): labels laid out so that none overlaps
another, scenes that fill their frame, the race's boats clear of the caption band, the
sail's scale bar clear of the mark, and GIFs of long runs and episodes under 3 MB and
300 frames, still in real time."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from bbgym.render.labels import boxes_overlap, disc_box, place_labels

MB3 = 3_000_000


def no_two_overlap(boxes) -> bool:
    return not any(boxes_overlap(a, b) for a, b in itertools.combinations(boxes, 2))


# -- the layout, pure ---------------------------------------------------------------------------


def test_labels_of_balls_at_one_spot_do_not_overlap() -> None:
    """Three balls on top of one another (the Magnus scene's start): their three labels,
    each 110 x 14 px, stack clear of each other and of the balls, inside the frame."""
    anchors = [(320.0, 300.0, 10.0), (321.0, 302.0, 10.0), (322.0, 304.0, 10.0)]
    bounds = (0.0, 44.0, 640.0, 400.0)
    boxes = place_labels(anchors, [(110.0, 14.0)] * 3, bounds)
    assert no_two_overlap(boxes)
    for box in boxes:
        assert bounds[0] <= box[0] and box[2] <= bounds[2]
        assert bounds[1] <= box[1] and box[3] <= bounds[3]
        assert not any(boxes_overlap(box, disc_box(*a)) for a in anchors)
        # near its ball: within three label heights
        assert min(abs(box[1] - 300.0), abs(box[3] - 300.0)) < 3 * 14 + 20


def test_a_label_at_the_frame_edge_is_pulled_inside() -> None:
    (box,) = place_labels([(635.0, 395.0, 3.0)], [(120.0, 14.0)], (0.0, 0.0, 640.0, 400.0))
    assert box[0] >= 0.0 and box[2] <= 640.0 and box[1] >= 0.0 and box[3] <= 400.0


# -- scenes ---------------------------------------------------------------------------------------


def scene_views(name: str, steps: tuple[int, ...]):
    """The view and each ``steps``' frame of scene ``name`` (its label boxes with it)."""
    pytest.importorskip("pygame")
    from bbgym.scenes import get_scene, simulate
    from bbgym.scenes.view import TITLE_BAND_PX, SceneView

    scene = get_scene(name)
    states = []
    run = simulate(scene, steps=max(steps), on_step=lambda p, s: states.append(s))
    view = SceneView(scene, run.params)
    out = []
    for k in steps:
        view.render((k * run.params.dt_s, scene.frame(run.params, states[k])))
        out.append(list(view.label_boxes))
    view.close()
    return scene, run, view, out, TITLE_BAND_PX


@pytest.mark.parametrize(
    ("name", "steps"), [("magnus", (0, 20, 40, 80, 120)), ("bowling-balls", (0, 150, 300))]
)
def test_a_scenes_ball_labels_never_overlap(name: str, steps: tuple[int, ...]) -> None:
    scene, run, view, frames, title_px = scene_views(name, steps)
    for boxes in frames:
        assert len(boxes) == len(scene.names(run.params))
        assert no_two_overlap(boxes), boxes
        assert all(b[1] >= title_px and b[3] <= view.height for b in boxes)


def test_the_magnus_flights_fill_the_frame_and_the_clip_ends_soon_after_landing() -> None:
    from bbgym.scenes import get_scene, simulate
    from bbgym.scenes.wind import MagnusParams

    scene = get_scene("magnus")
    run = simulate(scene)
    height = run.measures["height_m"]
    landed = max(run.times_s[int(np.argmax(height[:, k] <= 0.0))] for k in range(3))
    assert 0.0 < run.times_s[-1] - landed <= 0.5  # was 0.86 s of a 1.6 s clip
    pytest.importorskip("pygame")
    from bbgym.scenes.view import TITLE_BAND_PX, SceneView

    view = SceneView(scene, MagnusParams())
    usable = view.height - TITLE_BAND_PX
    launch_row = view.to_px(0.0, MagnusParams().launch_height_m)[1]
    floor_row = view.to_px(0.0, 0.0)[1]
    assert floor_row - launch_row > 0.35 * usable  # was a sixth of it
    farthest = float(run.measures["distance_m"][-1].max())
    assert view.to_px(farthest, 0.0)[0] > 0.6 * view.width  # the flights span the width


def test_points_of_sail_wind_arrows_stay_by_their_own_boat() -> None:
    from bbgym.scenes import get_scene
    from bbgym.scenes.boat import LANES_M, WIND

    scene = get_scene("points-of-sail")
    params = scene.make_params(None)
    frame = scene.frame(params, scene.initial(params, np))
    wind = [s for s in frame.segments if s.color == WIND]
    assert len(wind) == 9  # a shaft and two barbs for each boat
    gap = abs(LANES_M[0] - LANES_M[1])
    for k, lane in enumerate(LANES_M):
        for seg in wind[3 * k : 3 * k + 3]:
            for y in (seg.y0_m, seg.y1_m):
                assert abs(y - lane) < 0.55 * gap  # nearer its own boat than the next


def test_the_points_of_sail_gif_is_small_and_in_real_time(tmp_path, capsys) -> None:
    """60 s of the scene: was 1,201 frames, 5.9 MB."""
    pytest.importorskip("pygame")
    Image = pytest.importorskip("PIL.Image")
    from bbgym.cli import main

    gif = tmp_path / "points.gif"
    assert main(["scene", "points-of-sail", "--out", str(gif)]) == 0
    assert gif.stat().st_size < MB3
    with Image.open(gif) as image:
        assert image.n_frames <= 300
        total = 0
        for k in range(image.n_frames):
            image.seek(k)
            total += image.info["duration"]
    assert total == pytest.approx(60_000, abs=500)  # real time
    assert "real time" in capsys.readouterr().out


# -- the GIF writer -------------------------------------------------------------------------------


def test_the_gif_writer_keeps_a_frame_budget_the_held_and_the_last_frame(tmp_path) -> None:
    pytest.importorskip("PIL")
    from PIL import Image

    from bbgym.render.gif import GifWriter

    writer = GifWriter(tmp_path / "a.gif", fps=20.0, max_frames=50)
    for k in range(400):
        frame = np.zeros((24, 32, 3), np.uint8)
        frame[:, : k % 32] = (200, 40, 40)  # each frame unlike its neighbours
        frame[0, 0] = (k % 7 * 30, 0, 0)
        writer(frame, 40 if k == 123 else 1)
    last = np.full((24, 32, 3), 255, np.uint8)
    writer(last, 20)
    writer.close()
    with Image.open(tmp_path / "a.gif") as image:
        assert image.n_frames <= 50
        durations = []
        for k in range(image.n_frames):
            image.seek(k)
            durations.append(image.info["duration"])
        assert np.asarray(image.convert("RGB"))[5, 5].tolist() == [255, 255, 255]  # last
    assert sum(durations) == pytest.approx((399 + 40 + 20) * 50, abs=20)  # real time
    assert durations[-1] >= 1000  # the last frame, held 20 periods of 50 ms
    assert max(durations[:-1]) >= 2000  # the held frame (123) kept, 40 periods


def test_frames_the_gif_drops_are_not_drawn_and_the_file_is_the_same(tmp_path) -> None:
    """A frame given as a function is drawn only where the GIF keeps it: a long episode
    (400 frames into 50, so every 8th is kept by the end) draws under half of them, held
    frames and the last included, and writes the same bytes as drawing every frame."""
    pytest.importorskip("PIL")
    pytest.importorskip("pygame")
    from bbgym.cli.record import _CaptionedFrames
    from bbgym.render.gif import GifWriter

    def frame(k: int) -> np.ndarray:
        image = np.zeros((48, 64, 3), np.uint8)
        image[:, : k % 64] = (200, 40, 40)
        image[0, 0] = (k % 7 * 30, 0, 0)
        return image

    drawn = []

    def lazily(k: int):
        return lambda: drawn.append(k) or frame(k)

    for name, given in (("eager.gif", frame), ("lazy.gif", lazily)):
        writer = GifWriter(tmp_path / name, fps=20.0, max_frames=50)
        frames = _CaptionedFrames(writer, "left", title=True, frame_skip=1, hold_periods=8)
        for k in range(400):
            frames.add(given(k), f"step {k}", key=k == 123)
        frames.add(frame(400), "step 400", key=False)  # the last: always drawn
        frames.finish("done", (255, 255, 255))
        writer.close()
        assert frames.kept == 401  # every frame passed on, drawn or not
    eager, lazy = ((tmp_path / n).read_bytes() for n in ("eager.gif", "lazy.gif"))
    assert lazy == eager
    assert 123 in drawn and len(drawn) < 200  # of 400
    writer = GifWriter(tmp_path / "c.gif", fps=20.0, max_frames=4)
    for k in range(9):  # the stride is 2 or more by now, and 9 is odd
        writer(frame(k))
    assert writer.stride > 1 and not writer.keeps() and writer.keeps(held=True)
    with pytest.raises(ValueError, match="skip"):
        writer.skip(periods=2)  # a held frame is kept: it needs its image


def test_the_gif_writer_halves_a_gif_over_its_size_budget(tmp_path, capsys) -> None:
    pytest.importorskip("PIL")
    from bbgym.render.gif import GifWriter

    rng = np.random.default_rng(0)
    writer = GifWriter(tmp_path / "noise.gif", fps=10.0, max_bytes=150_000)
    for _ in range(40):  # noise: about 50 KB a frame however it is coded
        writer(rng.integers(0, 256, (120, 160, 3), dtype=np.uint8))
    writer.close()
    assert (tmp_path / "noise.gif").stat().st_size <= 150_000
    assert 2 <= len(writer.images) <= 5
    assert "written again" in capsys.readouterr().err


def test_a_long_sail_v2_episode_gif_is_under_3_mb(tmp_path) -> None:
    """Sail-v2's waves and current, 160 frames (16 s at 10 fps): was 21.7 MB for 120
    frames (each frame its own palette, the waves a gradient)."""
    pytest.importorskip("pygame")
    import gymnasium as gym
    from PIL import Image

    import bbgym  # noqa: F401
    from bbgym.render.gif import GifWriter

    env = gym.make("BeachballSail-v2", render_mode="rgb_array")
    env.reset(seed=16)
    writer = GifWriter(tmp_path / "sail.gif", fps=10.0)
    action = np.zeros(env.action_space.shape, np.float32)
    action[-1] = 0.5
    for _ in range(160):
        writer(env.render())
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    writer(env.render(), 10)
    env.close()
    writer.close()
    size = (tmp_path / "sail.gif").stat().st_size
    assert size < MB3
    with Image.open(tmp_path / "sail.gif") as image:
        assert 20 <= image.n_frames <= 300


# -- the race -------------------------------------------------------------------------------------


def test_places_in_words() -> None:
    from bbgym.envs.race.view import ordinal, places_text

    assert places_text([4, 1, 2, 3]) == "1st boat_1, 2nd boat_2, 3rd boat_3, 4th boat_0"
    assert places_text([0, 1, 2, 0]) == "1st boat_1, 2nd boat_2; boat_0, boat_3 did not finish"
    assert places_text([0, 0], [True, False]) == "boat_0*, boat_1 did not finish"
    assert [ordinal(n) for n in (1, 2, 3, 4, 11, 12, 13, 21, 22, 101)] == [
        "1st",
        "2nd",
        "3rd",
        "4th",
        "11th",
        "12th",
        "13th",
        "21st",
        "22nd",
        "101st",
    ]


def race_scene_of(positions, places, stopped):
    """A race frame on the registered course's shape: the line 40 m wide, the windward
    mark 150 m up, the view 25 m below the line (the deepest start, 20 m, and 5 m)."""
    from bbgym.envs.race.view import BoatView, RaceScene

    boats = tuple(
        BoatView(
            number=k,
            position_m=p,
            heading_rad=0.0,
            boom_angle_rad=0.3,
            capsized=False,
            stopped=stopped,
            place=places[k],
            cone=None,
        )
        for k, p in enumerate(positions)
    )
    return RaceScene(
        clock_s=340.0,
        upwind=(0.0, 1.0),
        wind_speed_mps=5.0,
        committee_m=(-20.0, 0.0),
        pin_m=(20.0, 0.0),
        windward_m=(0.0, 150.0),
        gate_m=((-10.0, -20.0), (10.0, -20.0)),
        top_m=160.0,
        bottom_m=25.0,
        half_width_m=30.0,
        boats=boats,
    )


def test_the_race_first_frame_shows_every_boat_above_the_caption_band() -> None:
    """Boats at the start, 20 m below the line (the deepest start): each boat (drawn twice
    its 4.2 m, about 20 px) and its label above the recording's caption band."""
    pytest.importorskip("pygame")
    from bbgym.envs.race.view import RaceRenderer
    from bbgym.render.annotations import CAPTION_BAND_PX

    scene = race_scene_of(
        [(-15.0, -20.0), (-5.0, -20.0), (5.0, -20.0), (15.0, -20.0)], [0, 0, 0, 0], stopped=False
    )
    renderer = RaceRenderer("rgb_array", 640, 480, 20)
    renderer.render(scene)
    rows = [renderer._to_screen(scene, boat.position_m)[1] for boat in scene.boats]
    boxes = renderer.label_boxes
    renderer.close()
    assert max(rows) + 10 < 480 - CAPTION_BAND_PX
    assert all(box[3] <= 480 - CAPTION_BAND_PX for box in boxes)
    assert no_two_overlap(boxes)


def test_finished_boats_at_one_spot_have_four_readable_labels() -> None:
    """The race's last frame: four boats stopped on the finish line together."""
    pytest.importorskip("pygame")
    from bbgym.envs.race.view import RaceRenderer

    scene = race_scene_of([(0.3 * k, 0.0) for k in range(4)], [4, 1, 2, 3], stopped=True)
    renderer = RaceRenderer("rgb_array", 640, 480, 20)
    renderer.render(scene)
    boxes = renderer.label_boxes
    renderer.close()
    assert len(boxes) == 4 and no_two_overlap(boxes)


# -- the sail's scale bar and the mark ------------------------------------------------------------


@pytest.mark.parametrize("mark", [(-200.0, -150.0), (-12.0, -14.0), (200.0, 0.0)])
def test_the_sail_scale_bar_keeps_clear_of_the_mark(mark, monkeypatch) -> None:
    pytest.importorskip("pygame")
    monkeypatch.syspath_prepend(Path(__file__).parent / "sail")  # where test_render_sail is
    from test_render_sail import make_scene

    from bbgym.envs.sail.view import SailRenderer

    renderer = SailRenderer("rgb_array", 640, 480, pixels_per_meter=12.0)
    scene = make_scene(mark_m=mark)
    renderer.render(scene)
    box = renderer.scale_bar_box
    mx, my = renderer._mark_px(scene)
    renderer.close()
    assert box is not None
    # 40 px clear of the buoy or of the tip of its edge arrow
    dx = max(box[0] - mx, mx - box[2], 0.0)
    dy = max(box[1] - my, my - box[3], 0.0)
    assert math.hypot(dx, dy) > 40.0


# -- the wind compass's label -------------------------------------------------------------------


@pytest.mark.parametrize(("width", "lines"), [(126, 2), (300, 1)])
def test_the_wind_compass_label_stays_inside_its_rect(width, lines) -> None:
    """Topple's compass, 126 px wide: "true wind 2.1 m/s" is wider than the room right of the
    disc, so it is drawn on two lines, nothing past the rect's right edge (where the top
    view's inset is drawn); with room, on one line."""
    pg = pytest.importorskip("pygame")
    from bbgym.render.beach import READOUT_COLOR, draw_wind_compass

    pg.font.init()
    font = pg.font.Font(None, 17)
    surface = pg.Surface((400, 60))
    surface.fill(READOUT_COLOR)
    rect = (10, 10, width, 40)
    draw_wind_compass(pg, surface, font, rect, (1.5, -1.5))
    pixels = np.transpose(pg.surfarray.array3d(surface), (1, 0, 2))
    drawn = np.any(pixels != np.array(READOUT_COLOR), axis=2)
    columns = np.flatnonzero(drawn.any(axis=0))
    assert columns.max() < 10 + width
    # the text's rows, right of the disc (38 px across, then a 6 px gap)
    text_rows = np.flatnonzero(drawn[:, 10 + 38 + 6 :].any(axis=1))
    runs = 1 + int(np.count_nonzero(np.diff(text_rows) > 1))
    assert runs == lines
    assert text_rows.min() >= 10 and text_rows.max() < 50


def test_boat_labels_keep_clear_of_the_marks_names() -> None:
    """Boats on the names of the windward mark, the line's and the gate's: their labels
    are laid elsewhere, overlapping neither the names nor each other."""
    pytest.importorskip("pygame")
    from bbgym.envs.race.view import RaceRenderer
    from bbgym.render.labels import boxes_overlap

    positions = [(4.0, 149.0), (10.0, 149.0), (-16.0, 0.0), (-10.0, 0.0), (13.0, -20.0)]
    scene = race_scene_of(positions, [0] * 5, stopped=False)
    renderer = RaceRenderer("rgb_array", 640, 480, 20)
    renderer.render(scene)
    boxes, names = renderer.label_boxes, renderer.course_label_boxes
    renderer.close()
    assert len(boxes) == 5 and len(names) == 3 and no_two_overlap(boxes + names)
    # each name really is where a boat is: the boat's disc meets it
    anchors = [renderer._to_screen(scene, p) for p in positions]
    discs = [disc_box(x, y, 9.0) for x, y in anchors]
    assert sum(any(boxes_overlap(d, n) for n in names) for d in discs) >= 3
