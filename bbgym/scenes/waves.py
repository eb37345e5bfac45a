"""Gerstner waves (§10): a water surface moved by pure kinematics, each surface point
carried round a circle, the circles' phases running along the surface.

The text's vertex shader, in SI units: a point at rest at ``x0`` on a flat surface is at

    x = x0 + a cos(w t + k x0),    y = a sin(w t + k x0)

(``a`` the amplitude, ``k = 2 pi / wavelength`` the wavenumber, ``w`` the angular speed):
a trochoid, its crests sharper than its troughs. The wave's shape travels at ``w / k``
(toward -x with this sign convention) while each point only circles. The text warns that
the wave "deteriorates and self-intersects" for some parameters: that is when
``k a > 1``, where ``dx / dx0 = 1 - k a sin(w t + k x0)`` turns negative and neighbouring
points pass each other (at ``k a = 1`` the crest is a cusp).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.namespace import Array
from bbgym.physics.validation import CheckedFields, interval, param
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment

WATER = (40, 110, 210)


class Surface(NamedTuple):
    """The surface's points ``(1, points)``: their rest positions and the time."""

    rest_x_m: Array
    x_m: Array
    y_m: Array
    time_s: Array


@dataclass(frozen=True)
class GerstnerParams(CheckedFields):
    """One Gerstner wave on a strip of surface a few wavelengths long."""

    wavelength_m: float = param(10.0, interval(0.01, 1000.0))
    amplitude_m: float = param(1.0, interval(0.0, 1000.0))
    """``a``: each point's circle's radius; the wave self-intersects past
    ``wavelength / (2 pi)``."""
    angular_speed_radps: float = param(2.5, interval(0.0, 100.0))
    """``w``; deep water's dispersion would make it ``sqrt(g k)``: 2.48 rad/s at 10 m."""
    wavelengths: int = param(3, interval(1, 50), integer=True)
    points: int = param(240, interval(8, 100_000), integer=True)
    dt_s: float = param(1.0 / 30.0, interval(1e-4, 1.0))

    @property
    def wavenumber_radpm(self) -> float:
        return 2.0 * math.pi / self.wavelength_m

    @property
    def steepness(self) -> float:
        """``k a``: under 1 the surface stays a curve; over 1 it loops through itself."""
        return self.wavenumber_radpm * self.amplitude_m


def surface_at(p: GerstnerParams, rest_x: Array, time_s: Array, xp: Any) -> tuple[Array, Array]:
    """The Gerstner surface's points at ``time_s`` (the module docstring's formula)."""
    phase = p.angular_speed_radps * time_s + p.wavenumber_radpm * rest_x
    return rest_x + p.amplitude_m * xp.cos(phase), p.amplitude_m * xp.sin(phase)


def gerstner_initial(p: GerstnerParams, xp: Any) -> Surface:
    length = p.wavelengths * p.wavelength_m
    rest = xp.asarray(np.linspace(0.0, length, p.points, endpoint=False)[None, :], dtype=xp.float64)
    time = xp.zeros((1,), dtype=xp.float64)
    x, y = surface_at(p, rest, time[:, None], xp)
    return Surface(rest, x, y, time)


def gerstner_step(p: GerstnerParams, s: Surface, xp: Any) -> Surface:
    """Kinematics: the surface at the next time, from the formula (nothing integrates)."""
    time = s.time_s + p.dt_s
    x, y = surface_at(p, s.rest_x_m, time[:, None], xp)
    return Surface(s.rest_x_m, x, y, time)


def gerstner_measures(p: GerstnerParams, s: Surface, xp: Any) -> dict[str, Array]:
    """How far each point is from its rest position (its circle's radius), the smallest
    step from one point to the next along x (negative: the surface crosses itself), the
    crest's height and where the first crest is."""
    radius = xp.sqrt((s.x_m - s.rest_x_m) ** 2 + s.y_m**2)
    gaps = s.x_m[:, 1:] - s.x_m[:, :-1]
    # The points inside the first wavelength: ceil(points / wavelengths), the point at 0
    # at least (fewer points than wavelengths once left none, and argmax failed).
    count = -(-s.x_m.shape[1] // p.wavelengths)
    first = xp.argmax(s.y_m[:, :count], axis=1)
    crest_x = xp.take(s.x_m[0, :], first)
    return {
        "circle_radius_m": xp.max(radius, axis=1),
        "smallest_gap_m": xp.min(gaps, axis=1),
        "crest_m": xp.max(s.y_m, axis=1),
        "first_crest_x_m": crest_x,
    }


def gerstner_frame(p: GerstnerParams, s: Surface) -> Frame:
    x, y = np.asarray(s.x_m)[0], np.asarray(s.y_m)[0]
    segments = [
        Segment(float(x[i]), float(y[i]), float(x[i + 1]), float(y[i + 1]), WATER, 2)
        for i in range(len(x) - 1)
    ]
    marker = Circle(
        float(x[0]),
        float(y[0]),
        0.08 * p.wavelength_m / 10.0,
        (230, 70, 60),
        "a point of the surface",
    )
    shape = "loops through itself" if p.steepness > 1.0 else "a curve"
    return Frame([marker], segments, [f"k a = {p.steepness:.2f}: the surface is {shape}"])


GERSTNER = Scene(
    name="gerstner",
    section="§10",
    title="Gerstner waves",
    claim="every point circles at the amplitude while the wave's shape travels at w / k; "
    "with k a < 1 the points stay in order, past 1 neighbours pass each other (the "
    "self-intersection the text warns of)",
    params=GerstnerParams,
    functions=SceneFunctions(gerstner_initial, gerstner_step, gerstner_measures, gerstner_frame),
    view_box_m=lambda p: (
        -p.amplitude_m - 1.0,
        p.wavelengths * p.wavelength_m + 1.0,
        -p.wavelength_m,
        p.wavelength_m,
    ),
    # one period (a still surface: 10 s)
    duration_s=lambda p: 2.0 * math.pi / p.angular_speed_radps if p.angular_speed_radps else 10.0,
    bodies=("surface",),
    test="test_gerstner_points_circle_and_the_wave_self_intersects_past_ka_1",
    floor=False,
)

SCENES = (GERSTNER,)
