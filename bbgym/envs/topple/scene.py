"""What the topple renderer draws, described from one env's state and step samples."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np

from bbgym.envs.common import (
    renderer_mode,
)
from bbgym.envs.topple.records import recorded_rows
from bbgym.envs.topple.task import ToppleState, ToppleTask
from bbgym.physics.namespace import floats
from bbgym.physics.wall import (
    LOOSE,
    STATE_NAMES,
)


def flight_scenes(scene: Any) -> list[Any]:
    """The frames of a step's interval: the scene at each sample."""
    return [replace(scene, frame_index=k) for k in range(len(scene.wall_angle_samples))]


def make_renderer(env: Any) -> Any:
    from bbgym.envs.topple.view import ToppleRenderer

    return ToppleRenderer(renderer_mode(env.render_mode), render_fps=env.metadata["render_fps"])


def describe_scene(task: ToppleTask, state: ToppleState, record: dict[str, Any]) -> Any:
    """Drawing description of one env's state, as floats, and its last step's samples (one
    env's :func:`step_records`; no physics in the renderer)."""
    from bbgym.envs.topple.frame import ToppleScene

    record = recorded_rows(record)
    sc, wall = state.scenario, state.wall
    m = task.measure(state, floats)
    status = int(wall.status)
    hit_point = None
    if float(state.hit_height) >= 0.0 and float(state.last_hit) > 0:
        hit_point = (float(sc.wall_distance), float(state.hit_y), float(state.hit_height))
    wp = task.wall
    return ToppleScene(
        wall_distance_m=float(sc.wall_distance),
        wall_height_m=wp.height_m,
        wall_width_m=wp.width_m,
        wall_thickness_m=wp.thickness_m,
        base_depth_m=wp.base_depth_m,
        wall_angle_rad=float(wall.angle),
        pivot_side=int(wall.pivot),
        wall_state=STATE_NAMES[status],
        loose_panel=(wall.loose_x, wall.loose_z, wall.loose_angle) if status == LOOSE else None,
        ball_trajectory_m=record["ball_trajectory"],
        ball_orientations=record["ball_orientations"],
        ball_radius_m=task.ball.radius_m,
        wall_angle_samples=record["wall_angle_samples"],
        # The renderer marks samples of an attached wall as NaN rows.
        loose_samples=np.where(record["loose_mask"][:, None], record["loose_samples"], np.nan),
        hit_point_m=hit_point,
        wind_mps=(m["wind_x"], m["wind_y"]),
        windsock_mps=(m["sock_x"], m["sock_y"]),
        throws_left=int(state.throws_left),
        throws_total=task.throws_per_episode,
        hits=int(state.hits),
    )
