"""The fuzz's draws: a :data:`Draw` (a NumPy generator's, or hypothesis's in the tests)
and the tools every sampler builds on: numbers over an accepted interval, pairs, flags,
ints, vectors, every field of a parameter dataclass, and the :data:`COST_CAPS`. Nothing
here knows an env: the families' samplers (``bbgym/envs/*/spec.py``) import it."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.validation import Interval, interval
from bbgym.physics.wall import WallParams

Draw = Callable[[str, Interval, bool], float]
"""``draw(name, interval, log) -> float``: a number inside ``interval`` (log-uniform if
``log``); ``name`` identifies the draw (hypothesis labels it)."""

COST_CAPS = {
    "sail_sim_dt": interval(0.02, 0.25),
    "sail_substeps": interval(1, 10),
    "ball_sim_dt": interval(0.005, 0.05),
    "max_flight_time": interval(0.5, 12.0),
    "topple_interval": interval(0.5, 4.0),
    "mark_distance": interval(0.0, 500.0),
    "race_countdown_s": interval(0.0, 30.0),
}
"""Where the fuzzer draws from less than the accepted interval, to bound the cost of a
step (each is the cheap end of an interval the validation accepts)."""


def numpy_draw(rng: np.random.Generator) -> Draw:
    """A :data:`Draw` from a NumPy generator: ends of closed intervals one time in ten
    each, else uniform (log-uniform for ``log``)."""

    def draw(name: str, accepted: Interval, log: bool) -> float:
        lo, hi = accepted.low, accepted.high
        u = rng.random()
        if u < 0.1 and not accepted.low_open:
            return lo
        if u < 0.2 and not accepted.high_open:
            return hi
        if log and hi > 0.0:
            low = log_floor(accepted)
            value = math.exp(rng.uniform(math.log(low), math.log(hi)))
        else:
            value = rng.uniform(lo, hi)
        return float(min(max(value, lo), hi)) if accepted.contains(value) else (lo + hi) / 2

    return draw


def log_floor(accepted: Interval) -> float:
    """Where a log-uniform draw starts: the low end, or six decades below the high end
    for an interval open at 0."""
    return accepted.low if accepted.low > 0.0 else accepted.high * 1e-6


def draw_pair(draw: Draw, name: str, accepted: Interval, log: bool = False) -> tuple:
    """A ``(low, high)`` range inside ``accepted``."""
    a, b = draw(f"{name}[0]", accepted, log), draw(f"{name}[1]", accepted, log)
    return (min(a, b), max(a, b))


def draw_flag(draw: Draw, name: str) -> bool:
    return draw(name, interval(0.0, 1.0), False) < 0.5


def draw_int(draw: Draw, name: str, low: int, high: int) -> int:
    return int(min(high, math.floor(draw(name, interval(low, high + 1, high_open=True), False))))


def sample_params(
    draw: Draw, cls: type, prefix: str, caps: Mapping[str, Interval] | None = None
) -> dict[str, Any]:
    """Every field of a parameter dataclass over its accepted interval (or over its
    ``caps`` entry, a part of it that bounds the cost). Cross-field constraints are met by
    construction where the class has them.

    Args:
        draw: draws each number.
        cls: the dataclass.
        prefix: the draws' labels begin with it (``dinghy``: ``dinghy.mass_kg``).
        caps: intervals to draw some fields from instead, by field name.

    Returns:
        The drawn fields by name (those without a finite interval left out).
    """
    values: dict[str, Any] = {}
    for f in fields(cls):
        if isinstance(f.default, bool):
            values[f.name] = draw_flag(draw, f"{prefix}.{f.name}")
            continue
        accepted = (caps or {}).get(f.name, f.metadata.get("interval"))
        if accepted is None:
            continue
        lo, hi = accepted.low, accepted.high
        if math.isinf(lo) or math.isinf(hi):
            continue
        if f.metadata.get("integer"):
            values[f.name] = draw_int(draw, f"{prefix}.{f.name}", int(lo), int(hi))
            continue
        values[f.name] = draw(f"{prefix}.{f.name}", accepted, lo > 0.0 or accepted.low_open)
    order = {
        DinghyParams: (
            ("sheet_min_rad", "sheet_max_rad"),
            ("jib_sheet_min_rad", "jib_sheet_max_rad"),
        ),
        WallParams: (("thickness_m", "base_depth_m"),),
    }
    for small, large in order.get(cls, ()):
        if not (small in values and large in values):
            continue
        lo, hi = sorted((values[small], values[large]))
        if lo == hi:  # strict order needed: fall back to the defaults' pair
            defaults = cls()
            lo, hi = getattr(defaults, small), getattr(defaults, large)
        values[small], values[large] = lo, hi
    return values


def draw_vector(draw: Draw, key: str, lengths: Interval) -> tuple[float, float]:
    """An ``options[key]`` vector ``(x, y)`` of a length inside ``lengths``, any direction."""
    length = draw(f"options[{key!r}].length", lengths, False)
    angle = draw(f"options[{key!r}].angle", interval(-math.pi, math.pi), False)
    # Rounding may take the length just out of an open interval: pull it in.
    x, y = length * math.cos(angle), length * math.sin(angle)
    if not lengths.contains(math.hypot(x, y)):
        x, y = x * (1 - 1e-9), y * (1 - 1e-9)
        if not lengths.contains(math.hypot(x, y)):
            x, y = x * (1 + 2e-9), y * (1 + 2e-9)
    return (x, y)
