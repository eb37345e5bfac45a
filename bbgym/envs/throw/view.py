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

pygame is an optional dependency (``pip install "bbgym[render]"``). It is imported only when a
:class:`ThrowRenderer` is created, so importing this module never needs it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from bbgym.render.base import (
    Color,
    PygameRenderer,
    Vec2,
    blend,
    draw_edge_marker,
    is_finite_px,
)

Rect = tuple[int, int, int, int]  # x, y, width, height in pixels

# --- colours ---------------------------------------------------------------------------------
# Kept far apart from each other so elements stay recognisable (and testable by colour).
SKY_COLOR: Color = (178, 216, 242)
SKY_GRID_COLOR: Color = (158, 198, 228)
SAND_COLOR: Color = (236, 221, 180)
SAND_GRID_COLOR: Color = (222, 203, 156)
SAND_GRID_MAJOR_COLOR: Color = (205, 184, 132)
GROUND_LINE_COLOR: Color = (150, 122, 76)
PANEL_EDGE_COLOR: Color = (40, 44, 56)
READOUT_COLOR: Color = (22, 42, 68)
TEXT_COLOR: Color = (245, 245, 245)
DIM_TEXT_COLOR: Color = (160, 172, 190)
LABEL_COLOR: Color = (70, 80, 96)  # panel titles and axis labels, on sky and sand
TARGET_COLOR: Color = (226, 28, 142)  # magenta: unlike every ball gore and the sand
TARGET_INNER_COLOR: Color = (252, 252, 252)
BULLSEYE_COLOR: Color = (255, 208, 0)
HIT_COLOR: Color = (46, 204, 84)
MISS_COLOR: Color = (255, 112, 96)
SCREEN_COLOR: Color = (58, 96, 120)  # a blue-grey tarp
SCREEN_EDGE_COLOR: Color = (28, 44, 58)
THROWER_COLOR: Color = (255, 140, 0)  # orange shirt
SKIN_COLOR: Color = (236, 196, 158)
LEG_COLOR: Color = (52, 58, 84)
TRACE_COLOR: Color = (30, 58, 138)
LANDING_COLOR: Color = (24, 24, 28)
LANDING_OUTLINE_COLOR: Color = (255, 255, 255)
SOCK_COLOR: Color = (228, 52, 36)
SOCK_STRIPE_COLOR: Color = (250, 250, 250)
POLE_COLOR: Color = (90, 90, 96)
WIND_ARROW_COLOR: Color = (250, 250, 250)

# The classic beach ball: six gores in alternating bright colours, white caps at the poles.
GORE_COLORS: tuple[Color, ...] = (
    (222, 38, 38),  # red
    (255, 214, 0),  # yellow
    (24, 92, 220),  # blue
    (250, 250, 250),  # white
    (30, 170, 72),  # green
    (255, 128, 0),  # orange
)
CAP_COLOR: Color = (250, 250, 250)
CAP_COS = 0.94  # |body z| above this (within ~20 deg of a pole) is the cap
BALL_LIGHT_VIEW = (-0.45, 0.55, 0.70)  # light direction in view coords (right, up, to viewer)

# --- geometry (metres unless noted) ----------------------------------------------------------
SIDE_MIN_S_M = -1.0  # the side view starts just behind the thrower...
SIDE_MIN_RANGE_END_M = 12.0  # ...and reaches at least this far, or 2 m past the target
SIDE_PAST_TARGET_M = 2.0
SIDE_MAX_RANGE_END_M = 40.0  # like TOP_VIEW_LIMIT_M: a farther target gets an edge marker
SIDE_HEIGHT_M = 5.0
THROWER_HEIGHT_M = 1.75
SCREEN_MIN_THICKNESS_PX = 6  # a screen square to the bearing projects to a line: keep it visible
TOP_THROWER_BOX_M = (-2.0, 3.0, -2.0, 2.0)  # x0, x1, y0, y1 always shown around the thrower
TOP_CONTENT_MARGIN_M = 0.5
TOP_VIEW_LIMIT_M = 40.0  # a wild throw must not shrink the target to a dot
SOCK_POLE_M: Vec2 = (-1.2, 1.2)  # behind-left of the thrower, away from the usual flight path
SOCK_LENGTH_M = 1.3
SOCK_FULL_MPS = 6.0  # a windsock stands out fully at about this speed and droops below it
GRID_STEP_M = 1.0
GRID_MAJOR_EVERY = 5

# --- screen layout (pixels) ------------------------------------------------------------------
SIDE_PANEL_HEIGHT_FRACTION = 0.42
READOUT_WIDTH_FRACTION = 0.28
READOUT_MIN_WIDTH_PX = 150
PANEL_MARGIN_PX = 6
SIDE_GROUND_BAND_PX = 16  # sand under the side view's ground line, room for distance labels
BALL_MIN_RADIUS_PX = 9.0
GHOST_SCALE = 0.7
GHOST_MIN_RADIUS_PX = 6.0
GHOST_OPACITY = 0.85
GHOST_EVERY = 5  # every n-th trajectory point gets a ghost ball
BALL_SUPERSAMPLE = 3  # 3x3 samples per pixel: smooth rim and gore edges...
# ...fewer for a huge ball: at most this many samples per image (a 2 m ball, the largest the
# physics takes, still gets 3x3 in every view of the default frame size)
BALL_SAMPLE_BUDGET = 1_000_000
BALL_MARKER_COLOR: Color = GORE_COLORS[0]  # the off-screen ball's edge marker: its red gore
SMALL_FONT_PX = 15
READOUT_FONT_PX = 21
BIG_FONT_PX = 40
CROSS_PX = 7
WIND_ARROW_MAX_PX = 30.0
WIND_ARROW_PX_PER_MPS = 5.0
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


def quat_normalize(q: Sequence[float] | np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z); a zero or non-finite one counts as no rotation."""
    arr = np.asarray(q, dtype=float).reshape(4)
    norm = float(np.linalg.norm(arr))
    if not math.isfinite(norm) or norm < 1e-12:
        return np.array([1.0, 0.0, 0.0, 0.0])
    return arr / norm


def quat_from_axis_angle(axis: Sequence[float], angle_rad: float) -> np.ndarray:
    """Quaternion (w, x, y, z) rotating by ``angle_rad`` counterclockwise about ``axis``."""
    a = np.asarray(axis, dtype=float).reshape(3)
    a = a / np.linalg.norm(a)
    half = 0.5 * angle_rad
    return np.array([math.cos(half), *(math.sin(half) * a)])


def quat_to_matrix(q: Sequence[float] | np.ndarray) -> np.ndarray:
    """3x3 rotation matrix of a quaternion (w, x, y, z): ``world = R @ body``."""
    w, x, y, z = quat_normalize(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quat_rotate(q: Sequence[float] | np.ndarray, v: Sequence[float] | np.ndarray) -> np.ndarray:
    """Rotate vector(s) ``v`` (shape (3,) or (N, 3)) by the quaternion ``q`` = (w, x, y, z)."""
    return np.asarray(v, dtype=float) @ quat_to_matrix(q).T


# --- layout and projections ------------------------------------------------------------------


@dataclass(frozen=True)
class ViewMap:
    """Maps a panel's plane coordinates (a to the right, b up, metres) to pixels."""

    rect: Rect
    origin_px: Vec2  # pixel of (a, b) = (0, 0)
    pixels_per_meter: float

    def to_px(self, a: float, b: float) -> Vec2:
        """Pixel of the plane point (a, b); pixel y grows downwards."""
        return (
            self.origin_px[0] + a * self.pixels_per_meter,
            self.origin_px[1] - b * self.pixels_per_meter,
        )


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


def view_axes(view: str, bearing: Vec2) -> tuple[np.ndarray, np.ndarray]:
    """World unit vectors of a view's screen right and screen up.

    The viewer looks along -(right x up): the top view looks down (-z); the side view looks
    along the horizontal normal of the bearing, so the bearing runs left to right.
    """
    if view == "top":
        return np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    return np.array([bearing[0], bearing[1], 0.0]), np.array([0.0, 0.0, 1.0])


# --- the beach ball --------------------------------------------------------------------------


def beach_ball_image(
    rotation: np.ndarray,
    right: np.ndarray,
    up: np.ndarray,
    center_px: Vec2,
    radius_px: float,
    samples: int = BALL_SUPERSAMPLE,
    window: tuple[int, int, int, int] | None = None,
) -> tuple[int, int, np.ndarray, np.ndarray]:
    """Shaded beach ball as pixels: (x0, y0, rgb (h, w, 3) uint8, coverage (h, w) in [0, 1]).

    Every sample on the visible disc is lifted onto the sphere's near hemisphere, taken back to
    the ball's body frame with ``rotation`` (body -> world) and coloured by its longitude about
    the body z axis (one gore per 60 deg) or as a polar cap; so the stripes turn with the ball.
    ``(x0, y0)`` is the top-left pixel of the image; arrays are indexed [row, column]. The image
    is the ball's square (h = w = 2 ceil(r) + 3), cut to ``window`` (x, y, width, height) if
    given; an image of more than BALL_SAMPLE_BUDGET samples gets fewer samples per pixel.
    """
    # Rounding kills the ~1e-16 residue of e.g. a full turn, so equal rotations give equal
    # pixels even where a gore edge crosses a sample exactly; "+ 0.0" turns -0.0 into 0.0.
    rot = np.round(np.asarray(rotation, dtype=float), 12) + 0.0
    toward = np.cross(right, up)
    half = int(math.ceil(radius_px)) + 1
    x0 = int(math.floor(center_px[0])) - half
    y0 = int(math.floor(center_px[1])) - half
    nx = ny = 2 * half + 1
    if window is not None:
        # Each pixel's colour depends on its own position only: cropping changes none of them,
        # and a ball far bigger than the view costs no more than the view.
        wx, wy, ww, wh = (int(v) for v in window)
        x1, y1 = min(x0 + nx, wx + ww), min(y0 + ny, wy + wh)
        x0, y0 = max(x0, wx), max(y0, wy)
        nx, ny = max(x1 - x0, 0), max(y1 - y0, 0)
    if nx == 0 or ny == 0:
        return x0, y0, np.zeros((ny, nx, 3), dtype=np.uint8), np.zeros((ny, nx))
    samples = max(1, min(samples, math.isqrt(BALL_SAMPLE_BUDGET // (nx * ny))))
    if window is not None and radius_px > max(window[2], window[3]):
        samples = 1  # a ball larger than the whole view shows no rim to smooth
    sub = (np.arange(samples) + 0.5) / samples
    # Sample coordinates in units of the radius; v points up on screen.
    cols = (x0 + np.arange(nx)[:, None] + sub[None, :]).reshape(-1) - center_px[0]
    rows = (y0 + np.arange(ny)[:, None] + sub[None, :]).reshape(-1) - center_px[1]
    u = (cols / radius_px)[None, :]
    v = (-rows / radius_px)[:, None]
    u, v = np.broadcast_arrays(u, v)
    rr = u * u + v * v
    inside = rr <= 1.0
    w = np.sqrt(np.clip(1.0 - rr, 0.0, 1.0))
    world = u[..., None] * right + v[..., None] * up + w[..., None] * toward
    body = world @ rot  # rows are world^T R = (R^T world)^T
    lon = np.mod(np.arctan2(body[..., 1], body[..., 0]), 2 * math.pi)
    gore = np.floor(lon / (2 * math.pi / len(GORE_COLORS))).astype(int) % len(GORE_COLORS)
    palette = np.array(GORE_COLORS, dtype=float)
    color = palette[gore]
    color[np.abs(body[..., 2]) > CAP_COS] = CAP_COLOR
    # Lambert shading, a specular glint and a darker rim make it read as a sphere.
    light = np.array(BALL_LIGHT_VIEW) / np.linalg.norm(BALL_LIGHT_VIEW)
    n_dot_l = np.clip(u * light[0] + v * light[1] + w * light[2], 0.0, 1.0)
    halfway = light + np.array([0.0, 0.0, 1.0])
    halfway /= np.linalg.norm(halfway)
    glint = np.clip(u * halfway[0] + v * halfway[1] + w * halfway[2], 0.0, 1.0) ** 24 * 0.5
    shade = (0.55 + 0.45 * n_dot_l) * (0.6 + 0.4 * np.clip(w / 0.35, 0.0, 1.0))
    color = color * shade[..., None]
    color = color + (255.0 - color) * glint[..., None]
    # Average the samples of each pixel: (h*s, w*s) -> (h, s, w, s).
    weight = inside.astype(float).reshape(ny, samples, nx, samples)
    color = color.reshape(ny, samples, nx, samples, 3)
    covered = weight.sum(axis=(1, 3))
    rgb = (color * weight[..., None]).sum(axis=(1, 3)) / np.maximum(covered, 1.0)[..., None]
    coverage = covered / (samples * samples)
    return x0, y0, np.clip(np.rint(rgb), 0, 255).astype(np.uint8), coverage


# --- small geometry helpers ------------------------------------------------------------------


def windsock_fill(speed_mps: float) -> float:
    """How far the sock stands out, 0 (hanging down) to 1 (horizontal), seen from above."""
    return min(max(speed_mps / SOCK_FULL_MPS, 0.0), 1.0)


def ghost_indices(last: int) -> list[int]:
    """Trajectory indices that get a ghost ball: every GHOST_EVERY-th before the current one.

    Index 0 is left out: at launch the ball is in the thrower's hand and would hide them.
    """
    return list(range(GHOST_EVERY, last, GHOST_EVERY))


# --- drawing helpers shared with other views ------------------------------------------------
# Plain functions on a pygame module ``pg`` and a target ``surface``, so other renderers (e.g.
# the topple view) draw the same ball, thrower, windsock and wind compass without copies.


def rotation_at(orientations: np.ndarray, index: int) -> np.ndarray:
    """Rotation matrix of ``orientations[index]``; the identity where none is given."""
    if index < len(orientations):
        return quat_to_matrix(orientations[index])
    return np.eye(3)  # no orientation given: draw the ball unrotated


def blit_beach_ball(
    pg: Any,
    surface: Any,
    rotation: np.ndarray,
    right: np.ndarray,
    up: np.ndarray,
    center_px: Vec2,
    radius_px: float,
    opacity: float = 1.0,
) -> None:
    """Draw the shaded, striped beach ball (see :func:`beach_ball_image`) onto ``surface``.

    Only the part inside the surface's clip is made, so a far or huge ball costs little.
    """
    if not (is_finite_px(center_px) and math.isfinite(radius_px) and radius_px > 0.0):
        return
    clip = surface.get_clip()
    window = (clip[0], clip[1], clip[2], clip[3])
    x0, y0, rgb, coverage = beach_ball_image(
        rotation, right, up, center_px, radius_px, window=window
    )
    if rgb.size == 0:
        return
    img = pg.Surface((rgb.shape[1], rgb.shape[0]), pg.SRCALPHA)
    # surfarray views are indexed (x, y): transpose from (row, column).
    color_view = pg.surfarray.pixels3d(img)
    color_view[...] = np.transpose(rgb, (1, 0, 2))
    del color_view  # unlock the surface
    alpha_view = pg.surfarray.pixels_alpha(img)
    alpha_view[...] = np.rint(np.transpose(coverage) * 255.0 * opacity).astype(np.uint8)
    del alpha_view
    surface.blit(img, (x0, y0))


def draw_ball_flight(
    pg: Any,
    surface: Any,
    view: ViewMap,
    plane_m: np.ndarray,
    orientations: np.ndarray,
    current: int,
    right: np.ndarray,
    up: np.ndarray,
    radius_px: float,
    ghost_min_radius_px: float = GHOST_MIN_RADIUS_PX,
) -> None:
    """Trace up to ``current``, striped ghost balls along it, then the ball at ``current``.

    ``plane_m`` holds the flight's (a, b) view-plane coordinates (N, 2); ``right``/``up`` are
    the view's world axes (see :func:`view_axes`), used to turn the stripes with the ball. A ball
    out of the view gets an edge marker in BALL_MARKER_COLOR pointing at it.
    """
    # Far points need no clamping: pg.draw is SafeDraw, blit_beach_ball draws only what shows.
    pts = [view.to_px(float(a), float(b)) for a, b in plane_m[: current + 1]]
    if len(pts) >= 2:
        pg.draw.lines(surface, TRACE_COLOR, False, pts, 2)
    ghost_r = max(GHOST_SCALE * radius_px, ghost_min_radius_px)
    last_ghost: Vec2 | None = None
    for i in ghost_indices(current):
        p = pts[i]
        # Skip ghosts that would pile up (slow parts of the flight) or hide the ball.
        if last_ghost is not None and math.dist(p, last_ghost) < 1.5 * ghost_r:
            continue
        if math.dist(p, pts[current]) < radius_px + ghost_r:
            continue
        rot = rotation_at(orientations, i)
        blit_beach_ball(pg, surface, rot, right, up, p, ghost_r, GHOST_OPACITY)
        last_ghost = p
    ball = pts[current]
    blit_beach_ball(pg, surface, rotation_at(orientations, current), right, up, ball, radius_px)
    draw_edge_marker(pg, surface, ball, view.rect, BALL_MARKER_COLOR, pad=radius_px)


def draw_side_thrower(pg: Any, surface: Any, view: ViewMap) -> None:
    """Stick figure at distance 0 in a side view, facing +a, throwing arm up and forward."""
    surf = surface
    ppm = view.pixels_per_meter

    def p(s: float, z: float) -> Vec2:
        return view.to_px(s, z)

    limb = max(2, round(0.07 * ppm))
    hip, shoulder = 0.92, 1.42
    pg.draw.line(surf, LEG_COLOR, p(0.0, hip), p(-0.18, 0.0), limb)
    pg.draw.line(surf, LEG_COLOR, p(0.0, hip), p(0.2, 0.0), limb)
    # Shirt: a trapezoid from the hips to the shoulders.
    shirt = [p(-0.14, hip), p(0.14, hip), p(0.16, shoulder), p(-0.16, shoulder)]
    pg.draw.polygon(surf, THROWER_COLOR, shirt)
    pg.draw.line(surf, THROWER_COLOR, p(0.0, shoulder), p(0.3, 1.72), limb)  # sleeve
    pg.draw.line(surf, SKIN_COLOR, p(0.3, 1.72), p(0.45, 1.95), limb)  # throwing forearm
    pg.draw.line(surf, THROWER_COLOR, p(0.0, shoulder), p(-0.22, 1.15), limb)
    head_r = max(3, round(0.13 * ppm))
    pg.draw.circle(surf, SKIN_COLOR, p(0.02, THROWER_HEIGHT_M - 0.13), head_r)


def draw_top_thrower(pg: Any, surface: Any, view: ViewMap, bearing: Vec2) -> None:
    """Shoulders (orange) and head from above, the throwing arm towards ``bearing``."""
    ppm = view.pixels_per_meter
    bx, by = bearing
    c = view.to_px(0.0, 0.0)
    # The throwing (right) arm: forward along the bearing, offset to the right of it.
    shoulder = view.to_px(0.2 * by, -0.2 * bx)
    hand = view.to_px(0.2 * by + 0.45 * bx, -0.2 * bx + 0.45 * by)
    pg.draw.line(surface, SKIN_COLOR, shoulder, hand, max(2, round(0.08 * ppm)))
    body_r = max(6.0, 0.24 * ppm)
    pg.draw.circle(surface, THROWER_COLOR, c, body_r)
    pg.draw.circle(surface, SKIN_COLOR, c, max(3.0, 0.11 * ppm))


def draw_top_windsock(
    pg: Any,
    surface: Any,
    label_font: Any,
    view: ViewMap,
    pole_m: Vec2,
    windsock_mps: Vec2,
    label_min_y_px: float = 20.0,
) -> None:
    """Windsock seen from above at ``pole_m``, pointing where the (read) wind blows.

    A sock droops in light air, so from above it looks shorter: its length shows the speed.
    The label ("sock 2.3 m/s") stays inside ``view.rect``, at least ``label_min_y_px`` below
    its top edge (room for a panel title).
    """
    surf = surface
    pole = view.to_px(*pole_m)
    wx, wy = windsock_mps
    speed = math.hypot(wx, wy)
    fill = windsock_fill(speed)
    length_px = SOCK_LENGTH_M * view.pixels_per_meter * (0.2 + 0.8 * fill)
    mouth_half = max(4.0, 0.16 * view.pixels_per_meter)
    if speed > 1e-6:
        ux, uy = wx / speed, -wy / speed  # screen y points down
        nx, ny = -uy, ux
        bands = 4
        for k in range(bands):
            t0, t1 = k / bands, (k + 1) / bands
            # The sock tapers towards its tail, more so when it hangs limp.
            h0 = mouth_half * (1.0 - 0.45 * t0)
            h1 = mouth_half * (1.0 - 0.45 * t1)
            a = (pole[0] + ux * length_px * t0, pole[1] + uy * length_px * t0)
            b = (pole[0] + ux * length_px * t1, pole[1] + uy * length_px * t1)
            quad = [
                (a[0] + nx * h0, a[1] + ny * h0),
                (b[0] + nx * h1, b[1] + ny * h1),
                (b[0] - nx * h1, b[1] - ny * h1),
                (a[0] - nx * h0, a[1] - ny * h0),
            ]
            pg.draw.polygon(surf, SOCK_COLOR if k % 2 == 0 else SOCK_STRIPE_COLOR, quad)
            pg.draw.polygon(surf, POLE_COLOR, quad, 1)
        label_dir = (-ux, -uy)  # the label goes on the side the sock does not cover
    else:
        label_dir = (0.0, 1.0)
    pg.draw.circle(surf, POLE_COLOR, pole, 3)
    label = label_font.render(f"sock {speed:.1f} m/s", True, LABEL_COLOR)
    lx = pole[0] + label_dir[0] * 14 - label.get_width() / 2
    ly = pole[1] + label_dir[1] * 14 - label.get_height() / 2
    x, y, w, h = view.rect
    lx = min(max(lx, x + 2), x + w - label.get_width() - 2)
    ly = min(max(ly, y + label_min_y_px), y + h - label.get_height() - 2)
    surf.blit(label, (lx, ly))


def draw_wind_compass(
    pg: Any,
    surface: Any,
    label_font: Any,
    rect: Rect,
    wind_mps: Vec2,
    background: Color = READOUT_COLOR,
) -> None:
    """True wind in ``rect``: a disc with an arrow (north up) where the air moves, and its speed."""
    x, y, w, h = rect
    radius = max(min(WIND_ARROW_MAX_PX / 2 + 4, h / 2), 6.0)
    cx, cy = x + radius, y + h / 2
    pg.draw.circle(surface, blend(background, TEXT_COLOR, 0.15), (cx, cy), radius)
    wx, wy = wind_mps
    speed = math.hypot(wx, wy)
    if speed > 1e-6:
        length = min(max(speed * WIND_ARROW_PX_PER_MPS, 10.0), 2 * radius - 6)
        ux, uy = wx / speed, -wy / speed  # screen y points down
        tail = (cx - ux * length / 2, cy - uy * length / 2)
        tip = (cx + ux * length / 2, cy + uy * length / 2)
        pg.draw.line(surface, WIND_ARROW_COLOR, tail, tip, 2)
        base = (tip[0] - ux * 7, tip[1] - uy * 7)
        head = [
            tip,
            (base[0] - uy * 4, base[1] + ux * 4),
            (base[0] + uy * 4, base[1] - ux * 4),
        ]
        pg.draw.polygon(surface, WIND_ARROW_COLOR, head)
    text = label_font.render(f"wind {speed:.1f} m/s", True, TEXT_COLOR)
    surface.blit(text, (cx + radius + 6, cy - text.get_height() / 2))


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
