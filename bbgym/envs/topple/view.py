"""Renderer for the wall-toppling task: a side view of the wall, a top-view inset, a readout.

The renderer only *draws* a :class:`ToppleScene`, a plain snapshot of the latest env step; it
never steps or recomputes physics, so it can be tested and reused on its own.

Conventions (shared with the physics):

* world frame: x east, y north, z up, metres; the thrower stands at the origin, the wall at
  x = ``wall_distance_m``, centred on y = 0, its face towards the thrower;
* lean angle: positive when the top moves away from the thrower (+x); +-pi/2 is lying flat.
  A wall on its foot can only lean forward by rotating about the foot's far bottom edge and
  backward about the near one, so the pivot follows the sign of the lean (``pivot_side`` is
  used only where the lean is exactly 0);
* the wall (panel and foot) is one rigid body. Its body frame has its origin at the middle of
  the foot's bottom face, ``u`` across the panel (+x when upright) and ``v`` up along it; a loose
  panel's (x, z) is the centre of the panel rectangle, body point (0, height/2);
* ball orientation: unit quaternion (w, x, y, z), as in :mod:`bbgym.render.beach`.

Layout: the upper part is a SIDE VIEW looking north (+x to the right, z up) at a fixed scale
that depends only on the wall distance; below it, the readout (left) and a TOP-VIEW inset
(right, x east to the right, y north up, with a scale bar). The beach ball, thrower, windsock
and wind compass come from :mod:`bbgym.render.beach`; what a frame shows (poses, banner,
view maps) from :mod:`bbgym.envs.topple.frame`. How an episode ends goes on a big
banner across the side view (:func:`banner`): "WALL DOWN!" or "BROKE LOOSE!" (success), or
"FAILED: wall fell toward you" / "FAILED: out of throws" (the wall still stands after the
last throw).

pygame is an optional dependency (bbgym's ``render`` extra). It is imported only when a
:class:`ToppleRenderer` is created, so importing this module never needs it.
"""

from __future__ import annotations

import math

import numpy as np

from bbgym.envs.topple.frame import (
    STATE_COLORS,
    STATE_LABELS,
    TOP_X_MIN_M,
    Banner,
    FrameState,
    ToppleScene,
    WallPose,
    banner,
    frame_state,
    hit_body_v,
    loose_pose,
    panel_rects,
    side_view_map,
    top_view_map,
)
from bbgym.physics.common import wrap_angle
from bbgym.physics.namespace import floats
from bbgym.render.base import CAPTION_BAND_PX, Color, PygameRenderer, Vec2, blend
from bbgym.render.beach import (
    BALL_MIN_RADIUS_PX,
    DIM_TEXT_COLOR,
    GROUND_LINE_COLOR,
    LABEL_COLOR,
    PANEL_EDGE_COLOR,
    READOUT_COLOR,
    SAND_COLOR,
    SAND_GRID_COLOR,
    SKY_COLOR,
    SKY_GRID_COLOR,
    TEXT_COLOR,
    Rect,
    ViewMap,
    draw_ball_flight,
    draw_side_thrower,
    draw_top_thrower,
    draw_top_windsock,
    draw_wind_compass,
    view_axes,
)

WALL_STATES = ("standing", "fallen_away", "fallen_toward", "loose")

# --- colours ---------------------------------------------------------------------------------
WALL_COLOR: Color = (214, 170, 112)  # a plywood stage flat
WALL_EDGE_COLOR: Color = (96, 62, 30)
FOOT_COLOR: Color = (112, 86, 64)
UPRIGHT_GUIDE_COLOR: Color = (120, 150, 178)  # dashed "where upright would be" line
PIVOT_COLOR: Color = (200, 30, 30)
HIT_STAR_COLOR: Color = (255, 226, 0)
HIT_STAR_EDGE_COLOR: Color = (200, 40, 20)
SIDE_WIND_COLOR: Color = (30, 62, 120)
SCAR_COLOR: Color = (120, 86, 52)  # torn-up ground where a loose wall stood
BANNER_TEXT_COLOR: Color = (255, 255, 255)

# --- geometry (metres unless noted) ----------------------------------------------------------
FOOT_HEIGHT_M = 0.14
FOOT_TOP_FRACTION = 0.35  # the foot's top face, as a fraction of its depth: a low trapezoid
WALL_MIN_THICKNESS_PX = 7.0  # a 4 cm panel would be 2 px wide: exaggerate it to stay visible
SOCK_POLE_M: Vec2 = (1.5, 1.9)  # the top view's windsock: left of the usual flight path
LOOSE_GHOST_EVERY = 5  # every n-th loose sample leaves a faded outline of the tumbling panel
LOOSE_GHOST_MAX = 5  # at most this many (the latest) outlines

# --- screen layout (pixels) ------------------------------------------------------------------
INSET_BALL_RADIUS_PX = 5.0
SMALL_FONT_PX = 15
READOUT_FONT_PX = 21
STATE_FONT_PX = 40
BANNER_FONT_PX = 48
BANNER_DETAIL_FONT_PX = 24
BANNER_TOP_PX = 74  # below the side view's title and its wind arrow and label
INSET_SCALE_BAR_MAX_PX = 80.0
COMPASS_WIDTH_PX = 130
WIND_ARROW_PX_PER_MPS = 8.0
WIND_ARROW_MAX_PX = 90.0
HIT_STAR_RADIUS_PX = 9.0


# --- pure geometry ---------------------------------------------------------------------------


# --- layout ----------------------------------------------------------------------------------


# --- renderer --------------------------------------------------------------------------------


class ToppleRenderer(PygameRenderer[ToppleScene]):
    """Draws :class:`ToppleScene` frames, either into a window or into an RGB array.

    ``render(scene)`` returns a (height, width, 3) uint8 array in ``rgb_array`` mode and None in
    ``human`` mode; ``close()`` closes the window.
    """

    caption = "bbgym beach-ball topple"

    def __init__(
        self, render_mode: str, width: int = 640, height: int = 480, render_fps: int = 20
    ) -> None:
        super().__init__(render_mode, width, height, render_fps)

    # -- frame ---------------------------------------------------------------------------------

    def _draw_scene(self, scene: ToppleScene) -> None:
        self._surface.fill(READOUT_COLOR)
        frame = frame_state(scene)
        side = side_view_map(scene, self.width, self.height)
        top = top_view_map(scene, self.width, self.height)
        _, readout, _ = panel_rects(self.width, self.height)
        self._with_clip(side.rect, lambda: self._draw_side_view(scene, frame, side))
        self._with_clip(readout, lambda: self._draw_readout(scene, frame, readout))
        self._with_clip(top.rect, lambda: self._draw_top_view(scene, frame, top))
        pg = self._pg
        sx, sy, sw, sh = side.rect
        tx, ty, tw, th = top.rect
        pg.draw.line(
            self._surface, PANEL_EDGE_COLOR, (0, sy + sh - 1), (self.width, sy + sh - 1), 2
        )
        pg.draw.line(self._surface, PANEL_EDGE_COLOR, (tx, ty), (tx, ty + th), 2)

    # -- side view -----------------------------------------------------------------------------

    def _draw_side_view(self, scene: ToppleScene, frame: FrameState, view: ViewMap) -> None:
        pg, surf = self._pg, self._surface
        x, y, w, h = view.rect
        ground_y = view.origin_px[1]
        pg.draw.rect(surf, SKY_COLOR, view.rect)
        pg.draw.rect(surf, SAND_COLOR, (x, ground_y, w, y + h - ground_y))
        self._draw_side_grid(view)
        pg.draw.line(surf, GROUND_LINE_COLOR, (x, ground_y), (x + w, ground_y), 2)
        draw_side_thrower(pg, surf, view)
        self._draw_upright_guide(scene, view)
        if frame.loose:
            self._draw_loose_wall(scene, frame, view)
        else:
            self._draw_wall(scene, frame.pose, view)
            if frame.pivot_side != 0:
                px, pz = view.to_px(
                    scene.wall_distance_m + frame.pivot_side * scene.base_depth_m / 2, 0.0
                )
                pg.draw.circle(surf, PIVOT_COLOR, (px, pz), 4)
        panel, foot = self._wall_polygons(scene, frame.pose, view)
        self._draw_wall_marker(scene, frame.pose, [*panel, *foot], view)
        self._draw_side_hit(scene, frame, view)
        if frame.ball_index is not None:
            traj = np.asarray(scene.ball_trajectory_m, dtype=float).reshape(-1, 3)
            right, up = view_axes("side", (1.0, 0.0))
            radius = max(scene.ball_radius_m * view.pixels_per_meter, BALL_MIN_RADIUS_PX)
            draw_ball_flight(
                pg,
                surf,
                view,
                traj[:, [0, 2]],
                scene.ball_orientations,
                frame.ball_index,
                right,
                up,
                radius,
            )
        self._draw_side_wind(scene, view)
        self._draw_text("side view (looking north)", (x + 8, y + 6), LABEL_COLOR, SMALL_FONT_PX)
        shown = banner(scene, frame)
        if shown is not None:
            self._draw_banner(shown, view.rect)

    def _draw_side_grid(self, view: ViewMap) -> None:
        """Faint height lines every metre and distance ticks with labels along the ground."""
        pg, surf = self._pg, self._surface
        x, y, w, h = view.rect
        ppm = view.pixels_per_meter
        # Zoomed out (a tall or far wall), label every 5th height and 10th distance only, so
        # the labels do not run into each other.
        height_every = 1 if ppm >= 10 else 5
        distance_every = 2 if ppm >= 10 else 10
        top_m = int((view.origin_px[1] - y) / ppm)
        for k in range(1, top_m + 1):
            py = view.to_px(0.0, float(k))[1]
            pg.draw.line(surf, SKY_GRID_COLOR, (x, py), (x + w, py), 1)
            if k % height_every == 0:
                self._draw_text(f"{k} m", (x + w - 30, py - 12), LABEL_COLOR, SMALL_FONT_PX)
        s_first = math.ceil((x - view.origin_px[0]) / ppm)
        s_last = int((x + w - view.origin_px[0]) / ppm)
        for s in range(s_first, s_last + 1):
            px, py = view.to_px(float(s), 0.0)
            pg.draw.line(surf, GROUND_LINE_COLOR, (px, py), (px, py + (5 if s % 2 == 0 else 3)), 1)
            if s % distance_every == 0 and s > 0:
                label = self._get_font(SMALL_FONT_PX).render(f"{s}", True, LABEL_COLOR)
                surf.blit(label, (px - label.get_width() / 2, py + 4))

    def _draw_upright_guide(self, scene: ToppleScene, view: ViewMap) -> None:
        """A dashed vertical line where the upright panel would stand: the lean reads against it."""
        pg = self._pg
        d = scene.wall_distance_m
        n = 12
        for i in range(0, n, 2):
            a = view.to_px(d, scene.wall_height_m * i / n)
            b = view.to_px(d, scene.wall_height_m * (i + 1) / n)
            pg.draw.line(self._surface, UPRIGHT_GUIDE_COLOR, a, b, 1)

    def _wall_polygons(
        self, scene: ToppleScene, pose: WallPose, view: ViewMap
    ) -> tuple[list[Vec2], list[Vec2]]:
        """Pixel outlines of the panel and its foot (a low trapezoid) for ``pose``."""
        half_t = max(scene.wall_thickness_m, WALL_MIN_THICKNESS_PX / view.pixels_per_meter) / 2
        half_b = scene.base_depth_m / 2
        half_top = max(half_b * FOOT_TOP_FRACTION, 1.5 * half_t)
        panel_body = [
            (-half_t, 0.0),
            (half_t, 0.0),
            (half_t, scene.wall_height_m),
            (-half_t, scene.wall_height_m),
        ]
        foot_body = [
            (-half_b, 0.0),
            (half_b, 0.0),
            (half_top, FOOT_HEIGHT_M),
            (-half_top, FOOT_HEIGHT_M),
        ]

        def px(points: list[Vec2]) -> list[Vec2]:
            return [view.to_px(*pose.to_world(u, v)) for u, v in points]  # SafeDraw clips

        return px(panel_body), px(foot_body)

    def _draw_wall(
        self, scene: ToppleScene, pose: WallPose, view: ViewMap, fade: float = 0.0
    ) -> None:
        """The panel (thin rectangle) and its foot, rotated together; ``fade`` mixes in sky."""
        pg, surf = self._pg, self._surface
        panel, foot = self._wall_polygons(scene, pose, view)
        wall_c = blend(WALL_COLOR, SKY_COLOR, fade)
        edge_c = blend(WALL_EDGE_COLOR, SKY_COLOR, fade)
        foot_c = blend(FOOT_COLOR, SKY_COLOR, fade)
        if fade > 0.0:  # ghosts: the panel's outline only; the current wall is the solid one
            pg.draw.polygon(surf, edge_c, panel, 2)
            return
        pg.draw.polygon(surf, wall_c, panel)
        pg.draw.polygon(surf, edge_c, panel, 1)
        pg.draw.polygon(surf, foot_c, foot)
        pg.draw.polygon(surf, edge_c, foot, 1)

    def _draw_loose_wall(self, scene: ToppleScene, frame: FrameState, view: ViewMap) -> None:
        """The free panel, faded outlines where it tumbled, and the torn-up spot it left."""
        pg, surf = self._pg, self._surface
        d = scene.wall_distance_m
        # Where it tore off the ground: a jagged burst of churned earth at the foot.
        cx, cy = view.to_px(d, 0.0)
        r = max(8.0, scene.base_depth_m * view.pixels_per_meter * 0.7)
        burst = _star_points((cx, cy), r, r * 0.45, 7, 0.3)
        pg.draw.polygon(surf, SCAR_COLOR, burst)
        pg.draw.polygon(surf, WALL_EDGE_COLOR, burst, 1)
        trail = frame.loose_trail
        # Faded outlines where it tumbled, counted back from now: older ones fainter.
        ghosts = list(range(len(trail) - 1 - LOOSE_GHOST_EVERY, -1, -LOOSE_GHOST_EVERY))
        for age, i in reversed(list(enumerate(ghosts[:LOOSE_GHOST_MAX]))):
            self._draw_wall(scene, loose_pose(scene, trail[i]), view, fade=0.45 + 0.1 * age)
        if len(trail) >= 2:
            centres = [view.to_px(t[0], t[1]) for t in trail]
            pg.draw.lines(surf, STATE_COLORS["loose"], False, centres, 2)
        self._draw_wall(scene, frame.pose, view)

    def _draw_wall_marker(
        self, scene: ToppleScene, pose: WallPose, outline_px: list[Vec2], view: ViewMap
    ) -> None:
        """Edge marker (with the distance) for a wall, standing or loose, wholly out of ``view``;
        ``outline_px`` are its drawn outline's points."""
        xs = [p[0] for p in outline_px]
        ys = [p[1] for p in outline_px]
        centre = (0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys)))
        half_diagonal = 0.5 * math.hypot(max(xs) - min(xs), max(ys) - min(ys))
        wall_x, wall_z = pose.to_world(0.0, scene.wall_height_m / 2)
        self._draw_edge_marker(
            centre,
            view.rect,
            WALL_COLOR,
            math.hypot(wall_x, wall_z),
            pad=half_diagonal,
            font_size_px=SMALL_FONT_PX,
            label_color=LABEL_COLOR,
        )

    def _hit_world(self, scene: ToppleScene, frame: FrameState) -> tuple[Vec2, float] | None:
        """Where the hit mark is now (x, z) on the face, and its y; None before the impact."""
        found = hit_body_v(scene)
        if found is None or scene.hit_point_m is None:
            return None
        v, k_hit = found
        if frame.ball_index is not None and frame.ball_index < k_hit:
            return None  # the ball has not got there yet
        half_t = scene.wall_thickness_m / 2
        return frame.pose.to_world(-half_t, v), float(scene.hit_point_m[1])

    def _draw_side_hit(self, scene: ToppleScene, frame: FrameState, view: ViewMap) -> None:
        hit = self._hit_world(scene, frame)
        if hit is None:
            return
        c = view.to_px(*hit[0])
        self._draw_star(c, HIT_STAR_RADIUS_PX)

    def _draw_star(self, c: Vec2, r: float) -> None:
        pts = _star_points(c, r, r * 0.45, 8, 0.0)
        self._pg.draw.polygon(self._surface, HIT_STAR_COLOR, pts)
        self._pg.draw.polygon(self._surface, HIT_STAR_EDGE_COLOR, pts, 2)

    def _draw_side_wind(self, scene: ToppleScene, view: ViewMap) -> None:
        """The wind's x component (what pushes the wall) as an arrow in the sky, with speeds."""
        pg, surf = self._pg, self._surface
        x, y, _, _ = view.rect
        wx, wy = scene.wind_mps
        cx, cy = x + 16 + WIND_ARROW_MAX_PX / 2, y + 40
        # At least a short arrow for any breath of wind: its direction matters more than speed.
        length = min(max(abs(wx) * WIND_ARROW_PX_PER_MPS, 16.0), WIND_ARROW_MAX_PX)
        if abs(wx) >= 0.05:
            sgn = 1.0 if wx > 0 else -1.0
            tail = (cx - sgn * length / 2, cy)
            tip = (cx + sgn * length / 2, cy)
            pg.draw.line(surf, SIDE_WIND_COLOR, tail, (tip[0] - sgn * 8, cy), 4)
            pg.draw.polygon(
                surf,
                SIDE_WIND_COLOR,
                [tip, (tip[0] - sgn * 12, cy - 7), (tip[0] - sgn * 12, cy + 7)],
            )
        else:
            pg.draw.circle(surf, SIDE_WIND_COLOR, (cx, cy), 3)
        speed = math.hypot(wx, wy)
        self._draw_text(
            f"wind {speed:.1f} m/s, pushing x {wx:+.1f}",
            (x + 16, cy + 12),
            SIDE_WIND_COLOR,
            SMALL_FONT_PX + 2,
        )

    def _draw_banner(self, shown: Banner, rect: Rect) -> None:
        """A big banner (its colour says success or failure) across the top of ``rect``,
        its text made smaller where it would not fit."""
        pg = self._pg
        x, y, w, _ = rect
        size = BANNER_FONT_PX
        img = self._get_font(size).render(shown.text, True, BANNER_TEXT_COLOR)
        while img.get_width() + 36 > w - 8 and size > 20:
            size -= 4
            img = self._get_font(size).render(shown.text, True, BANNER_TEXT_COLOR)
        detail = None
        if shown.detail:
            font = self._get_font(BANNER_DETAIL_FONT_PX)
            detail = font.render(shown.detail, True, BANNER_TEXT_COLOR)
        detail_w = detail.get_width() if detail is not None else 0
        detail_h = detail.get_height() + 2 if detail is not None else 0
        bw = max(img.get_width(), detail_w) + 36
        bh = img.get_height() + detail_h + 14
        bx, by = x + (w - bw) / 2, y + BANNER_TOP_PX
        pg.draw.rect(self._surface, shown.color, (bx, by, bw, bh), border_radius=8)
        pg.draw.rect(self._surface, shown.edge_color, (bx, by, bw, bh), 3, border_radius=8)
        self._surface.blit(img, (bx + (bw - img.get_width()) / 2, by + 8))
        if detail is not None:
            dy = by + 8 + img.get_height() + 2
            self._surface.blit(detail, (bx + (bw - detail_w) / 2, dy))

    # -- top-view inset ------------------------------------------------------------------------

    def _draw_top_view(self, scene: ToppleScene, frame: FrameState, view: ViewMap) -> None:
        pg, surf = self._pg, self._surface
        x, y, w, h = view.rect
        pg.draw.rect(surf, SAND_COLOR, view.rect)
        ppm = view.pixels_per_meter
        # Metre lines from behind the thrower to past the wall, but only those in the inset:
        # a wall a thousand kilometres away must not cost a million lines.
        i_lo = max(math.floor(TOP_X_MIN_M), math.floor((x - view.origin_px[0]) / ppm))
        i_hi = min(
            math.ceil(scene.wall_distance_m + 4), math.ceil((x + w - view.origin_px[0]) / ppm) + 1
        )
        for i in range(i_lo, i_hi):
            px = view.to_px(float(i), 0.0)[0]
            pg.draw.line(surf, SAND_GRID_COLOR, (px, y), (px, y + h), 1)
        for j in range(-int(h / ppm) - 1, int(h / ppm) + 2):
            py = view.to_px(0.0, float(j))[1]
            pg.draw.line(surf, SAND_GRID_COLOR, (x, py), (x + w, py), 1)
        # Bottom left, under everything else (a ball or marker there stays in sight).
        bar_max = min(INSET_SCALE_BAR_MAX_PX, 0.4 * w)
        self._draw_scale_bar(view.pixels_per_meter, view.rect, LABEL_COLOR, bar_max)
        self._draw_top_wall(scene, frame, view)
        draw_top_windsock(
            pg,
            surf,
            self._get_font(SMALL_FONT_PX - 2),
            view,
            SOCK_POLE_M,
            scene.windsock_mps,
            label_min_y_px=4.0,
        )
        draw_top_thrower(pg, surf, view, (1.0, 0.0))
        hit = self._hit_world(scene, frame)
        if hit is not None:
            self._draw_star(view.to_px(hit[0][0], hit[1]), HIT_STAR_RADIUS_PX * 0.7)
        if frame.ball_index is not None:
            traj = np.asarray(scene.ball_trajectory_m, dtype=float).reshape(-1, 3)
            right, up = view_axes("top", (1.0, 0.0))
            radius = max(scene.ball_radius_m * ppm, INSET_BALL_RADIUS_PX)
            draw_ball_flight(
                pg,
                surf,
                view,
                traj[:, :2],
                scene.ball_orientations,
                frame.ball_index,
                right,
                up,
                radius,
                ghost_min_radius_px=3.0,
            )
        self._draw_text("top view", (x + w - 62, y + 4), LABEL_COLOR, SMALL_FONT_PX)

    def _draw_top_wall(self, scene: ToppleScene, frame: FrameState, view: ViewMap) -> None:
        """The wall from above: its footprint from foot to top (a line when upright)."""
        pg, surf = self._pg, self._surface
        half_w = scene.wall_width_m / 2
        half_b = scene.base_depth_m / 2
        if not frame.loose:
            foot = [view.to_px(*frame.pose.to_world(s * half_b, 0.0)) for s in (-1, 1)]
            xs = [p[0] for p in foot]
            y0, y1 = view.to_px(0.0, half_w)[1], view.to_px(0.0, -half_w)[1]
            pg.draw.rect(surf, FOOT_COLOR, (min(xs), y0, max(xs) - min(xs), y1 - y0), 1)
        bottom = frame.pose.to_world(0.0, 0.0)[0]
        top = frame.pose.to_world(0.0, scene.wall_height_m)[0]
        a, b = min(bottom, top), max(bottom, top)
        (ax, ay), (bx, by) = view.to_px(a, half_w), view.to_px(b, -half_w)
        thick = max(4.0, bx - ax)
        cx = 0.5 * (ax + bx)
        rect = (cx - thick / 2, ay, thick, by - ay)
        pg.draw.rect(surf, WALL_COLOR, rect)
        pg.draw.rect(surf, WALL_EDGE_COLOR, rect, 1)
        corners = [(cx - thick / 2, ay), (cx + thick / 2, by)]
        self._draw_wall_marker(scene, frame.pose, corners, view)

    # -- readout -------------------------------------------------------------------------------

    def _draw_readout(self, scene: ToppleScene, frame: FrameState, rect: Rect) -> None:
        """Big wall state, lean, throws, hits, last throw and the wind compass."""
        x, y, w, h = rect
        self._pg.draw.rect(self._surface, READOUT_COLOR, rect)
        left = x + 12
        line_y = y + 8
        state = frame.state if frame.state in STATE_LABELS else "standing"
        _, th = self._draw_text(
            STATE_LABELS[state], (left, line_y), STATE_COLORS[state], STATE_FONT_PX
        )
        line_y += th + 2
        lean = math.degrees(wrap_angle(frame.pose.angle_rad, floats))
        edge = {1: "far edge", -1: "near edge"}.get(frame.pivot_side, "on its foot")
        lines = [
            f"tumbling, at {lean:+.0f} deg" if frame.loose else f"lean {lean:+.1f} deg ({edge})",
            f"throws left {scene.throws_left}/{scene.throws_total}    hits {scene.hits}",
        ]
        for text in lines:
            _, th = self._draw_text(text, (left, line_y), TEXT_COLOR, READOUT_FONT_PX)
            line_y += th + 2
        found = hit_body_v(scene)
        if len(scene.ball_trajectory_m) == 0:
            last, color = "last: waited", DIM_TEXT_COLOR
        elif frame.ball_index is not None and frame.ball_index < (
            found[1] if found else len(scene.ball_trajectory_m) - 1
        ):
            last, color = "ball in the air...", DIM_TEXT_COLOR
        elif scene.hit_point_m is not None:
            last, color = (
                f"last: HIT at {scene.hit_point_m[2]:.2f} m up",
                STATE_COLORS["fallen_away"],
            )
        else:
            last, color = "last: missed", STATE_COLORS["fallen_toward"]
        self._draw_text(last, (left, line_y), color, READOUT_FONT_PX)
        # Bottom right, above the strip a recording's caption covers.
        bottom = y + h - (CAPTION_BAND_PX if y + h >= self.height else 0)
        draw_wind_compass(
            self._pg,
            self._surface,
            self._get_font(SMALL_FONT_PX + 2),
            (x + w - COMPASS_WIDTH_PX, bottom - 44, COMPASS_WIDTH_PX - 4, 40),
            scene.wind_mps,
        )


def _star_points(c: Vec2, r_out: float, r_in: float, spikes: int, phase: float) -> list[Vec2]:
    """A star/burst outline around ``c`` with ``spikes`` points."""
    pts: list[Vec2] = []
    for i in range(2 * spikes):
        r = r_out if i % 2 == 0 else r_in
        a = phase + math.pi * i / spikes - math.pi / 2
        pts.append((c[0] + r * math.cos(a), c[1] + r * math.sin(a)))
    return pts


__all__ = ["WALL_STATES", "ToppleRenderer"]
