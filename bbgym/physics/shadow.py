"""Wind shadow: the air a sail has turned, downwind of it (seed §9, "apparent wind";
Newton's third law).

A sail drives its boat by pushing the air the other way: the aerodynamic force ``F`` on
the sails is, reversed, the force on the air flowing past them. Over the time the air
takes to pass the sail and settle, ``acting_time_s``, that air receives the momentum
``-F t``. Spread over the air of a cone that opens downwind along the sail's apparent
wind, it is a change of velocity that both slows the wind (the drag part of ``F``) and
bends it (the lift part): a boat sailing in another's cone feels less wind and a header.

The cone and its profile follow the "windwise" cone of jax-monohull-dynamics
(``dynamics/boat_wind_interaction.py``, H. Tomkins): 20 m long (about five dinghy
lengths), about a sail's chord wide at the sail and 7 m wide at its end, the effect
falling off as a Gaussian along it (the cone's length two standard deviations) and across
it (the local half-width one), an air layer 6 m high (the rig's height) and 3 s of
action. Where that model divides the momentum by an assumed air mass, here the momentum
is conserved exactly: the velocity change at the cone's peak is ``F t / (rho h A)`` with
``A`` the integral of the profile over the cone (:func:`profile_area_m2`), so the air of
the cone carries ``-F t`` in all. For a dinghy beating in 5 m/s of wind (a sail force of
some 250 N) that is a deficit of a third just behind the sail, a fifth two boat lengths
on, under a tenth four boat lengths on, and none past the cone: the "dirty air" sailors
keep out of.

Pure functions over a batch of races, each of ``K`` boats: positions and forces are
``(races, K)`` arrays, pairs ``(races, K, K)`` (receiver, source).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from bbgym.physics.common import AIR_DENSITY_KGM3
from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, interval, param


@dataclass(frozen=True)
class ShadowParams(CheckedFields):
    """The cone of turned air behind a sail (module docstring).

    Accepted intervals (checked on construction, errors name ``ShadowParams.<field>``):

    ================  ==============  =====================================================
    field             interval        why the bounds
    ================  ==============  =====================================================
    length_m          [1, 200]        a sail's chord .. the length of a start line
    base_width_m      [0.1, 50]       half-width at the sail
    end_width_m       [0.1, 100]      half-width at the cone's end
    acting_time_s     [0, 30]         0: no shadow at all
    air_height_m      [0.5, 50]       the layer of air the rig turns
    ================  ==============  =====================================================
    """

    length_m: float = param(20.0, interval(1.0, 200.0))
    """How far downwind of the sail the cone reaches."""
    base_width_m: float = param(1.0, interval(0.1, 50.0))
    """The cone's half-width at the sail."""
    end_width_m: float = param(7.0, interval(0.1, 100.0))
    """The cone's half-width at its end."""
    acting_time_s: float = param(3.0, interval(0.0, 30.0))
    """How long the sail's force acts on the air that passes it."""
    air_height_m: float = param(6.0, interval(0.5, 50.0))
    """Height of the layer of air the cone holds."""


def cone_profile(p: ShadowParams, along_m: Array, across_m: Array, xp: Any = np) -> Array:
    """The shadow's strength, 1 at the sail, at a point ``along_m`` downwind of it on the
    cone's axis and ``across_m`` off it: Gaussian along (two standard deviations over the
    length) and across (one over the local half-width), 0 outside the cone."""
    half_width = p.base_width_m + (p.end_width_m - p.base_width_m) * along_m / p.length_m
    half_width = xp.maximum(half_width, 1e-9)
    sigma_along = 0.5 * p.length_m
    profile = xp.exp(-0.5 * (along_m / sigma_along) ** 2 - 0.5 * (across_m / half_width) ** 2)
    inside = (along_m > 0.0) & (along_m < p.length_m) & (xp.abs(across_m) < half_width)
    return xp.where(inside, profile, 0.0)


@functools.lru_cache(maxsize=64)
def profile_area_m2(p: ShadowParams) -> float:
    """The integral of :func:`cone_profile` over the cone (m^2): across, in closed form
    (``sqrt(2 pi) w erf(1 / sqrt 2)`` for the half-width ``w``), along by Simpson's rule
    on 2001 points (relative error below 1e-12 for any accepted cone)."""
    along = np.linspace(0.0, p.length_m, 2001)
    half_width = p.base_width_m + (p.end_width_m - p.base_width_m) * along / p.length_m
    across = math.sqrt(2.0 * math.pi) * math.erf(1.0 / math.sqrt(2.0)) * half_width
    values = np.exp(-0.5 * (along / (0.5 * p.length_m)) ** 2) * across
    h = along[1] - along[0]
    weights = np.ones_like(along)
    weights[1:-1:2], weights[2:-1:2] = 4.0, 2.0
    return float(h / 3.0 * np.sum(weights * values))


def shadow_velocity(
    p: ShadowParams,
    source_x_m: Array,
    source_y_m: Array,
    force_x_n: Array,
    force_y_n: Array,
    flow_x_mps: Array,
    flow_y_mps: Array,
    casts: Array,
    x_m: Array,
    y_m: Array,
    xp: Any = np,
    area_m2: float | None = None,
) -> tuple[Array, Array]:
    """The change of wind velocity at each boat ``(x_m, y_m)`` from every other boat's sails,
    summed (``(races, K)`` each): source ``j`` at ``(source_x_m, source_y_m)`` with the
    aerodynamic force ``(force_x_n, force_y_n)`` on its sails and its apparent wind
    ``(flow_x_mps, flow_y_mps)`` (where the air moves past it: the cone's axis) gives the
    air of its cone ``-F t_act`` of momentum, ``dv = -F t_act profile / (rho h A)``.
    Boats where ``casts`` is false (capsized, finished) cast none; no boat shadows itself.
    ``area_m2`` is :func:`profile_area_m2` of ``p``, from a caller that computed it once (a
    compiled step cannot call the cached NumPy integral without breaking its graph)."""
    flow_speed = xp.maximum(xp.hypot(flow_x_mps, flow_y_mps), 1e-9)
    axis_x, axis_y = flow_x_mps / flow_speed, flow_y_mps / flow_speed
    # (receiver i, source j): the receiver's place in source j's cone
    dx = x_m[:, :, None] - source_x_m[:, None, :]
    dy = y_m[:, :, None] - source_y_m[:, None, :]
    along = dx * axis_x[:, None, :] + dy * axis_y[:, None, :]
    across = -dx * axis_y[:, None, :] + dy * axis_x[:, None, :]
    profile = cone_profile(p, along, across, xp)
    k = x_m.shape[1]
    others = xp.logical_not(xp.eye(k, dtype=xp.bool, device=_device(x_m)))
    profile = xp.where(others[None, :, :] & casts[:, None, :], profile, 0.0)
    area_m2 = profile_area_m2(p) if area_m2 is None else area_m2
    scale = -p.acting_time_s / (AIR_DENSITY_KGM3 * p.air_height_m * area_m2)
    dvx = scale * xp.sum(profile * force_x_n[:, None, :], axis=2)
    dvy = scale * xp.sum(profile * force_y_n[:, None, :], axis=2)
    return dvx, dvy


def shadowed_wind(
    wind_x: Array, wind_y: Array, dvx: Array, dvy: Array, xp: Any = np
) -> tuple[Array, Array]:
    """The wind with a shadow's change of velocity added, never faster than the wind
    itself: turned air has given momentum away, it cannot have gained speed (several cones
    that overlap, each bending the wind, could otherwise add up to more)."""
    speed = xp.hypot(wind_x, wind_y)
    new_x, new_y = wind_x + dvx, wind_y + dvy
    new_speed = xp.hypot(new_x, new_y)
    scale = xp.where(new_speed > speed, speed / xp.maximum(new_speed, 1e-12), 1.0)
    return new_x * scale, new_y * scale


def _device(array: Any) -> Any:
    return getattr(array, "device", None)
