"""A real dinghy's polar, and how far a :class:`~bbgym.physics.dinghy.DinghyParams` boat is
from it.

The reference points are a Laser's (4.2 m, 7.06 m^2, one sailor of about 80 kg) in flat
water, as the issue that asked for them gives them (read off the papers' figures by
others; the papers themselves were not reachable from this project's machines):

* Day, A. H. (2017), "Performance prediction for sailing dinghies", Ocean Engineering 136,
  67-79: a velocity prediction program's best upwind course (true wind angle, velocity made
  good and boat speed) at 6, 8, 10 and 12 knots of wind;
* Binns, J. R., Bethwaite, F. W. and Saunders, N. R. (2002), "Development of a more
  realistic sailing simulator", HPYD: a measured Laser's speed at 9 and 12 knots.

:func:`compare` sails the polar (:func:`~bbgym.physics.polar.compute_polar`) at each
reference wind and lines it up against the points; :func:`calibrated_sloop` is the boat
that ``scripts/calibrate_sloop.py`` fitted to them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.polar import Polar, compute_polars

KNOT_MPS = 1852.0 / 3600.0
"""One knot in m/s."""


@dataclass(frozen=True)
class UpwindPoint:
    """The best upwind course at one wind speed (knots, degrees)."""

    wind_kn: float
    true_wind_angle_deg: float
    vmg_kn: float
    boat_speed_kn: float


@dataclass(frozen=True)
class SpeedPoint:
    """Boat speed at one true wind angle and wind speed (knots, degrees)."""

    wind_kn: float
    true_wind_angle_deg: float
    boat_speed_kn: float


DAY_2017 = (
    UpwindPoint(6.0, 43.6, 2.65, 3.66),
    UpwindPoint(8.0, 41.0, 3.27, 4.33),
    UpwindPoint(10.0, 40.6, 3.63, 4.78),
    UpwindPoint(12.0, 41.7, 3.73, 5.00),
)
"""Day 2017, Laser VPP, 80 kg sailor, flat water: the best upwind course."""

BINNS_2002 = (
    SpeedPoint(12.0, 40.0, 4.90),
    SpeedPoint(12.0, 60.0, 6.32),
    SpeedPoint(12.0, 90.0, 7.37),
    SpeedPoint(12.0, 120.0, 8.16),
    SpeedPoint(12.0, 180.0, 6.68),
    SpeedPoint(9.0, 42.0, 4.65),
    SpeedPoint(9.0, 60.0, 5.85),
    SpeedPoint(9.0, 180.0, 5.63),
)
"""Binns, Bethwaite and Saunders 2002, a measured Laser: speed by true wind angle (at
12 knots fastest at 120 deg)."""

SPEED_TOLERANCE = 0.10
"""Every reference speed (boat speed and VMG) within 10%."""
ANGLE_TOLERANCE_DEG = 3.0
"""The best upwind true wind angle within 3 degrees."""


@dataclass(frozen=True)
class Comparison:
    """One reference quantity beside bbgym's."""

    source: str
    wind_kn: float
    quantity: str
    """``"best TWA"`` (degrees), ``"VMG"`` or ``"speed"`` (knots)."""
    true_wind_angle_deg: float
    """The reference's angle (for ``"best TWA"``, the reference's best)."""
    reference: float
    bbgym: float

    @property
    def error(self) -> float:
        """Degrees for the best angle, a fraction of the reference for speeds."""
        if self.quantity == "best TWA":
            return self.bbgym - self.reference
        return self.bbgym / self.reference - 1.0

    @property
    def within(self) -> bool:
        limit = ANGLE_TOLERANCE_DEG if self.quantity == "best TWA" else SPEED_TOLERANCE
        return abs(self.error) <= limit


UPWIND_GRID_DEG = np.arange(30.0, 56.0, 1.0)
"""Angles searched for the best upwind course (1 degree apart)."""
BROAD_GRID_DEG = np.arange(70.0, 176.0, 5.0)
"""Angles searched for the fastest course."""


def reference_winds_kn() -> list[float]:
    """Every wind speed with a reference point, in knots."""
    return sorted({pt.wind_kn for pt in DAY_2017} | {pt.wind_kn for pt in BINNS_2002})


def polar_angles_deg() -> np.ndarray:
    """The true wind angles :func:`compare` sails: the grids and every reference angle."""
    points = [pt.true_wind_angle_deg for pt in BINNS_2002]
    return np.unique(np.concatenate([UPWIND_GRID_DEG, BROAD_GRID_DEG, points]))


def polars(
    params: DinghyParams,
    winds_kn: list[float] | None = None,
    dt_s: float = 0.05,
    duration_s: float = 60.0,
    sheets: int = 21,
    angles_deg: np.ndarray | None = None,
) -> dict[float, Polar]:
    """``params``' polar at each reference wind speed (knots) over ``angles_deg``
    (:func:`polar_angles_deg` by default; others should include them for :func:`compare`)."""
    winds_kn = winds_kn or reference_winds_kn()
    angles = np.radians(polar_angles_deg() if angles_deg is None else angles_deg)
    sailed = compute_polars(
        params,
        [kn * KNOT_MPS for kn in winds_kn],
        angles,
        np.linspace(0.0, 1.0, sheets),
        duration_s,
        dt_s,
    )
    return dict(zip(winds_kn, sailed, strict=True))


def compare(params: DinghyParams, by_wind: dict[float, Polar] | None = None) -> list[Comparison]:
    """``params``' polar against every reference point (:data:`DAY_2017`,
    :data:`BINNS_2002`); ``by_wind``: polars already sailed by :func:`polars`."""
    by_wind = by_wind or polars(params)
    rows = []
    for pt in DAY_2017:
        polar = by_wind[pt.wind_kn]
        i = int(np.argmax(polar.vmg_mps))
        angle = math.degrees(polar.true_wind_angle_rad[i])
        for quantity, ref, ours in (
            ("best TWA", pt.true_wind_angle_deg, angle),
            ("VMG", pt.vmg_kn, polar.vmg_mps[i] / KNOT_MPS),
            ("speed", pt.boat_speed_kn, polar.boat_speed_mps[i] / KNOT_MPS),
        ):
            rows.append(
                Comparison("Day 2017", pt.wind_kn, quantity, pt.true_wind_angle_deg, ref, ours)
            )
    for pt in BINNS_2002:
        polar = by_wind[pt.wind_kn]
        j = int(np.argmin(np.abs(np.degrees(polar.true_wind_angle_rad) - pt.true_wind_angle_deg)))
        speed = float(polar.boat_speed_mps[j] / KNOT_MPS)
        rows.append(
            Comparison(
                "Binns 2002", pt.wind_kn, "speed", pt.true_wind_angle_deg, pt.boat_speed_kn, speed
            )
        )
    return rows


def comparison_table(rows: list[Comparison]) -> str:
    """The comparison as a Markdown table."""
    lines = [
        "| source | wind (kn) | quantity | TWA (deg) | reference | bbgym | error | within |",
        "|---|---:|---|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        if r.quantity == "best TWA":
            ref, ours, err = f"{r.reference:.1f} deg", f"{r.bbgym:.1f} deg", f"{r.error:+.1f} deg"
        else:
            ref, ours, err = f"{r.reference:.2f} kn", f"{r.bbgym:.2f} kn", f"{100 * r.error:+.1f}%"
        lines.append(
            f"| {r.source} | {r.wind_kn:g} | {r.quantity} | {r.true_wind_angle_deg:g} | {ref} "
            f"| {ours} | {err} | {'yes' if r.within else 'no'} |"
        )
    return "\n".join(lines)


CALIBRATED_SLOOP = {
    "rig": "sloop",
    "sail_model": "cambered",
    "sail_area_m2": 5.76,
    "jib_area_m2": 1.3,
    "sail_cl_peak": 1.13948,
    "sail_stall_rad": 0.341207,
    "sail_drag_parasitic": 0.0149414,
    "sail_drag_induced": 0.156036,
    "sail_cn_flat": 2.85592,
    "hull_drag_forward": 0.00294925,
    "hull_wave_speed_mps": 1.54929,
    "hull_planing_speed_mps": 24.3507,
    "keel_lift_slope": 3369.87,
    "windage": 0.999286,
    "crew_righting_nm": 700.0,
}
"""The fields of :func:`calibrated_sloop` that differ from the default boat (the sail
spec registers its newest version with them as the ``dinghy`` argument)."""


def calibrated_sloop() -> DinghyParams:
    """A Laser-sized sloop (the Laser's 7.06 m^2 shared by a main and a jib) with a
    cambered sail and a planing hull, its constants fitted to :data:`DAY_2017` and
    :data:`BINNS_2002` by ``scripts/calibrate_sloop.py``."""
    return DinghyParams(**CALIBRATED_SLOOP)
