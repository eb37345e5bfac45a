"""The beach scene's drawing that the ball envs share: the palette, the beach ball (a
shaded sphere of six gores, turned by its orientation quaternion), its flight with ghosts
and trace, the thrower, the windsock and the wind compass, and the map from metres to a
panel's pixels.

Conventions: world frame x east, y north, z up, metres; a ball's orientation is a unit
quaternion (w, x, y, z) rotating its body frame to the world, its poles (where the gores
meet) on the body z axis. Each env's view (``bbgym.envs.throw.view``,
``bbgym.envs.topple.view``) composes these into its panels. pygame is passed in by the
renderer, never imported here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from bbgym.render.base import (
    Color,
    Vec2,
    blend,
    draw_edge_marker,
    is_finite_px,
)

Rect = tuple[int, int, int, int]  # x, y, width, height in pixels


# Kept far apart from each other so elements stay recognisable (and testable by colour).
SKY_COLOR: Color = (178, 216, 242)
SKY_GRID_COLOR: Color = (158, 198, 228)
SAND_COLOR: Color = (236, 221, 180)
SAND_GRID_COLOR: Color = (222, 203, 156)
GROUND_LINE_COLOR: Color = (150, 122, 76)
PANEL_EDGE_COLOR: Color = (40, 44, 56)
READOUT_COLOR: Color = (22, 42, 68)
TEXT_COLOR: Color = (245, 245, 245)
DIM_TEXT_COLOR: Color = (160, 172, 190)
LABEL_COLOR: Color = (70, 80, 96)  # panel titles and axis labels, on sky and sand
THROWER_COLOR: Color = (255, 140, 0)  # orange shirt
SKIN_COLOR: Color = (236, 196, 158)
LEG_COLOR: Color = (52, 58, 84)
TRACE_COLOR: Color = (30, 58, 138)
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


THROWER_HEIGHT_M = 1.75


SOCK_LENGTH_M = 1.3


SOCK_FULL_MPS = 6.0  # a windsock stands out fully at about this speed and droops below it


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


WIND_ARROW_MAX_PX = 30.0


WIND_ARROW_PX_PER_MPS = 5.0


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


def view_axes(view: str, bearing: Vec2) -> tuple[np.ndarray, np.ndarray]:
    """World unit vectors of a view's screen right and screen up.

    The viewer looks along -(right x up): the top view looks down (-z); the side view looks
    along the horizontal normal of the bearing, so the bearing runs left to right.
    """
    if view == "top":
        return np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
    return np.array([bearing[0], bearing[1], 0.0]), np.array([0.0, 0.0, 1.0])


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


def windsock_fill(speed_mps: float) -> float:
    """How far the sock stands out, 0 (hanging down) to 1 (horizontal), seen from above."""
    return min(max(speed_mps / SOCK_FULL_MPS, 0.0), 1.0)


def ghost_indices(last: int) -> list[int]:
    """Trajectory indices that get a ghost ball: every GHOST_EVERY-th before the current one.

    Index 0 is left out: at launch the ball is in the thrower's hand and would hide them.
    """
    return list(range(GHOST_EVERY, last, GHOST_EVERY))


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
) -> tuple[Rect, Rect]:
    """Windsock seen from above at ``pole_m``, pointing where the (read) wind blows.

    A sock droops in light air, so from above it looks shorter: its length shows the speed.
    The label ("sock reads 2.3 m/s") stands clear of the sock, below it or above it, inside
    ``view.rect`` and at least ``label_min_y_px`` below its top edge (room for a panel
    title). Returns the label's and the sock's (pole included) rectangles in pixels.
    """
    surf = surface
    pole = view.to_px(*pole_m)
    wx, wy = windsock_mps
    speed = math.hypot(wx, wy)
    fill = windsock_fill(speed)
    length_px = SOCK_LENGTH_M * view.pixels_per_meter * (0.2 + 0.8 * fill)
    mouth_half = max(4.0, 0.16 * view.pixels_per_meter)
    corners = [(pole[0] - 3.0, pole[1] - 3.0), (pole[0] + 3.0, pole[1] + 3.0)]  # the pole
    uy = 0.0
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
            corners += quad
    pg.draw.circle(surf, POLE_COLOR, pole, 3)
    left, top = min(c[0] for c in corners), min(c[1] for c in corners)
    right, bottom = max(c[0] for c in corners), max(c[1] for c in corners)
    sock = (int(left), int(top), math.ceil(right - left) + 1, math.ceil(bottom - top) + 1)

    # the sock's reading (the wind now, with reading noise), told apart from the compass's
    label = label_font.render(f"sock reads {speed:.1f} m/s", True, LABEL_COLOR)
    lw, lh = label.get_width(), label.get_height()
    x, y, w, h = view.rect
    lx = min(max(pole[0] - lw / 2, x + 2), x + w - lw - 2)
    below, above = bottom + 3, top - 3 - lh  # just clear of the sock's box
    fits_below = below + lh <= y + h - 2
    fits_above = above >= y + label_min_y_px
    # Below the sock unless it points down (then above), or where there is no room.
    ly = below if (uy <= 0.0 and fits_below) or not fits_above else above
    ly = min(max(ly, y + label_min_y_px), y + h - lh - 2)
    surf.blit(label, (lx, ly))
    return (int(lx), int(ly), lw, lh), sock


def draw_wind_compass(
    pg: Any,
    surface: Any,
    label_font: Any,
    rect: Rect,
    wind_mps: Vec2,
    background: Color = READOUT_COLOR,
) -> None:
    """True wind in ``rect``: a disc with an arrow (north up) where the air moves, and its
    speed ("true wind 1.9 m/s": the wind now, gusts included; the windsock reads it with
    noise) right of it, on two lines ("true wind" over "1.9 m/s") where one line would
    run past the rect's right edge."""
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
    left = cx + radius + 6
    line = f"true wind {speed:.1f} m/s"
    if left + label_font.size(line)[0] <= x + w:
        lines = [line]
    else:
        lines = ["true wind", f"{speed:.1f} m/s"]
    step = label_font.get_linesize()
    top = cy - step * len(lines) / 2
    for k, words in enumerate(lines):
        text = label_font.render(words, True, TEXT_COLOR)
        surface.blit(text, (left, top + k * step + (step - text.get_height()) / 2))
