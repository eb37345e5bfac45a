"""Shared physical constants and vector tools (seed §8, §9).

Everything here works on arrays with a leading batch axis, or on plain floats for one
env, through the namespace ``xp`` (see :mod:`bbgym.physics.namespace`).

2D vectors are passed as separate ``x`` and ``y`` arrays of shape ``(batch,)``: the
physics is small per element, and two flat arrays are both faster and easier to read
than an ``(batch, 2)`` array sliced everywhere.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from bbgym.physics.namespace import Array

GRAVITY_MPS2 = 9.81
AIR_DENSITY_KGM3 = 1.2
WATER_DENSITY_KGM3 = 1025.0
KNOT_MPS = 0.514444
NORM_FLOOR = 1e-30
"""Floor of a norm (a speed, a distance) that a direction divides by, where the vector may
be zero: small enough to change no float64 result of a real motion, and, with its inverse
(1e30), representable in float32 (1e-300 underflows to 0 there, and 0 / 0 is NaN: a boat
in a calm on the float32 torch backend went NaN on its first step)."""


def wrap_angle(angle_rad: Array, xp: Any = np) -> Array:
    """Wrap angles to (-pi, pi]."""
    return math.pi - xp.remainder(math.pi - angle_rad, 2.0 * math.pi)


def split_along(x: Array, y: Array, dir_x: Array, dir_y: Array) -> tuple[Array, Array]:
    """Split (x, y) into components along and across the unit direction (dir_x, dir_y).

    Seed §9 ("splitting vectors"): the parallel part is ``v . d``; the perpendicular part
    is measured along ``d`` turned 90 degrees counterclockwise, ``(-d_y, d_x)``. With the
    boat's heading as ``d`` this is the world-to-body transform: (surge, sway).
    """
    along = x * dir_x + y * dir_y
    across = -x * dir_y + y * dir_x
    return along, across


def quadratic_drag_rate(drag_area_m2: float, density_kgm3: float, speed_mps: Array) -> Array:
    """Quadratic drag ``F = -1/2 C_d A rho |v| v`` (seed §8) as the coefficient ``k`` of
    ``F = -k v``: ``k = 1/2 C_d A rho |v|`` (N s/m). Integrators that treat the drag
    implicitly need ``k`` itself; the force is ``-k v``."""
    return 0.5 * drag_area_m2 * density_kgm3 * speed_mps
