"""True wind: a steady wind with optional gusts and shifts (seed §8, "model it with randomness").

Gusts and shifts are a smooth random process: an Ornstein-Uhlenbeck process (mean
reverting, stationary standard deviation ``*_std``, correlation time ``time_constant_s``)
fed through a first-order lag, so the wind has no kinks a controller could not follow.
All randomness comes from the ``numpy.random.Generator`` passed in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class GustParams:
    """Statistics of gusts (speed) and shifts (direction) of the true wind."""

    speed_std: float = 0.15
    """Standard deviation of the wind speed, as a fraction of the mean speed."""
    shift_std_rad: float = math.radians(8.0)
    """Standard deviation of the wind direction about its mean."""
    time_constant_s: float = 20.0
    """Correlation time of the underlying process."""
    smoothing_s: float = 4.0
    """Time constant of the lag that smooths the process."""

    def __post_init__(self) -> None:
        for name in ("speed_std", "shift_std_rad"):
            value = getattr(self, name)
            if not math.isfinite(value) or value < 0.0:
                raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
        for name in ("time_constant_s", "smoothing_s"):
            value = getattr(self, name)
            if not math.isfinite(value) or value <= 0.0:
                raise ValueError(f"{name} must be finite and > 0, got {value!r}")


@dataclass
class GustState:
    """Per-env gust process: raw OU values and their smoothed versions."""

    speed_raw: np.ndarray
    speed: np.ndarray
    shift_raw: np.ndarray
    shift: np.ndarray


def gust_init(params: GustParams, batch: int, rng: np.random.Generator) -> GustState:
    """Draw the gust process from its stationary distribution."""
    speed = rng.normal(0.0, params.speed_std, batch)
    shift = rng.normal(0.0, params.shift_std_rad, batch)
    return GustState(speed_raw=speed, speed=speed.copy(), shift_raw=shift, shift=shift.copy())


def gust_step(
    state: GustState,
    params: GustParams,
    dt_s: float,
    rng: np.random.Generator,
    enabled: np.ndarray,
) -> GustState:
    """Advance the gust process by ``dt_s`` (exact OU discretisation, then the lag).

    Where ``enabled`` is false the gust stays at zero (steady wind). Random numbers are
    drawn for every element either way, so one env's draws do not depend on another's
    options.
    """
    decay = math.exp(-dt_s / params.time_constant_s)
    noise_scale = math.sqrt(1.0 - decay * decay)
    lag = 1.0 - math.exp(-dt_s / params.smoothing_s)
    noise = rng.normal(0.0, 1.0, (2, state.speed.shape[0]))
    speed_raw = decay * state.speed_raw + params.speed_std * noise_scale * noise[0]
    shift_raw = decay * state.shift_raw + params.shift_std_rad * noise_scale * noise[1]
    speed_raw = np.where(enabled, speed_raw, 0.0)
    shift_raw = np.where(enabled, shift_raw, 0.0)
    return GustState(
        speed_raw=speed_raw,
        speed=state.speed + lag * (speed_raw - state.speed),
        shift_raw=shift_raw,
        shift=state.shift + lag * (shift_raw - state.shift),
    )


def wind_vector(
    mean_speed_mps: np.ndarray, mean_from_rad: np.ndarray, gusts: GustState
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """True wind now: ``(vx, vy, speed, from)``.

    ``from`` is where the wind blows from (sailing usage); the vector points where the air
    moves, so it is ``-speed * (cos(from), sin(from))``. Gusts never reverse the wind.
    """
    speed = mean_speed_mps * np.maximum(1.0 + gusts.speed, 0.0)
    wind_from = mean_from_rad + gusts.shift
    return -speed * np.cos(wind_from), -speed * np.sin(wind_from), speed, wind_from
