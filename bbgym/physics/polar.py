"""The dinghy's polar diagram, computed from the physics (not typed in).

For each true wind angle the boat is held on a fixed heading (as a helmsman holding a
course would) and sailed to steady state for each sheet setting in a grid, all in one
batch; the best sheet per angle gives the polar: boat speed, velocity made good upwind,
leeway and heel.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bbgym.physics.dinghy import DinghyParams, DinghyState, dinghy_at_rest
from bbgym.physics.namespace import replaced
from bbgym.physics.sailing_step import substep


@dataclass
class Polar:
    """Steady-state performance by true wind angle (arrays of shape ``(angles,)``)."""

    wind_speed_mps: float
    true_wind_angle_rad: np.ndarray
    boat_speed_mps: np.ndarray
    vmg_mps: np.ndarray
    """Velocity made good toward the wind (negative: losing ground to leeward)."""
    leeway_rad: np.ndarray
    """Drift angle to leeward while moving ahead (NaN where the boat is pushed astern)."""
    heel_rad: np.ndarray
    sheet: np.ndarray
    """Best sheet setting found, 0 (in) .. 1 (out)."""
    capsized: np.ndarray

    def best_upwind(self) -> tuple[float, float]:
        """(true wind angle, VMG) of the best upwind VMG."""
        i = int(np.argmax(self.vmg_mps))
        return float(self.true_wind_angle_rad[i]), float(self.vmg_mps[i])

    def fastest(self) -> tuple[float, float]:
        """(true wind angle, boat speed) of the fastest point of sail."""
        i = int(np.argmax(self.boat_speed_mps))
        return float(self.true_wind_angle_rad[i]), float(self.boat_speed_mps[i])


def sail_steady(
    params: DinghyParams,
    wind_speed_mps: np.ndarray,
    true_wind_angle_rad: np.ndarray,
    sheet: np.ndarray,
    duration_s: float = 90.0,
    dt_s: float = 0.05,
) -> DinghyState:
    """Boats (one per element of the equal-shaped arrays) held on heading 0 (east) with
    the wind from ``true_wind_angle_rad`` counterclockwise of the bow (from port) and the
    sheet at ``sheet`` (0 in .. 1 out), sailed for ``duration_s``: their final state."""
    twa = np.asarray(true_wind_angle_rad, dtype=np.float64)
    batch = twa.size
    wind_x, wind_y = -wind_speed_mps * np.cos(twa), -wind_speed_mps * np.sin(twa)
    limit = params.sheet_min_rad + sheet * (params.sheet_max_rad - params.sheet_min_rad)
    state = dinghy_at_rest(batch, speed_mps=1.0, boom_rad=-limit)
    rudder = np.zeros(batch)
    # A sloop's jib is trimmed with the main, on the leeward (starboard) sheet: in as far
    # as the main is in.
    jib_sheet = sheet - 1.0 if params.rig == "sloop" else None
    for _ in range(int(round(duration_s / dt_s))):
        state, _, _ = substep(
            params, state, rudder, limit, wind_x, wind_y, dt_s, jib_sheet=jib_sheet
        )
        # Hold the course: the helmsman keeps the bow where it is.
        state = replaced(state, heading_rad=np.zeros(batch), yaw_rate_rps=np.zeros(batch))
    return state


def compute_polar(
    params: DinghyParams | None = None,
    wind_speed_mps: float = 5.0,
    true_wind_angles_rad: np.ndarray | None = None,
    sheets: np.ndarray | None = None,
    duration_s: float = 90.0,
    dt_s: float = 0.05,
) -> Polar:
    """Sail every (angle, sheet) pair on a held heading until steady; keep the best sheet.

    The best sheet maximises speed through the water, as a sailor trims for speed; an
    angle's VMG is then ``speed_over_ground . wind_direction_unit``. Boats that capsize
    count as speed 0.
    """
    return compute_polars(params, [wind_speed_mps], true_wind_angles_rad, sheets, duration_s, dt_s)[
        0
    ]


def compute_polars(
    params: DinghyParams | None,
    wind_speeds_mps: list[float],
    true_wind_angles_rad: np.ndarray | None = None,
    sheets: np.ndarray | None = None,
    duration_s: float = 90.0,
    dt_s: float = 0.05,
) -> list[Polar]:
    """:func:`compute_polar` at several wind speeds, sailed in one batch."""
    params = params or DinghyParams()
    if true_wind_angles_rad is None:
        true_wind_angles_rad = np.radians(np.arange(0.0, 181.0, 5.0))
    if sheets is None:
        sheets = np.linspace(0.0, 1.0, 41)
    angles = np.asarray(true_wind_angles_rad, dtype=np.float64)
    sheets = np.asarray(sheets, dtype=np.float64)
    winds = np.asarray(wind_speeds_mps, dtype=np.float64)
    shape = (winds.size, angles.size, sheets.size)
    wind, twa, sheet = (np.broadcast_to(a, shape).ravel() for a in np.ix_(winds, angles, sheets))
    state = sail_steady(params, wind, twa, sheet, duration_s, dt_s)

    speed = np.hypot(state.vx_mps, state.vy_mps)
    speed = np.where(state.capsized, 0.0, speed).reshape(shape)
    best = np.argmax(speed, axis=2)
    rows = np.arange(angles.size)
    polars = []
    for k, wind_speed_mps in enumerate(winds.tolist()):

        def pick(values: np.ndarray, k: int = k) -> np.ndarray:
            return values.reshape(shape)[k, rows, best[k]]

        vx, vy = pick(state.vx_mps), pick(state.vy_mps)
        polars.append(
            Polar(
                wind_speed_mps=wind_speed_mps,
                true_wind_angle_rad=angles,
                boat_speed_mps=speed[k, rows, best[k]],
                vmg_mps=vx * np.cos(angles) + vy * np.sin(angles),
                # Leeway is the drift angle of a boat moving ahead; one pushed astern has none.
                leeway_rad=np.where(vx > 0.05, np.arctan2(-vy, np.maximum(vx, 1e-9)), np.nan),
                heel_rad=np.abs(pick(state.heel_rad)),
                sheet=sheets[best[k]],
                capsized=pick(state.capsized),
            )
        )
    return polars
