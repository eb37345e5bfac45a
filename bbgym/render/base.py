"""What every bbgym pygame renderer shares: lazy import, render modes, surfaces, text.

A renderer subclasses :class:`PygameRenderer` and implements ``_draw_scene(scene)``, drawing onto
``self._surface``. The base class owns everything around that: checking ``render_mode``, making
the off-screen surface (and, in human mode, the window and its clock), handing the frame back as
an RGB array or showing it, fonts, and ``close()``.

pygame is an optional dependency (``pip install "bbgym[render]"``). It is imported only when a
renderer is created, so importing this module (or a view module built on it) never needs it.

Far-away and extreme objects. pygame's drawing calls take C ints (``pygame.gfxdraw`` even 16-bit
ones) and raise ``OverflowError`` past them; a huge circle or dashed ring can also take forever.
So a renderer's ``self._pg`` is pygame with its ``draw`` module replaced by :class:`SafeDraw`:
the same calls, which hand pygame exactly what they were given whenever every coordinate lies
within :func:`safe_box` (a normal scene's frame is unchanged) and otherwise first clip the shape
to that box, keeping the visible part exact, or leave out what cannot be seen. A thing outside
its view gets an arrow at the view's edge pointing at it (:func:`draw_edge_marker`).

Scale and captions. Every view that maps the world draws a scale bar (:func:`scale_bar` picks
a round number of metres from the view's pixels per metre, so it is right at any zoom). A
recording (``bbgym record``) writes a caption over the bottom CAPTION_BAND_PX of each frame
(:func:`draw_caption`); the views keep their readouts and scale bars above that band.
"""

from __future__ import annotations

import importlib
import math
import os
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

import numpy as np
from gymnasium.error import DependencyNotInstalled

Vec2 = tuple[float, float]
Color = tuple[int, int, int]
Box = tuple[float, float, float, float]  # x0, y0, x1, y1 in pixels (x1 > x0, y1 > y0)
RectLike = Sequence[float]  # x, y, width, height in pixels (a tuple or a pygame.Rect)

RENDER_MODES = ("human", "rgb_array")
FONT_SIZE_PX = 18
FAR_AWAY_PX = 1.0e5  # clamp_px's bound (kept for callers); SafeDraw clips much closer in

# --- safe drawing limits ---------------------------------------------------------------------
SAFE_EXTENT_FACTOR = 10.0  # shapes are clipped to the surface grown by 10 surface sizes...
GFX_SAFE_PX = 16_000.0  # ...but never past this: gfxdraw takes 16-bit ints (+-32767)
# Farther points are first pinned here (each axis), only so the clipping arithmetic cannot
# overflow; a line from a point in view keeps its direction exactly up to this.
PIN_PX = 1.0e150
ARC_MAX_ERROR_PX = 0.25  # a huge circle drawn as a polygon strays at most this far from it
ARC_MAX_POINTS = 4096

# --- off-screen markers ----------------------------------------------------------------------
EDGE_MARKER_MARGIN_PX = 26.0  # the arrow's tip stays this far inside the view's edge
EDGE_MARKER_LENGTH_PX = 18.0
EDGE_MARKER_HALF_WIDTH_PX = 9.0
MARKER_OUTLINE_COLOR: Color = (40, 40, 48)
MARKER_LABEL_COLOR: Color = (245, 245, 245)

# --- scale bar and caption -------------------------------------------------------------------
SCALE_BAR_STEPS = (1.0, 2.0, 5.0)  # a bar is 1, 2 or 5 times a power of ten metres long...
SCALE_BAR_MAX_PX = 120.0  # ...the longest such that is no longer than this (so >= 48 px)
SCALE_BAR_MARGIN_PX = 12  # from the view's left and bottom edges (above the caption band)
SCALE_BAR_COLOR: Color = (255, 255, 255)  # the bar: white in a black outline, on any ground
SCALE_BAR_OUTLINE_COLOR: Color = (0, 0, 0)
SCALE_BAR_FONT_PX = 16
CAPTION_BAND_PX = 22  # a recording's caption covers this strip at the bottom of a frame
CAPTION_FONT_PX = 18
CAPTION_BACKGROUND: Color = (10, 14, 22)
CAPTION_OPACITY = 0.78
CAPTION_TEXT_COLOR: Color = (245, 245, 245)

SceneT = TypeVar("SceneT")


def import_pygame() -> Any:
    """Import pygame on demand, so the package works without the render extra."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import pygame
    except ImportError as err:
        raise DependencyNotInstalled(
            'pygame is not installed, run `pip install "bbgym[render]"`'
        ) from err
    return pygame


def check_render_mode(render_mode: str) -> None:
    """Raise ``ValueError`` (naming ``render_mode``) unless it is one of :data:`RENDER_MODES`."""
    if render_mode not in RENDER_MODES:
        raise ValueError(
            f"render_mode must be one of {RENDER_MODES}, got render_mode={render_mode!r}"
        )


def blend(a: Color, b: Color, t: float) -> Color:
    """Linear colour mix: t=0 gives a, t=1 gives b."""
    t = min(max(t, 0.0), 1.0)
    return (
        round(a[0] + (b[0] - a[0]) * t),
        round(a[1] + (b[1] - a[1]) * t),
        round(a[2] + (b[2] - a[2]) * t),
    )


def clamp_px(p: Vec2) -> Vec2:
    """Keep a pixel coordinate within +-FAR_AWAY_PX, each axis on its own.

    That moves a far point off its bearing; to draw, :class:`SafeDraw` clips exactly instead.
    """
    return (
        min(max(p[0], -FAR_AWAY_PX), FAR_AWAY_PX),
        min(max(p[1], -FAR_AWAY_PX), FAR_AWAY_PX),
    )


# --- clipping geometry (pure functions on pixel coordinates) ---------------------------------


def safe_box(size: tuple[int, int]) -> Box:
    """The box shapes are clipped to: the surface grown by SAFE_EXTENT_FACTOR times its larger
    side on every side, but nowhere past +-GFX_SAFE_PX (16-bit gfxdraw stays well in range)."""
    width, height = size
    big = float(max(width, height))
    grow = max(min(SAFE_EXTENT_FACTOR * big, GFX_SAFE_PX - big), 0.0)
    return (-grow, -grow, width + grow, height + grow)


def is_finite_px(p: Sequence[float]) -> bool:
    """Both coordinates are finite numbers."""
    return math.isfinite(p[0]) and math.isfinite(p[1])


def in_box(p: Sequence[float], box: Box) -> bool:
    """``p`` lies in ``box`` (edges included); False for NaN."""
    return box[0] <= p[0] <= box[2] and box[1] <= p[1] <= box[3]


def _pin(p: Sequence[float]) -> Vec2:
    # Within +-PIN_PX the clip arithmetic below is exact to far under a pixel.
    return (min(max(float(p[0]), -PIN_PX), PIN_PX), min(max(float(p[1]), -PIN_PX), PIN_PX))


def clip_segment(a: Sequence[float], b: Sequence[float], box: Box) -> tuple[Vec2, Vec2] | None:
    """The part of segment ``a``-``b`` inside ``box`` (Liang-Barsky), or None if none is.

    An endpoint inside the box comes back unchanged, so a clipped polyline joins up exactly.
    """
    if not (is_finite_px(a) and is_finite_px(b)):
        return None
    a, b = _pin(a), _pin(b)
    dx, dy = b[0] - a[0], b[1] - a[1]
    t0, t1 = 0.0, 1.0
    edges = ((-dx, a[0] - box[0]), (dx, box[2] - a[0]), (-dy, a[1] - box[1]), (dy, box[3] - a[1]))
    for p, q in edges:
        if p == 0.0:
            if q < 0.0:
                return None  # parallel to this edge and outside it
            continue
        t = q / p
        if p < 0.0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return None
    start = a if t0 == 0.0 else _into(box, (a[0] + t0 * dx, a[1] + t0 * dy))
    end = b if t1 == 1.0 else _into(box, (a[0] + t1 * dx, a[1] + t1 * dy))
    return start, end


def _into(box: Box, p: Vec2) -> Vec2:
    """A point clipped onto an edge, held inside the box: from far endpoints (1e12 px) the
    interpolation's rounding alone can leave it a fraction of a pixel outside."""
    return (min(max(p[0], box[0]), box[2]), min(max(p[1], box[1]), box[3]))


def clip_polyline(points: Iterable[Sequence[float]], box: Box) -> list[list[Vec2]]:
    """The parts of an open polyline inside ``box``, as runs of two or more points.

    A non-finite point breaks the line there (nothing is drawn to or from it).
    """
    runs: list[list[Vec2]] = []
    run: list[Vec2] = []
    prev: Sequence[float] | None = None
    for p in points:
        if not is_finite_px(p):
            prev = None
            run = _flush(runs, run)
            continue
        if prev is not None:
            seg = clip_segment(prev, p, box)
            if seg is None:
                run = _flush(runs, run)
            elif run and run[-1] == seg[0]:
                run.append(seg[1])
            else:
                _flush(runs, run)
                run = [seg[0], seg[1]]
        prev = p
    _flush(runs, run)
    return runs


def _flush(runs: list[list[Vec2]], run: list[Vec2]) -> list[Vec2]:
    if len(run) >= 2:
        runs.append(run)
    return []


def clip_polygon(points: Iterable[Sequence[float]], box: Box) -> list[Vec2]:
    """The polygon cut to ``box`` (Sutherland-Hodgman): inside the box it covers exactly the
    same pixels; new edges run along the box's edges, which lie far off the surface. Empty if
    nothing is inside or a vertex is not finite."""
    pts = [_pin(p) if is_finite_px(p) else None for p in points]
    if not pts or any(p is None for p in pts):
        return []
    out: list[Vec2] = pts  # type: ignore[assignment]
    for axis, bound, keep_above in ((0, box[0], True), (0, box[2], False), (1, box[1], True),
                                    (1, box[3], False)):  # fmt: skip
        src, out = out, []
        for i, cur in enumerate(src):
            prev = src[i - 1]
            cur_in = cur[axis] >= bound if keep_above else cur[axis] <= bound
            prev_in = prev[axis] >= bound if keep_above else prev[axis] <= bound
            if cur_in != prev_in:
                t = (bound - prev[axis]) / (cur[axis] - prev[axis])
                cut = [prev[0] + t * (cur[0] - prev[0]), prev[1] + t * (cur[1] - prev[1])]
                cut[axis] = bound
                out.append((cut[0], cut[1]))
            if cur_in:
                out.append(cur)
        if not out:
            return []
    return out


def arc_span(center: Vec2, rx: float, ry: float, box: Box) -> tuple[float, float] | None:
    """Where the ellipse ``(cx + rx cos t, cy + ry sin t)`` may cross ``box``: an interval of
    ``t`` (at most 2 pi long) outside which its outline is certainly outside the box; None when
    the outline misses the box (the box is wholly outside the ellipse or wholly inside it)."""
    cx, cy = center
    # In units of the radii the ellipse is the unit circle about the origin.
    u0, u1 = (box[0] - cx) / rx, (box[2] - cx) / rx
    v0, v1 = (box[1] - cy) / ry, (box[3] - cy) / ry
    near_u, near_v = min(max(0.0, u0), u1), min(max(0.0, v0), v1)
    if math.hypot(near_u, near_v) > 1.0:
        return None
    if math.hypot(max(abs(u0), abs(u1)), max(abs(v0), abs(v1))) < 1.0:
        return None
    if u0 <= 0.0 <= u1 and v0 <= 0.0 <= v1:
        return (-math.pi, math.pi)
    # Seen from outside a convex box, its corners lie within half a turn of its middle.
    ref = math.atan2(0.5 * (v0 + v1), 0.5 * (u0 + u1))
    offsets = [
        (math.atan2(v, u) - ref + math.pi) % (2.0 * math.pi) - math.pi
        for u in (u0, u1)
        for v in (v0, v1)
    ]
    return (ref + min(offsets), ref + max(offsets))


def ellipse_covers(center: Vec2, rx: float, ry: float, box: Box) -> bool:
    """The filled ellipse covers the whole box."""
    cx, cy = center
    far_u = max(abs(box[0] - cx), abs(box[2] - cx)) / rx
    far_v = max(abs(box[1] - cy), abs(box[3] - cy)) / ry
    return math.hypot(far_u, far_v) <= 1.0


def arc_points(center: Vec2, rx: float, ry: float, span: tuple[float, float]) -> list[Vec2]:
    """Points along the ellipse over ``span`` of its parameter, close enough together that the
    polyline strays at most ARC_MAX_ERROR_PX from the curve (up to ARC_MAX_POINTS points)."""
    t0, t1 = span
    step = math.sqrt(8.0 * ARC_MAX_ERROR_PX / max(rx, ry, 1.0))
    n = min(max(math.ceil((t1 - t0) / step), 8), ARC_MAX_POINTS)
    cx, cy = center
    return [
        (cx + rx * math.cos(t0 + (t1 - t0) * k / n), cy + ry * math.sin(t0 + (t1 - t0) * k / n))
        for k in range(n + 1)
    ]


# --- safe drawing ----------------------------------------------------------------------------


def _safe_width(width: float, cap: float) -> int | None:
    """A line width pygame can take: whole pixels, at most ``cap``; None if not finite."""
    if not math.isfinite(width):
        return None
    return int(min(width, cap))


class SafeDraw:
    """``pygame.draw``'s calls (``line``, ``lines``, ``polygon``, ``circle``, ``ellipse``,
    ``rect``) made safe for any coordinates and sizes, plus ``aa_disc`` (an antialiased disc).

    A call whose points (and a circle's or ellipse's bounding box) all lie within
    :func:`safe_box` of its surface, with a width no larger than the surface, goes to pygame
    exactly as given: frames of normal scenes are what pygame draws. Otherwise the shape is
    clipped to that box first (what can be seen of it stays exact; a huge circle becomes a
    fine polygon over the part near the view), widths are capped at the surface's larger side,
    a shape with a non-finite coordinate is left out (a polyline just breaks there), and
    nothing that cannot reach the surface is drawn. A polygon of fewer than 3 points or a
    polyline of fewer than 2 (an object shrunk to nothing) draws nothing, where pygame would
    raise. Other names are pygame.draw's own.
    """

    def __init__(self, pg: Any) -> None:
        self._draw = pg.draw
        self._module = pg
        self._gfx: Any = None

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        return getattr(self._draw, name)

    @staticmethod
    def _limits(surface: Any) -> tuple[Box, float]:
        size = surface.get_size()
        return safe_box(size), float(max(size))

    def line(
        self, surface: Any, color: Any, start_pos: Sequence[float], end_pos: Sequence[float],
        width: int = 1,
    ) -> Any:  # fmt: skip
        box, cap = self._limits(surface)
        if in_box(start_pos, box) and in_box(end_pos, box) and width <= cap:
            return self._draw.line(surface, color, start_pos, end_pos, width)
        w = _safe_width(width, cap)
        seg = clip_segment(start_pos, end_pos, box)
        if w is None or seg is None:
            return None
        return self._draw.line(surface, color, seg[0], seg[1], w)

    def lines(
        self, surface: Any, color: Any, closed: bool, points: Sequence[Sequence[float]],
        width: int = 1,
    ) -> Any:  # fmt: skip
        box, cap = self._limits(surface)
        pts = list(points)
        if len(pts) < 2:
            return None  # a vanishing object: pygame would raise
        if all(in_box(p, box) for p in pts) and width <= cap:
            return self._draw.lines(surface, color, closed, pts, width)
        w = _safe_width(width, cap)
        if w is None:
            return None
        path = pts + pts[:1] if closed else pts
        for run in clip_polyline(path, box):
            self._draw.lines(surface, color, False, run, w)
        return None

    def polygon(
        self, surface: Any, color: Any, points: Sequence[Sequence[float]], width: int = 0
    ) -> Any:
        box, cap = self._limits(surface)
        pts = list(points)
        if len(pts) < 3:
            return None  # a vanishing object: pygame would raise
        if all(in_box(p, box) for p in pts) and width <= cap:
            return self._draw.polygon(surface, color, pts, width)
        w = _safe_width(width, cap)
        clipped = clip_polygon(pts, box)
        if w is None or len(clipped) < 3:
            return None
        return self._draw.polygon(surface, color, clipped, w)

    def circle(
        self, surface: Any, color: Any, center: Sequence[float], radius: float, width: int = 0
    ) -> Any:
        box, cap = self._limits(surface)
        cx, cy = center[0], center[1]
        if (
            in_box((cx - radius, cy - radius), box)
            and in_box((cx + radius, cy + radius), box)
            and width <= cap
        ):
            return self._draw.circle(surface, color, center, radius, width)
        return self._big_ellipse(surface, color, (cx, cy), radius, radius, width)

    def ellipse(self, surface: Any, color: Any, rect: RectLike, width: int = 0) -> Any:
        box, cap = self._limits(surface)
        x, y, w, h = (float(v) for v in rect)
        if in_box((x, y), box) and in_box((x + w, y + h), box) and width <= cap:
            return self._draw.ellipse(surface, color, rect, width)
        return self._big_ellipse(surface, color, (x + w / 2, y + h / 2), w / 2, h / 2, width)

    def rect(self, surface: Any, color: Any, rect: RectLike, width: int = 0, **kwargs: Any) -> Any:
        box, cap = self._limits(surface)
        x, y, w, h = (float(v) for v in rect)
        if in_box((x, y), box) and in_box((x + w, y + h), box) and width <= cap:
            return self._draw.rect(surface, color, rect, width, **kwargs)
        line_w = _safe_width(width, cap)
        if line_w is None or not (w >= 0.0 and h >= 0.0):  # pygame draws no negative rect
            return None
        x0, y0 = max(x, box[0]), max(y, box[1])
        x1, y1 = min(x + w, box[2]), min(y + h, box[3])
        if not (x0 < x1 and y0 < y1):
            return None
        kwargs = {k: int(min(v, cap)) for k, v in kwargs.items() if math.isfinite(v)}
        return self._draw.rect(surface, color, (x0, y0, x1 - x0, y1 - y0), line_w, **kwargs)

    def aa_disc(self, surface: Any, color: Any, center: Sequence[float], radius: float) -> None:
        """Filled disc with an antialiased rim (gfxdraw, whole pixels, at least 1 px)."""
        box, _ = self._limits(surface)
        if is_finite_px(center) and math.isfinite(radius):
            x, y, r = round(center[0]), round(center[1]), max(1, round(radius))
            if in_box((x - r, y - r), box) and in_box((x + r, y + r), box):
                if self._gfx is None:  # a submodule that `import pygame` does not load
                    self._gfx = importlib.import_module("pygame.gfxdraw")
                self._gfx.filled_circle(surface, x, y, r, color)
                self._gfx.aacircle(surface, x, y, r, color)
                return
        self.circle(surface, color, center, radius)

    def _big_ellipse(
        self, surface: Any, color: Any, center: Vec2, rx: float, ry: float, width: float
    ) -> None:
        """A circle or ellipse too big or too far for pygame: the part near the view."""
        box, cap = self._limits(surface)
        w = _safe_width(width, cap)
        if w is None or not is_finite_px(center) or not (rx > 0.0 and ry > 0.0):
            return
        if not (math.isfinite(rx) and math.isfinite(ry)):
            return
        clip = surface.get_clip()
        pad = w + 2.0
        view = (clip[0] - pad, clip[1] - pad, clip[0] + clip[2] + pad, clip[1] + clip[3] + pad)
        if w == 0 and ellipse_covers(center, rx, ry, view):
            self._draw.rect(surface, color, clip)
            return
        # pygame draws a ring of width w inward from the radius: follow its middle line.
        inset = 0.0 if w == 0 else min(w / 2.0, rx, ry)
        span = arc_span(center, rx - inset, ry - inset, view)
        if span is None:
            return
        arc = arc_points(center, rx - inset, ry - inset, span)
        if w == 0:
            whole = span[1] - span[0] >= 2.0 * math.pi
            polygon = clip_polygon(arc if whole else [*arc, center], box)
            if len(polygon) >= 3:
                self._draw.polygon(surface, color, polygon)
            return
        for run in clip_polyline(arc, box):
            self._draw.lines(surface, color, False, run, w)


class SafePygame:
    """The pygame module with ``draw`` replaced by :class:`SafeDraw`; all else is pygame's."""

    def __init__(self, pg: Any) -> None:
        self.module = pg
        self.draw = SafeDraw(pg)

    def __getattr__(self, name: str) -> Any:
        if name == "module":  # not set yet (e.g. while copying): no recursion
            raise AttributeError(name)
        return getattr(self.module, name)


# --- off-screen markers ----------------------------------------------------------------------


def is_outside(p: Sequence[float], rect: RectLike, pad: float = 0.0) -> bool:
    """``p`` is outside ``rect`` grown by ``pad`` on every side, so a thing of that half-size
    centred there cannot be seen; False for a non-finite point (there is nowhere to point)."""
    if not is_finite_px(p):
        return False
    x, y, w, h = rect
    return not (x - pad <= p[0] < x + w + pad and y - pad <= p[1] < y + h + pad)


def edge_marker_tip(
    target_px: Sequence[float], rect: RectLike, margin_px: float
) -> tuple[Vec2, Vec2]:
    """Where an arrow to ``target_px`` goes: (tip, unit direction from the rect's centre to the
    target), the tip on the rect's edge inset by ``margin_px``."""
    x, y, w, h = rect
    cx, cy = x + w / 2.0, y + h / 2.0
    tx, ty = _pin(target_px)
    dx, dy = tx - cx, ty - cy
    norm = math.hypot(dx, dy)
    if norm < 1e-9:
        return (cx, cy), (1.0, 0.0)
    ux, uy = dx / norm, dy / norm
    half_w, half_h = max(w / 2.0 - margin_px, 0.0), max(h / 2.0 - margin_px, 0.0)
    # Scale the direction until it hits the inset rectangle.
    scales = []
    if abs(ux) > 1e-12:
        scales.append(half_w / abs(ux))
    if abs(uy) > 1e-12:
        scales.append(half_h / abs(uy))
    scale = min(scales)
    return (cx + ux * scale, cy + uy * scale), (ux, uy)


def format_distance(distance_m: float) -> str:
    """A marker's distance label: whole metres, km from 10 km, powers of ten past that."""
    if distance_m < 1e4:
        return f"{distance_m:.0f} m"
    if distance_m < 1e7:
        return f"{distance_m / 1000.0:.0f} km"
    return f"{distance_m / 1000.0:.1e} km"


def draw_edge_marker(
    pg: Any,
    surface: Any,
    target_px: Sequence[float],
    rect: RectLike,
    color: Color,
    *,
    pad: float = 0.0,
    label: str | None = None,
    font: Any = None,
    label_color: Color = MARKER_LABEL_COLOR,
    outline_color: Color = MARKER_OUTLINE_COLOR,
    margin_px: float = EDGE_MARKER_MARGIN_PX,
    length_px: float = EDGE_MARKER_LENGTH_PX,
    half_width_px: float = EDGE_MARKER_HALF_WIDTH_PX,
) -> bool:
    """If ``target_px`` is outside ``rect`` (grown by ``pad``, the thing's half-size in pixels),
    draw an arrow in ``color`` just inside the rect's edge, on the line from the rect's centre
    to the target and pointing at it, with ``label`` (rendered with ``font``) beside it.
    Returns whether it drew one. The arrow is the one off-screen marker of every view."""
    if not is_outside(target_px, rect, pad):
        return False
    x, y, w, h = rect
    margin = min(margin_px, w / 2.0, h / 2.0)  # a small view still gets its arrow inside
    tip, (ux, uy) = edge_marker_tip(target_px, rect, margin)
    base = (tip[0] - ux * length_px, tip[1] - uy * length_px)
    side = (-uy * half_width_px, ux * half_width_px)
    triangle = [
        tip,
        (base[0] + side[0], base[1] + side[1]),
        (base[0] - side[0], base[1] - side[1]),
    ]
    pg.draw.polygon(surface, color, triangle)
    pg.draw.polygon(surface, outline_color, triangle, 1)
    if label and font is not None:
        img = font.render(label, True, label_color)
        # Just inside the arrow, far enough back that the label's box clears it, and kept
        # wholly inside the rect.
        lw, lh = img.get_width(), img.get_height()
        back = 4 + half_width_px / 2 + (abs(ux) * lw + abs(uy) * lh) / 2
        lx = base[0] - ux * back - lw / 2
        ly = base[1] - uy * back - lh / 2
        lx = min(max(lx, x + 2), x + w - lw - 2)
        ly = min(max(ly, y + 2), y + h - lh - 2)
        surface.blit(img, (lx, ly))
    return True


# --- scale bar -------------------------------------------------------------------------------


@dataclass(frozen=True)
class ScaleBar:
    """A scale bar: ``metres`` long in the world, ``length_px`` on screen, labelled ``label``."""

    metres: float
    length_px: float
    label: str


def format_metres(metres: float) -> str:
    """A scale bar's label: ``"10 m"``, ``"2 km"``, ``"50 cm"``, ``"5 mm"``."""
    if metres >= 1000.0:
        return f"{metres / 1000.0:g} km"
    if metres >= 1.0:
        return f"{metres:g} m"
    if metres >= 0.01:
        return f"{round(metres * 100.0, 6):g} cm"
    return f"{metres * 1000.0:g} mm"


def scale_bar(pixels_per_meter: float, max_px: float = SCALE_BAR_MAX_PX) -> ScaleBar | None:
    """The longest bar of 1, 2 or 5 times a power of ten metres that is at most ``max_px``
    long at ``pixels_per_meter`` (so at least ``max_px / 2.5``); None for a scale that is not
    a positive finite number. Its ``length_px`` is exactly ``metres * pixels_per_meter``."""
    ppm = float(pixels_per_meter)
    if not (math.isfinite(ppm) and ppm > 0.0 and max_px > 0.0):
        return None
    limit_m = max_px / ppm
    if not math.isfinite(limit_m) or limit_m <= 0.0:
        return None
    decade = math.floor(math.log10(limit_m))
    metres = 0.0
    for power in (decade - 1, decade, decade + 1):
        for step in SCALE_BAR_STEPS:
            candidate = step * 10.0**power
            if candidate <= limit_m * (1.0 + 1e-9):  # 120 px at 12 px/m: exactly 10 m
                metres = max(metres, candidate)
    if metres <= 0.0:
        return None
    return ScaleBar(metres, metres * ppm, format_metres(metres))


def scale_bar_origin(rect: RectLike, frame_height: int) -> tuple[int, int]:
    """Pixel of the left end of the scale bar of a view in ``rect``: SCALE_BAR_MARGIN_PX in
    from its left edge and up from its bottom, or from the caption band's top when the view
    reaches the bottom of the frame."""
    x, y, _, h = (int(round(v)) for v in rect)
    bottom = y + h
    if bottom >= frame_height:
        bottom = frame_height - CAPTION_BAND_PX
    return x + SCALE_BAR_MARGIN_PX, bottom - SCALE_BAR_MARGIN_PX


def draw_scale_bar(
    pg: Any,
    surface: Any,
    font: Any,
    bar: ScaleBar,
    origin: tuple[int, int],
    label_color: Color,
) -> None:
    """The bar from ``origin`` (its left end) to the right: along the row ``origin[1]``
    exactly ``round(bar.length_px)`` pixels of SCALE_BAR_COLOR between black end ticks, the
    label centred above it."""
    x0, y0 = origin
    length = max(1, int(round(bar.length_px)))
    outline, fill = SCALE_BAR_OUTLINE_COLOR, SCALE_BAR_COLOR
    pg.draw.rect(surface, outline, (x0 - 1, y0 - 2, length + 2, 5))
    pg.draw.rect(surface, outline, (x0 - 1, y0 - 7, 2, 10))  # end ticks, outside the bar
    pg.draw.rect(surface, outline, (x0 + length - 1, y0 - 7, 2, 10))
    pg.draw.rect(surface, fill, (x0, y0 - 1, length, 3))
    img = font.render(bar.label, True, label_color)
    surface.blit(img, (x0 + length / 2 - img.get_width() / 2, y0 - 8 - img.get_height()))


# --- caption ---------------------------------------------------------------------------------


def fit_text(text: str, width_px: float, measure: Callable[[str], float]) -> str:
    """``text``, cut short with "..." if ``measure(text)`` (its width) exceeds ``width_px``."""
    if measure(text) <= width_px:
        return text
    for end in range(len(text) - 1, 0, -1):
        short = text[:end].rstrip() + "..."
        if measure(short) <= width_px:
            return short
    return ""


class Captioner:
    """Draws captions (:func:`draw_caption`) with one font, made on first use and made again
    after ``pygame.quit()`` (a font kept past it would crash pygame). One per recording."""

    def __init__(self) -> None:
        self._pg: Any = None
        self._font: Any = None

    def _get_font(self) -> Any:
        if self._pg is None:
            self._pg = import_pygame()
        if self._font is None or not self._pg.font.get_init():
            self._pg.font.init()  # works headless, no display needed
            self._font = self._pg.font.Font(None, CAPTION_FONT_PX)
        return self._font

    def __call__(
        self,
        frame: np.ndarray,
        left: str,
        right: str = "",
        *,
        right_color: Color = CAPTION_TEXT_COLOR,
    ) -> np.ndarray:
        """A copy of the ``(H, W, 3)`` uint8 ``frame`` with a caption over its bottom
        CAPTION_BAND_PX rows: a dark, mostly opaque band with ``left`` at its left end and
        ``right`` (in ``right_color``) at its right end; ``left`` is cut short if both do not
        fit. The frame keeps its size."""
        font = self._get_font()
        pg = self._pg
        img = np.ascontiguousarray(frame, dtype=np.uint8)
        height, width = img.shape[:2]
        band = min(CAPTION_BAND_PX, height)
        surface = pg.surfarray.make_surface(np.transpose(img, (1, 0, 2)))
        shade = pg.Surface((width, band))
        shade.fill(CAPTION_BACKGROUND)
        shade.set_alpha(round(255 * CAPTION_OPACITY))
        surface.blit(shade, (0, height - band))
        pad = 6
        right_img = font.render(right, True, right_color) if right else None
        right_w = right_img.get_width() + 2 * pad if right_img is not None else 0
        text = fit_text(left, width - right_w - 2 * pad, lambda t: font.size(t)[0])
        text_y = height - band + (band - font.get_height()) / 2 + 1
        if text:
            surface.blit(font.render(text, True, CAPTION_TEXT_COLOR), (pad, text_y))
        if right_img is not None:
            surface.blit(right_img, (width - right_img.get_width() - pad, text_y))
        return np.ascontiguousarray(np.transpose(pg.surfarray.array3d(surface), (1, 0, 2)))


def draw_caption(
    frame: np.ndarray,
    left: str,
    right: str = "",
    *,
    right_color: Color = CAPTION_TEXT_COLOR,
) -> np.ndarray:
    """A copy of ``frame`` with a caption along its bottom (see :class:`Captioner`, which a
    recording keeps to reuse its font)."""
    return Captioner()(frame, left, right, right_color=right_color)


class PygameRenderer(Generic[SceneT]):
    """Base for the scene renderers: ``render(scene)`` draws one frame and presents it.

    ``rgb_array`` draws off-screen and returns a (height, width, 3) uint8 array; ``human`` draws
    the same off-screen surface, blits it to a window and waits to keep ``render_fps``.
    """

    caption = "bbgym"  # window title in human mode

    def __init__(self, render_mode: str, width: int, height: int, render_fps: int = 30) -> None:
        check_render_mode(render_mode)
        if width <= 0 or height <= 0:
            raise ValueError("width and height must be positive")
        self.render_mode = render_mode
        self.width = int(width)
        self.height = int(height)
        self.render_fps = int(render_fps)
        # pygame with a safe draw module: see SafeDraw (nothing far away or huge can break it).
        self._pg: Any = SafePygame(import_pygame())
        self._surface: Any = None
        self._window: Any = None
        self._clock: Any = None
        self._fonts: dict[int, Any] = {}

    # -- public API ----------------------------------------------------------------------------

    def render(self, scene: SceneT) -> np.ndarray | None:
        """Draw one frame. rgb_array: returns (height, width, 3) uint8; human: returns None."""
        self._ensure_ready()
        self._draw_scene(scene)
        return self._present()

    def close(self) -> None:
        """Close the window (human mode) and drop the drawing resources."""
        if self._window is not None:
            self._pg.display.quit()
        self._window = None
        self._clock = None
        self._surface = None
        self._fonts = {}

    # -- for subclasses ------------------------------------------------------------------------

    def _draw_scene(self, scene: SceneT) -> None:
        raise NotImplementedError

    @property
    def _font(self) -> Any:
        """The default-size font (created on first use, then cached)."""
        return self._get_font(FONT_SIZE_PX)

    def _get_font(self, size_px: int) -> Any:
        """pygame's default font at ``size_px``, cached: making a font is slow."""
        font = self._fonts.get(size_px)
        if font is None:
            self._pg.font.init()  # works headless, no display needed
            font = self._pg.font.Font(None, size_px)
            self._fonts[size_px] = font
        return font

    def _draw_text(
        self, text: str, topleft: Vec2, color: Color, size_px: int = FONT_SIZE_PX
    ) -> tuple[int, int]:
        """Blit antialiased text with its top-left corner at ``topleft``; returns its size."""
        img = self._get_font(size_px).render(text, True, color)
        self._surface.blit(img, topleft)
        return img.get_width(), img.get_height()

    def _draw_text_panel(
        self,
        lines: Sequence[tuple[str, Color]],
        topleft: Vec2,
        panel_color: Color,
        pad_x: int = 6,
        pad_y: int = 4,
    ) -> None:
        """Lines of text on a filled rectangle sized to fit them."""
        if not lines:
            return
        font = self._font
        rendered = [font.render(text, True, color) for text, color in lines]
        line_h = font.get_linesize()
        panel_w = max(r.get_width() for r in rendered) + 2 * pad_x
        panel_h = line_h * len(rendered) + 2 * pad_y
        x, y = topleft
        self._pg.draw.rect(self._surface, panel_color, (x, y, panel_w, panel_h))
        for k, img in enumerate(rendered):
            self._surface.blit(img, (x + pad_x, y + pad_y + k * line_h))

    def _draw_edge_marker(
        self,
        target_px: Sequence[float],
        rect: RectLike,
        color: Color,
        distance_m: float | None = None,
        *,
        pad: float = 0.0,
        font_size_px: int = FONT_SIZE_PX,
        label_color: Color = MARKER_LABEL_COLOR,
    ) -> bool:
        """:func:`draw_edge_marker` on this frame, labelled with ``distance_m`` if given."""
        label = None if distance_m is None else format_distance(distance_m)
        return draw_edge_marker(
            self._pg,
            self._surface,
            target_px,
            rect,
            color,
            pad=pad,
            label=label,
            font=self._get_font(font_size_px),
            label_color=label_color,
        )

    def _draw_scale_bar(
        self,
        pixels_per_meter: float,
        rect: RectLike,
        label_color: Color,
        max_px: float = SCALE_BAR_MAX_PX,
    ) -> ScaleBar | None:
        """The scale bar of a view of ``pixels_per_meter`` in ``rect``, at its bottom left
        (:func:`scale_bar_origin`); returns the bar drawn, if any."""
        bar = scale_bar(pixels_per_meter, max_px)
        if bar is not None:
            origin = scale_bar_origin(rect, self.height)
            font = self._get_font(SCALE_BAR_FONT_PX)
            draw_scale_bar(self._pg, self._surface, font, bar, origin, label_color)
        return bar

    def _with_clip(self, rect: tuple[int, int, int, int], draw: Callable[[], None]) -> None:
        """Run ``draw()`` with drawing limited to ``rect``: nothing spills into other panels."""
        self._surface.set_clip(self._pg.Rect(rect))
        try:
            draw()
        finally:
            self._surface.set_clip(None)

    # -- internals -----------------------------------------------------------------------------

    def _ensure_ready(self) -> None:
        pg = self._pg
        size = (self.width, self.height)
        if self.render_mode == "human" and self._window is None:
            pg.display.init()
            self._window = pg.display.set_mode(size)
            pg.display.set_caption(self.caption)
            self._clock = pg.time.Clock()
        if self._surface is None:
            # Draw off-screen in both modes; human mode blits it to the window.
            self._surface = pg.Surface(size)
        self._get_font(FONT_SIZE_PX)  # fail early (at the first frame) if fonts do not work

    def _present(self) -> np.ndarray | None:
        pg = self._pg
        if self.render_mode == "rgb_array":
            # surfarray is indexed (x, y); images are (row, column).
            pixels = pg.surfarray.array3d(self._surface)
            return np.ascontiguousarray(np.transpose(pixels, (1, 0, 2)), dtype=np.uint8)
        self._window.blit(self._surface, (0, 0))
        pg.event.pump()  # keeps the window responsive
        pg.display.flip()
        self._clock.tick(self.render_fps)
        return None
