"""Water that moves: a current and Gerstner waves (seed §9 "relative the water, if that
moves", §10 "Gerstner waves").

The hull, centreboard and rudder of a boat push against the water, not the ground, so they
need the water's velocity where the boat is. This module gives it as a pure function of
position and time: :func:`water_velocity` is the current plus the waves' orbital velocity.

**The current** flows toward ``current_set_rad`` (a sailor's *set*; its speed is the
*drift*). It may vary across its own direction, ``1 + variation * sin(2 pi n / L)`` where
``n`` is the distance across the flow: a shear like a tidal channel's. A speed that changes
only across the flow keeps the field divergence free (no water appears or vanishes).

**Gerstner waves** (trochoidal waves, seed §10) are kinematic: each surface particle with
rest position ``a`` circles about it,

    x = a - sum_i d_i A_i sin(theta_i),   z = sum_i A_i cos(theta_i),
    theta_i = k_i (d_i . a) - omega_i t + phase_i,

for components of amplitude ``A_i``, wavenumber ``k_i = 2 pi / wavelength_i``, unit
direction of travel ``d_i`` and the deep-water dispersion ``omega_i^2 = g k_i``. A particle's
velocity, ``sum_i d_i A_i omega_i cos(theta_i)`` across and ``sum_i A_i omega_i sin(theta_i)``
up, is periodic: its orbit closes, Gerstner waves carry no water along (no Stokes drift).

The text warns that the surface self-intersects for some parameters. That happens where the
map ``a -> x`` folds: its Jacobian ``I - sum_i k_i A_i cos(theta_i) d_i d_i^T`` is
singular once ``sum_i k_i A_i`` reaches 1 (for one wave, ``k A = 1``, the cusped trochoid).
The accepted waves keep ``sum_i k_i A_i`` at most :data:`MAX_WAVE_STEEPNESS`, below the
fold and near the steepness at which real deep-water waves break (about 0.44, wave height
1/7 of the wavelength).

A boat sits at a fixed point ``p`` of the surface, not on a particle, so the water's
velocity there needs the particle that is at ``p`` now: the label ``a`` with ``x(a) = p``.
It is found by the fixed-point iteration ``a <- p + sum_i d_i A_i sin(theta_i(a))``, a
contraction by ``sum_i k_i A_i`` per iteration; :class:`WaterParams` picks the number of
iterations that brings the error below 1e-4 of the amplitude (4 for gentle waves, 19 at
the steepest accepted). The count is fixed per params: the step keeps static shapes.

Everything here runs on any namespace of :mod:`bbgym.physics.namespace`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import ANGLE_RAD, check_fields, interval, param

MAX_WAVE_STEEPNESS = 0.6
"""The largest accepted ``sum_i k_i A_i``: real waves break near 0.44, the Gerstner surface
folds at 1; the margin keeps the label iteration a contraction by 0.6."""

LABEL_TOLERANCE = 1e-4
"""Error of the particle label found by :func:`particle_label`, as a fraction of the sum
of the amplitudes (the iteration's error shrinks by the steepness each time)."""


class WaveComponent(NamedTuple):
    """One Gerstner component, its constants precomputed (Python floats)."""

    amplitude_m: float
    wavenumber_rad_per_m: float
    angular_frequency_rps: float
    direction_x: float
    direction_y: float


@dataclass(frozen=True)
class WaterParams:
    """A current and a sea of Gerstner waves (all zero by default: still water).

    The sea is ``wave_components`` waves spread evenly over ``wave_spread_rad`` about
    ``wave_direction_rad`` (each a direction of travel), with wavelengths from
    ``wavelength_m`` (the middle one) to 0.6 of it (the outermost ones: shorter waves off
    the main direction) and amplitudes ``wave_amplitude_m / sqrt(n)`` each, so the sea's
    rms height is that of one wave of ``wave_amplitude_m``. Each env draws its components'
    phases (:func:`wave_phases`).

    Accepted intervals (checked on construction, errors name ``WaterParams.<field>``):

    ==========================  ===============  ==========================================
    field                       interval         why the bounds
    ==========================  ===============  ==========================================
    current_mps                 [0, 3]           3 m/s (6 kn) is a strong tidal race
    current_set_rad             any angle        where the current flows to
    current_variation           [0, 1]           1 stops the current at the channel's edges
    current_variation_length_m  [10, 1e5]        shorter than a boat's lengths means nothing
    wave_amplitude_m            [0, 5]           5 m is a storm sea; steepness bounds it too
    wavelength_m                [1, 500]         from ripples on a hull to ocean swell
    wave_direction_rad          any angle        where the waves travel to
    wave_components             1 .. 8 (int)     a few components make a sea (seed §10)
    wave_spread_rad             [0, pi/2]        beyond, waves meet from opposite sides
    ==========================  ===============  ==========================================

    Together: the steepness ``sum_i k_i A_i`` is at most 0.6 (see the module docstring).
    """

    current_mps: float = param(0.0, interval(0.0, 3.0))
    """Speed of the current (its drift), at the middle of its variation."""
    current_set_rad: float = param(0.0, ANGLE_RAD)
    """Direction the current flows toward, counterclockwise from +x."""
    current_variation: float = param(0.0, interval(0.0, 1.0))
    """Relative change of the current's speed across its direction."""
    current_variation_length_m: float = param(400.0, interval(10.0, 1e5))
    """Wavelength of that change, measured across the flow."""
    wave_amplitude_m: float = param(0.0, interval(0.0, 5.0))
    """Amplitude of a single wave of the same rms height as the sea."""
    wavelength_m: float = param(12.0, interval(1.0, 500.0))
    """Wavelength of the main component."""
    wave_direction_rad: float = param(0.0, ANGLE_RAD)
    """Direction the main component travels toward, counterclockwise from +x."""
    wave_components: int = param(1, interval(1, 8), integer=True)
    """Number of Gerstner components."""
    wave_spread_rad: float = param(0.0, interval(0.0, 0.5 * math.pi))
    """Spread of the components' directions about the main one."""

    def __post_init__(self) -> None:
        check_fields(self)
        components = _components(self)
        steepness = sum(c.amplitude_m * c.wavenumber_rad_per_m for c in components)
        if steepness > MAX_WAVE_STEEPNESS:
            most = self.wave_amplitude_m * MAX_WAVE_STEEPNESS / steepness
            raise ValueError(
                f"WaterParams.wave_amplitude_m must be at most {most:.4g} m with "
                f"wavelength_m={self.wavelength_m!r} and wave_components="
                f"{self.wave_components!r} (steepness sum(k A) <= {MAX_WAVE_STEEPNESS}: "
                f"the Gerstner surface folds at 1, real waves break near 0.44), got "
                f"{self.wave_amplitude_m!r} (steepness {steepness:.3g})"
            )
        # Derived constants, not fields: equality and repr see the parameters only.
        # ``components`` (empty for a flat sea), ``steepness`` (sum k A) and
        # ``label_iterations`` (the fixed-point count of :func:`particle_label`).
        iterations = 0
        if steepness > 0.0:
            iterations = max(1, math.ceil(math.log(LABEL_TOLERANCE) / math.log(steepness)))
        object.__setattr__(self, "components", components if steepness > 0.0 else ())
        object.__setattr__(self, "steepness", steepness)
        object.__setattr__(self, "label_iterations", iterations)
        set_x, set_y = math.cos(self.current_set_rad), math.sin(self.current_set_rad)
        object.__setattr__(self, "_current_set", (set_x, set_y))

    def replace(self, **changes: object) -> WaterParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)

    @property
    def still(self) -> bool:
        """No current and no waves: the water's velocity is zero everywhere."""
        return self.current_mps == 0.0 and not self.components


def _components(p: WaterParams) -> tuple[WaveComponent, ...]:
    n = p.wave_components
    amplitude = p.wave_amplitude_m / math.sqrt(n)
    out = []
    for i in range(n):
        # Offsets -1 .. 1 from the main direction; the outer ones are shorter waves.
        offset = 0.0 if n == 1 else 2.0 * i / (n - 1) - 1.0
        wavelength = p.wavelength_m * (1.0 - 0.4 * abs(offset))
        k = 2.0 * math.pi / wavelength
        direction = p.wave_direction_rad + offset * p.wave_spread_rad
        out.append(
            WaveComponent(
                amplitude_m=amplitude,
                wavenumber_rad_per_m=k,
                angular_frequency_rps=deep_water_frequency(k),
                direction_x=math.cos(direction),
                direction_y=math.sin(direction),
            )
        )
    return tuple(out)


def deep_water_frequency(wavenumber_rad_per_m: float) -> float:
    """Deep-water dispersion ``omega^2 = g k``: a wave of length L travels at
    ``c = omega / k = sqrt(g L / (2 pi))`` (12 m waves at 4.3 m/s)."""
    return math.sqrt(GRAVITY_MPS2 * wavenumber_rad_per_m)


class Sea(NamedTuple):
    """Where each env's waves are in their cycle: the time since the episode began and each
    component's phase (constant over an episode, drawn by :func:`sea_at_start`)."""

    time_s: Array
    phases: tuple[Array, ...]


def sea_at_start(p: WaterParams, uniform: Any) -> Sea:
    """A sea at time 0 with phases ``2 pi u`` for the caller's uniform draws ``uniform`` of
    shape ``(components, batch)`` (the caller owns the randomness)."""
    phases = tuple(2.0 * math.pi * uniform[i] for i in range(len(p.components)))
    return Sea(time_s=0.0 * uniform[0], phases=phases)


def current_velocity(p: WaterParams, x_m: Array, y_m: Array, xp: Any = np) -> tuple[Array, Array]:
    """The current at ``(x, y)``: along its set, its speed varying across it only."""
    set_x, set_y = p._current_set
    speed = p.current_mps + 0.0 * x_m  # shaped like the positions even where uniform
    if p.current_variation > 0.0:
        across = -x_m * set_y + y_m * set_x
        wave = xp.sin((2.0 * math.pi / p.current_variation_length_m) * across)
        speed = p.current_mps * (1.0 + p.current_variation * wave)
    return speed * set_x, speed * set_y


def _phase_angle(c: WaveComponent, phase: Array, a_x: Array, a_y: Array, time_s: Array) -> Array:
    """``theta = k (d . a) - omega t + phase``: where a particle is in its orbit."""
    k = c.wavenumber_rad_per_m
    return (
        k * (c.direction_x * a_x + c.direction_y * a_y) - c.angular_frequency_rps * time_s + phase
    )


def _displacement(
    p: WaterParams, a_x: Array, a_y: Array, sea: Sea, xp: Any
) -> tuple[Array, Array, Array]:
    """``sum_i d_i A_i sin(theta_i)`` (the particle's offset against the waves' travel,
    with the opposite sign) and the height ``sum_i A_i cos(theta_i)``, at labels ``a``."""
    shift_x, shift_y, z = 0.0, 0.0, 0.0
    for c, phase in zip(p.components, sea.phases, strict=True):
        theta = _phase_angle(c, phase, a_x, a_y, sea.time_s)
        s = c.amplitude_m * xp.sin(theta)
        shift_x = shift_x + c.direction_x * s
        shift_y = shift_y + c.direction_y * s
        z = z + c.amplitude_m * xp.cos(theta)
    return shift_x, shift_y, z


def particle_label(p: WaterParams, x_m: Array, y_m: Array, sea: Sea, xp: Any = np) -> tuple:
    """The rest position ``a`` of the surface particle that is at ``(x, y)`` now: the fixed
    point of ``a = p + sum_i d_i A_i sin(theta_i(a))`` (module docstring)."""
    a_x, a_y = x_m, y_m
    for _ in range(p.label_iterations):
        shift_x, shift_y, _ = _displacement(p, a_x, a_y, sea, xp)
        a_x, a_y = x_m + shift_x, y_m + shift_y
    return a_x, a_y


def particle_position(p: WaterParams, a_x: Array, a_y: Array, sea: Sea, xp: Any = np) -> tuple:
    """Where the surface particle with rest position ``a`` is now: ``(x, y, z)`` (the
    Gerstner map, module docstring); ``z`` is the height above the still level."""
    shift_x, shift_y, z = _displacement(p, a_x, a_y, sea, xp)
    return a_x - shift_x, a_y - shift_y, z


def orbital_velocity(p: WaterParams, x_m: Array, y_m: Array, sea: Sea, xp: Any = np) -> tuple:
    """The waves at the fixed point ``(x, y)``: the water's orbital velocity there
    ``(vx, vy, vz)`` and the surface's height ``z`` (of the particle at that point now).
    A particle's velocity is its offset's time derivative, ``d_i A_i omega_i cos(theta_i)``
    across and ``A_i omega_i sin(theta_i)`` up (``d theta / dt = -omega``)."""
    zero = 0.0 * x_m
    if not p.components:
        return zero, zero, zero, zero
    a_x, a_y = particle_label(p, x_m, y_m, sea, xp)
    vx, vy, vz, z = zero, zero, zero, zero
    for c, phase in zip(p.components, sea.phases, strict=True):
        theta = _phase_angle(c, phase, a_x, a_y, sea.time_s)
        cos_t, sin_t = xp.cos(theta), xp.sin(theta)
        speed = c.amplitude_m * c.angular_frequency_rps
        vx = vx + c.direction_x * speed * cos_t
        vy = vy + c.direction_y * speed * cos_t
        vz = vz + speed * sin_t
        z = z + c.amplitude_m * cos_t
    return vx, vy, vz, z


def water_velocity(p: WaterParams, x_m: Array, y_m: Array, sea: Sea, xp: Any = np) -> tuple:
    """The horizontal velocity ``(vx, vy)`` of the surface water at ``(x, y)``: the current
    plus the waves' orbital velocity."""
    current_x, current_y = current_velocity(p, x_m, y_m, xp)
    if not p.components:
        return current_x, current_y
    wave_x, wave_y, _, _ = orbital_velocity(p, x_m, y_m, sea, xp)
    return current_x + wave_x, current_y + wave_y
