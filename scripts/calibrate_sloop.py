"""Fit the calibrated sloop's hull and sail constants to a real Laser's polar.

    python scripts/calibrate_sloop.py [--evaluations 600] [--start calibrated|default]
        [--set NAME=VALUE ...] [--hold NAME ...] [--fine]

Nelder-Mead (SciPy, from the ``train`` extra) on the logarithms of the fitted constants,
minimising the squared errors of every reference point of
:mod:`bbgym.physics.calibration` in units of its tolerance (10% of a speed, 3 degrees of the
best upwind angle), plus a smaller pull of the fastest angle at 12 knots toward the
measured 120 degrees. The search sails a coarser polar (0.1 s steps, 40 s, 13 sheets) than
the test does (0.05 s, 60 s, 21 sheets; ``--fine`` searches at that): steady states do not
depend on the step, but the best sheet and angle of a coarser grid do a little. ``--set``
changes a constant of the start, ``--hold`` keeps a fitted one at its start. It prints
the constants to copy into :func:`bbgym.physics.calibration.calibrated_sloop` and the
comparison at the test's resolution.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.optimize import minimize

from bbgym.physics.calibration import (
    ANGLE_TOLERANCE_DEG,
    KNOT_MPS,
    SPEED_TOLERANCE,
    calibrated_sloop,
    compare,
    comparison_table,
    polars,
)
from bbgym.physics.dinghy import DinghyParams

FITTED = (
    "sail_cl_peak",
    "sail_stall_rad",
    "sail_drag_parasitic",
    "sail_drag_induced",
    "sail_cn_flat",
    "hull_drag_forward",
    "hull_wave_speed_mps",
    "hull_planing_speed_mps",
    "keel_lift_slope",
    "windage",
    "crew_righting_nm",
)


def objective(params: DinghyParams, coarse: bool = True) -> float:
    kw = {"dt_s": 0.1, "duration_s": 40.0, "sheets": 13} if coarse else {}
    by_wind = polars(params, **kw)
    total = 0.0
    for row in compare(params, by_wind):
        limit = ANGLE_TOLERANCE_DEG if row.quantity == "best TWA" else SPEED_TOLERANCE
        total += (row.error / limit) ** 2
    fastest_deg = math.degrees(by_wind[12.0].fastest()[0])
    return total + 0.25 * ((fastest_deg - 120.0) / 10.0) ** 2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--evaluations", type=int, default=600)
    parser.add_argument("--start", choices=("calibrated", "default"), default="calibrated")
    parser.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    parser.add_argument("--hold", nargs="*", default=[], choices=FITTED)
    parser.add_argument("--fine", action="store_true", help="search at the test's resolution")
    args = parser.parse_args()
    start = (
        calibrated_sloop()
        if args.start == "calibrated"
        else DinghyParams(rig="sloop", sail_model="cambered", hull_planing_speed_mps=3.0)
    )
    start = start.replace(**{k: float(v) for k, v in (kv.split("=") for kv in args.set)})
    fitted = [name for name in FITTED if name not in args.hold]
    x0 = np.log([getattr(start, name) for name in fitted])
    best = [math.inf, start]
    began = time.perf_counter()

    def cost(x: np.ndarray) -> float:
        try:
            params = start.replace(**dict(zip(fitted, np.exp(x).tolist(), strict=True)))
        except ValueError:  # outside an accepted interval
            return 1e6
        value = objective(params, coarse=not args.fine)
        if value < best[0]:
            best[:] = [value, params]
            changed = {name: getattr(params, name) for name in fitted}
            print(f"{time.perf_counter() - began:7.0f} s  cost {value:8.3f}  {changed}", flush=True)
        return value

    minimize(
        cost,
        x0,
        method="Nelder-Mead",
        options={"maxfev": args.evaluations, "xatol": 1e-3, "fatol": 1e-3, "initial_simplex": None},
    )
    params = best[1]
    print("\nfitted constants:")
    for name in FITTED:
        print(f"    {name}={getattr(params, name)!r},")
    print(f"\ncost at the test's resolution: {objective(params, coarse=False):.3f}\n")
    by_wind = polars(params)
    print(comparison_table(compare(params, by_wind)))
    for kn, polar in by_wind.items():
        angle, speed = polar.fastest()
        print(f"{kn:g} kn: fastest {math.degrees(angle):.0f} deg at {speed / KNOT_MPS:.2f} kn")


if __name__ == "__main__":
    main()
