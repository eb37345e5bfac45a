"""Compute and plot the dinghy's polar diagram from the physics.

    bbgym polar [--wind-speed MPS] [--sail-model lift|seed|cambered] [--out runs/polar]
    bbgym polar --compare [--out runs/polar]

Writes ``<out>/polar.png`` (boat speed by true wind angle, 0 deg = upwind at the top,
mirrored to both tacks) and ``<out>/polar.csv``, and prints a summary.

``--compare`` sails the calibrated sloop (:func:`bbgym.physics.calibration.calibrated_sloop`)
at every reference wind speed of a real Laser's polar and writes ``<out>/compare.png`` (its
polars over the reference points, in knots) and ``<out>/compare.csv`` (each reference
point, bbgym's figure, the error and whether it is within the tolerance), and prints the
table.
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from bbgym.cli import UsageError, positive_float, require_all
from bbgym.physics.calibration import (
    BINNS_2002,
    DAY_2017,
    KNOT_MPS,
    Comparison,
    calibrated_sloop,
    compare,
    comparison_table,
    polar_angles_deg,
    polars,
)
from bbgym.physics.dinghy import SAIL_MODELS, DinghyParams
from bbgym.physics.polar import Polar, compute_polar

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


DEG = "\N{DEGREE SIGN}"
RADIAL_LABEL_CLEARANCE_PX = 4.0  # a radial tick label keeps at least this far from the curves


def _display_points(ax: Any, line: Any) -> np.ndarray:
    """A plotted line's points in display pixels, every ~2 px along its segments (lines in
    polar axes are straight between their vertices on screen)."""
    xy = np.column_stack([np.asarray(d, dtype=float) for d in line.get_data()])
    if not len(xy):
        return np.zeros((0, 2))
    px = ax.transData.transform(xy)
    runs, current = [], []
    for p in px:  # a NaN breaks the line
        if np.all(np.isfinite(p)):
            current.append(p)
        elif current:
            runs.append(np.array(current))
            current = []
    if current:
        runs.append(np.array(current))
    out = []
    for run in runs:
        out.append(run)
        for a, b in zip(run[:-1], run[1:], strict=True):
            n = int(np.hypot(*(b - a)) // 2.0)
            if n > 1:
                t = np.linspace(0.0, 1.0, n)[:, None]
                out.append(a + t * (b - a))
    return np.concatenate(out) if out else np.zeros((0, 2))


def _box_distance(points: np.ndarray, box: Any) -> float:
    """Smallest distance (px) from ``points`` to a display bounding box (0 inside it)."""
    if not len(points):
        return math.inf
    dx = np.maximum(np.maximum(box.x0 - points[:, 0], points[:, 0] - box.x1), 0.0)
    dy = np.maximum(np.maximum(box.y0 - points[:, 1], points[:, 1] - box.y1), 0.0)
    return float(np.min(np.hypot(dx, dy)))


def label_layout(fig: Any, ax: Any) -> dict[str, Any]:
    """Where the polar axes' tick labels are, drawn as they will be saved: the radial and
    angular labels' display boxes, the plotted curves' display points, and the radial
    labels' clearance from the curves (px) and whether any two labels overlap."""
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    radial = [t.get_window_extent(renderer) for t in ax.get_yticklabels() if t.get_text()]
    angular = [t.get_window_extent(renderer) for t in ax.get_xticklabels() if t.get_text()]
    lines = [_display_points(ax, line) for line in ax.get_lines()]
    points = np.concatenate(lines) if lines else np.zeros((0, 2))
    clearance = min((_box_distance(points, b) for b in radial), default=math.inf)
    boxes = radial + angular
    overlap = any(
        boxes[i].overlaps(boxes[j])
        for i in range(len(boxes))
        for j in range(i + 1, len(boxes))
        if i < len(radial)
    )
    return {
        "radial": radial,
        "angular": angular,
        "points": points,
        "clearance_px": clearance,
        "overlap": overlap,
    }


def place_radial_labels(fig: Any, ax: Any, candidates_deg: Sequence[float] | None = None) -> float:
    """Put the radial (speed) tick labels along the ray, among ``candidates_deg`` (default:
    every 5 deg of the right half, away from the angular grid lines), where they overlap
    no other label and stay farthest from the plotted curves; returns that angle (deg)."""
    if candidates_deg is None:
        candidates_deg = [a for a in range(5, 180, 5) if min(a % 30, 30 - a % 30) >= 7]
    best, best_key = float(candidates_deg[0]), None
    for angle in candidates_deg:
        ax.set_rlabel_position(angle)
        layout = label_layout(fig, ax)
        clearance = min(float(layout["clearance_px"]), 1e6)
        key = (not layout["overlap"], clearance >= RADIAL_LABEL_CLEARANCE_PX, clearance)
        if best_key is None or key > best_key:
            best, best_key = float(angle), key
    ax.set_rlabel_position(best)
    return best


def polar_figure(polar: Polar, sail_model: str) -> Any:
    """The polar diagram of :func:`plot_polar` (a matplotlib Figure)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    angles = polar.true_wind_angle_rad
    speed = polar.boat_speed_mps
    fig = plt.figure(figsize=(7, 7.6))
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
        label=f"best upwind VMG {best_vmg:.2f} m/s at {math.degrees(best_angle):.0f}{DEG} TWA",
    )
    ax.plot(
        [fast_angle, -fast_angle],
        [fast_speed] * 2,
        "s",
        color="tab:red",
        label=f"fastest {fast_speed:.2f} m/s at {math.degrees(fast_angle):.0f}{DEG} TWA",
    )
    ticks = list(range(0, 360, 30))
    ax.set_thetagrids(ticks, [f"{min(t, 360 - t)}{DEG}" for t in ticks])
    ax.tick_params(axis="x", pad=6)
    top = float(np.nanmax(speed)) if np.isfinite(speed).any() else 1.0
    r_max = 1.12 * max(top, 1e-3)
    r_ticks = [
        float(t)
        for t in MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10]).tick_values(0.0, r_max)
        if 0.0 < t < r_max
    ]
    ax.set_rlim(0.0, r_max)
    ax.set_rgrids(r_ticks, [f"{t:g} m/s" for t in r_ticks], fontsize=9)
    for label in ax.get_yticklabels():
        label.set_bbox({"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8})
    ax.set_xlabel(f"true wind angle (TWA): 0{DEG} head to wind, at the top", labelpad=8)
    ax.set_title(
        f"Dinghy polar, true wind {polar.wind_speed_mps:g} m/s ({sail_model} sail model)\n"
        "boat speed (m/s) by true wind angle, both tacks",
        pad=20,
    )
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), fontsize=9)
    place_radial_labels(fig, ax)
    return fig


def plot_polar(path: Path, polar: Polar, sail_model: str) -> None:
    """Polar axes, 0 deg (upwind) at the top, both tacks; best VMG and fastest marked. The
    radial axis is boat speed with its ticks labelled in m/s, placed along the ray where
    they clear the curves; the angular ticks are true wind angles in degrees."""
    import matplotlib.pyplot as plt

    fig = polar_figure(polar, sail_model)
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


COMPARE_COLUMNS = (
    "source",
    "wind_kn",
    "quantity",
    "true_wind_angle_deg",
    "reference",
    "bbgym",
    "error",
    "within",
)
"""Columns of ``compare.csv``: ``error`` is in degrees for ``best TWA``, a fraction of the
reference for the speeds (``VMG``, ``speed``, in knots)."""


def write_compare_csv(path: Path, rows: list[Comparison]) -> None:
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(COMPARE_COLUMNS)
        for r in rows:
            writer.writerow(
                [
                    r.source,
                    f"{r.wind_kn:g}",
                    r.quantity,
                    f"{r.true_wind_angle_deg:g}",
                    f"{r.reference:g}",
                    f"{r.bbgym:.6g}",
                    f"{r.error:.6g}",
                    int(r.within),
                ]
            )


REFERENCE_MARKS = (
    (DAY_2017, "^", 9, "Day 2017 best upwind"),
    (BINNS_2002, "o", 7, "Binns 2002"),
)
"""The measured Laser polars :func:`compare_figure` marks: points, marker, its size and
the source's name in the legend."""


def compare_figure(by_wind: dict[float, Polar]) -> Any:
    """The calibrated sloop's polar at each reference wind (knots) over the reference points:
    a half polar (starboard tack), 0 deg at the top."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(7.5, 7.5))
    ax = fig.add_subplot(projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(0)
    ax.set_thetamax(180)
    colors = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, len(by_wind)))
    for color, (kn, polar) in zip(colors, sorted(by_wind.items()), strict=True):
        order = np.argsort(polar.true_wind_angle_rad)
        ax.plot(
            polar.true_wind_angle_rad[order],
            polar.boat_speed_mps[order] / KNOT_MPS,
            color=color,
            lw=1.8,
            label=f"bbgym, {kn:g} kn",
        )
        for points, marker, size, source in REFERENCE_MARKS:
            measured = [pt for pt in points if pt.wind_kn == kn]
            if measured:
                ax.plot(
                    [math.radians(pt.true_wind_angle_deg) for pt in measured],
                    [pt.boat_speed_kn for pt in measured],
                    marker,
                    color=color,
                    ms=size,
                    mec="black",
                    label=f"{source}, {kn:g} kn",
                )
    ax.set_thetagrids(range(0, 181, 30), [f"{a}{DEG}" for a in range(0, 181, 30)])
    ax.set_xlabel(f"true wind angle: 0{DEG} head to wind; boat speed in knots", labelpad=8)
    ax.set_title("The calibrated sloop against a Laser's polar", pad=16)
    ax.legend(loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize=8)
    return fig


def run_compare(out: Path) -> int:
    """``bbgym polar --compare``."""
    import matplotlib.pyplot as plt

    params = calibrated_sloop()
    t0 = time.perf_counter()
    sail_angles = np.union1d(polar_angles_deg(), np.arange(20.0, 181.0, 2.0))
    by_wind = polars(params, angles_deg=sail_angles)
    rows = compare(params, by_wind)
    seconds = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    png, csv_path = out / "compare.png", out / "compare.csv"
    write_compare_csv(csv_path, rows)
    fig = compare_figure(by_wind)
    fig.savefig(png, dpi=100, bbox_inches="tight")
    plt.close(fig)
    print(
        f"polar --compare: the calibrated sloop at {len(by_wind)} wind speeds, "
        f"computed in {seconds:.1f} s"
    )
    print(comparison_table(rows))
    missed = sum(not r.within for r in rows)
    print(f"{len(rows) - missed} of {len(rows)} reference figures within tolerance")
    print(f"wrote {png}")
    print(f"wrote {csv_path}")
    return 0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--wind-speed", type=positive_float, default=None, help="true wind, m/s (default 5)"
    )
    parser.add_argument(
        "--sail-model", choices=SAIL_MODELS, default=None, help="sail model (default lift)"
    )
    parser.add_argument(
        "--compare",
        action="store_true",
        help="the calibrated sloop against a Laser's reference polar",
    )
    parser.add_argument("--out", type=Path, default=Path("runs/polar"), help="output folder")
    parser.add_argument(
        "--step-deg", type=positive_float, default=1.0, help="angle grid step, deg, in (0, 90]"
    )


def needs(args: argparse.Namespace) -> list[tuple[str, str]]:
    """``(module, extra)`` the run needs: matplotlib (``plots``)."""
    return [("matplotlib", "plots")]


def run(args: argparse.Namespace) -> int:
    if not (0 < args.step_deg <= 90):
        raise UsageError("--step-deg must be in (0, 90]")
    if args.compare:
        given = [
            f
            for f, v in (("--wind-speed", args.wind_speed), ("--sail-model", args.sail_model))
            if v is not None
        ]
        if given:
            raise UsageError(
                f"{given[0]} does not go with --compare (it sails the calibrated sloop at "
                "the reference winds)"
            )
    require_all(needs(args))
    if args.compare:
        return run_compare(args.out)
    args.wind_speed = 5.0 if args.wind_speed is None else args.wind_speed
    args.sail_model = args.sail_model or "lift"

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
