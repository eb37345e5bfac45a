"""Top-view renderer for the sailing dinghy.

The renderer only *draws* a :class:`SailScene`, a plain snapshot of what the environment knows;
it never steps or recomputes physics, so it can be tested and reused on its own.

Conventions (shared with the physics):

* world frame: x east, y north, metres; the screen shows world y *up* (the y axis is flipped);
* body frame: x forward (towards the bow), y to port (left);
* angles are counterclockwise, radians.

pygame is an optional dependency (bbgym's ``render`` extra). It is imported only when a
:class:`SailRenderer` is created (see :mod:`bbgym.render.base`), so importing this module never
needs it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from bbgym.render.annotations import (
    SCALE_BAR_FONT_PX,
    SCALE_BAR_MAX_PX,
    draw_scale_bar,
    scale_bar,
    scale_bar_origin,
)
from bbgym.render.base import (
    EDGE_MARKER_HALF_WIDTH_PX,
    EDGE_MARKER_LENGTH_PX,
    EDGE_MARKER_MARGIN_PX,
    Color,
    PygameRenderer,
    Vec2,
    arc_span,
    blend,
    check_renderer_mode,
    edge_marker_tip,
    safe_box,
)

MPS_TO_KNOTS = 1.943844

# --- colours ---------------------------------------------------------------------------------
# Kept far apart from each other so elements stay recognisable (and testable by colour).
WATER_COLOR: Color = (28, 98, 158)
GRID_DOT_COLOR: Color = (72, 140, 196)
WAKE_COLOR: Color = (225, 238, 248)
HULL_COLOR: Color = (245, 245, 238)
HULL_OUTLINE_COLOR: Color = (40, 40, 48)
HULL_SHADE_COLOR: Color = (110, 116, 128)  # the side pressed down by the heel
HULL_BOTTOM_COLOR: Color = (62, 66, 88)  # capsized: we look at the bottom of the hull
SAIL_FILL_COLOR: Color = (214, 222, 230)
SAIL_LINE_COLOR: Color = (252, 252, 252)
SAIL_EDGE_COLOR: Color = (96, 106, 122)  # thin edge so the sail reads over the white hull
SAIL_FLAT_COLOR: Color = (150, 184, 210)  # sail lying in the water, seen through it
SPAR_COLOR: Color = (70, 52, 36)  # mast, boom, tiller
RUDDER_COLOR: Color = (30, 30, 30)
CREW_COLOR: Color = (255, 140, 0)  # life-jacket orange
CREW_HEAD_COLOR: Color = (240, 200, 160)
MARK_COLOR: Color = (225, 45, 35)  # buoy red-orange, distinct from the crew orange
MARK_RADIUS_COLOR: Color = (235, 235, 235)
WIND_COLOR: Color = (250, 250, 250)
TEXT_COLOR: Color = (245, 245, 245)
WARN_TEXT_COLOR: Color = (255, 90, 80)
PANEL_COLOR: Color = (16, 52, 88)
FLY_COLOR: Color = (255, 232, 70)  # masthead wind indicator; not red, to keep it unlike the mark
JIB_FILL_COLOR: Color = (242, 214, 150)  # straw: told apart from the main and the hull
JIB_EDGE_COLOR: Color = (150, 110, 60)
CURRENT_COLOR: Color = (120, 230, 220)  # teal arrows: the water's own motion
CREST_COLOR: Color = (92, 156, 206)  # a wave's crest is lighter than the mean water...
TROUGH_COLOR: Color = (14, 62, 112)  # ...and its trough darker

# --- geometry (metres unless noted) ----------------------------------------------------------
GRID_SPACING_M = 5.0  # world-fixed dots: they scroll past and make the boat's motion visible
GRID_MAJOR_EVERY = 5  # every n-th dot is drawn bigger (a 25 m lattice)
MAST_FROM_BOW = 1.0 / 3.0  # fraction of the hull length
RUDDER_LENGTH_M = 0.55
TILLER_LENGTH_M = 0.9
CREW_RADIUS_M = 0.3
BUOY_RADIUS_M = 0.6
FLY_LENGTH_M = 0.8
SAIL_MIN_DEPTH = 0.03  # belly depth as a fraction of the boom length, with no force...
SAIL_MAX_DEPTH = 0.14  # ...and at SAIL_FULL_FORCE_N or more
SAIL_FULL_FORCE_N = 600.0
SAIL_SEGMENTS = 16
LUFF_ZIGZAGS = 9
LUFF_AMPLITUDE_M = 0.2
MIN_HEEL_BEAM_SCALE = 0.3  # never let heel squash the hull to a line
JIB_LUFF_SIN = math.sin(math.radians(4.0))  # the jib luffs with the flow this close along it
CURRENT_ARROW_SPACING_M = 8.0  # world-fixed arrows, so they scroll past like the grid
CURRENT_ARROW_M_PER_MPS = 6.0  # an arrow is the water's travel in 6 s
CURRENT_ARROW_MAX_M = 6.0
WAVE_CELL_M = 1.0  # the sea's height is shaded on a world-fixed grid of 1 m cells
WAVE_BAND = 0.35  # a crest where the height is over this fraction of the amplitude, ...
WAVE_BAND_SHADE = 0.5  # ...shaded this far toward CREST_COLOR
CREST_BAND_COLOR: Color = blend(WATER_COLOR, CREST_COLOR, WAVE_BAND_SHADE)

# --- screen layout (pixels) ------------------------------------------------------------------
EDGE_ARROW_MARGIN_PX = EDGE_MARKER_MARGIN_PX  # the shared off-screen marker (base.py)
EDGE_ARROW_LENGTH_PX = EDGE_MARKER_LENGTH_PX
EDGE_ARROW_HALF_WIDTH_PX = EDGE_MARKER_HALF_WIDTH_PX
WIND_ARROW_CENTER_FROM_CORNER_PX = 52
WIND_ARROW_PX_PER_MPS = 6.0
WIND_ARROW_MIN_PX = 12.0
WIND_ARROW_MAX_PX = 64.0

# Hull outline in units of (length, beam), from the bow along the port side to the stern.
# The starboard side is the mirror image.
_HULL_PORT_SIDE: tuple[Vec2, ...] = (
    (0.50, 0.0),
    (0.36, 0.28),
    (0.18, 0.44),
    (0.00, 0.50),
    (-0.25, 0.48),
    (-0.50, 0.40),
)


@dataclass(frozen=True)
class SailScene:
    """Everything the renderer needs for one frame; plain numbers, no physics objects."""

    time_s: float
    position_m: Vec2  # world frame: x east, y north (metres)
    heading_rad: float  # bow direction, counterclockwise from +x
    heel_rad: float  # signed roll; + means the PORT (left) side is down
    boom_angle_rad: float  # from the aft-pointing centreline, + = boom out to port
    rudder_angle_rad: float  # + turns the bow counterclockwise when moving ahead
    sail_force_n: float  # magnitude of the aerodynamic sail force; sets how full the sail looks
    sail_luffing: bool  # flapping sail (no drive): drawn as a zig-zag
    mark_m: Vec2  # world position of the target mark buoy
    mark_radius_m: float  # arrival radius around the mark
    true_wind_mps: Vec2  # true wind vector: points where the air moves
    apparent_wind_speed_mps: float
    apparent_wind_angle_rad: float  # direction the apparent wind comes FROM, + = from port
    boat_speed_mps: float
    wake_m: tuple[Vec2, ...]  # past boat positions, oldest first (may be empty)
    capsized: bool
    hull_length_m: float = 4.2
    hull_beam_m: float = 1.4
    boom_length_m: float = 2.7
    jibes: int = 0
    tacks: int = 0
    jib_angle_rad: float | None = None  # a sloop's jib, like the boom (+ = clew to port)
    jib_tack_body_m: Vec2 = (2.0, 0.0)  # the jib's tack (forestay foot), body frame
    jib_foot_m: float = 1.5
    current_arrows: tuple[tuple[Vec2, Vec2], ...] = ()  # (world point, water velocity m/s)
    current_mps: float | None = None  # the current's speed at the boat (None: still water)
    wave_cells: tuple[Vec2, tuple[tuple[float, ...], ...]] | None = None
    """The sea's height over the view: the world centre of the first cell and rows (along
    y) of heights over the sea's amplitude, in [-1, 1], on a grid of ``WAVE_CELL_M``."""


# --- pure geometry helpers -------------------------------------------------------------------


def rotate(vec: Vec2, angle_rad: float) -> Vec2:
    """Rotate a 2-D vector counterclockwise by ``angle_rad``."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return (c * vec[0] - s * vec[1], s * vec[0] + c * vec[1])


def body_to_world(body_xy: Vec2, position_m: Vec2, heading_rad: float) -> Vec2:
    """Body-frame point (x forward, y port) to world coordinates."""
    wx, wy = rotate(body_xy, heading_rad)
    return (position_m[0] + wx, position_m[1] + wy)


def world_to_screen(
    world_xy: Vec2, camera_m: Vec2, pixels_per_meter: float, screen_size: tuple[int, int]
) -> Vec2:
    """World point to screen pixels, with ``camera_m`` at the screen centre and world y up."""
    width, height = screen_size
    sx = width / 2.0 + (world_xy[0] - camera_m[0]) * pixels_per_meter
    sy = height / 2.0 - (world_xy[1] - camera_m[1]) * pixels_per_meter
    return (sx, sy)


def leeward_sign(boom_angle_rad: float, apparent_wind_angle_rad: float) -> float:
    """+1 if the leeward side (where the sail belly and boom go) is port, -1 for starboard.

    The boom side decides; with the boom on the centreline we fall back to the apparent wind,
    whose leeward side is opposite to the side it comes from.
    """
    if abs(boom_angle_rad) > 1e-3:
        return 1.0 if boom_angle_rad > 0 else -1.0
    return -1.0 if apparent_wind_angle_rad > 0 else 1.0


def sail_curve_body(
    mast_body: Vec2,
    boom_angle_rad: float,
    boom_length_m: float,
    depth_m: float,
    side: float,
) -> list[Vec2]:
    """Points of a sail foot bellied by ``depth_m`` towards ``side`` (+1 port), in body frame.

    The draft sits a bit forward of mid-chord, as on a real sail.
    """
    boom_dir = (-math.cos(boom_angle_rad), math.sin(boom_angle_rad))
    # Perpendicular to the boom pointing to the leeward side: for a boom out to port this is
    # (sin b, cos b), which has a +y (port) component.
    normal = (side * math.sin(boom_angle_rad), side * math.cos(boom_angle_rad))
    points = []
    for i in range(SAIL_SEGMENTS + 1):
        t = i / SAIL_SEGMENTS
        # sin(pi * t**0.8) peaks at t ~ 0.42: draft forward of the middle.
        offset = depth_m * math.sin(math.pi * t**0.8)
        along = t * boom_length_m
        points.append(
            (
                mast_body[0] + boom_dir[0] * along + normal[0] * offset,
                mast_body[1] + boom_dir[1] * along + normal[1] * offset,
            )
        )
    return points


def luffing_sail_body(
    mast_body: Vec2, boom_angle_rad: float, boom_length_m: float, time_s: float
) -> list[Vec2]:
    """Zig-zag along the boom for a flapping sail; the phase moves with time so it flutters."""
    boom_dir = (-math.cos(boom_angle_rad), math.sin(boom_angle_rad))
    normal = (math.sin(boom_angle_rad), math.cos(boom_angle_rad))
    points = []
    for i in range(LUFF_ZIGZAGS + 1):
        t = i / LUFF_ZIGZAGS
        # Amplitude grows towards the leech (the free aft edge flaps most) and varies with time.
        amp = LUFF_AMPLITUDE_M * (0.4 + t) * (0.7 + 0.3 * math.sin(11.0 * time_s + 1.7 * i))
        offset = amp if i % 2 else -amp
        if i == 0:
            offset = 0.0  # the luff stays on the mast
        along = t * boom_length_m
        points.append(
            (
                mast_body[0] + boom_dir[0] * along + normal[0] * offset,
                mast_body[1] + boom_dir[1] * along + normal[1] * offset,
            )
        )
    return points


def hull_outline_body(length_m: float, beam_m: float) -> list[Vec2]:
    """Pointed hull outline in body frame, counterclockwise from the bow."""
    port = [(fx * length_m, fy * beam_m) for fx, fy in _HULL_PORT_SIDE]
    starboard = [(x, -y) for x, y in reversed(port) if y != 0.0]
    return port + starboard


# --- renderer --------------------------------------------------------------------------------


class SailRenderer(PygameRenderer[SailScene]):
    """Draws :class:`SailScene` frames, either into a window or into an RGB array.

    ``render(scene)`` returns a (height, width, 3) uint8 array in ``rgb_array`` mode and None in
    ``human`` mode; ``close()`` closes the window. Both come from :class:`PygameRenderer`.
    """

    caption = "bbgym sailing"

    def __init__(
        self,
        render_mode: str,
        width: int = 640,
        height: int = 480,
        pixels_per_meter: float = 12.0,
        render_fps: int = 30,
    ) -> None:
        # Checked here too (not only in the base) so the error order and message stay as before.
        check_renderer_mode(render_mode)
        if width <= 0 or height <= 0 or pixels_per_meter <= 0:
            raise ValueError("width, height and pixels_per_meter must be positive")
        super().__init__(render_mode, width, height, render_fps)
        self.pixels_per_meter = float(pixels_per_meter)
        self.scale_bar_box: tuple[float, float, float, float] | None = None
        """The last frame's scale bar and its label, ``(x0, y0, x1, y1)`` px."""

    # -- coordinate helpers --------------------------------------------------------------------

    def _to_screen(self, scene: SailScene, world_xy: Vec2) -> Vec2:
        return world_to_screen(
            world_xy, scene.position_m, self.pixels_per_meter, (self.width, self.height)
        )

    def _body_to_screen(self, scene: SailScene, body_xy: Vec2) -> Vec2:
        world = body_to_world(body_xy, scene.position_m, scene.heading_rad)
        return self._to_screen(scene, world)

    def _body_points(self, scene: SailScene, points: Iterable[Vec2]) -> list[Vec2]:
        return [self._body_to_screen(scene, p) for p in points]

    def _body_line(
        self, scene: SailScene, color: Color, start: Vec2, end: Vec2, width_px: int
    ) -> None:
        """A line between two points of the boat's body frame."""
        self._pg.draw.line(self._surface, color, *self._body_points(scene, (start, end)), width_px)

    def _px(self, metres: float, minimum: int = 1) -> int:
        return max(minimum, round(metres * self.pixels_per_meter))

    # -- drawing -------------------------------------------------------------------------------

    def _draw_scene(self, scene: SailScene) -> None:
        surf = self._surface
        surf.fill(WATER_COLOR)
        self._draw_waves(scene)
        self._draw_grid(scene)
        self._draw_current(scene)
        self._draw_mark(scene)
        self._draw_wake(scene)
        if scene.capsized:
            self._draw_capsized_boat(scene)
        else:
            self._draw_upright_boat(scene)
        self.scale_bar_box = self._draw_scale_bar_clear_of_the_mark(scene)
        self._draw_mark_edge_arrow(scene)
        self._draw_wind_arrow(scene)
        self._draw_readout(scene)

    def _mark_px(self, scene: SailScene) -> Vec2:
        """Where the mark shows: its buoy, or the tip of its edge arrow when off screen."""
        center = self._to_screen(scene, scene.mark_m)
        if 0.0 <= center[0] <= self.width and 0.0 <= center[1] <= self.height:
            return center
        rect = (0, 0, self.width, self.height)
        return edge_marker_tip(center, rect, EDGE_ARROW_MARGIN_PX)[0]

    def _draw_scale_bar_clear_of_the_mark(
        self, scene: SailScene
    ) -> tuple[float, float, float, float] | None:
        """The scale bar at the bottom left, or at the bottom right where the mark (or its
        edge arrow and distance) would sit on it; returns the box it takes (x0, y0, x1, y1)."""
        bar = scale_bar(self.pixels_per_meter, SCALE_BAR_MAX_PX)
        if bar is None:
            return None
        x, y = scale_bar_origin((0, 0, self.width, self.height), self.height)
        font = self._get_font(SCALE_BAR_FONT_PX)
        # the bar with its label above; the mark's arrow and label reach ~45 px from its tip
        reach = 45.0
        box = (x - 2.0, y - 8.0 - font.get_height(), x + bar.length_px + 2.0, y + 4.0)
        mx, my = self._mark_px(scene)
        if box[0] - reach < mx < box[2] + reach and box[1] - reach < my < box[3] + reach:
            x = round(self.width - x - bar.length_px)
            box = (x - 2.0, box[1], x + bar.length_px + 2.0, box[3])
        draw_scale_bar(self._pg, self._surface, font, bar, (x, y), TEXT_COLOR)
        return box

    def _draw_grid(self, scene: SailScene) -> None:
        """World-fixed dot lattice: only the visible part is drawn."""
        draw = self._pg.draw
        half_w = self.width / 2.0 / self.pixels_per_meter
        half_h = self.height / 2.0 / self.pixels_per_meter
        cx, cy = scene.position_m
        i0 = math.floor((cx - half_w) / GRID_SPACING_M)
        i1 = math.ceil((cx + half_w) / GRID_SPACING_M)
        j0 = math.floor((cy - half_h) / GRID_SPACING_M)
        j1 = math.ceil((cy + half_h) / GRID_SPACING_M)
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                p = self._to_screen(scene, (i * GRID_SPACING_M, j * GRID_SPACING_M))
                major = i % GRID_MAJOR_EVERY == 0 and j % GRID_MAJOR_EVERY == 0
                draw.circle(self._surface, GRID_DOT_COLOR, p, 2 if major else 1)

    def _draw_waves(self, scene: SailScene) -> None:
        """The sea's surface height as flat bands: the crests light, the rest the plain
        water (calm to the eye). The heights sit on a grid fixed to the world, so the
        crests move over it as the waves travel; the grid is scaled up smoothly before it
        is cut into bands (round outlines, no blocks). Flat bands, not a gradient: a
        recording's frames then take few colours and compress well (a GIF of waves stays
        small: 13 KB a frame, against 96 KB for the gradient)."""
        if scene.wave_cells is None:
            return
        import numpy as np

        (x0, y0), rows = scene.wave_cells
        height = np.clip(np.asarray(rows, dtype=np.float64), -1.0, 1.0)[::-1]  # north on top
        grey = np.round(127.5 + 127.5 * height).astype(np.uint8)
        pg = self._pg
        image = pg.surfarray.make_surface(np.repeat(grey.T[..., None], 3, axis=2))
        n_rows, n_cols = height.shape
        size = (
            round(n_cols * WAVE_CELL_M * self.pixels_per_meter),
            round(n_rows * WAVE_CELL_M * self.pixels_per_meter),
        )
        half = 0.5 * WAVE_CELL_M
        top_left = self._to_screen(scene, (x0 - half, y0 + (n_rows - 1) * WAVE_CELL_M + half))
        # only the part on screen is banded (the grid may reach far past it)
        left, top = round(top_left[0]), round(top_left[1])
        x_a, y_a = max(0, -left), max(0, -top)
        x_b, y_b = min(size[0], self.width - left), min(size[1], self.height - top)
        if x_b <= x_a or y_b <= y_a:
            return
        smooth = pg.surfarray.array_red(pg.transform.smoothscale(image, size))[x_a:x_b, y_a:y_b]
        level = smooth.astype(np.float64) / 127.5 - 1.0
        shades = np.asarray([WATER_COLOR, CREST_BAND_COLOR], dtype=np.uint8)
        band = (level > WAVE_BAND).astype(np.intp)
        self._surface.blit(pg.surfarray.make_surface(shades[band]), (left + x_a, top + y_a))

    def _draw_current(self, scene: SailScene) -> None:
        """Arrows fixed to the world, each the water's travel over a few seconds."""
        draw = self._pg.draw
        for point, (vx, vy) in scene.current_arrows:
            speed = math.hypot(vx, vy)
            if speed < 1e-3:
                continue
            length = min(speed * CURRENT_ARROW_M_PER_MPS, CURRENT_ARROW_MAX_M)
            ux, uy = vx / speed, vy / speed
            tail = self._to_screen(
                scene, (point[0] - 0.5 * length * ux, point[1] - 0.5 * length * uy)
            )
            tip = self._to_screen(
                scene, (point[0] + 0.5 * length * ux, point[1] + 0.5 * length * uy)
            )
            draw.line(self._surface, CURRENT_COLOR, tail, tip, 2)
            sx, sy = ux, -uy  # screen y points down
            base = (tip[0] - 7 * sx, tip[1] - 7 * sy)
            head = [tip, (base[0] - 4 * sy, base[1] + 4 * sx), (base[0] + 4 * sy, base[1] - 4 * sx)]
            draw.polygon(self._surface, CURRENT_COLOR, head)

    def _draw_wake(self, scene: SailScene) -> None:
        """Line through past positions, fading into the water with age."""
        points = [*scene.wake_m, scene.position_m]
        if len(points) < 2:
            return
        screen = [self._to_screen(scene, p) for p in points]  # far points: SafeDraw clips
        n = len(screen) - 1
        for k in range(n):
            # k=0 is the oldest segment: nearly water coloured.
            color = blend(WATER_COLOR, WAKE_COLOR, (k + 1) / n)
            self._pg.draw.line(self._surface, color, screen[k], screen[k + 1], 2)

    def _draw_mark(self, scene: SailScene) -> None:
        """Buoy plus a dashed circle for the arrival radius."""
        center = self._to_screen(scene, scene.mark_m)
        radius_px = scene.mark_radius_m * self.pixels_per_meter
        visible = (
            -radius_px <= center[0] <= self.width + radius_px
            and -radius_px <= center[1] <= self.height + radius_px
        )
        if not visible:
            return  # the edge arrow shows where it is
        if radius_px >= 3:
            self._draw_dashed_circle(center, radius_px, MARK_RADIUS_COLOR)
        buoy_px = self._px(BUOY_RADIUS_M, minimum=5)
        self._pg.draw.circle(self._surface, MARK_COLOR, center, buoy_px)

    def _draw_dashed_circle(self, center: Vec2, radius_px: float, color: Color) -> None:
        # About one dash per 8 px of circumference, drawn every other segment.
        segments = max(12, int(2 * math.pi * radius_px / 8) // 2 * 2)
        dashes = range(0, segments, 2)
        x0, y0, x1, y1 = safe_box((self.width, self.height))
        if not (x0 <= center[0] - radius_px and center[0] + radius_px <= x1) or not (
            y0 <= center[1] - radius_px and center[1] + radius_px <= y1
        ):
            # A huge ring would be millions of dashes: only those near the screen are drawn.
            near = (-2.0, -2.0, self.width + 2.0, self.height + 2.0)
            span = arc_span(center, radius_px, radius_px, near)
            if span is None:
                return
            k0 = math.floor(span[0] / (2 * math.pi) * segments / 2) * 2
            k1 = math.ceil(span[1] / (2 * math.pi) * segments)
            dashes = range(k0, k1 + 1, 2)
        for k in dashes:
            a0 = 2 * math.pi * k / segments
            a1 = 2 * math.pi * (k + 1) / segments
            p0 = (center[0] + radius_px * math.cos(a0), center[1] + radius_px * math.sin(a0))
            p1 = (center[0] + radius_px * math.cos(a1), center[1] + radius_px * math.sin(a1))
            self._pg.draw.line(self._surface, color, p0, p1, 1)

    def _draw_mark_edge_arrow(self, scene: SailScene) -> None:
        """Off-screen mark: arrow on the screen border pointing at it, with the distance.

        The view always follows the boat, so the boat itself never needs one.
        """
        distance = math.hypot(
            scene.mark_m[0] - scene.position_m[0], scene.mark_m[1] - scene.position_m[1]
        )
        center = self._to_screen(scene, scene.mark_m)
        screen = (0, 0, self.width, self.height)
        self._draw_edge_marker(center, screen, MARK_COLOR, distance, label_color=TEXT_COLOR)

    def _hull_beam_scale(self, scene: SailScene) -> float:
        # Seen from above, a heeled hull looks narrower by cos(heel).
        return max(abs(math.cos(scene.heel_rad)), MIN_HEEL_BEAM_SCALE)

    def _draw_hull(self, scene: SailScene, fill: Color) -> float:
        """Hull outline, with the side pressed down by the heel shaded. Returns the beam used."""
        pg = self._pg
        beam = scene.hull_beam_m * self._hull_beam_scale(scene)
        outline_body = hull_outline_body(scene.hull_length_m, beam)
        outline = self._body_points(scene, outline_body)
        pg.draw.polygon(self._surface, fill, outline)
        if not scene.capsized and abs(scene.heel_rad) > 0.02:
            # Half hull on the low side (port when heel > 0), darker the more it heels.
            down = 1.0 if scene.heel_rad > 0 else -1.0
            # The outline runs bow -> port -> stern -> starboard -> bow, so each side's points
            # are already in order; close them along the centreline.
            side_pts = [(x, y) for x, y in outline_body if y * down > 0]
            bow, stern = (scene.hull_length_m / 2, 0.0), (-scene.hull_length_m / 2, 0.0)
            half = [bow, *side_pts, stern] if down > 0 else [stern, *side_pts, bow]
            strength = min(abs(scene.heel_rad) / (math.pi / 4), 1.0)
            shade = blend(fill, HULL_SHADE_COLOR, 0.25 + 0.75 * strength)
            pg.draw.polygon(self._surface, shade, self._body_points(scene, half))
        pg.draw.polygon(self._surface, HULL_OUTLINE_COLOR, outline, 1)
        return beam

    def _draw_rudder(self, scene: SailScene, with_tiller: bool) -> None:
        """Rudder blade behind the stern and the tiller forward of it.

        A positive rudder angle turns the bow counterclockwise (to port). For that the blade's
        trailing edge must point to port: it deflects the water to port, the reaction pushes the
        stern to starboard and the bow swings to port. The tiller is on the other side.
        """
        r = scene.rudder_angle_rad
        stern = (-scene.hull_length_m / 2, 0.0)
        blade_end = (
            stern[0] - RUDDER_LENGTH_M * math.cos(r),
            stern[1] + RUDDER_LENGTH_M * math.sin(r),
        )
        width = self._px(0.1, minimum=2)
        self._body_line(scene, RUDDER_COLOR, stern, blade_end, width)
        if with_tiller:
            tiller_end = (
                stern[0] + TILLER_LENGTH_M * math.cos(r),
                stern[1] - TILLER_LENGTH_M * math.sin(r),
            )
            self._body_line(scene, SPAR_COLOR, stern, tiller_end, max(1, width - 1))

    def _draw_crew(self, scene: SailScene, positions_body: Sequence[Vec2]) -> None:
        """Crew as orange life jackets with a head in the middle."""
        pg = self._pg
        radius = self._px(CREW_RADIUS_M, minimum=4)
        for p in positions_body:
            c = self._body_to_screen(scene, p)
            pg.draw.circle(self._surface, CREW_COLOR, c, radius)
            pg.draw.circle(self._surface, CREW_HEAD_COLOR, c, max(1, radius // 2))

    def _draw_upright_boat(self, scene: SailScene) -> None:
        pg = self._pg
        beam = self._draw_hull(scene, HULL_COLOR)
        self._draw_rudder(scene, with_tiller=True)

        mast = (scene.hull_length_m * (0.5 - MAST_FROM_BOW), 0.0)
        side = leeward_sign(scene.boom_angle_rad, scene.apparent_wind_angle_rad)
        boom = scene.boom_angle_rad
        boom_end = (
            mast[0] - scene.boom_length_m * math.cos(boom),
            mast[1] + scene.boom_length_m * math.sin(boom),
        )

        # Crew hike out on the windward rail (opposite the boom), aft of the mast.
        windward = -side
        rail = windward * 0.36 * beam
        crew_x = (mast[0] - 0.30 * scene.hull_length_m, mast[0] - 0.48 * scene.hull_length_m)
        self._draw_crew(scene, [(crew_x[0], rail), (crew_x[1], rail)])

        mast_px = self._body_to_screen(scene, mast)
        boom_px = (mast_px, self._body_to_screen(scene, boom_end))
        spar_width = self._px(0.08, minimum=2)
        if scene.sail_luffing:
            # Boom first: the flapping cloth is above it and must stay visible over the hull.
            pg.draw.line(self._surface, SPAR_COLOR, *boom_px, spar_width)
            flap = self._body_points(
                scene, luffing_sail_body(mast, boom, scene.boom_length_m, scene.time_s)
            )
            pg.draw.lines(self._surface, SAIL_LINE_COLOR, False, flap, 3)
            pg.draw.lines(self._surface, SAIL_EDGE_COLOR, False, flap, 1)
        else:
            fullness = min(max(scene.sail_force_n / SAIL_FULL_FORCE_N, 0.0), 1.0)
            depth = scene.boom_length_m * (
                SAIL_MIN_DEPTH + (SAIL_MAX_DEPTH - SAIL_MIN_DEPTH) * fullness
            )
            curve = self._body_points(
                scene, sail_curve_body(mast, boom, scene.boom_length_m, depth, side)
            )
            # Filled between the boom (chord) and the curved foot, so the belly reads at a glance.
            pg.draw.polygon(self._surface, SAIL_FILL_COLOR, curve)
            pg.draw.line(self._surface, SPAR_COLOR, *boom_px, spar_width)
            pg.draw.lines(self._surface, SAIL_LINE_COLOR, False, curve, 2)
            pg.draw.lines(self._surface, SAIL_EDGE_COLOR, False, curve, 1)
        pg.draw.circle(self._surface, SPAR_COLOR, mast_px, self._px(0.12, minimum=3))
        if scene.jib_angle_rad is not None:
            self._draw_jib(scene, scene.jib_angle_rad)

        # Masthead fly: points where the apparent wind blows to (downwind of the mast).
        awa = scene.apparent_wind_angle_rad
        fly_end = (mast[0] - FLY_LENGTH_M * math.cos(awa), mast[1] - FLY_LENGTH_M * math.sin(awa))
        pg.draw.line(self._surface, FLY_COLOR, mast_px, self._body_to_screen(scene, fly_end), 1)

    def _draw_jib(self, scene: SailScene, angle_rad: float) -> None:
        """The jib from its tack: bellied to leeward when the flow meets it at an angle
        (trimmed, or backed), a zig-zag when it lies along the flow (luffing)."""
        pg = self._pg
        awa = scene.apparent_wind_angle_rad
        # where the air goes, body frame, against the jib's aft-pointing chord
        cross = math.cos(angle_rad) * math.sin(awa) - math.sin(angle_rad) * math.cos(awa)
        tack = scene.jib_tack_body_m
        if abs(cross) < JIB_LUFF_SIN or scene.apparent_wind_speed_mps < 0.5:
            flap = luffing_sail_body(tack, angle_rad, scene.jib_foot_m, scene.time_s + 0.37)
            points = self._body_points(scene, flap)
            pg.draw.lines(self._surface, JIB_FILL_COLOR, False, points, 3)
            pg.draw.lines(self._surface, JIB_EDGE_COLOR, False, points, 1)
            return
        side = -1.0 if awa > 0 else 1.0  # the belly goes where the air goes: to leeward
        depth = 0.1 * scene.jib_foot_m
        curve = self._body_points(
            scene, sail_curve_body(tack, angle_rad, scene.jib_foot_m, depth, side)
        )
        pg.draw.polygon(self._surface, JIB_FILL_COLOR, curve)
        pg.draw.lines(self._surface, JIB_EDGE_COLOR, False, curve, 2)

    def _draw_capsized_boat(self, scene: SailScene) -> None:
        """Boat on its side: mast and sail lie flat in the water on the low side."""
        pg = self._pg
        down = 1.0 if scene.heel_rad >= 0 else -1.0
        mast = (scene.hull_length_m * (0.5 - MAST_FROM_BOW), 0.0)
        mast_len = 1.6 * scene.boom_length_m
        mast_tip = (mast[0], mast[1] + down * mast_len)
        clew = (mast[0] - 0.9 * scene.boom_length_m, mast[1] + down * 0.3)
        # Sail first, so the hull covers its foot.
        sail = self._body_points(scene, [mast, mast_tip, clew])
        pg.draw.polygon(self._surface, SAIL_FLAT_COLOR, sail)
        pg.draw.polygon(self._surface, SAIL_LINE_COLOR, sail, 1)
        self._body_line(scene, SPAR_COLOR, mast, mast_tip, self._px(0.08, minimum=2))
        beam = self._draw_hull(scene, HULL_BOTTOM_COLOR)
        # Centreboard sticks out of the hull towards the high side.
        board_root = (mast[0] - 0.4, -down * beam * 0.3)
        board_tip = (mast[0] - 0.4, -down * (beam * 0.3 + 0.9))
        self._body_line(scene, RUDDER_COLOR, board_root, board_tip, self._px(0.12, minimum=3))
        self._draw_rudder(scene, with_tiller=False)
        # Crew in the water by the centreboard, about to right the boat.
        self._draw_crew(
            scene,
            [
                (mast[0] - 0.1, -down * (beam * 0.5 + 1.1)),
                (mast[0] - 1.0, -down * (beam * 0.5 + 0.6)),
            ],
        )

    def _draw_wind_arrow(self, scene: SailScene) -> None:
        """True wind arrow in the top-right corner, pointing where the air moves."""
        pg = self._pg
        cx = self.width - WIND_ARROW_CENTER_FROM_CORNER_PX
        cy = WIND_ARROW_CENTER_FROM_CORNER_PX
        pg.draw.circle(self._surface, PANEL_COLOR, (cx, cy), WIND_ARROW_MAX_PX // 2 + 8)
        wx, wy = scene.true_wind_mps
        speed = math.hypot(wx, wy)
        if speed > 1e-6:
            length = min(max(speed * WIND_ARROW_PX_PER_MPS, WIND_ARROW_MIN_PX), WIND_ARROW_MAX_PX)
            ux, uy = wx / speed, -wy / speed  # screen y points down
            tail = (cx - ux * length / 2, cy - uy * length / 2)
            tip = (cx + ux * length / 2, cy + uy * length / 2)
            pg.draw.line(self._surface, WIND_COLOR, tail, tip, 2)
            head_base = (tip[0] - ux * 9, tip[1] - uy * 9)
            head = [
                tip,
                (head_base[0] - uy * 5, head_base[1] + ux * 5),
                (head_base[0] + uy * 5, head_base[1] - ux * 5),
            ]
            pg.draw.polygon(self._surface, WIND_COLOR, head)
        label = self._font.render(f"wind {speed:.1f} m/s", True, TEXT_COLOR)
        left, top = cx - label.get_width() / 2, cy + WIND_ARROW_MAX_PX // 2 + 10
        # On a panel of its own: the mark's dashed ring or the wake may pass under it.
        backing = (left - 3, top - 1, label.get_width() + 6, label.get_height() + 2)
        pg.draw.rect(self._surface, PANEL_COLOR, backing)
        self._surface.blit(label, (left, top))

    def _draw_readout(self, scene: SailScene) -> None:
        """Small text panel in the top-left corner."""
        distance = math.hypot(
            scene.mark_m[0] - scene.position_m[0], scene.mark_m[1] - scene.position_m[1]
        )
        lines: list[tuple[str, Color]] = [
            (f"t {scene.time_s:7.1f} s", TEXT_COLOR),
            (
                f"speed {scene.boat_speed_mps:5.2f} m/s "
                f"({scene.boat_speed_mps * MPS_TO_KNOTS:4.1f} kn)",
                TEXT_COLOR,
            ),
            (
                f"app. wind {scene.apparent_wind_speed_mps:4.1f} m/s "
                f"{math.degrees(scene.apparent_wind_angle_rad):+5.0f}\u00b0",
                TEXT_COLOR,
            ),
            (f"heel {math.degrees(scene.heel_rad):+5.0f}\u00b0", TEXT_COLOR),
            (f"jibes {scene.jibes}  tacks {scene.tacks}", TEXT_COLOR),
            (f"mark {distance:6.0f} m", TEXT_COLOR),
        ]
        if scene.current_mps is not None:
            # in the arrows' colour: the legend of the teal arrows on the water
            lines.append((f"current {scene.current_mps:4.2f} m/s (arrows)", CURRENT_COLOR))
        if scene.capsized:
            lines.append(("CAPSIZED", WARN_TEXT_COLOR))
        self._draw_text_panel(lines, (4, 4), PANEL_COLOR)
