"""What the sailing renderer draws, described from one env's state (the renderer does no
physics).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from bbgym.envs.common import (
    renderer_mode,
)
from bbgym.envs.sail.task import RENDER_PIXELS_PER_M, SailState, SailTask
from bbgym.physics.namespace import floats
from bbgym.physics.sailing import (
    apparent_wind_body,
    sail_force,
)


def make_renderer(env: Any) -> Any:
    from bbgym.envs.sail.view import SailRenderer

    return SailRenderer(
        renderer_mode(env.render_mode),
        pixels_per_meter=RENDER_PIXELS_PER_M,
        render_fps=env.metadata["render_fps"],  # real time: one frame per env step
    )


def describe_scene(task: SailTask, state: SailState, wake: tuple, action: np.ndarray) -> Any:
    """Drawing description of one env's state, as floats (the renderer does no physics)."""
    from bbgym.envs.sail.view import SailScene

    xp = floats
    boat, scenario = state.boat, state.scenario
    jibes, tacks, elapsed = int(state.jibes), int(state.tacks), float(state.elapsed_s)
    p = task.params
    m = task.measure(state, xp)
    wind_x, wind_y, _, _ = task.wind(state, xp)
    cos_h, sin_h = xp.cos(boat.heading_rad), xp.sin(boat.heading_rad)
    aw_u, aw_v = apparent_wind_body(boat, wind_x, wind_y, cos_h, sin_h)
    sail_normal_n = abs(sail_force(p, boat, aw_u, aw_v, xp)[2])
    return SailScene(
        time_s=elapsed,
        position_m=(boat.x_m, boat.y_m),
        heading_rad=boat.heading_rad,
        heel_rad=boat.heel_rad,
        boom_angle_rad=boat.boom_rad,
        rudder_angle_rad=float(action[0]) * p.rudder_max_rad,
        sail_force_n=sail_normal_n,
        sail_luffing=sail_normal_n < 5.0,
        mark_m=(scenario.mark_x_m, scenario.mark_y_m),
        mark_radius_m=task.mark_radius,
        true_wind_mps=(wind_x, wind_y),
        apparent_wind_speed_mps=m["apparent_wind_speed"],
        apparent_wind_angle_rad=m["apparent_wind_angle"],
        boat_speed_mps=m["boat_speed"],
        wake_m=wake,
        capsized=boat.capsized,
        hull_length_m=p.hull_length_m,
        hull_beam_m=p.hull_beam_m,
        boom_length_m=p.boom_length_m,
        jibes=jibes,
        tacks=tacks,
    )
