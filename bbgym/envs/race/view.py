"""Drawing a race: the whole course from above, turned so that the race's mean wind blows
from the top of the frame. Boats (drawn twice their size, so that a 4 m hull on a 200 m
course is more than a speck) with their booms and numbers, each sail's shadow cone
shaded, the marks, the start and finish line, the gate, the clock and the standings.
The view reads a :class:`RaceScene` of plain numbers; it never steps the physics.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from bbgym.envs.sail.view import hull_outline_body, rotate
from bbgym.render.annotations import CAPTION_BAND_PX
from bbgym.render.base import Color, PygameRenderer, Vec2, blend
from bbgym.render.labels import place_labels

WATER_COLOR: Color = (28, 96, 148)
LINE_COLOR: Color = (240, 240, 240)
MARK_COLOR: Color = (255, 140, 0)
SHADOW_COLOR: Color = (10, 40, 70)
SHADOW_ALPHA = 70
TEXT_COLOR: Color = (250, 250, 250)
PANEL_COLOR: Color = (16, 60, 96)
BOAT_COLORS: tuple[Color, ...] = (
    (250, 250, 250),
    (255, 205, 60),
    (240, 90, 80),
    (120, 220, 120),
    (200, 140, 255),
    (90, 210, 240),
    (255, 150, 200),
    (190, 190, 120),
)
BOAT_DRAW_SCALE = 2.0
"""Boats are drawn this many times their size (the course is two hundred metres tall)."""
MARGIN_M = 15.0
LABEL_FONT_PX = 16
BOAT_LABEL_RADIUS_PX = 9.0
"""A boat's label keeps this far from its centre (the boat drawn twice its size)."""


def ordinal(place: int) -> str:
    """``1st``, ``2nd``, ``3rd``, ``4th``, ... ``11th``, ``21st``."""
    suffix = "th" if 10 <= place % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(place % 10, "th")
    return f"{place}{suffix}"


def places_text(place: Sequence[int], learned: Sequence[bool] = ()) -> str:
    """A race's result in words: ``"1st boat_1, 2nd boat_2, 3rd boat_3; boat_0 did not
    finish"`` (``place[k]`` boat ``k``'s place, 0 where it did not finish; a boat that learns,
    where only some do, is marked ``*``)."""
    marks = any(learned) and not all(learned)
    names = [f"boat_{k}" + ("*" if marks and learned[k] else "") for k in range(len(place))]
    done = sorted((int(p), names[k]) for k, p in enumerate(place) if int(p) > 0)
    out = ", ".join(f"{ordinal(p)} {name}" for p, name in done)
    left = [names[k] for k, p in enumerate(place) if int(p) <= 0]
    if left:
        tail = f"{', '.join(left)} did not finish"
        out = f"{out}; {tail}" if out else tail
    return out


@dataclass(frozen=True)
class BoatView:
    """One boat, in the world frame (x east, y north)."""

    number: int
    position_m: Vec2
    heading_rad: float
    boom_angle_rad: float
    capsized: bool
    stopped: bool
    """Crossed the finish or capsized: drawn faded."""
    place: int
    cone: tuple[Vec2, Vec2, Vec2, Vec2] | None
    """The shadow cone's corners (world), None where it casts none."""


@dataclass(frozen=True)
class RaceScene:
    """Everything one frame of a race shows; plain numbers, no physics objects."""

    clock_s: float
    """Time from the gun (negative before it)."""
    upwind: Vec2
    """Unit vector toward where the mean wind comes from: the frame's up."""
    wind_speed_mps: float
    committee_m: Vec2
    pin_m: Vec2
    windward_m: Vec2
    gate_m: tuple[Vec2, Vec2]
    top_m: float
    """How far upwind of the line the view reaches, and how far below it (``bottom_m``)."""
    bottom_m: float
    half_width_m: float
    boats: tuple[BoatView, ...]
    hull_length_m: float = 4.2
    hull_beam_m: float = 1.4
    boom_length_m: float = 2.7


class RaceRenderer(PygameRenderer[RaceScene]):
    """Draws :class:`RaceScene` frames into a window (``human``) or an RGB array."""

    caption = "bbgym race"
    label_boxes: list[tuple[float, float, float, float]] = []
    """The last frame's boat labels, ``(x0, y0, x1, y1)`` px: no two overlap."""
    course_label_boxes: list[tuple[float, float, float, float]] = []
    """The last frame's names of the marks (windward mark, start / finish, gate), px."""

    @property
    def course_height_px(self) -> int:
        """The rows the course is fitted to: all but the bottom CAPTION_BAND_PX, where a
        recording writes its caption (no boat is hidden under it)."""
        return max(self.height - CAPTION_BAND_PX, 1)

    def _scale(self, scene: RaceScene) -> float:
        tall = scene.top_m + scene.bottom_m + 2.0 * MARGIN_M
        wide = 2.0 * (scene.half_width_m + MARGIN_M)
        return min(self.course_height_px / tall, self.width / wide)

    def _to_screen(self, scene: RaceScene, world: Vec2) -> Vec2:
        """World point to pixels: upwind is up, the course's middle in the frame's."""
        ux, uy = scene.upwind
        up = world[0] * ux + world[1] * uy
        left = -world[0] * uy + world[1] * ux  # across, to the left facing upwind
        scale = self._scale(scene)
        middle = 0.5 * (scene.top_m - scene.bottom_m)
        down = self.course_height_px / 2.0 - (up - middle) * scale
        return (self.width / 2.0 - left * scale, down)

    def _draw_scene(self, scene: RaceScene) -> None:
        pg, surface = self._pg, self._surface
        surface.fill(WATER_COLOR)
        shade = pg.Surface((self.width, self.height), pg.SRCALPHA)
        for boat in scene.boats:
            if boat.cone is not None:
                corners = [self._to_screen(scene, p) for p in boat.cone]
                pg.draw.polygon(shade, (*SHADOW_COLOR, SHADOW_ALPHA), corners)
        surface.blit(shade, (0, 0))
        course_labels = self._draw_course(scene)
        for boat in scene.boats:
            self._draw_boat(scene, boat)
        panel = self._draw_panel(scene)
        self._draw_boat_labels(scene, [panel, *course_labels])

    def _draw_course(self, scene: RaceScene) -> list[tuple[float, float, float, float]]:
        """The line, the marks, their names and the wind arrow; returns the boxes (px) of
        the names and the arrow, which the boats' labels keep clear of."""
        pg, surface = self._pg, self._surface
        committee, pin = (self._to_screen(scene, p) for p in (scene.committee_m, scene.pin_m))
        pg.draw.line(surface, LINE_COLOR, committee, pin, 1)
        pg.draw.rect(surface, LINE_COLOR, (committee[0] - 4, committee[1] - 3, 8, 6))
        for mark in (scene.pin_m, scene.windward_m, *scene.gate_m):
            centre = self._to_screen(scene, mark)
            pg.draw.circle(surface, MARK_COLOR, (round(centre[0]), round(centre[1])), 4)
        windward = self._to_screen(scene, scene.windward_m)
        # the gate's name right of its right-hand mark (as drawn), below the line's
        gate = max((self._to_screen(scene, m) for m in scene.gate_m), key=lambda p: p[0])
        names = [
            ("windward mark", (windward[0] + 8, windward[1] - 8)),
            ("start / finish", (committee[0] + 8, committee[1] - 6)),
            ("gate", (gate[0] + 8, gate[1] - 8)),
        ]
        boxes = []
        for text, (x, y) in names:
            w, h = self._draw_text(text, (x, y), TEXT_COLOR, LABEL_FONT_PX)
            boxes.append((x, y, x + w, y + h))
        # the wind: an arrow down from the top edge
        x = self.width - 30
        pg.draw.line(surface, TEXT_COLOR, (x, 12), (x, 48), 2)
        pg.draw.polygon(surface, TEXT_COLOR, [(x - 6, 40), (x + 6, 40), (x, 50)])
        self._draw_text(f"{scene.wind_speed_mps:.1f} m/s", (x - 60, 54), TEXT_COLOR, 16)
        self.course_label_boxes = boxes
        return [*boxes, (self.width - 100.0, 0.0, float(self.width), 72.0)]

    def _draw_boat(self, scene: RaceScene, boat: BoatView) -> None:
        pg, surface = self._pg, self._surface
        size = BOAT_DRAW_SCALE
        color = BOAT_COLORS[boat.number % len(BOAT_COLORS)]
        if boat.stopped:
            color = blend(color, WATER_COLOR, 0.6)

        def world(body: Vec2) -> Vec2:
            dx, dy = rotate((body[0] * size, body[1] * size), boat.heading_rad)
            return self._to_screen(scene, (boat.position_m[0] + dx, boat.position_m[1] + dy))

        hull = [world(p) for p in hull_outline_body(scene.hull_length_m, scene.hull_beam_m)]
        pg.draw.polygon(surface, color, hull)
        pg.draw.polygon(surface, (20, 20, 20), hull, 1)
        if not boat.capsized:
            mast = (0.15 * scene.hull_length_m, 0.0)
            end = (
                mast[0] - scene.boom_length_m * math.cos(boat.boom_angle_rad),
                scene.boom_length_m * math.sin(boat.boom_angle_rad),
            )
            pg.draw.line(surface, (20, 20, 20), world(mast), world(end), 2)

    def _draw_boat_labels(
        self, scene: RaceScene, keep_clear: list[tuple[float, float, float, float]]
    ) -> None:
        """Each boat's number (and its place once finished) beside it, laid out by measured
        width so that no two overlap, nor the boxes ``keep_clear`` (the panel, the marks'
        names, the wind arrow), nor the caption band."""
        font = self._get_font(LABEL_FONT_PX)
        texts, anchors = [], []
        for boat in scene.boats:
            texts.append(str(boat.number) + (f" ({ordinal(boat.place)})" if boat.place else ""))
            anchors.append((*self._to_screen(scene, boat.position_m), BOAT_LABEL_RADIUS_PX))
        bounds = (0.0, 0.0, float(self.width), float(self.course_height_px))
        boxes = place_labels(anchors, [font.size(t) for t in texts], bounds, keep_clear)
        for boat, text, box in zip(scene.boats, texts, boxes, strict=True):
            color = BOAT_COLORS[boat.number % len(BOAT_COLORS)]
            if boat.stopped:
                color = blend(color, TEXT_COLOR, 0.3)
            backing = (box[0] - 1, box[1], box[2] - box[0] + 2, box[3] - box[1])
            self._pg.draw.rect(self._surface, PANEL_COLOR, backing)  # readable on the line
            self._draw_text(text, (box[0], box[1]), color, LABEL_FONT_PX)
        self.label_boxes = boxes

    def _draw_panel(self, scene: RaceScene) -> tuple[float, float, float, float]:
        clock = scene.clock_s
        if clock < 0.0:
            head = f"start in {-clock:4.1f} s"
        else:
            head = f"race {int(clock // 60):d}:{clock % 60:04.1f}"
        lines = [(head, TEXT_COLOR)]
        finished = sorted((b.place, b.number) for b in scene.boats if b.place)
        lines += [(f"{ordinal(p)} boat_{n}", TEXT_COLOR) for p, n in finished]
        self._draw_text_panel(lines, (8, 8), PANEL_COLOR)
        font = self._font  # the panel's size, as _draw_text_panel draws it
        width = max(font.size(text)[0] for text, _ in lines) + 12
        return (8.0, 8.0, 8.0 + width, 8.0 + font.get_linesize() * len(lines) + 8)


def race_scene(task: object, state: object, race: int = 0) -> RaceScene:
    """The frame of race ``race`` of a :class:`~bbgym.envs.race.task.RaceState` batch
    (NumPy) for ``task`` (a :class:`~bbgym.envs.race.task.RaceTask`)."""
    import numpy as np

    from bbgym.envs.functional import element
    from bbgym.physics.wind import wind_vector

    k = task.num_boats
    rows = range(race * k, (race + 1) * k)
    boats = state.boats
    wind_x, wind_y, _, _ = wind_vector(
        boats.scenario.wind_speed_mps, boats.scenario.wind_from_rad, boats.gust, np
    )
    course = task.course(state, np)
    ux, uy = float(course.upwind_x[race, 0]), float(course.upwind_y[race, 0])
    ax, ay = -uy, ux
    shadow = task.shadow_params
    views = []
    stopped, place = np.asarray(state.stopped)[race], np.asarray(state.place)[race]
    for i, row in enumerate(rows):
        boat = element(boats.boat, row)
        position = (boat.x_m, boat.y_m)
        cone = None
        if task.shadow and not stopped[i]:
            fx, fy = wind_x[row] - boat.vx_mps, wind_y[row] - boat.vy_mps
            norm = max(math.hypot(fx, fy), 1e-9)
            fx, fy = fx / norm, fy / norm
            near, far, length = shadow.base_width_m, shadow.end_width_m, shadow.length_m
            corners = ((0.0, near), (length, far), (length, -far), (0.0, -near))
            cone = tuple(
                (position[0] + u * fx - v * fy, position[1] + u * fy + v * fx) for u, v in corners
            )
        views.append(
            BoatView(
                number=i,
                position_m=position,
                heading_rad=boat.heading_rad,
                boom_angle_rad=boat.boom_rad,
                capsized=bool(boat.capsized),
                stopped=bool(stopped[i]),
                place=int(place[i]),
                cone=cone,
            )
        )
    h = course.line_half_m
    gate_x, gate_y, g = (
        float(course.gate_x_m[race, 0]),
        float(course.gate_y_m[race, 0]),
        course.gate_half_m,
    )
    depth = task.start_depth_range[1]
    p = task.sail.params
    return RaceScene(
        clock_s=float(state.clock_s[race]),
        upwind=(ux, uy),
        wind_speed_mps=float(state.wind_speed_mps[race]),
        committee_m=(-h * ax, -h * ay),
        pin_m=(h * ax, h * ay),
        windward_m=(float(course.windward_x_m[race, 0]), float(course.windward_y_m[race, 0])),
        gate_m=((gate_x - g * ax, gate_y - g * ay), (gate_x + g * ax, gate_y + g * ay)),
        top_m=task.leg_length_m + 10.0,
        bottom_m=max(depth, task.gate_depth_m) + 5.0,
        half_width_m=max(h, g) + 10.0,
        boats=tuple(views),
        hull_length_m=p.hull_length_m,
        hull_beam_m=p.hull_beam_m,
        boom_length_m=p.boom_length_m,
    )
