"""What the views draw over a scene: off-screen markers, the scale bar and captions.

A thing outside its view gets an arrow at the view's edge pointing at it
(:func:`draw_edge_marker`). Every view that maps the world draws a scale bar
(:func:`scale_bar` picks a round number of metres from the view's pixels per metre, so it is
right at any zoom). A recording (``bbgym record``) writes a caption over the bottom
CAPTION_BAND_PX of each frame (:func:`draw_caption`); the views keep their readouts and scale
bars above that band.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from bbgym.render.geometry import Color, RectLike, edge_marker_tip, is_outside
from bbgym.render.safe_draw import import_pygame

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
