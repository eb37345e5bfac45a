"""True wind: a steady wind with optional gusts and shifts (seed §8, "model it with randomness").

Gusts and shifts are a smooth random process: an Ornstein-Uhlenbeck process (mean
reverting, stationary standard deviation ``*_std``, correlation time ``time_constant_s``)
fed through a first-order lag, so the wind has no kinks a controller could not follow.
The caller passes the standard normal draws, made with its own
``numpy.random.Generator``: the process itself holds no randomness.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, interval, param


@dataclass(frozen=True)
class GustParams(CheckedFields):
    """Statistics of gusts (speed) and shifts (direction) of the true wind.

    Accepted intervals (checked on construction, errors name ``GustParams.<field>``):

    ================  ==============  =====================================================
    field             interval        why the bounds
    ================  ==============  =====================================================
    speed_std         [0, 1]          a std of the whole mean speed already lulls to calm
    shift_std_rad     [0, pi/2]       beyond 90 deg the "mean" direction means nothing
    time_constant_s   [0.01, 1e4]     correlation time: from a flicker to hours
    smoothing_s       [0.01, 1e4]     lag of the smoothing filter, same span
    ================  ==============  =====================================================

    Zero standard deviations are valid: a steady wind.
    """

    speed_std: float = param(0.15, interval(0.0, 1.0))
    """Standard deviation of the wind speed, as a fraction of the mean speed."""
    shift_std_rad: float = param(math.radians(8.0), interval(0.0, 0.5 * math.pi))
    """Standard deviation of the wind direction about its mean."""
    time_constant_s: float = param(20.0, interval(0.01, 1e4))
    """Correlation time of the underlying process."""
    smoothing_s: float = param(4.0, interval(0.01, 1e4))
    """Time constant of the lag that smooths the process."""


class GustState(NamedTuple):
    """Per-env gust process: raw OU values and their smoothed versions (immutable)."""

    speed_raw: Array
    speed: Array
    shift_raw: Array
    shift: Array


def gust_init(params: GustParams, noise: Any, enabled: Array, xp: Any = np) -> GustState:
    """Start the gust process in its stationary distribution from ``noise`` ``(2, batch)``."""
    speed = xp.where(enabled, params.speed_std * noise[0], 0.0)
    shift = xp.where(enabled, params.shift_std_rad * noise[1], 0.0)
    return GustState(speed_raw=speed, speed=speed, shift_raw=shift, shift=shift)


def gust_step(
    state: GustState,
    params: GustParams,
    dt_s: float,
    noise: Any,
    enabled: Array,
    xp: Any = np,
) -> GustState:
    """Advance the gust process by ``dt_s`` (exact OU discretisation, then the lag).

    ``noise`` holds standard normal draws of shape ``(2, batch)`` (speed, direction), drawn
    by the caller from its ``numpy.random.Generator`` so each env can own its stream. Where
    ``enabled`` is false the gust stays at zero (steady wind).
    """
    decay = math.exp(-dt_s / params.time_constant_s)
    noise_scale = math.sqrt(1.0 - decay * decay)
    lag = 1.0 - math.exp(-dt_s / params.smoothing_s)
    speed_raw = decay * state.speed_raw + params.speed_std * noise_scale * noise[0]
    shift_raw = decay * state.shift_raw + params.shift_std_rad * noise_scale * noise[1]
    speed_raw = xp.where(enabled, speed_raw, 0.0)
    shift_raw = xp.where(enabled, shift_raw, 0.0)
    return GustState(
        speed_raw=speed_raw,
        speed=state.speed + lag * (speed_raw - state.speed),
        shift_raw=shift_raw,
        shift=state.shift + lag * (shift_raw - state.shift),
    )


def wind_vector(
    mean_speed_mps: Array, mean_from_rad: Array, gusts: GustState, xp: Any = np
) -> tuple[Array, Array, Array, Array]:
    """True wind now: ``(vx, vy, speed, from)``.

    ``from`` is where the wind blows from (sailing usage); the vector points where the air
    moves, so it is ``-speed * (cos(from), sin(from))``. Gusts never reverse the wind.
    """
    speed = mean_speed_mps * xp.maximum(1.0 + gusts.speed, 0.0)
    wind_from = mean_from_rad + gusts.shift
    return -speed * xp.cos(wind_from), -speed * xp.sin(wind_from), speed, wind_from
