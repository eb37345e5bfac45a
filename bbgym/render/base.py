"""What every bbgym pygame renderer shares: render modes, the window's lifecycle, fonts, text.

A renderer subclasses :class:`PygameRenderer` and implements ``_draw_scene(scene)``, drawing onto
``self._surface``. The base class owns everything around that: checking ``render_mode``, making
the off-screen surface (and, in human mode, the window and its clock), handing the frame back as
an RGB array or showing it, fonts, and ``close()``.

pygame is an optional dependency (bbgym's ``render`` extra). It is imported only when a
renderer is created, so importing this module (or a view module built on it) never needs it.

The rest lives by concern: :mod:`bbgym.render.geometry` (pure clipping geometry),
:mod:`bbgym.render.safe_draw` (pygame's ``draw`` made safe for far-away and huge shapes:
``self._pg`` is pygame with it), :mod:`bbgym.render.annotations` (off-screen markers, the
scale bar, captions); the names the views import from here stay importable here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Generic, TypeVar

import numpy as np

from bbgym.render.annotations import (
    CAPTION_BAND_PX,
    EDGE_MARKER_HALF_WIDTH_PX,
    EDGE_MARKER_LENGTH_PX,
    EDGE_MARKER_MARGIN_PX,
    MARKER_LABEL_COLOR,
    SCALE_BAR_FONT_PX,
    SCALE_BAR_MAX_PX,
    Captioner,
    ScaleBar,
    draw_edge_marker,
    draw_scale_bar,
    format_distance,
    scale_bar,
    scale_bar_origin,
)
from bbgym.render.geometry import (
    Color,
    RectLike,
    Vec2,
    arc_span,
    edge_marker_tip,
    is_finite_px,
    safe_box,
)
from bbgym.render.safe_draw import SafePygame, import_pygame

__all__ = [  # the renderer base, and the names the views and the CLI import from here
    "CAPTION_BAND_PX",
    "EDGE_MARKER_HALF_WIDTH_PX",
    "EDGE_MARKER_LENGTH_PX",
    "EDGE_MARKER_MARGIN_PX",
    "FONT_SIZE_PX",
    "RENDERER_MODES",
    "Captioner",
    "Color",
    "PygameRenderer",
    "Vec2",
    "arc_span",
    "blend",
    "check_renderer_mode",
    "draw_edge_marker",
    "edge_marker_tip",
    "import_pygame",
    "is_finite_px",
    "safe_box",
]

RENDERER_MODES = ("human", "rgb_array")
"""How a renderer shows a frame: in a window, or as an array. (An env's render modes add
``rgb_array_list``, which it draws frame by frame as ``rgb_array``:
:data:`bbgym.envs.common.RENDER_MODES`.)"""
FONT_SIZE_PX = 18

SceneT = TypeVar("SceneT")


def check_renderer_mode(render_mode: str) -> None:
    """Raise ``ValueError`` (naming ``render_mode``) unless it is one of
    :data:`RENDERER_MODES`."""
    if render_mode not in RENDERER_MODES:
        raise ValueError(
            f"render_mode must be one of {RENDERER_MODES}, got render_mode={render_mode!r}"
        )


def blend(a: Color, b: Color, t: float) -> Color:
    """Linear colour mix: t=0 gives a, t=1 gives b."""
    t = min(max(t, 0.0), 1.0)
    return (
        round(a[0] + (b[0] - a[0]) * t),
        round(a[1] + (b[1] - a[1]) * t),
        round(a[2] + (b[2] - a[2]) * t),
    )


class PygameRenderer(Generic[SceneT]):
    """Base for the scene renderers: ``render(scene)`` draws one frame and presents it.

    ``rgb_array`` draws off-screen and returns a (height, width, 3) uint8 array; ``human`` draws
    the same off-screen surface, blits it to a window and waits to keep ``render_fps``.
    """

    caption = "bbgym"  # window title in human mode

    def __init__(self, render_mode: str, width: int, height: int, render_fps: int = 30) -> None:
        check_renderer_mode(render_mode)
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
