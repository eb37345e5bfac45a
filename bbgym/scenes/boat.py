"""The first boat demo (§9): the three points of sail the text describes, with the boat's
heading and its sail set directly, on the sail envs' own dinghy.

Three boats head east, held on that heading (no rudder: the bow is set, as in the text's
demo), each with the true wind from its own angle and its sheet at its own setting: running
before the wind (wind from astern, the sail out square), a beam reach ("sidewind", wind
from the side, the sail about 45 deg out) and beating (wind 50 deg off the bow, the sail
nearly in). Each is stepped by the envs' dinghy physics
(:func:`bbgym.physics.sailing_step.substep`: the planar, friction-free sail's normal
force, the hull and keel's drag split along and across the boat, heel), from 1 m/s, as
:func:`bbgym.physics.polar.sail_steady` sails the polar's boats.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from bbgym.physics.dinghy import DinghyParams, DinghyState, dinghy_moving
from bbgym.physics.namespace import Array, replaced
from bbgym.physics.sailing_step import substep
from bbgym.physics.validation import CheckedFields, interval, param
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment

HULL = (120, 80, 40)
SAIL = (170, 150, 60)
WIND = (60, 120, 220)
LANES_M = (8.0, 0.0, -8.0)
"""Where the view draws each boat (across the picture): run, reach, beat."""


@dataclass(frozen=True)
class PointsOfSailParams(CheckedFields):
    """The three boats' true wind angles (off the bow) and sheets (0 in .. 1 out)."""

    wind_speed_mps: float = param(5.0, interval(0.5, 15.0))
    run_angle_deg: float = param(180.0, interval(0.0, 180.0))
    run_sheet: float = param(1.0, interval(0.0, 1.0))
    reach_angle_deg: float = param(90.0, interval(0.0, 180.0))
    reach_sheet: float = param(0.5, interval(0.0, 1.0))
    beat_angle_deg: float = param(50.0, interval(0.0, 180.0))
    beat_sheet: float = param(0.2, interval(0.0, 1.0))
    dt_s: float = param(0.05, interval(0.005, 0.1))

    def angles_rad(self) -> tuple[float, float, float]:
        return tuple(
            math.radians(a) for a in (self.run_angle_deg, self.reach_angle_deg, self.beat_angle_deg)
        )

    def sheets(self) -> tuple[float, float, float]:
        return self.run_sheet, self.reach_sheet, self.beat_sheet


DINGHY = DinghyParams()
"""The sail envs' dinghy, as registered."""


def boom_limits(p: PointsOfSailParams) -> np.ndarray:
    """How far each sheet lets the boom out (rad)."""
    low, high = DINGHY.sheet_min_rad, DINGHY.sheet_max_rad
    return np.array([low + s * (high - low) for s in p.sheets()])


def points_initial(p: PointsOfSailParams, xp: Any) -> DinghyState:
    """Heading east at 1 m/s, each boom at its sheet's limit on the leeward side."""
    zeros = xp.zeros((3,), dtype=xp.float64)
    limits = xp.asarray(boom_limits(p), dtype=xp.float64)
    return dinghy_moving(zeros, 1.0 + zeros, -limits, xp)


def points_step(p: PointsOfSailParams, s: DinghyState, xp: Any) -> DinghyState:
    """One step of the envs' dinghy physics, the bow then set back on its heading."""
    twa = xp.asarray(p.angles_rad(), dtype=xp.float64)
    wind_x, wind_y = -p.wind_speed_mps * xp.cos(twa), -p.wind_speed_mps * xp.sin(twa)
    limits = xp.asarray(boom_limits(p), dtype=xp.float64)
    moved, _, _ = substep(DINGHY, s, 0.0 * twa, limits, wind_x, wind_y, p.dt_s, xp)
    return replaced(moved, heading_rad=0.0 * twa, yaw_rate_rps=0.0 * twa)


def points_measures(p: PointsOfSailParams, s: DinghyState, xp: Any) -> dict[str, Array]:
    """Speed ahead, the drift (leeway, deg: the sideways velocity's angle), the velocity
    made good toward the wind, the boom's angle and the heel."""
    twa = xp.asarray(p.angles_rad(), dtype=xp.float64)
    return {
        "speed_mps": s.vx_mps,
        "drift_deg": 180.0 / math.pi * xp.atan2(-s.vy_mps, xp.abs(s.vx_mps) + 1e-9),
        "vmg_mps": s.vx_mps * xp.cos(twa) + s.vy_mps * xp.sin(twa),
        "boom_deg": 180.0 / math.pi * xp.abs(s.boom_rad),
        "heel_deg": 180.0 / math.pi * xp.abs(s.heel_rad),
    }


def points_frame(p: PointsOfSailParams, s: DinghyState) -> Frame:
    segments, circles = [], []
    half = 0.5 * DINGHY.hull_length_m
    for k, (lane, twa) in enumerate(zip(LANES_M, p.angles_rad(), strict=True)):
        boom = float(np.asarray(s.boom_rad)[k])
        speed = float(np.asarray(s.vx_mps)[k])
        segments.append(Segment(-half, lane, half, lane, HULL, 6))
        mast = 0.2 * half
        # the boom from the aft-pointing centreline, + to port (the sail view's convention)
        segments.append(
            Segment(mast, lane, mast - 2.0 * math.cos(boom), lane + 2.0 * math.sin(boom), SAIL, 4)
        )
        # the wind: an arrow blowing at the boat from where it comes, its head just clear
        # of the hull (an ellipse around it), so it stays by its own boat, not between two
        wx, wy = math.cos(twa), math.sin(twa)
        reach = half * abs(wx) + 1.0 * abs(wy) + 0.4
        tip = (reach * wx, lane + reach * wy)
        segments.append(Segment(tip[0] + 2.5 * wx, tip[1] + 2.5 * wy, *tip, WIND, 2))
        for side in (-0.45, 0.45):  # the arrowhead's two barbs
            bx, by = math.cos(twa + side), math.sin(twa + side)
            segments.append(Segment(tip[0] + 0.7 * bx, tip[1] + 0.7 * by, *tip, WIND, 2))
        segments.append(Segment(half, lane, half + speed, lane, (230, 70, 60), 3))
        name = ("run", "reach", "beat")[k]
        # the name and speed well astern, clear of the boom and of a wind from astern
        circles.append(Circle(-half - 5.5, lane, 0.15, WIND, f"{name}: {speed:.2f} m/s"))
    return Frame(
        circles,
        segments,
        [f"true wind {p.wind_speed_mps:g} m/s (blue), seen from above; red: the boat's speed"],
    )


POINTS_OF_SAIL = Scene(
    name="points-of-sail",
    section="§9",
    title="Boat 1: the three points of sail",
    claim="with the bow and the sheet set, each boat sails ahead: fastest on the beam "
    "reach, slower than the wind running before it, and beating it makes ground to "
    "windward, with the most drift",
    params=PointsOfSailParams,
    functions=SceneFunctions(points_initial, points_step, points_measures, points_frame),
    view_box_m=lambda p: (-11.5, 8.5, -10.5, 10.5),
    duration_s=lambda p: 60.0,
    bodies=("run", "reach", "beat"),
    test="test_points_of_sail_reach_fastest_run_slower_than_the_wind_beat_to_windward",
    floor=False,
)

SCENES = (POINTS_OF_SAIL,)
