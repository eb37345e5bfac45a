"""Two-panel renderer for the beach-ball throwing task: a side view and a top view.

The renderer only *draws* a :class:`ThrowScene`, a plain snapshot of the latest throw; it never
steps or recomputes physics, so it can be tested and reused on its own.

Conventions (shared with the physics):

* world frame: x east, y north, z up, metres; the thrower stands at the origin;
* ball orientation: unit quaternion (w, x, y, z) rotating the ball's body frame to the world;
  the beach ball's poles (where its six gores meet) are on the body z axis.

Layout: the top-left panel is a SIDE VIEW along the thrower->target bearing (horizontal axis:
distance along that bearing, vertical: height), the top-right column is the text readout, and
the bottom panel is a TOP VIEW (x east to the right, y north up) fitted to the scene, with a
scale bar at its bottom left. During a flight (a frame before the trajectory's last point)
nothing of the throw's outcome shows: the readout gives the time since the launch and the
ball's height, the results (hit or miss, miss distance, flight time, apex) and the landing
only on the landing frame (:func:`readout_text`).

pygame is an optional dependency (bbgym's ``render`` extra). It is imported only when a
:class:`ThrowRenderer` is created, so importing this module never needs it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from bbgym.render.base import (
    Color,
    PygameRenderer,
    Vec2,
    blend,
)
from bbgym.render.beach import (
    BALL_MIN_RADIUS_PX,
    DIM_TEXT_COLOR,
    GROUND_LINE_COLOR,
    LABEL_COLOR,
    PANEL_EDGE_COLOR,
    READOUT_COLOR,
    SAND_COLOR,
    SAND_GRID_COLOR,
    SKY_COLOR,
    SKY_GRID_COLOR,
    SOCK_LENGTH_M,
    TEXT_COLOR,
    Rect,
    ViewMap,
    draw_ball_flight,
    draw_side_thrower,
    draw_top_thrower,
    draw_top_windsock,
    draw_wind_compass,
    view_axes,
)

# --- colours ---------------------------------------------------------------------------------
SAND_GRID_MAJOR_COLOR: Color = (205, 184, 132)
TARGET_COLOR: Color = (226, 28, 142)  # magenta: unlike every ball gore and the sand
TARGET_INNER_COLOR: Color = (252, 252, 252)
BULLSEYE_COLOR: Color = (255, 208, 0)
HIT_COLOR: Color = (46, 204, 84)
MISS_COLOR: Color = (255, 112, 96)
SCREEN_COLOR: Color = (58, 96, 120)  # a blue-grey tarp
SCREEN_EDGE_COLOR: Color = (28, 44, 58)
LANDING_COLOR: Color = (24, 24, 28)
LANDING_OUTLINE_COLOR: Color = (255, 255, 255)


# --- geometry (metres unless noted) ----------------------------------------------------------
SIDE_MIN_S_M = -1.0  # the side view starts just behind the thrower...
SIDE_MIN_RANGE_END_M = 12.0  # ...and reaches at least this far, or 2 m past the target
SIDE_PAST_TARGET_M = 2.0
SIDE_MAX_RANGE_END_M = 40.0  # like TOP_VIEW_LIMIT_M: a farther target gets an edge marker
SIDE_HEIGHT_M = 5.0
SCREEN_MIN_THICKNESS_PX = 6  # a screen square to the bearing projects to a line: keep it visible
TOP_THROWER_BOX_M = (-2.0, 3.0, -2.0, 2.0)  # x0, x1, y0, y1 always shown around the thrower
TOP_CONTENT_MARGIN_M = 0.5
TOP_VIEW_LIMIT_M = 40.0  # a wild throw must not shrink the target to a dot
SOCK_POLE_M: Vec2 = (-1.2, 1.2)  # behind-left of the thrower, away from the usual flight path
GRID_STEP_M = 1.0
GRID_MAJOR_EVERY = 5

# --- screen layout (pixels) ------------------------------------------------------------------
SIDE_PANEL_HEIGHT_FRACTION = 0.42
READOUT_WIDTH_FRACTION = 0.28
READOUT_MIN_WIDTH_PX = 150
PANEL_MARGIN_PX = 6
SIDE_GROUND_BAND_PX = 16  # sand under the side view's ground line, room for distance labels
SMALL_FONT_PX = 15
READOUT_FONT_PX = 21
BIG_FONT_PX = 40
CROSS_PX = 7
TOP_SCALE_BAR_MAX_PX = 120.0
RECORD_DT_S = 0.05  # the envs record the ball's pose every 0.05 s (ThrowScene.sample_dt_s)


@dataclass(frozen=True)
class ThrowScreen:
    """A vertical panel standing on the ground."""

    center_m: Vec2  # ground point at the middle of the panel's bottom edge
    along_m: Vec2  # unit vector along the panel's width (horizontal)
    half_width_m: float
    height_m: float


@dataclass(frozen=True)
class ThrowScene:
    """Everything the renderer needs for one frame; plain numbers, no physics objects."""

    trajectory_m: np.ndarray  # (K, 3) ball centre positions of the latest throw (K may be 0)
    orientations: np.ndarray  # (K, 4) unit quaternions (w, x, y, z), body -> world
    ball_radius_m: float
    target_m: Vec2
    target_radius_m: float
    wind_mps: Vec2  # true wind vector now (where the air moves), horizontal
    windsock_mps: Vec2  # what the windsock shows (noisy reading)
    screen: ThrowScreen | None
    landing_m: Vec2 | None  # first touchdown of the latest throw
    previous_landings_m: tuple[Vec2, ...] = ()  # earlier throws' touchdowns this episode
    hit: bool = False
    throws_left: int = 0
    throws_total: int = 3
    miss_distance_m: float | None = None
    spin_parameter: float = 0.0  # S = r * omega / v at launch
    flight_time_s: float | None = None
    apex_height_m: float | None = None
    frame_index: int | None = None  # draw the ball at trajectory[frame_index]; None = last point
    sample_dt_s: float = RECORD_DT_S  # time between trajectory points (the readout's clock)


@dataclass(frozen=True)
class ReadoutText:
    """What the readout column says (see :func:`readout_text`)."""

    header: str  # throws left
    result: str  # "HIT!", "miss", "ready" or "in flight"
    result_color: Color
    result_size_px: int
    lines: tuple[str, ...]  # miss distance, spin, time, height


def current_index(scene: ThrowScene) -> int | None:
    """Index of the ball's trajectory point in this frame; None without a throw."""
    k = len(scene.trajectory_m)
    if k == 0:
        return None
    if scene.frame_index is None:
        return k - 1
    return min(max(int(scene.frame_index), 0), k - 1)


def in_flight(scene: ThrowScene) -> bool:
    """The frame shows the ball before the trajectory's last point: the throw is still
    going on, so none of its results (landing, hit, miss distance, flight time, apex) are
    known yet in this frame."""
    index = current_index(scene)
    return index is not None and index < len(scene.trajectory_m) - 1


def readout_text(scene: ThrowScene) -> ReadoutText:
    """The readout's text. After a throw (its landing frame, ``frame_index`` None or the
    last point) the throw's results: HIT!/miss, miss distance, spin, flight time (to the
    first touchdown) and apex. During a flight only what is known at that frame: the time
    since the launch (``frame_index * sample_dt_s``), the ball's height now and the launch
    spin; the final values never show before the landing frame."""
    header = f"throws left {scene.throws_left}/{scene.throws_total}"
    spin = f"spin S {scene.spin_parameter:.2f}"
    index = current_index(scene)
    if index is not None and in_flight(scene):
        traj = np.asarray(scene.trajectory_m, dtype=float).reshape(-1, 3)
        height = float(traj[index, 2])
        lines = (
            "miss dist --",
            spin,
            f"time {index * scene.sample_dt_s:.2f} s",
            f"height {_fmt(height if math.isfinite(height) else None, 'm')}",
        )
        return ReadoutText(header, "in flight", DIM_TEXT_COLOR, BIG_FONT_PX - 12, lines)
    if scene.hit:
        result, color, size = "HIT!", HIT_COLOR, BIG_FONT_PX
    elif scene.landing_m is not None:
        result, color, size = "miss", MISS_COLOR, BIG_FONT_PX - 8
    else:
        result, color, size = "ready", DIM_TEXT_COLOR, BIG_FONT_PX - 8
    lines = (
        f"miss dist {_fmt(scene.miss_distance_m, 'm')}",
        spin,
        f"flight {_fmt(scene.flight_time_s, 's')}",
        f"apex {_fmt(scene.apex_height_m, 'm')}",
    )
    return ReadoutText(header, result, color, size, lines)


# --- quaternions -----------------------------------------------------------------------------


# --- layout and projections ------------------------------------------------------------------


def panel_rects(width: int, height: int) -> tuple[Rect, Rect, Rect]:
    """(side view, readout, top view) rectangles for a frame of ``width`` x ``height``."""
    side_h = round(height * SIDE_PANEL_HEIGHT_FRACTION)
    readout_w = min(max(READOUT_MIN_WIDTH_PX, round(width * READOUT_WIDTH_FRACTION)), width // 2)
    side_w = width - readout_w
    return (
        (0, 0, side_w, side_h),
        (side_w, 0, readout_w, side_h),
        (0, side_h, width, height - side_h),
    )


def bearing_unit(target_m: Vec2) -> Vec2:
    """Horizontal unit vector from the thrower towards the target (+x if the target is at 0)."""
    d = math.hypot(target_m[0], target_m[1])
    if d < 1e-9:
        return (1.0, 0.0)
    return (target_m[0] / d, target_m[1] / d)


def side_view_map(scene: ThrowScene, width: int, height: int) -> ViewMap:
    """Side view: a = distance along the bearing, b = height; ground line at the panel bottom.

    Equal metres per pixel on both axes, as large as lets both ranges fit; the range ends at
    SIDE_MAX_RANGE_END_M at most, so a far target does not shrink the throw to a dot.
    """
    rect, _, _ = panel_rects(width, height)
    x, y, w, h = rect
    target_s = math.hypot(*scene.target_m)
    s_end = min(max(SIDE_MIN_RANGE_END_M, target_s + SIDE_PAST_TARGET_M), SIDE_MAX_RANGE_END_M)
    ground_y = y + h - SIDE_GROUND_BAND_PX
    ppm = min(
        (w - 2 * PANEL_MARGIN_PX) / (s_end - SIDE_MIN_S_M),
        (ground_y - y - PANEL_MARGIN_PX) / SIDE_HEIGHT_M,
    )
    origin = (x + PANEL_MARGIN_PX - SIDE_MIN_S_M * ppm, float(ground_y))
    return ViewMap(rect, origin, max(ppm, 1e-6))


def _top_view_bounds(scene: ThrowScene) -> tuple[float, float, float, float]:
    """World box (x0, x1, y0, y1) holding everything the top view should show."""
    x0, x1, y0, y1 = TOP_THROWER_BOX_M
    boxes: list[tuple[float, float, float]] = []  # (x, y, margin)
    tr = scene.target_radius_m + TOP_CONTENT_MARGIN_M
    boxes.append((scene.target_m[0], scene.target_m[1], tr))
    boxes.append((SOCK_POLE_M[0], SOCK_POLE_M[1], SOCK_LENGTH_M))
    if scene.screen is not None:
        for end in _screen_ends(scene.screen):
            boxes.append((end[0], end[1], TOP_CONTENT_MARGIN_M))
    # The whole throw, not only the animated part, so the view does not zoom during a flight.
    for px, py in _finite_xy(scene.trajectory_m):
        boxes.append((px, py, TOP_CONTENT_MARGIN_M))
    landings = [*scene.previous_landings_m]
    if scene.landing_m is not None:
        landings.append(scene.landing_m)
    for lx, ly in landings:
        boxes.append((lx, ly, TOP_CONTENT_MARGIN_M))
    for bx, by, m in boxes:
        x0, x1 = min(x0, bx - m), max(x1, bx + m)
        y0, y1 = min(y0, by - m), max(y1, by + m)
    lim = TOP_VIEW_LIMIT_M
    return (max(x0, -lim), min(x1, lim), max(y0, -lim), min(y1, lim))


def top_view_map(scene: ThrowScene, width: int, height: int) -> ViewMap:
    """Top view: a = x (east), b = y (north), fitted to the scene with equal scale."""
    _, _, rect = panel_rects(width, height)
    x, y, w, h = rect
    x0, x1, y0, y1 = _top_view_bounds(scene)
    ppm = min(
        (w - 2 * PANEL_MARGIN_PX) / max(x1 - x0, 1e-6),
        (h - 2 * PANEL_MARGIN_PX) / max(y1 - y0, 1e-6),
    )
    ppm = max(ppm, 1e-6)
    origin = (x + w / 2 - 0.5 * (x0 + x1) * ppm, y + h / 2 + 0.5 * (y0 + y1) * ppm)
    return ViewMap(rect, origin, ppm)


def _screen_ends(screen: ThrowScreen) -> tuple[Vec2, Vec2]:
    cx, cy = screen.center_m
    ax, ay = screen.along_m
    hw = screen.half_width_m
    return (cx - ax * hw, cy - ay * hw), (cx + ax * hw, cy + ay * hw)


def _finite_xy(trajectory_m: np.ndarray) -> list[Vec2]:
    traj = np.asarray(trajectory_m, dtype=float).reshape(-1, 3)
    ok = np.all(np.isfinite(traj), axis=1)
    return [(float(p[0]), float(p[1])) for p in traj[ok]]


def side_coords(points_m: np.ndarray, bearing: Vec2) -> np.ndarray:
    """(N, 3) world points -> (N, 2) side-view coordinates (distance along bearing, height)."""
    pts = np.asarray(points_m, dtype=float).reshape(-1, 3)
    s = pts[:, 0] * bearing[0] + pts[:, 1] * bearing[1]
    return np.stack([s, pts[:, 2]], axis=1)


# --- the beach ball --------------------------------------------------------------------------


# --- small geometry helpers ------------------------------------------------------------------


# --- drawing helpers shared with other views ------------------------------------------------
# Plain functions on a pygame module ``pg`` and a target ``surface``, so other renderers (e.g.
# the topple view) draw the same ball, thrower, windsock and wind compass without copies.


# --- renderer --------------------------------------------------------------------------------


class ThrowRenderer(PygameRenderer[ThrowScene]):
    """Draws :class:`ThrowScene` frames, either into a window or into an RGB array.

    ``render(scene)`` returns a (height, width, 3) uint8 array in ``rgb_array`` mode and None in
    ``human`` mode; ``close()`` closes the window.
    """

    caption = "bbgym beach-ball throw"

    def __init__(
        self, render_mode: str, width: int = 640, height: int = 480, render_fps: int = 30
    ) -> None:
        super().__init__(render_mode, width, height, render_fps)

    # -- scene bookkeeping ---------------------------------------------------------------------

    @staticmethod
    def _current_index(scene: ThrowScene) -> int | None:
        """Index of the ball's trajectory point in this frame; None without a throw."""
        return current_index(scene)

    def _ball_radius_px(self, scene: ThrowScene, view: ViewMap) -> float:
        return max(scene.ball_radius_m * view.pixels_per_meter, BALL_MIN_RADIUS_PX)

    # -- drawing -------------------------------------------------------------------------------

    def _draw_scene(self, scene: ThrowScene) -> None:
        self._surface.fill(READOUT_COLOR)
        side = side_view_map(scene, self.width, self.height)
        top = top_view_map(scene, self.width, self.height)
        if in_flight(scene):
            # The views keep their fit; the landing and the result are not known yet.
            scene = replace(scene, landing_m=None, hit=False, miss_distance_m=None)
        self._with_clip(side.rect, lambda: self._draw_side_view(scene, side))
        self._with_clip(top.rect, lambda: self._draw_top_view(scene, top))
        _, readout, _ = panel_rects(self.width, self.height)
        self._with_clip(readout, lambda: self._draw_readout(scene, readout))
        # Thin borders between the panels.
        pg = self._pg
        sx, sy, sw, sh = side.rect
        pg.draw.line(
            self._surface, PANEL_EDGE_COLOR, (0, sy + sh - 1), (self.width, sy + sh - 1), 2
        )
        pg.draw.line(self._surface, PANEL_EDGE_COLOR, (sx + sw - 1, 0), (sx + sw - 1, sy + sh), 2)

    # -- side view -----------------------------------------------------------------------------

    def _draw_side_view(self, scene: ThrowScene, view: ViewMap) -> None:
        pg, surf = self._pg, self._surface
        x, y, w, h = view.rect
        ground_y = view.origin_px[1]
        pg.draw.rect(surf, SKY_COLOR, view.rect)
        pg.draw.rect(surf, SAND_COLOR, (x, ground_y, w, y + h - ground_y))
        self._draw_side_grid(view)
        pg.draw.line(surf, GROUND_LINE_COLOR, (x, ground_y), (x + w, ground_y), 2)

        bearing = bearing_unit(scene.target_m)
        self._draw_side_target(scene, view)
        if scene.screen is not None:
            self._draw_side_screen(scene.screen, bearing, view)
        self._draw_side_thrower(view)
        if scene.landing_m is not None:
            s_land = scene.landing_m[0] * bearing[0] + scene.landing_m[1] * bearing[1]
            self._draw_cross(view.to_px(s_land, 0.0), CROSS_PX - 2, self._landing_color(scene))
        self._draw_flight(scene, view, "side", bearing)
        side_r = max(scene.target_radius_m * view.pixels_per_meter, 4.0)  # as drawn
        self._draw_target_marker(scene, view, (math.hypot(*scene.target_m), 0.0), side_r)
        self._draw_text("side view (along the throw)", (x + 8, y + 6), LABEL_COLOR, SMALL_FONT_PX)

    def _draw_side_grid(self, view: ViewMap) -> None:
        """Faint height lines every metre and distance ticks with labels along the ground."""
        pg, surf = self._pg, self._surface
        x, y, w, h = view.rect
        for k in range(1, int(SIDE_HEIGHT_M) + 1):
            py = view.to_px(0.0, float(k))[1]
            pg.draw.line(surf, SKY_GRID_COLOR, (x, py), (x + w, py), 1)
            self._draw_text(f"{k} m", (x + w - 30, py - 12), LABEL_COLOR, SMALL_FONT_PX)
        s_last = int((x + w - view.origin_px[0]) / view.pixels_per_meter)
        for s in range(0, s_last + 1):
            px, py = view.to_px(float(s), 0.0)
            tick = 5 if s % 2 == 0 else 3
            pg.draw.line(surf, GROUND_LINE_COLOR, (px, py), (px, py + tick), 1)
            if s % 2 == 0 and s > 0:
                label = self._get_font(SMALL_FONT_PX).render(f"{s}", True, LABEL_COLOR)
                surf.blit(label, (px - label.get_width() / 2, py + 4))

    def _draw_side_target(self, scene: ThrowScene, view: ViewMap) -> None:
        """The ring seen edge-on: a flat ellipse on the ground at the target distance."""
        pg = self._pg
        d = math.hypot(*scene.target_m)
        r_px = max(scene.target_radius_m * view.pixels_per_meter, 4.0)
        cx, cy = view.to_px(d, 0.0)
        thick = 10.0
        pg.draw.ellipse(self._surface, TARGET_COLOR, (cx - r_px, cy - thick / 2, 2 * r_px, thick))
        inner = 0.55 * r_px
        pg.draw.ellipse(
            self._surface, TARGET_INNER_COLOR, (cx - inner, cy - thick / 4, 2 * inner, thick / 2)
        )
        pg.draw.circle(self._surface, BULLSEYE_COLOR, (cx, cy), 2)

    def _draw_side_screen(self, screen: ThrowScreen, bearing: Vec2, view: ViewMap) -> None:
        """The panel projected onto the bearing: its span of distances, its full height."""
        pg = self._pg
        s_ends = [e[0] * bearing[0] + e[1] * bearing[1] for e in _screen_ends(screen)]
        left_px, top_px = view.to_px(min(s_ends), screen.height_m)
        right_px, ground_px = view.to_px(max(s_ends), 0.0)
        if right_px - left_px < SCREEN_MIN_THICKNESS_PX:
            mid = 0.5 * (left_px + right_px)
            left_px, right_px = mid - SCREEN_MIN_THICKNESS_PX / 2, mid + SCREEN_MIN_THICKNESS_PX / 2
        rect = (left_px, top_px, right_px - left_px, ground_px - top_px)
        pg.draw.rect(self._surface, SCREEN_COLOR, rect)
        pg.draw.rect(self._surface, SCREEN_EDGE_COLOR, rect, 1)

    def _draw_side_thrower(self, view: ViewMap) -> None:
        """Stick figure at distance 0, facing the target, throwing arm up and forward."""
        draw_side_thrower(self._pg, self._surface, view)

    # -- top view ------------------------------------------------------------------------------

    def _draw_top_view(self, scene: ThrowScene, view: ViewMap) -> None:
        pg = self._pg
        x, y, w, h = view.rect
        pg.draw.rect(self._surface, SAND_COLOR, view.rect)
        self._draw_top_grid(view)
        # Bottom left, under everything else (a ball or marker there stays in sight).
        self._draw_scale_bar(view.pixels_per_meter, view.rect, LABEL_COLOR, TOP_SCALE_BAR_MAX_PX)
        self._draw_top_target(scene, view)
        if scene.screen is not None:
            self._draw_top_screen(scene.screen, view)
        self._draw_windsock(scene, view)
        self._draw_top_thrower(scene, view)
        for lx, ly in scene.previous_landings_m:
            faded = blend(LANDING_COLOR, SAND_COLOR, 0.55)
            self._draw_cross(view.to_px(lx, ly), CROSS_PX - 2, faded, outline=False)
        if scene.landing_m is not None:
            # Larger than the ball: at the end of a throw the ball sits on it, arms still show.
            half = max(CROSS_PX, round(self._ball_radius_px(scene, view)) + 6)
            self._draw_cross(view.to_px(*scene.landing_m), half, self._landing_color(scene))
        self._draw_flight(scene, view, "top", bearing_unit(scene.target_m))
        top_r = self._top_target_radius_px(scene, view)
        self._draw_target_marker(scene, view, scene.target_m, top_r)
        self._draw_text("top view (north up)", (x + 8, y + 6), LABEL_COLOR, SMALL_FONT_PX)

    def _draw_top_grid(self, view: ViewMap) -> None:
        """World-fixed metre grid, a darker line every GRID_MAJOR_EVERY metres, for the scale."""
        pg, surf = self._pg, self._surface
        x, y, w, h = view.rect
        ppm = view.pixels_per_meter
        if ppm * GRID_STEP_M < 6:
            return  # too dense to help
        i0 = math.floor((x - view.origin_px[0]) / ppm / GRID_STEP_M)
        i1 = math.ceil((x + w - view.origin_px[0]) / ppm / GRID_STEP_M)
        for i in range(i0, i1 + 1):
            px = view.origin_px[0] + i * GRID_STEP_M * ppm
            color = SAND_GRID_MAJOR_COLOR if i % GRID_MAJOR_EVERY == 0 else SAND_GRID_COLOR
            pg.draw.line(surf, color, (px, y), (px, y + h), 1)
        j0 = math.floor((view.origin_px[1] - (y + h)) / ppm / GRID_STEP_M)
        j1 = math.ceil((view.origin_px[1] - y) / ppm / GRID_STEP_M)
        for j in range(j0, j1 + 1):
            py = view.origin_px[1] - j * GRID_STEP_M * ppm
            color = SAND_GRID_MAJOR_COLOR if j % GRID_MAJOR_EVERY == 0 else SAND_GRID_COLOR
            pg.draw.line(surf, color, (x, py), (x + w, py), 1)

    def _draw_top_target(self, scene: ThrowScene, view: ViewMap) -> None:
        """Rings in magenta and white with a gold bullseye; a green halo after a hit."""
        pg, surf = self._pg, self._surface
        c = view.to_px(*scene.target_m)
        r = self._top_target_radius_px(scene, view)
        if scene.hit:
            pg.draw.circle(surf, HIT_COLOR, c, r + 5, 4)
        self._disc(c, r, TARGET_COLOR)
        self._disc(c, 0.72 * r, TARGET_INNER_COLOR)
        self._disc(c, 0.45 * r, TARGET_COLOR)
        self._disc(c, 0.22 * r, TARGET_INNER_COLOR)
        self._disc(c, max(3.0, 0.12 * r), BULLSEYE_COLOR)

    @staticmethod
    def _top_target_radius_px(scene: ThrowScene, view: ViewMap) -> float:
        return max(scene.target_radius_m * view.pixels_per_meter, 6.0)

    def _draw_target_marker(
        self, scene: ThrowScene, view: ViewMap, at_m: Vec2, radius_px: float
    ) -> None:
        """Edge marker (with the distance) for a target ring wholly outside ``view``; ``at_m``
        is the ring's centre in the view's plane coordinates."""
        self._draw_edge_marker(
            view.to_px(*at_m),
            view.rect,
            TARGET_COLOR,
            math.hypot(*scene.target_m),
            pad=radius_px,
            font_size_px=SMALL_FONT_PX,
            label_color=LABEL_COLOR,
        )

    def _disc(self, c: Vec2, r: float, color: Color) -> None:
        """Filled circle with an antialiased rim (gfxdraw wants whole pixels)."""
        self._pg.draw.aa_disc(self._surface, color, c, r)

    def _draw_top_screen(self, screen: ThrowScreen, view: ViewMap) -> None:
        pg, surf = self._pg, self._surface
        a, b = (view.to_px(*e) for e in _screen_ends(screen))
        thick = max(5, round(0.12 * view.pixels_per_meter))
        pg.draw.line(surf, SCREEN_EDGE_COLOR, a, b, thick + 4)
        pg.draw.line(surf, SCREEN_COLOR, a, b, thick)
        for end in (a, b):  # the posts
            pg.draw.circle(surf, SCREEN_EDGE_COLOR, end, thick / 2 + 2)

    def _draw_top_thrower(self, scene: ThrowScene, view: ViewMap) -> None:
        """Shoulders (orange) and head from above, with the throwing arm towards the target."""
        draw_top_thrower(self._pg, self._surface, view, bearing_unit(scene.target_m))

    def _draw_windsock(self, scene: ThrowScene, view: ViewMap) -> None:
        """Windsock seen from above, pointing where the (read) wind blows."""
        font = self._get_font(SMALL_FONT_PX)
        draw_top_windsock(self._pg, self._surface, font, view, SOCK_POLE_M, scene.windsock_mps)

    # -- shared between the views --------------------------------------------------------------

    def _draw_flight(self, scene: ThrowScene, view: ViewMap, which: str, bearing: Vec2) -> None:
        """Trace up to the current frame, striped ghost balls along it, then the ball."""
        current = self._current_index(scene)
        if current is None:
            return
        traj = np.asarray(scene.trajectory_m, dtype=float).reshape(-1, 3)
        plane = traj[:, :2] if which == "top" else side_coords(traj, bearing)
        right, up = view_axes(which, bearing)
        radius = self._ball_radius_px(scene, view)
        draw_ball_flight(
            self._pg, self._surface, view, plane, scene.orientations, current, right, up, radius
        )

    def _landing_color(self, scene: ThrowScene) -> Color:
        return HIT_COLOR if scene.hit else LANDING_COLOR

    def _draw_cross(self, c: Vec2, half_px: int, color: Color, outline: bool = True) -> None:
        """An X marking a touchdown; a white outline keeps it readable on the target rings."""
        pg = self._pg
        a1, b1 = (c[0] - half_px, c[1] - half_px), (c[0] + half_px, c[1] + half_px)
        a2, b2 = (c[0] - half_px, c[1] + half_px), (c[0] + half_px, c[1] - half_px)
        if outline:
            pg.draw.line(self._surface, LANDING_OUTLINE_COLOR, a1, b1, 5)
            pg.draw.line(self._surface, LANDING_OUTLINE_COLOR, a2, b2, 5)
        pg.draw.line(self._surface, color, a1, b1, 3 if outline else 2)
        pg.draw.line(self._surface, color, a2, b2, 3 if outline else 2)

    # -- readout -------------------------------------------------------------------------------

    def _draw_readout(self, scene: ThrowScene, rect: Rect) -> None:
        """Throws left, the result (a big HIT! / miss), the throw's numbers and the wind: see
        :func:`readout_text` (no result before the landing frame)."""
        x, y, w, h = rect
        self._pg.draw.rect(self._surface, READOUT_COLOR, rect)
        left = x + 10
        line_y = y + 8
        readout = readout_text(scene)
        _, th = self._draw_text(readout.header, (left, line_y), TEXT_COLOR, READOUT_FONT_PX)
        line_y += th + 2
        _, th = self._draw_text(
            readout.result, (left, line_y), readout.result_color, readout.result_size_px
        )
        # At least a "miss"'s height: the lines below do not jump during a flight.
        line_y += max(th, self._get_font(BIG_FONT_PX - 8).get_height()) + 2
        for line in readout.lines:
            _, th = self._draw_text(line, (left, line_y), TEXT_COLOR, READOUT_FONT_PX)
            line_y += th + 1
        self._draw_wind_arrow(scene, (x + 10, line_y + 4, w - 20, y + h - line_y - 8))

    def _draw_wind_arrow(self, scene: ThrowScene, rect: Rect) -> None:
        """True wind: an arrow (north up) pointing where the air moves, and its speed."""
        font = self._get_font(SMALL_FONT_PX + 2)
        draw_wind_compass(self._pg, self._surface, font, rect, scene.wind_mps)


def _fmt(value: float | None, unit: str) -> str:
    return "--" if value is None else f"{value:.2f} {unit}"
