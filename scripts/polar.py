"""Compute and plot the dinghy's polar diagram from the physics.

    python scripts/polar.py [--wind-speed 5] [--sail-model lift|seed] [--out runs/polar]

Writes ``<out>/polar.png`` (boat speed by true wind angle, 0 deg = upwind at the top,
mirrored to both tacks) and ``<out>/polar.csv``, and prints a summary.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

from bbgym.physics.polar import Polar, compute_polar
from bbgym.physics.sailing import SAIL_MODELS, DinghyParams

CSV_COLUMNS = (
    "true_wind_angle_deg",
    "boat_speed_mps",
    "speed_over_wind",
    "vmg_mps",
    "leeway_deg",
    "heel_deg",
    "best_sheet",
)


def polar_rows(polar: Polar) -> list[dict[str, float]]:
    """One CSV row per true wind angle."""
    rows = []
    for i, angle in enumerate(polar.true_wind_angle_rad):
        rows.append(
            {
                "true_wind_angle_deg": round(math.degrees(float(angle)), 6),
                "boat_speed_mps": float(polar.boat_speed_mps[i]),
                "speed_over_wind": float(polar.boat_speed_mps[i]) / polar.wind_speed_mps,
                "vmg_mps": float(polar.vmg_mps[i]),
                "leeway_deg": math.degrees(float(polar.leeway_rad[i])),
                "heel_deg": math.degrees(float(polar.heel_rad[i])),
                "best_sheet": float(polar.sheet[i]),
            }
        )
    return rows


def write_csv(path: Path, polar: Polar) -> None:
    with path.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        for row in polar_rows(polar):
            writer.writerow({k: f"{v:.6g}" for k, v in row.items()})


def plot_polar(path: Path, polar: Polar, sail_model: str) -> None:
    """Polar axes, 0 deg (upwind) at the top, both tacks; best VMG and fastest marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    angles = polar.true_wind_angle_rad
    speed = polar.boat_speed_mps
    fig = plt.figure(figsize=(7, 7))
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    # Head to wind the boat cannot sail: it drifts astern (the polar has no leeway there).
    astern = np.isnan(polar.leeway_rad) | ((angles < math.pi / 4) & (polar.vmg_mps < 0.0))
    sailing = np.where(astern, np.nan, speed)
    drifting = np.where(astern | np.roll(astern, -1), speed, np.nan)
    for sign, first in ((1.0, True), (-1.0, False)):
        ax.plot(
            sign * angles, sailing, color="tab:blue", lw=2, label="boat speed" if first else None
        )
        if astern.any():
            ax.plot(
                sign * angles,
                drifting,
                color="grey",
                lw=1.5,
                ls=":",
                label="drifting astern (in irons)" if first else None,
            )

    best_angle, best_vmg = polar.best_upwind()
    i_best = int(np.argmax(polar.vmg_mps))
    fast_angle, fast_speed = polar.fastest()
    for sign in (1.0, -1.0):
        ax.plot(
            [0.0, sign * best_angle],
            [0.0, speed[i_best]],
            color="tab:green",
            lw=1,
            ls="--",
        )
    ax.plot(
        [best_angle, -best_angle],
        [speed[i_best]] * 2,
        "o",
        color="tab:green",
        label=f"best upwind VMG {best_vmg:.2f} m/s at {math.degrees(best_angle):.0f} deg",
    )
    ax.plot(
        [fast_angle, -fast_angle],
        [fast_speed] * 2,
        "s",
        color="tab:red",
        label=f"fastest {fast_speed:.2f} m/s at {math.degrees(fast_angle):.0f} deg",
    )
    ticks = list(range(0, 360, 30))
    ax.set_thetagrids(ticks, [f"{min(t, 360 - t)}\N{DEGREE SIGN}" for t in ticks])
    ax.set_rlabel_position(22)
    ax.set_title(
        f"Dinghy polar, true wind {polar.wind_speed_mps:g} m/s ({sail_model} sail model)\n"
        "boat speed (m/s) by true wind angle, wind from the top",
        pad=20,
    )
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.23), fontsize=9)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def summary(polar: Polar) -> list[str]:
    best_angle, best_vmg = polar.best_upwind()
    i_best = int(np.argmax(polar.vmg_mps))
    fast_angle, fast_speed = polar.fastest()
    i_zero = int(np.argmin(np.abs(polar.true_wind_angle_rad)))
    wind = polar.wind_speed_mps
    return [
        f"best upwind VMG: {best_vmg:.3f} m/s at {math.degrees(best_angle):.0f} deg TWA "
        f"(boat speed {polar.boat_speed_mps[i_best]:.2f} m/s)",
        f"fastest: {fast_speed:.3f} m/s at {math.degrees(fast_angle):.0f} deg TWA "
        f"(speed/wind {fast_speed / wind:.3f})",
        f"leeway at best upwind angle: {math.degrees(polar.leeway_rad[i_best]):.2f} deg "
        f"(heel {math.degrees(polar.heel_rad[i_best]):.1f} deg)",
        f"VMG at {math.degrees(polar.true_wind_angle_rad[i_zero]):.0f} deg "
        f"(head to wind): {polar.vmg_mps[i_zero]:.3f} m/s",
        f"capsized angles: {int(np.sum(polar.capsized))}",
    ]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wind-speed", type=float, default=5.0, help="true wind, m/s")
    parser.add_argument("--sail-model", choices=SAIL_MODELS, default="lift")
    parser.add_argument("--out", type=Path, default=Path("runs/polar"), help="output folder")
    parser.add_argument("--step-deg", type=float, default=1.0, help="angle grid step, deg")
    args = parser.parse_args(argv)
    if not (math.isfinite(args.wind_speed) and args.wind_speed > 0):
        parser.error("--wind-speed must be > 0")
    if not (0 < args.step_deg <= 90):
        parser.error("--step-deg must be in (0, 90]")

    angles = np.radians(np.arange(0.0, 180.0 + 1e-9, args.step_deg))
    t0 = time.perf_counter()
    polar = compute_polar(DinghyParams(sail_model=args.sail_model), args.wind_speed, angles)
    seconds = time.perf_counter() - t0

    args.out.mkdir(parents=True, exist_ok=True)
    png, csv_path = args.out / "polar.png", args.out / "polar.csv"
    write_csv(csv_path, polar)
    plot_polar(png, polar, args.sail_model)

    print(
        f"polar: {args.sail_model} sail model, true wind {args.wind_speed:g} m/s, "
        f"{angles.size} angles, computed in {seconds:.1f} s"
    )
    for line in summary(polar):
        print("  " + line)
    print(f"wrote {png}")
    print(f"wrote {csv_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
