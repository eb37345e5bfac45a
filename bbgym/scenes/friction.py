"""Friction (§6): a sliding block braked by kinetic friction, with and without the text's
check for the velocity crossing zero, and blocks on slopes of several angles (static
friction holds them below the friction angle, kinetic friction brakes them above).

Coulomb friction: at rest the friction matches the other forces along the surface up to
``mu_s N``; sliding, it is ``mu_k N`` against the motion (:func:`friction_step`). In
discrete time a friction force that would reverse the velocity in one step overshoots:
the block then rocks between two small velocities of opposite signs and creeps one way or
the other, by how its speed happened to fall (the text's "sliding block" demo). The fix is
the check: a step that would carry the velocity through zero stops it, and static
friction takes over.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_fields, interval, param
from bbgym.scenes.scene import Circle, Frame, Scene, Segment

BLOCK_COLORS = ((230, 70, 60), (60, 120, 220))
"""Without the zero-crossing check, with it."""


class Blocks(NamedTuple):
    """Each block's distance along its surface and its velocity along it ``(rows,)``; the
    per-row constants: its slope, whether it checks the zero crossing."""

    s_m: Array
    v_mps: Array
    slope_rad: Array
    checks: Array


def friction_step(s: Blocks, mu_static: float, mu_kinetic: float, dt_s: float,
                  xp: Any) -> Blocks:  # fmt: skip
    """One semi-implicit step of blocks on slopes (``s`` and ``v`` measured down the
    slope): gravity's share along it, ``g sin(theta)``; at rest, static friction holds
    the block if that is within ``mu_s g cos(theta)``; else kinetic friction
    ``mu_k g cos(theta)`` against the motion (down the slope for a block starting to
    slide). A block that checks the zero crossing stops where a step would reverse it."""
    along = GRAVITY_MPS2 * xp.sin(s.slope_rad)
    normal = GRAVITY_MPS2 * xp.cos(s.slope_rad)
    at_rest = s.v_mps == 0.0
    held = at_rest & (xp.abs(along) <= mu_static * normal)
    direction = xp.where(at_rest, xp.sign(along), xp.sign(s.v_mps))
    accel = xp.where(held, 0.0, along - mu_kinetic * normal * direction)
    v = s.v_mps + dt_s * accel
    reversed_ = (~at_rest) & (v * s.v_mps < 0.0) & (s.checks > 0.5)
    v = xp.where(reversed_, 0.0, v)
    return Blocks(s.s_m + dt_s * v, v, s.slope_rad, s.checks)


def check_coefficients(params: Any) -> None:
    """``mu_static >= mu_kinetic`` (static friction holds at least as hard as sliding
    friction brakes), or a ``ValueError`` naming the field."""
    if params.mu_static < params.mu_kinetic:
        raise ValueError(f"{type(params).__name__}.mu_static must be >= mu_kinetic "
                         f"({params.mu_kinetic}), got {params.mu_static}")  # fmt: skip


# -- the sliding block ------------------------------------------------------------------------


@dataclass(frozen=True)
class SlidingParams:
    """Blocks pushed off at several speeds on a level floor, each twice: without and
    with the zero-crossing check."""

    speed_min_mps: float = param(2.0, interval(0.01, 100.0))
    speed_max_mps: float = param(3.0, interval(0.01, 100.0))
    blocks: int = param(7, interval(1, 64), integer=True)
    """Speeds evenly from the least to the greatest."""
    mu_kinetic: float = param(0.4, interval(0.0, 2.0))
    mu_static: float = param(0.6, interval(0.0, 2.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)
        check_coefficients(self)
        if self.speed_max_mps < self.speed_min_mps:
            raise ValueError("SlidingParams.speed_max_mps must be >= speed_min_mps")

    def speeds(self) -> np.ndarray:
        return np.linspace(self.speed_min_mps, self.speed_max_mps, self.blocks)


def sliding_initial(p: SlidingParams, xp: Any) -> Blocks:
    speeds = np.concatenate([p.speeds(), p.speeds()])
    checks = np.repeat([0.0, 1.0], p.blocks)
    return Blocks(*(xp.asarray(a, dtype=xp.float64)
                    for a in (0.0 * speeds, speeds, 0.0 * speeds, checks)))  # fmt: skip


def sliding_step(p: SlidingParams, s: Blocks, xp: Any) -> Blocks:
    return friction_step(s, p.mu_static, p.mu_kinetic, p.dt_s, xp)


def sliding_measures(p: SlidingParams, s: Blocks, xp: Any) -> dict[str, Array]:
    return {"distance_m": s.s_m, "velocity_mps": s.v_mps}


def sliding_frame(p: SlidingParams, s: Blocks) -> Frame:
    distance = np.asarray(s.s_m)
    size = 0.3
    circles = []
    for row, d in enumerate(distance):
        check = row >= p.blocks
        lane = (row % p.blocks) + (p.blocks + 1) * check
        label = (f"{p.speeds()[row % p.blocks]:.1f} m/s" if lane % (p.blocks + 1) == 0
                 else "")  # fmt: skip
        circles.append(Circle(float(d), 0.4 * lane + size, 0.5 * size, BLOCK_COLORS[check], label))
    far = p.speed_max_mps**2 / (2.0 * p.mu_kinetic * GRAVITY_MPS2) if p.mu_kinetic else 1.0
    line = "red: no check (they creep); blue: the zero-crossing check (they stop)"
    return Frame(circles, [Segment(far, 0.0, far, 0.4 * (2 * p.blocks + 2), (120, 120, 120), 1)],
                 [line])  # fmt: skip


def sliding_duration(p: SlidingParams) -> float:
    """Twice the longest stop, ``v0 / (mu_k g)``."""
    return 2.0 * p.speed_max_mps / (p.mu_kinetic * GRAVITY_MPS2) if p.mu_kinetic else 5.0


SLIDING_BLOCK = Scene(
    name="sliding-block",
    section="§6",
    title="Sliding block: the zero crossing",
    claim="braked by kinetic friction, a block that checks its velocity crossing zero "
    "stops at v0^2 / (2 mu_k g) and stays; without the check it never stops, rocks about "
    "zero and creeps, left or right by its starting speed",
    params=SlidingParams,
    initial=sliding_initial,
    step=sliding_step,
    measures=sliding_measures,
    frame=sliding_frame,
    view_box_m=lambda p: (
        -0.5,
        sliding_duration(p) * p.speed_max_mps * 0.5 + 0.5,
        -0.3,
        0.4 * (2 * p.blocks + 2) + 0.3,
    ),  # fmt: skip
    duration_s=sliding_duration,
    body_names=lambda p: tuple(
        f"{v:.2f} m/s{', check' * check}" for check in (0, 1) for v in p.speeds()
    ),  # fmt: skip
    test="test_sliding_block_stops_with_the_zero_crossing_check_and_creeps_without",
)


# -- blocks on slopes ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SlopeParams:
    """Blocks at rest on slopes from ``angle_min_deg`` to ``angle_max_deg``, released."""

    angle_min_deg: float = param(10.0, interval(0.0, 89.0))
    angle_max_deg: float = param(50.0, interval(0.0, 89.0))
    slopes: int = param(9, interval(1, 64), integer=True)
    mu_static: float = param(0.6, interval(0.0, 2.0))
    """Its friction angle, ``atan(mu_s)``: 31 deg."""
    mu_kinetic: float = param(0.4, interval(0.0, 2.0))
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)
        check_coefficients(self)
        if self.angle_max_deg < self.angle_min_deg:
            raise ValueError("SlopeParams.angle_max_deg must be >= angle_min_deg")

    def angles_rad(self) -> np.ndarray:
        return np.radians(np.linspace(self.angle_min_deg, self.angle_max_deg, self.slopes))


def slope_initial(p: SlopeParams, xp: Any) -> Blocks:
    angles = p.angles_rad()
    return Blocks(*(xp.asarray(a, dtype=xp.float64)
                    for a in (0.0 * angles, 0.0 * angles, angles, 1.0 + 0.0 * angles)))  # fmt: skip


def slope_step(p: SlopeParams, s: Blocks, xp: Any) -> Blocks:
    return friction_step(s, p.mu_static, p.mu_kinetic, p.dt_s, xp)


def slope_frame(p: SlopeParams, s: Blocks) -> Frame:
    distance, angles = np.asarray(s.s_m), p.angles_rad()
    segments, circles = [], []
    for k, (d, a) in enumerate(zip(distance, angles, strict=True)):
        x0 = 3.0 * k
        segments.append(Segment(x0, 2.0, x0 + 2.0 * math.cos(a), 2.0 - 2.0 * math.sin(a),
                                (120, 120, 120), 2))  # fmt: skip
        along = min(float(d), 2.0)
        color = BLOCK_COLORS[int(float(d) > 0.0)]
        circles.append(Circle(x0 + along * math.cos(a), 2.0 - along * math.sin(a) + 0.12, 0.12,
                              color, f"{math.degrees(a):.0f}"))  # fmt: skip
    friction = math.degrees(math.atan(p.mu_static))
    return Frame(circles, segments, [f"friction angle {friction:.0f} deg: blue ones slide"])


SLIDING_BLOCK_2 = Scene(
    name="sliding-block-2",
    section="§6",
    title="Sliding block 2: static and kinetic friction on a slope",
    claim="a block stays put on a slope below the friction angle atan(mu_s) and slides "
    "above it, accelerating at g (sin theta - mu_k cos theta)",
    params=SlopeParams,
    initial=slope_initial,
    step=slope_step,
    measures=sliding_measures,
    frame=slope_frame,
    view_box_m=lambda p: (-0.5, 3.0 * p.slopes, -0.5, 2.8),
    duration_s=lambda p: 2.0,
    body_names=lambda p: tuple(f"{a:.0f} deg" for a in np.degrees(p.angles_rad())),
    test="test_blocks_on_slopes_hold_below_the_friction_angle_and_slide_above",
    floor=False,
)

SCENES = (SLIDING_BLOCK, SLIDING_BLOCK_2)
