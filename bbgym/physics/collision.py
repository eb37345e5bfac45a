"""Boats that touch: hulls as capsules, a contact impulse with restitution, and the
overlap pushed out (seed §4, "collisions"; §5, "the plank": an impulse off the centre
turns the body).

A hull seen from above is a capsule: a segment along the heading, ``hull_length_m -
hull_beam_m`` long, swept by a circle of half the beam. Two hulls touch where their
segments come closer than a beam. At a contact point ``c`` with normal ``n`` (from boat
``j`` to boat ``i``) the hulls' velocities there, ``v + omega x r`` with ``r = c -
centre``, approach along ``n`` at ``v_n < 0``; the impulse ``J n`` on ``i`` (``-J n`` on
``j``) with

    J = -(1 + e) v_n / (1/m_i + 1/m_j + (r_i x n)^2 / I_i + (r_j x n)^2 / I_j)

sends them apart at ``-e v_n`` (§4's restitution formula with each body's effective mass
at the point; ``e`` 0 plastic, 1 elastic). Linear momentum is conserved exactly (the pair's
impulses are equal and opposite), angular momentum about any point too, and kinetic energy
does not grow for ``e <= 1``. The overlap left is removed by moving both hulls apart
along ``n`` by half of it each (the boats are alike): positions only, so no momentum is
made. All pairs of a race are treated at once; a few passes of the push settle a
crowd. Where no hulls are near enough to touch, or none touch, nothing more is computed
(the checks are host decisions on the batch, once a substep, as a flight's "all landed"
is); on NumPy only the races with hulls that near are (:mod:`bbgym.physics.compaction`).

Pure functions over a batch of races: every array is ``(races, K)``, pairs
``(races, K, K)`` (boat ``i``, boat ``j``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import NORM_FLOOR
from bbgym.physics.compaction import scatter, take
from bbgym.physics.namespace import Array

PUSH_PASSES = 4
"""Passes of the overlap push per contact resolution: eight hulls heaped in a 12 m square
are within a centimetre of touching after a step's five (tests/race/test_race_physics.py)."""


class Hulls(NamedTuple):
    """The hull's shape and mass (one boat design for the fleet)."""

    half_segment_m: float
    """Half the length of the capsule's segment: ``(length - beam) / 2``."""
    radius_m: float
    """Half the beam."""
    mass_kg: float
    yaw_inertia_kgm2: float


def hulls(length_m: float, beam_m: float, mass_kg: float, yaw_inertia_kgm2: float) -> Hulls:
    """The capsule of a hull ``length_m`` long and ``beam_m`` wide (a beam at least the
    length makes a circle)."""
    return Hulls(max(0.5 * (length_m - beam_m), 0.0), 0.5 * beam_m, mass_kg, yaw_inertia_kgm2)


class Contacts(NamedTuple):
    """The closest points of every pair of hulls (``(races, K, K)`` each)."""

    gap_m: Array
    """Distance between the hulls' surfaces (< 0: overlapping)."""
    normal_x: Array
    """Unit normal from boat ``j``'s hull to boat ``i``'s."""
    normal_y: Array
    point_x_m: Array
    """The contact point: midway between the two closest points."""
    point_y_m: Array


def hull_contacts(h: Hulls, x: Array, y: Array, heading: Array, xp: Any) -> Contacts:
    """The closest points between the segments of every pair of hulls (Ericson,
    *Real-Time Collision Detection*, 5.1.9), their gap and normal. A pair whose segments
    meet (no direction between them) takes the direction between the centres, or the
    first boat's port side where those coincide too."""
    dx, dy = h.half_segment_m * xp.cos(heading), h.half_segment_m * xp.sin(heading)
    # segment i: p1 + s d1 (s in [0, 1]), stern to bow; segment j: p2 + t d2
    p1x, p1y = (x - dx)[:, :, None], (y - dy)[:, :, None]
    p2x, p2y = (x - dx)[:, None, :], (y - dy)[:, None, :]
    d1x, d1y = 2.0 * dx[:, :, None], 2.0 * dy[:, :, None]
    d2x, d2y = 2.0 * dx[:, None, :], 2.0 * dy[:, None, :]
    rx, ry = p1x - p2x, p1y - p2y
    a = xp.maximum(d1x * d1x + d1y * d1y, 1e-12)
    e = xp.maximum(d2x * d2x + d2y * d2y, 1e-12)
    b = d1x * d2x + d1y * d2y
    c = d1x * rx + d1y * ry
    f = d2x * rx + d2y * ry
    denom = a * e - b * b
    parallel = denom <= 1e-12 * a * e
    s = xp.where(parallel, 0.0, xp.clip((b * f - c * e) / xp.where(parallel, 1.0, denom), 0.0, 1.0))
    t = (b * s + f) / e
    s = xp.where(
        t < 0.0, xp.clip(-c / a, 0.0, 1.0), xp.where(t > 1.0, xp.clip((b - c) / a, 0.0, 1.0), s)
    )
    t = xp.clip(t, 0.0, 1.0)
    c1x, c1y = p1x + s * d1x, p1y + s * d1y
    c2x, c2y = p2x + t * d2x, p2y + t * d2y
    sep_x, sep_y = c1x - c2x, c1y - c2y
    distance = xp.hypot(sep_x, sep_y)
    centre_x = x[:, :, None] - x[:, None, :]
    centre_y = y[:, :, None] - y[:, None, :]
    centre = xp.hypot(centre_x, centre_y)
    port_x, port_y = (
        -xp.sin(heading)[:, :, None] + 0.0 * centre,
        xp.cos(heading)[:, :, None] + 0.0 * centre,
    )
    apart = distance > 1e-9
    centres_apart = centre > 1e-9
    nx = xp.where(apart, sep_x, xp.where(centres_apart, centre_x, port_x))
    ny = xp.where(apart, sep_y, xp.where(centres_apart, centre_y, port_y))
    norm = xp.maximum(xp.hypot(nx, ny), NORM_FLOOR)
    return Contacts(
        gap_m=distance - 2.0 * h.radius_m,
        normal_x=nx / norm,
        normal_y=ny / norm,
        point_x_m=0.5 * (c1x + c2x),
        point_y_m=0.5 * (c1y + c2y),
    )


def collide(
    h: Hulls,
    restitution: float,
    x: Array,
    y: Array,
    heading: Array,
    vx: Array,
    vy: Array,
    yaw_rate: Array,
    active: Array,
    xp: Any,
) -> tuple[Array, Array, Array, Array, Array, Array]:
    """Resolve every touching pair of ``active`` hulls (module docstring): the impulses of
    the pairs approaching at their contact, then the overlap pushed out. Returns the new
    ``(x, y, vx, vy, yaw_rate, touching)``, ``touching`` ``(races, K, K)`` the pairs whose
    hulls met."""
    k = x.shape[1]
    others = xp.logical_not(xp.eye(k, dtype=xp.bool, device=getattr(x, "device", None)))
    pairs = others[None, :, :] & active[:, :, None] & active[:, None, :]
    # Broad phase: hulls whose centres are further apart than a hull's length cannot touch;
    # on NumPy, where no pair is that close (most steps of a race), nothing is computed. On
    # torch every branch here is computed and masked instead: a branch on the data would
    # break the compiled step's graph (and the masked result is the same).
    reach = 2.0 * (h.half_segment_m + h.radius_m)
    near = xp.hypot(x[:, :, None] - x[:, None, :], y[:, :, None] - y[:, None, :]) < reach
    close = xp.any(pairs & near, axis=(1, 2))
    if xp is np and not close.any():
        return x, y, vx, vy, yaw_rate, pairs & near
    boats = (x, y, heading, vx, vy, yaw_rate)
    if xp is np and not close.all():  # NumPy: the races with boats close, alone
        busy = np.flatnonzero(close)
        out = _resolve(h, restitution, [take(a, busy) for a in boats], take(pairs, busy), xp)
        full = (x, y, vx, vy, yaw_rate, np.zeros_like(pairs))
        return tuple(scatter(a, busy, b) for a, b in zip(full, out, strict=True))
    return _resolve(h, restitution, boats, pairs, xp)


def _resolve(
    h: Hulls, restitution: float, boats: Sequence[Array], pairs: Array, xp: Any
) -> tuple[Array, Array, Array, Array, Array, Array]:
    """:func:`collide`'s narrow phase, impulses and push for the races given: ``boats``
    their ``(x, y, heading, vx, vy, yaw_rate)``."""
    x, y, heading, vx, vy, yaw_rate = boats
    contacts = hull_contacts(h, x, y, heading, xp)
    touching = pairs & (contacts.gap_m < 0.0)
    if xp is np and not touching.any():  # close, but none touching: nothing to resolve
        return x, y, vx, vy, yaw_rate, touching
    nx, ny = contacts.normal_x, contacts.normal_y
    # lever arms from each centre to the contact point
    rix, riy = contacts.point_x_m - x[:, :, None], contacts.point_y_m - y[:, :, None]
    rjx, rjy = contacts.point_x_m - x[:, None, :], contacts.point_y_m - y[:, None, :]
    wi, wj = yaw_rate[:, :, None], yaw_rate[:, None, :]
    rel_x = (vx[:, :, None] - wi * riy) - (vx[:, None, :] - wj * rjy)
    rel_y = (vy[:, :, None] + wi * rix) - (vy[:, None, :] + wj * rjx)
    approach = rel_x * nx + rel_y * ny
    arm_i = rix * ny - riy * nx
    arm_j = rjx * ny - rjy * nx
    inverse_mass = 2.0 / h.mass_kg + (arm_i * arm_i + arm_j * arm_j) / h.yaw_inertia_kgm2
    impulse = xp.where(
        touching & (approach < 0.0), -(1.0 + restitution) * approach / inverse_mass, 0.0
    )
    vx = vx + xp.sum(impulse * nx, axis=2) / h.mass_kg
    vy = vy + xp.sum(impulse * ny, axis=2) / h.mass_kg
    yaw_rate = yaw_rate + xp.sum(impulse * arm_i, axis=2) / h.yaw_inertia_kgm2
    for push in range(PUSH_PASSES):
        overlap = xp.where(pairs, xp.maximum(-contacts.gap_m, 0.0), 0.0)
        x = x + 0.5 * xp.sum(overlap * contacts.normal_x, axis=2)
        y = y + 0.5 * xp.sum(overlap * contacts.normal_y, axis=2)
        if push < PUSH_PASSES - 1:
            contacts = hull_contacts(h, x, y, heading, xp)
            if xp is np and not (pairs & (contacts.gap_m < 0.0)).any():
                break
    return x, y, vx, vy, yaw_rate, touching
