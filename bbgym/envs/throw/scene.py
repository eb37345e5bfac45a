"""What the throw renderer draws, described from one env's state and flight records."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from bbgym.envs.common import (
    renderer_mode,
)
from bbgym.envs.throw.records import FlightRecords
from bbgym.envs.throw.task import ThrowState, ThrowTask
from bbgym.physics.namespace import floats
from bbgym.physics.wind import wind_vector


def flight_scenes(scene: Any) -> list[Any]:
    """The in-flight frames of a throw's scene: the ball at each recorded point but the
    last, with no landing shown yet."""
    in_flight = replace(scene, landing_m=None, hit=False, miss_distance_m=None)
    return [replace(in_flight, frame_index=k) for k in range(len(scene.trajectory_m) - 1)]


def make_renderer(env: Any) -> Any:
    from bbgym.envs.throw.view import ThrowRenderer

    return ThrowRenderer(renderer_mode(env.render_mode), render_fps=env.metadata["render_fps"])


def describe_scene(
    task: ThrowTask, state: ThrowState, records: FlightRecords, previous: tuple
) -> Any:
    """Drawing description of one env's latest throw, from its state as floats and its
    records (no physics in the renderer)."""
    from bbgym.envs.throw.view import ThrowScene, ThrowScreen

    xp = floats
    scenario = state.scenario
    wind_x, wind_y, _, _ = wind_vector(scenario.wind_speed, scenario.wind_from, state.gust, xp)
    screen = None
    if scenario.screen:
        g = task.screen_geometry(scenario, xp)
        screen = ThrowScreen(
            center_m=(g.center_x, g.center_y),
            along_m=(g.along_x, g.along_y),
            half_width_m=task.screen_half_width,
            height_m=task.screen_height,
        )
    thrown = bool(state.thrown)
    trajectory, orientations = records.recorded()
    return ThrowScene(
        trajectory_m=trajectory,
        orientations=orientations,
        ball_radius_m=task.ball.radius_m,
        target_m=(scenario.target_x, scenario.target_y),
        target_radius_m=task.target_radius,
        wind_mps=(wind_x, wind_y),
        windsock_mps=(float(state.sock_x), float(state.sock_y)),
        screen=screen,
        landing_m=(float(state.landing_x), float(state.landing_y)) if thrown else None,
        previous_landings_m=previous,
        hit=bool(state.is_success),
        throws_left=int(state.throws_left),
        throws_total=task.throws_per_episode,
        miss_distance_m=float(state.miss_distance) if thrown else None,
        spin_parameter=float(state.spin_parameter),
        flight_time_s=float(state.flight_time) if thrown else None,
        apex_height_m=float(state.apex_height) if thrown else None,
    )
