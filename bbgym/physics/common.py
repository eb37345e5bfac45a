"""Shared physical constants and vector tools (seed §8, §9).

Everything here works on arrays with a leading batch axis and uses only functions that
the Python array API standard also has (``sin``, ``cos``, ``atan2``, ``where``, ...), so
a second array library can run the same code later.

2D vectors are passed as separate ``x`` and ``y`` arrays of shape ``(batch,)``: the
physics is small per element, and two flat arrays are both faster and easier to read
than an ``(batch, 2)`` array sliced everywhere.
"""

from __future__ import annotations

import math

import numpy as np

GRAVITY_MPS2 = 9.81
AIR_DENSITY_KGM3 = 1.2
WATER_DENSITY_KGM3 = 1025.0
KNOT_MPS = 0.514444


def wrap_angle(angle_rad: np.ndarray) -> np.ndarray:
    """Wrap angles to (-pi, pi]."""
    return math.pi - np.remainder(math.pi - angle_rad, 2.0 * math.pi)


def rotate(x: np.ndarray, y: np.ndarray, angle_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotate the vector (x, y) counterclockwise by ``angle_rad``."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return c * x - s * y, s * x + c * y


def split_along(
    x: np.ndarray, y: np.ndarray, dir_x: np.ndarray, dir_y: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Split (x, y) into components along and across the unit direction (dir_x, dir_y).

    Seed §9 ("splitting vectors"): the parallel part is ``v . d``; the perpendicular part
    is measured along ``d`` turned 90 degrees counterclockwise, ``(-d_y, d_x)``. With the
    boat's heading as ``d`` this is the world-to-body transform: (surge, sway).
    """
    along = x * dir_x + y * dir_y
    across = -x * dir_y + y * dir_x
    return along, across


def quadratic_drag(
    drag_coefficient: float,
    area_m2: float,
    density_kgm3: float,
    rel_x: np.ndarray,
    rel_y: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Quadratic drag ``F = -1/2 C_d A rho |v| v`` against the relative velocity (seed §8).

    ``rel`` is the body's velocity relative to the fluid; the force opposes it.
    """
    k = -0.5 * drag_coefficient * area_m2 * density_kgm3 * np.hypot(rel_x, rel_y)
    return k * rel_x, k * rel_y
