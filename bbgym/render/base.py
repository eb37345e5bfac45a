"""What every bbgym pygame renderer shares: lazy import, render modes, surfaces, text.

A renderer subclasses :class:`PygameRenderer` and implements ``_draw_scene(scene)``, drawing onto
``self._surface``. The base class owns everything around that: checking ``render_mode``, making
the off-screen surface (and, in human mode, the window and its clock), handing the frame back as
an RGB array or showing it, fonts, and ``close()``.

pygame is an optional dependency (``pip install "bbgym[render]"``). It is imported only when a
renderer is created, so importing this module (or a view module built on it) never needs it.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import Any, Generic, TypeVar

import numpy as np
from gymnasium.error import DependencyNotInstalled

Vec2 = tuple[float, float]
Color = tuple[int, int, int]

RENDER_MODES = ("human", "rgb_array")
FONT_SIZE_PX = 18
FAR_AWAY_PX = 1.0e5  # coordinates beyond this are clamped before drawing (pygame needs ints)

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
    """Keep a pixel coordinate within +-FAR_AWAY_PX: far-off points still draw the right way."""
    return (
        min(max(p[0], -FAR_AWAY_PX), FAR_AWAY_PX),
        min(max(p[1], -FAR_AWAY_PX), FAR_AWAY_PX),
    )


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
        self._pg = import_pygame()
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
