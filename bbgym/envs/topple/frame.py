"""What a frame of the topple view shows, as numbers (no pygame): the scene a renderer
draws (:class:`ToppleScene`), the wall's pose at each sample of a step's interval, how an
episode ended (the banner), and the maps from metres to the panels' pixels. Conventions
are those of :mod:`bbgym.envs.topple.view`; the renderer there draws what these decide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bbgym.render.base import Color, Vec2
from bbgym.render.beach import (
    Rect,
    ViewMap,
)

WallState = str  # "standing" | "fallen_away" | "fallen_toward" | "loose"


STATE_COLORS: dict[str, Color] = {
    "standing": (190, 194, 202),
    "fallen_away": (46, 204, 84),
    "fallen_toward": (236, 64, 52),
    "loose": (255, 150, 20),
}


STATE_LABELS: dict[str, str] = {
    "standing": "STANDING",
    "fallen_away": "FELL AWAY",
    "fallen_toward": "FELL TOWARD YOU",
    "loose": "BROKE LOOSE!",
}


BANNER_EDGE_COLOR: Color = (150, 70, 0)


SUCCESS_BANNER_COLOR: Color = (34, 160, 70)


SUCCESS_BANNER_EDGE_COLOR: Color = (14, 84, 34)


FAILURE_BANNER_COLOR: Color = (200, 36, 36)


FAILURE_BANNER_EDGE_COLOR: Color = (110, 14, 14)


SIDE_X_MIN_M = -1.0  # the side view shows x from just behind the thrower...


SIDE_PAST_WALL_M = 4.0  # ...to this far past the wall (room for a wall lying flat)


SIDE_HEIGHT_M = 4.5  # at least this much height shows


VIEW_MAX_WALL_DISTANCE_M = 50.0  # both views fit a wall up to this far; a farther one is off


# view (with an edge marker) rather than shrinking the thrower and the throw to a dot
WALL_FIT_MARGIN_M = 0.3  # a tall wall (standing or lying either way) fits with this to spare...


VIEW_MAX_WALL_HEIGHT_M = 25.0  # ...up to this height or width (the physics takes up to 20 m)


TOP_X_MIN_M = -1.8


TOP_PAST_WALL_M = 3.0


TOP_HALF_Y_M = 2.6  # at least this much y either side of the centre line


FALLEN_TOLERANCE_RAD = 0.03  # within this of +-pi/2 a frame counts as lying flat


SIDE_PANEL_HEIGHT_FRACTION = 0.70


INSET_WIDTH_FRACTION = 0.40


PANEL_MARGIN_PX = 8


SIDE_GROUND_BAND_PX = 20


@dataclass(frozen=True)
class ToppleScene:
    """Everything the renderer needs for one frame; plain numbers, no physics objects."""

    wall_distance_m: float
    wall_height_m: float
    wall_width_m: float
    wall_thickness_m: float
    base_depth_m: float
    wall_angle_rad: float  # lean, + = top toward +x (away from the thrower); +-pi/2 = flat
    pivot_side: int  # +1 far foot edge, -1 near edge, 0 standing on its foot
    wall_state: WallState  # "standing" | "fallen_away" | "fallen_toward" | "loose"
    loose_panel: tuple[float, float, float] | None  # when loose: panel centre x, z and angle
    ball_trajectory_m: np.ndarray  # (K, 3) ball centres of the latest step, 0.05 s apart
    ball_orientations: np.ndarray  # (K, 4) unit quaternions (w, x, y, z)
    ball_radius_m: float
    wall_angle_samples: np.ndarray  # (K2,) lean at the same 0.05 s intervals
    loose_samples: np.ndarray  # (K2, 3) loose panel (x, z, angle), NaN rows while attached
    hit_point_m: tuple[float, float, float] | None  # where the last ball hit the face
    wind_mps: Vec2  # true wind (where the air moves)
    windsock_mps: Vec2
    throws_left: int = 0
    throws_total: int = 8
    hits: int = 0
    frame_index: int | None = None  # draw the state at sample k; None = the final state


@dataclass(frozen=True)
class Banner:
    """A big banner across the side view: ``text``, a smaller ``detail`` line under it."""

    text: str
    detail: str
    color: Color
    edge_color: Color
    success: bool


@dataclass(frozen=True)
class WallPose:
    """Where the wall's body frame is in the x-z plane: body (u, v) -> world (x, z)."""

    origin_m: Vec2  # world position of the middle of the foot's bottom face
    angle_rad: float  # + = top toward +x

    def to_world(self, u: float, v: float) -> Vec2:
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        return (self.origin_m[0] + u * c + v * s, self.origin_m[1] - u * s + v * c)

    def to_body(self, x: float, z: float) -> Vec2:
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        dx, dz = x - self.origin_m[0], z - self.origin_m[1]
        return (dx * c - dz * s, dx * s + dz * c)


@dataclass(frozen=True)
class FrameState:
    """What one frame shows: the ball's trajectory index, the wall pose and its state."""

    ball_index: int | None  # None: no throw this step
    pose: WallPose
    loose: bool
    state: WallState  # the state to announce in this frame
    pivot_side: int  # the edge it rotates about (0: upright or loose)
    loose_trail: tuple[Triple, ...]  # loose samples (x, z, angle) up to this frame
    sample: int | None  # the sample index drawn (None: the final scalar state)


def pivot_side_for(angle_rad: float, hint: int = 0) -> int:
    """Foot edge a wall leaning by ``angle_rad`` rotates about: +1 far, -1 near, 0 upright."""
    if angle_rad > 0.0:
        return 1
    if angle_rad < 0.0:
        return -1
    return int(np.sign(hint))


def attached_pose(scene: ToppleScene, angle_rad: float, hint: int = 0) -> WallPose:
    """Pose of a wall on the ground leaning by ``angle_rad`` about its pivot edge."""
    side = pivot_side_for(angle_rad, hint)
    pivot_u = side * scene.base_depth_m / 2  # the pivot edge, in body coordinates (v = 0)
    pivot_world = (scene.wall_distance_m + pivot_u, 0.0)
    # origin + R(angle) @ (pivot_u, 0) = pivot_world
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return WallPose((pivot_world[0] - pivot_u * c, pivot_world[1] + pivot_u * s), angle_rad)


def loose_pose(scene: ToppleScene, panel: tuple[float, float, float]) -> WallPose:
    """Pose of a loose wall whose panel centre is at (x, z) with the given angle."""
    x, z, angle = (float(v) for v in panel)
    c, s = math.cos(angle), math.sin(angle)
    half_h = scene.wall_height_m / 2  # the centre is body point (0, half_h)
    return WallPose((x - half_h * s, z - half_h * c), angle)


Triple = tuple[float, float, float]


def _triple(row: np.ndarray | tuple[float, ...]) -> Triple:
    return (float(row[0]), float(row[1]), float(row[2]))


def frame_state(scene: ToppleScene) -> FrameState:
    """Resolve ``frame_index`` into what to draw (see :attr:`ToppleScene.frame_index`)."""
    traj = np.asarray(scene.ball_trajectory_m, dtype=float).reshape(-1, 3)
    angles = np.asarray(scene.wall_angle_samples, dtype=float).reshape(-1)
    loose = np.asarray(scene.loose_samples, dtype=float).reshape(-1, 3)
    n_samples = min(len(angles), len(loose)) if len(loose) else len(angles)
    k = scene.frame_index
    ball_index: int | None = None
    if len(traj):
        ball_index = len(traj) - 1 if k is None else min(max(int(k), 0), len(traj) - 1)

    loose_ok = np.all(np.isfinite(loose), axis=1)
    if k is None or n_samples == 0:
        # The final state: the scalar fields.
        trail = tuple(_triple(row) for row in loose[loose_ok])
        panel = None if scene.loose_panel is None else _triple(scene.loose_panel)
        if scene.wall_state == "loose" and panel is None and trail:
            panel = trail[-1]
        if scene.wall_state == "loose" and panel is not None:
            pose = loose_pose(scene, panel)
            return FrameState(ball_index, pose, True, "loose", 0, trail, None)
        pose = attached_pose(scene, scene.wall_angle_rad, scene.pivot_side)
        side = pivot_side_for(scene.wall_angle_rad, scene.pivot_side)
        return FrameState(ball_index, pose, False, scene.wall_state, side, (), None)

    s = min(max(int(k), 0), n_samples - 1)
    last = s >= n_samples - 1
    if s < len(loose) and loose_ok[s]:
        trail = tuple(_triple(row) for row in loose[: s + 1][loose_ok[: s + 1]])
        return FrameState(
            ball_index, loose_pose(scene, _triple(loose[s])), True, "loose", 0, trail, s
        )
    angle = float(angles[s]) if s < len(angles) and math.isfinite(angles[s]) else 0.0
    if last and scene.wall_state != "loose":
        state = scene.wall_state
    elif (
        scene.wall_state in ("fallen_away", "fallen_toward")
        and abs(abs(angle) - math.pi / 2) <= FALLEN_TOLERANCE_RAD
    ):
        state = scene.wall_state
    else:
        state = "standing"
    hint = scene.pivot_side if last else 0
    pose = attached_pose(scene, angle, hint)
    return FrameState(ball_index, pose, False, state, pivot_side_for(angle, hint), (), s)


def is_final_frame(scene: ToppleScene, frame: FrameState | None = None) -> bool:
    """The frame shows the end of the step (``frame_index`` None, or its last sample)."""
    if scene.frame_index is None:
        return True
    frame = frame if frame is not None else frame_state(scene)
    if frame.sample is None:
        return True
    angles = np.asarray(scene.wall_angle_samples).reshape(-1)
    loose = np.asarray(scene.loose_samples).reshape(-1, 3)
    n_samples = min(len(angles), len(loose)) if len(loose) else len(angles)
    return frame.sample >= n_samples - 1


def banner(scene: ToppleScene, frame: FrameState | None = None) -> Banner | None:
    """The banner a frame gets: how the episode ends, as soon as the frame shows it.

    The wall fell away (success), broke loose (success: its banner shows while it tumbles)
    or fell toward the thrower (failure); or, on the final frame of the last throw, it still
    stands (failure: out of throws). None while the episode goes on.
    """
    frame = frame if frame is not None else frame_state(scene)
    used = scene.throws_total - scene.throws_left
    throws = f"{used} throw" + ("" if used == 1 else "s")
    if frame.state == "loose":
        color = STATE_COLORS["loose"]
        return Banner(
            STATE_LABELS["loose"], f"wall down after {throws}", color, BANNER_EDGE_COLOR, True
        )
    if frame.state == "fallen_away":
        return Banner(
            "WALL DOWN!",
            f"it fell away after {throws}",
            SUCCESS_BANNER_COLOR,
            SUCCESS_BANNER_EDGE_COLOR,
            True,
        )
    if frame.state == "fallen_toward":
        return Banner(
            "FAILED: wall fell toward you",
            f"after {throws}",
            FAILURE_BANNER_COLOR,
            FAILURE_BANNER_EDGE_COLOR,
            False,
        )
    if scene.throws_left <= 0 and is_final_frame(scene, frame):
        return Banner(
            "FAILED: out of throws",
            f"wall still standing after {throws}",
            FAILURE_BANNER_COLOR,
            FAILURE_BANNER_EDGE_COLOR,
            False,
        )
    return None


def hit_body_v(scene: ToppleScene) -> tuple[float, int] | None:
    """The hit's height along the panel (body v) and the trajectory index of the impact.

    The wall may have moved since: the hit is found on the wall as it stood at the sample
    nearest the impact, so the mark can ride on the panel afterwards.
    """
    if scene.hit_point_m is None:
        return None
    hx, _, hz = (float(v) for v in scene.hit_point_m)
    traj = np.asarray(scene.ball_trajectory_m, dtype=float).reshape(-1, 3)
    ok = np.all(np.isfinite(traj), axis=1)
    k_hit = 0
    if np.any(ok):
        dist = np.where(ok, np.linalg.norm(traj - np.asarray(scene.hit_point_m), axis=1), np.inf)
        k_hit = int(np.argmin(dist))
    angles = np.asarray(scene.wall_angle_samples, dtype=float).reshape(-1)
    angle = scene.wall_angle_rad if len(angles) == 0 else float(angles[min(k_hit, len(angles) - 1)])
    if not math.isfinite(angle):
        angle = 0.0
    _, v = attached_pose(scene, angle, scene.pivot_side).to_body(hx, hz)
    return min(max(v, 0.0), scene.wall_height_m), k_hit


def panel_rects(width: int, height: int) -> tuple[Rect, Rect, Rect]:
    """(side view, readout, top-view inset) rectangles for a frame of ``width`` x ``height``."""
    side_h = round(height * SIDE_PANEL_HEIGHT_FRACTION)
    inset_w = round(width * INSET_WIDTH_FRACTION)
    low_h = height - side_h
    return (
        (0, 0, width, side_h),
        (0, side_h, width - inset_w, low_h),
        (width - inset_w, side_h, inset_w, low_h),
    )


def side_view_map(scene: ToppleScene, width: int, height: int) -> ViewMap:
    """Side view: a = x, b = z, ground at the panel bottom; x in [-1, d + 4] and z in [0, 4.5]
    always fit (equal scale on both axes, set by the wall distance only), and more for a wall
    taller than about 3.5 m, so that it fits standing and lying either way. A wall beyond
    VIEW_MAX_WALL_DISTANCE_M is fitted as if there (it gets an edge marker)."""
    rect, _, _ = panel_rects(width, height)
    x, y, w, h = rect
    d, reach = _fitted_wall_distance_m(scene), _wall_reach_m(scene)
    x0 = min(SIDE_X_MIN_M, d - reach)
    x1 = d + max(SIDE_PAST_WALL_M, reach)
    ground_y = y + h - SIDE_GROUND_BAND_PX
    ppm = min(
        (w - 2 * PANEL_MARGIN_PX) / (x1 - x0),
        (ground_y - y - PANEL_MARGIN_PX)
        / max(SIDE_HEIGHT_M, min(scene.wall_height_m, VIEW_MAX_WALL_HEIGHT_M) + WALL_FIT_MARGIN_M),
    )
    ppm = max(ppm, 1e-6)
    # Centre the x range horizontally (there is slack when the height limits the scale).
    left = x + w / 2 - 0.5 * (x1 - x0) * ppm
    return ViewMap(rect, (left - x0 * ppm, float(ground_y)), ppm)


def _fitted_wall_distance_m(scene: ToppleScene) -> float:
    return min(scene.wall_distance_m, VIEW_MAX_WALL_DISTANCE_M)


def _wall_reach_m(scene: ToppleScene) -> float:
    """How far from the wall's foot (x = d) a flat-lying wall reaches, with a margin (no
    farther than VIEW_MAX_WALL_HEIGHT_M: a bigger one just runs out of the view)."""
    reach = scene.wall_height_m + scene.base_depth_m / 2
    return min(reach, VIEW_MAX_WALL_HEIGHT_M) + WALL_FIT_MARGIN_M


def top_view_map(scene: ToppleScene, width: int, height: int) -> ViewMap:
    """Top-view inset: a = x (east), b = y (north); x in [-1.8, d + 3] (more for a wall taller
    than about 2.5 m, as in :func:`side_view_map`), y centred on 0."""
    _, _, rect = panel_rects(width, height)
    x, y, w, h = rect
    d, reach = _fitted_wall_distance_m(scene), _wall_reach_m(scene)
    x0, x1 = min(TOP_X_MIN_M, d - reach), d + max(TOP_PAST_WALL_M, reach)
    half_y = max(TOP_HALF_Y_M, min(scene.wall_width_m, VIEW_MAX_WALL_HEIGHT_M) / 2 + 0.5)
    ppm = min((w - 2 * PANEL_MARGIN_PX) / (x1 - x0), (h - 2 * PANEL_MARGIN_PX) / (2 * half_y))
    ppm = max(ppm, 1e-6)
    origin = (x + w / 2 - 0.5 * (x0 + x1) * ppm, y + h / 2)
    return ViewMap(rect, origin, ppm)


__all__ = [
    "Banner",
    "FrameState",
    "ToppleScene",
    "WallPose",
    "attached_pose",
    "banner",
    "frame_state",
    "is_final_frame",
    "loose_pose",
    "panel_rects",
    "pivot_side_for",
    "side_view_map",
    "top_view_map",
]
