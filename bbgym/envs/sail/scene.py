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
from bbgym.physics.water import current_velocity, waves_at

VIEW_HALF_M = (24.0, 18.0)
"""Half the width and height of the water the sea is drawn over: the 640 x 480 view at
16 px/m is 20 m by 15 m each way, and a little more covers a heeled or turning frame."""


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
        **_rig_and_sea(task, state, m),
    )


def _world_lattice(centre: tuple, spacing_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Points on a world-fixed lattice covering the view about ``centre``."""
    axes = [
        spacing_m * np.arange(np.floor((c - h) / spacing_m), np.ceil((c + h) / spacing_m) + 1)
        for c, h in zip(centre, VIEW_HALF_M, strict=True)
    ]
    ys, xs = np.meshgrid(axes[1], axes[0], indexing="ij")  # rows along y
    return xs, ys


def _rig_and_sea(task: SailTask, state: SailState, m: dict) -> dict[str, Any]:
    """The jib, the current arrows and the sea's height over the view (what exists)."""
    from bbgym.envs.sail.view import CURRENT_ARROW_SPACING_M, MAST_FROM_BOW, WAVE_CELL_M

    p, boat, out = task.params, state.boat, {}
    if task.sloop:
        mast_x = p.hull_length_m * (0.5 - MAST_FROM_BOW)
        # The drawing's mast sits where the hull's third is; the forestay keeps its distance.
        tack_x = min(mast_x + p.jib_tack_ahead_m - p.mast_ahead_m, 0.5 * p.hull_length_m)
        out["jib_angle_rad"] = float(m["jib_angle"])
        out["jib_tack_body_m"] = (tack_x, 0.0)
        out["jib_foot_m"] = 3.0 * p.jib_ce_aft_m  # a triangle's centre is a third along
    if not task.moving_water:
        return out
    centre = (boat.x_m, boat.y_m)
    xs, ys = _world_lattice(centre, CURRENT_ARROW_SPACING_M)
    vx, vy = current_velocity(task.water, state.sea, xs, ys, np)
    out["current_arrows"] = tuple(
        ((float(x), float(y)), (float(u), float(v)))
        for x, y, u, v in zip(xs.ravel(), ys.ravel(), np.ravel(vx), np.ravel(vy), strict=True)
    )
    here = current_velocity(task.water, state.sea, boat.x_m, boat.y_m, xp=floats)
    out["current_mps"] = float(np.hypot(*here))
    if task.water.components:
        xs, ys = _world_lattice(centre, WAVE_CELL_M)
        height = waves_at(task.water, state.sea, xs, ys, np)[3]
        rows = np.clip(height / sum(c.amplitude_m for c in task.water.components), -1.0, 1.0)
        out["wave_cells"] = ((float(xs[0, 0]), float(ys[0, 0])), tuple(map(tuple, rows.tolist())))
    return out
