"""Water that moves: a current and Gerstner waves (seed §9 "relative the water, if that
moves", §10 "Gerstner waves").

The hull, centreboard and rudder of a boat push against the water, not the ground, so they
need the water's velocity where the boat is; and the pressure that accelerates the water in
a wave accelerates a floating boat with it. :func:`water_velocity` gives the velocity at
any point and time (the current plus the waves' orbital velocity), :func:`water_over`
follows the water particle at a boat through a substep.

What is fixed for a run (wave sizes, how the current varies) is :class:`WaterParams`,
Python floats; what each env draws per episode (the current's drift and set, the waves'
direction and phases) and the time is :class:`Sea`, arrays of the batch.

**The current** flows along ``(current_x, current_y)`` (toward a sailor's *set*, at its
*drift*). It may vary across its own direction, ``1 + variation sin(2 pi n / L)`` where ``n``
is the distance across the flow: a shear like a tidal channel's. A speed that changes only
across the flow keeps the field divergence free (no water appears or vanishes) and gives
its particles no acceleration.

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
fold and above the steepness at which real deep-water waves break (about 0.44, a wave
height of 1/7 of the wavelength).

A boat sits at a fixed point ``p`` of the surface, not on a particle, so the water's
velocity there needs the particle that is at ``p`` now: the label ``a`` with ``x(a) = p``.
It is found by the fixed-point iteration ``a <- p + sum_i d_i A_i sin(theta_i(a))``, a
contraction by ``sum_i k_i A_i`` per iteration; :class:`WaterParams` picks the number of
iterations that brings the error below 1e-6 of the amplitude (4 at steepness 0.03, 11 at
0.26, 28 at the steepest accepted): a boat riding a wave for minutes strays from its orbit
by no more. The count is fixed per params: the step keeps static shapes.

Everything here runs on any namespace of :mod:`bbgym.physics.namespace`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array, iterate, replaced
from bbgym.physics.validation import accepted_interval, check_fields, interval, param

MAX_WAVE_STEEPNESS = 0.6
"""The largest accepted ``sum_i k_i A_i``: real waves break near 0.44, the Gerstner surface
folds at 1; the margin keeps the label iteration a contraction by 0.6."""

LABEL_TOLERANCE = 1e-6
"""Error of the particle label found by :func:`particle_label`, as a fraction of the sum
of the amplitudes (the iteration's error shrinks by the steepness each time)."""


class WaveComponent(NamedTuple):
    """One Gerstner component's constants (Python floats); its direction is the sea's
    (per env, :class:`Sea`) turned by ``offset_rad``."""

    amplitude_m: float
    wavenumber_rad_per_m: float
    angular_frequency_rps: float
    offset_rad: float


@dataclass(frozen=True)
class WaterParams:
    """How the water moves, apart from what each episode draws (:class:`Sea`): the current's
    variation and the sea's waves. The default is a uniform current and a flat sea.

    The sea is ``wave_components`` waves spread evenly over ``wave_spread_rad`` about the
    episode's wave direction, with wavelengths from ``wavelength_m`` (the middle one) to 0.6
    of it (the outermost ones: shorter waves off the main direction) and amplitudes
    ``wave_amplitude_m / sqrt(n)`` each, so the sea's rms height is that of one wave of
    ``wave_amplitude_m``.

    Accepted intervals (checked on construction, errors name ``WaterParams.<field>``):

    ==========================  ===============  ==========================================
    field                       interval         why the bounds
    ==========================  ===============  ==========================================
    current_variation           [0, 1]           1 stops the current at the channel's edges
    current_variation_length_m  [10, 1e5]        shorter than a few boat lengths means nothing
    wave_amplitude_m            [0, 5]           5 m is a storm sea; steepness bounds it too
    wavelength_m                [1, 500]         from ripples on a hull to ocean swell
    wave_components             1 .. 8 (int)     a few components make a sea (seed §10)
    wave_spread_rad             [0, pi/2]        beyond, waves meet from opposite sides
    ==========================  ===============  ==========================================

    Together: the steepness ``sum_i k_i A_i`` is at most 0.6 (see the module docstring).
    """

    current_variation: float = param(0.0, interval(0.0, 1.0))
    """Relative change of the current's speed across its direction."""
    current_variation_length_m: float = param(400.0, interval(10.0, 1e5))
    """Wavelength of that change, measured across the flow."""
    wave_amplitude_m: float = param(0.0, interval(0.0, 5.0))
    """Amplitude of a single wave of the same rms height as the sea."""
    wavelength_m: float = param(12.0, interval(1.0, 500.0))
    """Wavelength of the main component."""
    wave_components: int = param(1, interval(1, 8), integer=True)
    """Number of Gerstner components."""
    wave_spread_rad: float = param(0.0, interval(0.0, 0.5 * math.pi))
    """Spread of the components' directions about the main one."""

    def __post_init__(self) -> None:
        check_fields(self)
        components = _components(self)
        steepness = sum(c.amplitude_m * c.wavenumber_rad_per_m for c in components)
        if steepness > MAX_WAVE_STEEPNESS:
            most = max_wave_amplitude(self.wavelength_m, self.wave_components)
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

    def replace(self, **changes: object) -> WaterParams:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


def max_wave_amplitude(wavelength_m: float, wave_components: int) -> float:
    """The largest accepted ``wave_amplitude_m`` for these wavelength and components: the
    steepness ``sum_i k_i A_i`` grows in proportion to the amplitude and may reach
    :data:`MAX_WAVE_STEEPNESS`; the field's own interval caps long waves at 5 m."""
    root_n = math.sqrt(wave_components)
    wavenumbers = [
        c.wavenumber_rad_per_m
        for c in _components(
            WaterParams(wavelength_m=wavelength_m, wave_components=wave_components)
        )
    ]

    def steepness(amplitude: float) -> float:  # as WaterParams sums it, to the bit
        return sum((amplitude / root_n) * k for k in wavenumbers)

    most = min(
        MAX_WAVE_STEEPNESS * root_n / sum(wavenumbers),
        accepted_interval(WaterParams, "wave_amplitude_m").high,
    )
    while steepness(most) > MAX_WAVE_STEEPNESS:  # the division may round up
        most = math.nextafter(most, 0.0)
    return most


def _components(p: WaterParams) -> tuple[WaveComponent, ...]:
    n = p.wave_components
    amplitude = p.wave_amplitude_m / math.sqrt(n)
    out = []
    for i in range(n):
        # Offsets -1 .. 1 from the main direction; the outer ones are shorter waves.
        offset = 0.0 if n == 1 else 2.0 * i / (n - 1) - 1.0
        wavelength = p.wavelength_m * (1.0 - 0.4 * abs(offset))
        k = 2.0 * math.pi / wavelength
        out.append(WaveComponent(amplitude, k, deep_water_frequency(k), offset * p.wave_spread_rad))
    return tuple(out)


def deep_water_frequency(wavenumber_rad_per_m: float) -> float:
    """Deep-water dispersion ``omega^2 = g k``: a wave of length L travels at
    ``c = omega / k = sqrt(g L / (2 pi))`` (12 m waves at 4.3 m/s)."""
    return math.sqrt(GRAVITY_MPS2 * wavenumber_rad_per_m)


class Sea(NamedTuple):
    """The water of each env: what its episode drew and the time since it began (arrays of
    the batch; Python floats for one env)."""

    time_s: Array
    current_x_mps: Array
    """The current's velocity at the middle of its variation (world frame)."""
    current_y_mps: Array
    wave_x: tuple[Array, ...]
    """Each component's unit direction of travel (empty for a flat sea)."""
    wave_y: tuple[Array, ...]
    phases: tuple[Array, ...]


class WaterFlow(NamedTuple):
    """The water at a boat over one substep (world frame): the velocity of the water
    particle that is there at the start, its velocity at the end, and how far it moves
    (from :func:`water_over`). For a steady current the two velocities are equal and the
    shift is the velocity times the substep."""

    vx_mps: Array
    vy_mps: Array
    next_vx_mps: Array
    next_vy_mps: Array
    shift_x_m: Array
    shift_y_m: Array


def sea_at_start(
    p: WaterParams,
    current_mps: Array,
    current_set_rad: Array,
    wave_direction_rad: Array,
    uniform: Any,
    xp: Any = np,
) -> Sea:
    """The water of fresh episodes: a current of ``current_mps`` toward ``current_set_rad``,
    waves travelling toward ``wave_direction_rad`` (the main component), and each
    component's phase ``2 pi u`` from the caller's uniform draws ``uniform``, one row per
    component (the caller owns the randomness)."""
    zero = 0.0 * current_mps
    wave_x, wave_y, phases = [], [], []
    for i, c in enumerate(p.components):
        direction = wave_direction_rad + c.offset_rad
        wave_x.append(xp.cos(direction))
        wave_y.append(xp.sin(direction))
        phases.append(2.0 * math.pi * uniform[i])
    return Sea(
        time_s=zero,
        current_x_mps=current_mps * xp.cos(current_set_rad),
        current_y_mps=current_mps * xp.sin(current_set_rad),
        wave_x=tuple(wave_x),
        wave_y=tuple(wave_y),
        phases=tuple(phases),
    )


def current_velocity(
    p: WaterParams, sea: Sea, x_m: Array, y_m: Array, xp: Any = np
) -> tuple[Array, Array]:
    """The current at ``(x, y)``: along its set, its speed varying across it only."""
    if p.current_variation == 0.0:
        return sea.current_x_mps + 0.0 * x_m, sea.current_y_mps + 0.0 * x_m
    drift = xp.hypot(sea.current_x_mps, sea.current_y_mps)
    # distance across the flow, toward its left (any direction will do for no current)
    across = (y_m * sea.current_x_mps - x_m * sea.current_y_mps) / xp.maximum(drift, 1e-12)
    factor = 1.0 + p.current_variation * xp.sin(
        (2.0 * math.pi / p.current_variation_length_m) * across
    )
    return factor * sea.current_x_mps, factor * sea.current_y_mps


def _phase_angles(p: WaterParams, sea: Sea, a_x: Array, a_y: Array) -> list[Array]:
    """``theta_i = k_i (d_i . a) - omega_i t + phase_i``: where the particle labelled ``a``
    is in each component's orbit."""
    return [
        c.wavenumber_rad_per_m * (d_x * a_x + d_y * a_y)
        - c.angular_frequency_rps * sea.time_s
        + phase
        for c, d_x, d_y, phase in zip(p.components, sea.wave_x, sea.wave_y, sea.phases, strict=True)
    ]


def _displacement(
    p: WaterParams, sea: Sea, a_x: Array, a_y: Array, xp: Any
) -> tuple[Array, Array, Array]:
    """``sum_i d_i A_i sin(theta_i)`` (the particle's offset against the waves' travel,
    with the opposite sign) and the height ``sum_i A_i cos(theta_i)``, at labels ``a``."""
    shift_x, shift_y, z = 0.0, 0.0, 0.0
    thetas = _phase_angles(p, sea, a_x, a_y)
    for c, d_x, d_y, theta in zip(p.components, sea.wave_x, sea.wave_y, thetas, strict=True):
        s = c.amplitude_m * xp.sin(theta)
        shift_x = shift_x + d_x * s
        shift_y = shift_y + d_y * s
        z = z + c.amplitude_m * xp.cos(theta)
    return shift_x, shift_y, z


def particle_label(p: WaterParams, sea: Sea, x_m: Array, y_m: Array, xp: Any = np) -> tuple:
    """The rest position ``a`` of the surface particle that is at ``(x, y)`` now: the fixed
    point of ``a = p + sum_i d_i A_i sin(theta_i(a))`` (module docstring)."""

    def closer(label: tuple) -> tuple:
        shift_x, shift_y, _ = _displacement(p, sea, label[0], label[1], xp)
        return x_m + shift_x, y_m + shift_y

    return iterate(closer, p.label_iterations, (x_m, y_m), xp)


def particle_position(p: WaterParams, sea: Sea, a_x: Array, a_y: Array, xp: Any = np) -> tuple:
    """Where the surface particle with rest position ``a`` is now: ``(x, y, z)`` (the
    Gerstner map, module docstring); ``z`` is the height above the still level."""
    shift_x, shift_y, z = _displacement(p, sea, a_x, a_y, xp)
    return a_x - shift_x, a_y - shift_y, z


def waves_at(p: WaterParams, sea: Sea, x_m: Array, y_m: Array, xp: Any = np) -> tuple:
    """The waves at the fixed point ``(x, y)``, from the particle there now: its velocity
    ``(vx, vy, vz)`` and the surface's height ``z``. Differentiating the offsets in time
    (``d theta / dt = -omega``): ``d_i A_i omega_i cos(theta_i)`` across and
    ``A_i omega_i sin(theta_i)`` up."""
    a_x, a_y = particle_label(p, sea, x_m, y_m, xp)
    return _particle_velocity(p, sea, a_x, a_y, xp)


def _particle_velocity(p: WaterParams, sea: Sea, a_x: Array, a_y: Array, xp: Any) -> tuple:
    """``(vx, vy, vz, z)`` of the particle labelled ``a`` (see :func:`waves_at`)."""
    zero = 0.0 * a_x
    vx, vy, vz, z = zero, zero, zero, zero
    thetas = _phase_angles(p, sea, a_x, a_y)
    for c, d_x, d_y, theta in zip(p.components, sea.wave_x, sea.wave_y, thetas, strict=True):
        cos_t, sin_t = xp.cos(theta), xp.sin(theta)
        speed = c.amplitude_m * c.angular_frequency_rps
        vx, vy, vz = vx + d_x * speed * cos_t, vy + d_y * speed * cos_t, vz + speed * sin_t
        z = z + c.amplitude_m * cos_t
    return vx, vy, vz, z


def water_over(
    p: WaterParams, sea: Sea, x_m: Array, y_m: Array, dt_s: float, xp: Any = np
) -> WaterFlow:
    """The surface water at ``(x, y)`` over the next ``dt_s``: the particle there now (the
    waves' orbital velocity plus the current), followed exactly along its orbit. A boat
    integrated relative to this particle stays on it when nothing else pushes it: the
    orbit closes at any step size (:func:`bbgym.physics.sailing_step.substep`). The waves
    are defined over the ground; the current carries the boat across them (their
    Doppler shift is left out)."""
    current_x, current_y = current_velocity(p, sea, x_m, y_m, xp)
    if not p.components:
        return WaterFlow(
            current_x, current_y, current_x, current_y, dt_s * current_x, dt_s * current_y
        )
    a_x, a_y = particle_label(p, sea, x_m, y_m, xp)
    vx, vy, _, _ = _particle_velocity(p, sea, a_x, a_y, xp)
    later = replaced(sea, time_s=sea.time_s + dt_s)
    next_vx, next_vy, _, _ = _particle_velocity(p, later, a_x, a_y, xp)
    next_x, next_y, _ = particle_position(p, later, a_x, a_y, xp)
    return WaterFlow(
        current_x + vx,
        current_y + vy,
        current_x + next_vx,
        current_y + next_vy,
        next_x - x_m + dt_s * current_x,
        next_y - y_m + dt_s * current_y,
    )


def water_velocity(p: WaterParams, sea: Sea, x_m: Array, y_m: Array, xp: Any = np) -> tuple:
    """The horizontal velocity ``(vx, vy)`` of the surface water at ``(x, y)``: the
    current plus the waves' orbital velocity."""
    current_x, current_y = current_velocity(p, sea, x_m, y_m, xp)
    if not p.components:
        return current_x, current_y
    wave_x, wave_y, _, _ = waves_at(p, sea, x_m, y_m, xp)
    return current_x + wave_x, current_y + wave_y
