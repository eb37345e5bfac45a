"""pygame, imported on demand, with its ``draw`` module made safe for any coordinates.

pygame is an optional dependency (bbgym's ``render`` extra): :func:`import_pygame`
imports it only when a renderer (or a captioner) is created. :class:`SafePygame` is pygame with
``draw`` replaced by :class:`SafeDraw`: the same calls, which hand pygame exactly what they
were given whenever every coordinate lies within :func:`~bbgym.render.geometry.safe_box` (a
normal scene's frame is unchanged) and otherwise first clip the shape to that box
(:mod:`bbgym.render.geometry`), or leave out what cannot be seen.
"""

from __future__ import annotations

import importlib
import math
import os
from collections.abc import Sequence
from typing import Any

from gymnasium.error import DependencyNotInstalled

from bbgym.render.geometry import (
    Box,
    RectLike,
    Vec2,
    arc_points,
    arc_span,
    clip_polygon,
    clip_polyline,
    clip_segment,
    ellipse_covers,
    in_box,
    is_finite_px,
    safe_box,
)


def import_pygame() -> Any:
    """Import pygame on demand, so the package works without the render extra."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        import pygame
    except ImportError as err:
        from bbgym._extras import install_hint

        raise DependencyNotInstalled(
            f"pygame (bbgym's 'render' extra) is not installed: {install_hint('render')}"
        ) from err
    return pygame


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

    def _vertices(
        self, surface: Any, points: Sequence[Sequence[float]], least: int
    ) -> tuple[list, Box, float]:
        """``points`` as a list (empty if fewer than ``least``: an object shrunk to nothing,
        which pygame would refuse), with the surface's :meth:`_limits`."""
        box, cap = self._limits(surface)
        pts = list(points)
        return (pts if len(pts) >= least else []), box, cap

    def line(
        self,
        surface: Any,
        color: Any,
        start_pos: Sequence[float],
        end_pos: Sequence[float],
        width: int = 1,
    ) -> Any:
        box, cap = self._limits(surface)
        if in_box(start_pos, box) and in_box(end_pos, box) and width <= cap:
            return self._draw.line(surface, color, start_pos, end_pos, width)
        w = _safe_width(width, cap)
        seg = clip_segment(start_pos, end_pos, box)
        if w is None or seg is None:
            return None
        return self._draw.line(surface, color, seg[0], seg[1], w)

    def lines(
        self,
        surface: Any,
        color: Any,
        closed: bool,
        points: Sequence[Sequence[float]],
        width: int = 1,
    ) -> Any:
        pts, box, cap = self._vertices(surface, points, 2)
        if not pts:
            return None
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
        pts, box, cap = self._vertices(surface, points, 3)
        if not pts:
            return None
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
