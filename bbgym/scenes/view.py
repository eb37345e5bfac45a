"""Drawing a scene: its side view (x right, y up) fitted to the scene's view box, the floor
at y = 0, its balls and lines, the title, the clock and the measures the claim is about
(pygame, the ``render`` extra; no physics here)."""

from __future__ import annotations

from typing import Any

import numpy as np

from bbgym.render.base import PygameRenderer
from bbgym.render.labels import place_labels
from bbgym.scenes.scene import Frame, Scene

SKY = (236, 244, 250)
FLOOR = (120, 110, 95)
TEXT = (30, 30, 30)
TITLE_BAND_PX = 44
"""The band at the top for the title and the measures."""
LABEL_FONT_PX = 14
MIN_BALL_RADIUS_PX = 4.0
"""A ball smaller than this on screen is drawn this big (a 5 cm ball seen 30 m high)."""
LEADER_PX = 12.0
"""A label placed farther than this from its ball gets a thin line to it."""


class SceneView(PygameRenderer[tuple[float, Frame]]):
    """``render((time_s, frame))`` draws one frame of ``scene`` with ``params``."""

    caption = "bbgym scene"

    def __init__(
        self,
        scene: Scene,
        params: Any,
        render_mode: str = "rgb_array",
        width: int = 640,
        height: int = 400,
        render_fps: int = 30,
    ) -> None:
        super().__init__(render_mode, width, height, render_fps)
        self.scene, self.params = scene, params
        self.label_boxes: list[tuple[float, float, float, float]] = []
        """The last frame's ball labels, ``(x0, y0, x1, y1)`` px: no two overlap."""
        x0, x1, y0, y1 = scene.view_box_m(params)
        usable = height - TITLE_BAND_PX
        # One scale for both axes (circles stay round), the box centred in the view.
        self.px_per_m = min(width / (x1 - x0), usable / (y1 - y0))
        self.origin_px = (
            0.5 * (width - self.px_per_m * (x0 + x1)),
            TITLE_BAND_PX + 0.5 * (usable + self.px_per_m * (y0 + y1)),
        )

    def to_px(self, x_m: float, y_m: float) -> tuple[float, float]:
        """Screen pixel of a point of the scene (y up on the scene, down on the screen)."""
        return self.origin_px[0] + self.px_per_m * x_m, self.origin_px[1] - self.px_per_m * y_m

    def _draw_scene(self, scene: tuple[float, Frame]) -> None:
        time_s, frame = scene
        pg, surface = self._pg, self._surface
        surface.fill(SKY)
        if self.scene.floor:
            floor_y = self.to_px(0.0, 0.0)[1]
            pg.draw.rect(surface, FLOOR, (0, floor_y, self.width, max(self.height - floor_y, 0)))
        for seg in frame.segments:
            pg.draw.line(
                surface,
                seg.color,
                self.to_px(seg.x0_m, seg.y0_m),
                self.to_px(seg.x1_m, seg.y1_m),
                seg.width_px,
            )
        anchors = []
        for ball in frame.circles:
            center = self.to_px(ball.x_m, ball.y_m)
            radius = max(self.px_per_m * ball.radius_m, MIN_BALL_RADIUS_PX)
            pg.draw.circle(surface, ball.color, center, radius)
            pg.draw.circle(surface, TEXT, center, radius, 1)
            anchors.append((*center, radius))
        self._draw_labels(frame, anchors)
        section = f"{self.scene.section} {self.scene.title}"
        self._draw_text(f"{section}   t = {time_s:.2f} s", (8, 4), TEXT, 18)
        for k, line in enumerate(frame.lines):
            self._draw_text(line, (8, 22 + 14 * k), TEXT, 15)

    def _draw_labels(self, frame: Frame, anchors: list[tuple[float, float, float]]) -> None:
        """Each ball's label beside it, laid out by measured width so that none overlaps
        another, a ball or the title band; one moved away gets a line to its ball."""
        font = self._get_font(LABEL_FONT_PX)
        pairs = zip(frame.circles, anchors, strict=True)
        named = [(ball.label, anchor) for ball, anchor in pairs if ball.label]
        sizes = [font.size(label) for label, _ in named]
        title = (0.0, 0.0, float(self.width), float(TITLE_BAND_PX))
        bounds = (0.0, float(TITLE_BAND_PX), float(self.width), float(self.height))
        boxes = place_labels([a for _, a in named], sizes, bounds, [title])
        for (label, (x, y, r)), box in zip(named, boxes, strict=True):
            nx = min(max(x, box[0]), box[2])
            ny = min(max(y, box[1]), box[3])
            gap = ((nx - x) ** 2 + (ny - y) ** 2) ** 0.5 - r
            if gap > LEADER_PX:  # from the ball's edge to the label's nearest point
                ux, uy = (nx - x) / (gap + r), (ny - y) / (gap + r)
                start = (x + r * ux, y + r * uy)
                self._pg.draw.line(self._surface, (110, 110, 110), start, (nx, ny), 1)
            self._draw_text(label, (box[0], box[1]), TEXT, LABEL_FONT_PX)
        self.label_boxes = boxes


def frames(scene: Scene, params: Any, states: list[Any], every: int = 1) -> list[np.ndarray]:
    """RGB frames of ``states`` (NumPy states of ``scene`` with ``params``, ``every`` steps
    apart, the first the initial state)."""
    view = SceneView(scene, params)
    try:
        return [
            view.render((k * every * params.dt_s, scene.frame(params, state)))
            for k, state in enumerate(states)
        ]
    finally:
        view.close()
