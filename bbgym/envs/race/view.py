"""Drawing a race: the whole course from above, turned so that the race's mean wind blows
from the top of the frame. Boats (drawn twice their size, so that a 4 m hull on a 200 m
course is more than a speck) with their booms and numbers, each sail's shadow cone
shaded, the marks, the start and finish line, the gate, the clock and the standings.
The view reads a :class:`RaceScene` of plain numbers; it never steps the physics.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from bbgym.envs.sail.view import hull_outline_body, rotate
from bbgym.render.base import Color, PygameRenderer, Vec2, blend

WATER_COLOR: Color = (28, 96, 148)
LINE_COLOR: Color = (240, 240, 240)
MARK_COLOR: Color = (255, 140, 0)
SHADOW_COLOR: Color = (10, 40, 70)
SHADOW_ALPHA = 70
TEXT_COLOR: Color = (250, 250, 250)
PANEL_COLOR: Color = (16, 60, 96)
BOAT_COLORS: tuple[Color, ...] = (
    (250, 250, 250), (255, 205, 60), (240, 90, 80), (120, 220, 120),
    (200, 140, 255), (90, 210, 240), (255, 150, 200), (190, 190, 120),
)  # fmt: skip
BOAT_DRAW_SCALE = 2.0
"""Boats are drawn this many times their size (the course is two hundred metres tall)."""
MARGIN_M = 15.0


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

    def _scale(self, scene: RaceScene) -> float:
        tall = scene.top_m + scene.bottom_m + 2.0 * MARGIN_M
        wide = 2.0 * (scene.half_width_m + MARGIN_M)
        return min(self.height / tall, self.width / wide)

    def _to_screen(self, scene: RaceScene, world: Vec2) -> Vec2:
        """World point to pixels: upwind is up, the course's middle in the frame's."""
        ux, uy = scene.upwind
        up = world[0] * ux + world[1] * uy
        left = -world[0] * uy + world[1] * ux  # across, to the left facing upwind
        scale = self._scale(scene)
        middle = 0.5 * (scene.top_m - scene.bottom_m)
        return (self.width / 2.0 - left * scale, self.height / 2.0 - (up - middle) * scale)

    def _draw_scene(self, scene: RaceScene) -> None:
        pg, surface = self._pg, self._surface
        surface.fill(WATER_COLOR)
        shade = pg.Surface((self.width, self.height), pg.SRCALPHA)
        for boat in scene.boats:
            if boat.cone is not None:
                corners = [self._to_screen(scene, p) for p in boat.cone]
                pg.draw.polygon(shade, (*SHADOW_COLOR, SHADOW_ALPHA), corners)
        surface.blit(shade, (0, 0))
        self._draw_course(scene)
        for boat in scene.boats:
            self._draw_boat(scene, boat)
        self._draw_panel(scene)

    def _draw_course(self, scene: RaceScene) -> None:
        pg, surface = self._pg, self._surface
        committee, pin = (self._to_screen(scene, p) for p in (scene.committee_m, scene.pin_m))
        pg.draw.line(surface, LINE_COLOR, committee, pin, 1)
        pg.draw.rect(surface, LINE_COLOR, (committee[0] - 4, committee[1] - 3, 8, 6))
        for mark in (scene.pin_m, scene.windward_m, *scene.gate_m):
            centre = self._to_screen(scene, mark)
            pg.draw.circle(surface, MARK_COLOR, (round(centre[0]), round(centre[1])), 4)
        windward = self._to_screen(scene, scene.windward_m)
        self._draw_text("windward mark", (windward[0] + 8, windward[1] - 8), TEXT_COLOR, 16)
        self._draw_text("start / finish", (committee[0] + 8, committee[1] - 6), TEXT_COLOR, 16)
        # the wind: an arrow down from the top edge
        x = self.width - 30
        pg.draw.line(surface, TEXT_COLOR, (x, 12), (x, 48), 2)
        pg.draw.polygon(surface, TEXT_COLOR, [(x - 6, 40), (x + 6, 40), (x, 50)])
        self._draw_text(f"{scene.wind_speed_mps:.1f} m/s", (x - 60, 54), TEXT_COLOR, 16)

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
        label = str(boat.number) + (f" ({boat.place})" if boat.place else "")
        tip = world((-0.6 * scene.hull_length_m, 0.0))
        self._draw_text(label, (tip[0] + 4, tip[1] + 2), color, 16)

    def _draw_panel(self, scene: RaceScene) -> None:
        clock = scene.clock_s
        if clock < 0.0:
            head = f"start in {-clock:4.1f} s"
        else:
            head = f"race {int(clock // 60):d}:{clock % 60:04.1f}"
        lines = [(head, TEXT_COLOR)]
        finished = sorted((b.place, b.number) for b in scene.boats if b.place)
        if finished:
            lines.append(("finished: " + ", ".join(f"{n}" for _, n in finished), TEXT_COLOR))
        self._draw_text_panel(lines, (8, 8), PANEL_COLOR)


def race_scene(task: object, state: object, race: int = 0) -> RaceScene:
    """The frame of race ``race`` of a :class:`~bbgym.envs.race.task.RaceState` batch
    (NumPy) for ``task`` (a :class:`~bbgym.envs.race.task.RaceTask`)."""
    import numpy as np

    from bbgym.envs.functional import element
    from bbgym.physics.wind import wind_vector

    k = task.num_boats
    rows = range(race * k, (race + 1) * k)
    boats = state.boats
    wind_x, wind_y, _, _ = wind_vector(boats.scenario.wind_speed_mps,
                                       boats.scenario.wind_from_rad, boats.gust, np)  # fmt: skip
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
        views.append(BoatView(
            number=i, position_m=position, heading_rad=boat.heading_rad,
            boom_angle_rad=boat.boom_rad, capsized=bool(boat.capsized),
            stopped=bool(stopped[i]), place=int(place[i]), cone=cone,
        ))  # fmt: skip
    h = course.line_half_m
    gate_x, gate_y, g = (
        float(course.gate_x_m[race, 0]),
        float(course.gate_y_m[race, 0]),
        course.gate_half_m,
    )
    depth = task.start_depth_range[1]
    p = task.sail.params
    return RaceScene(
        clock_s=float(state.clock_s[race]), upwind=(ux, uy),
        wind_speed_mps=float(state.wind_speed_mps[race]),
        committee_m=(-h * ax, -h * ay), pin_m=(h * ax, h * ay),
        windward_m=(float(course.windward_x_m[race, 0]), float(course.windward_y_m[race, 0])),
        gate_m=((gate_x - g * ax, gate_y - g * ay), (gate_x + g * ax, gate_y + g * ay)),
        top_m=task.leg_length_m + 10.0, bottom_m=max(depth, task.gate_depth_m) + 5.0,
        half_width_m=max(h, g) + 10.0, boats=tuple(views), hull_length_m=p.hull_length_m,
        hull_beam_m=p.hull_beam_m, boom_length_m=p.boom_length_m,
    )  # fmt: skip
