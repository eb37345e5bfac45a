"""Smoothed particle hydrodynamics (§10): a dam break in a closed box, each particle's
neighbours found through a uniform grid (the text's "spatial hashing"), or by testing
every pair.

The text gives the algorithm's outline: each particle sums the density its neighbours
within a distance give it, then a force comes from those densities, so particles repel
"by a declining force varying by distance", not by a hit or a miss. Here that is the
weakly compressible SPH of Müller, Charypar and Gross (2003, "Particle-based fluid
simulation for interactive applications"), in 2D: the density from the poly6 kernel
(:func:`poly6`), a pressure ``c^2 (rho - rho_0)`` (never below zero: a free surface does
not pull), the pressure force from the spiky kernel's gradient (:func:`spiky_gradient`),
a viscosity from its Laplacian (:func:`viscosity_laplacian`), XSPH velocity smoothing,
gravity, and walls (:func:`wall_acceleration`).

**Why it settles.** An earlier try put a particle that crossed a wall back on the wall
and reversed its speed: particles piled up at one point on the wall, the pressure between
them (whose distance was zero) threw them apart again, and the kinetic energy never fell
below half its peak. Here every wall is a stiff spring-damper acting on the particles
within half a spacing of it: it holds each particle where the block's outer row started,
it never pulls, and its damping takes energy out of every impact rather than putting any
in. The viscosity and the XSPH smoothing damp the sloshing, and the time step obeys the
three limits of an explicit SPH step (:attr:`DamBreakParams.dt_s`): the sound's (CFL,
``dt <= 0.4 h / c``), the viscosity's and the gravity's.

**Neighbours.** With the grid, the box is cut into square cells of the kernels' support
``h``; the particles are sorted by cell (``argsort``), each cell's range found with
``searchsorted``, and each particle reads up to ``cell_capacity`` particles from each of
its 9 surrounding cells: ``9 x cell_capacity`` candidates, a cost linear in the particles.
A cell holding more than that (a fluid compressed far past its rest density) would lose
particles: :func:`fluid_measures` reports the fullest cell, and the tests check that the
grid's trajectory equals the all-pairs one. ``neighbour_search="all"`` (or 0) tests every
pair, a cost quadratic in the particles: the reference, and what the grid saves
(``bbgym bench --scenes``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_choice, check_fields, interval, param
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment

WATER = (40, 110, 210)
WALL = (90, 90, 90)
ALL_PAIRS, GRID = 0, 1
"""``neighbour_search``'s values; the strings ``"all"`` and ``"grid"`` name them too."""
SEARCHES = {"all": ALL_PAIRS, "grid": GRID}
MOST_ALL_PAIRS = 4096
"""All-pairs search keeps several ``(particles, particles)`` float64 arrays: at 4,096
particles each is 134 MB, about 2 GB in all; more is refused."""


class Fluid(NamedTuple):
    """The particles, ``(1, particles)`` (one row: the batch axis of the scene's measures),
    and what the forces at these positions and velocities give: the velocity change the
    next step applies, each particle's density and the fullest grid cell."""

    x_m: Array
    y_m: Array
    vx_mps: Array
    vy_mps: Array
    dvx_mps: Array
    dvy_mps: Array
    density_kgm3: Array
    fullest_cell: Array
    """``(1,)``: the most particles in one cell (all-pairs: every particle)."""


@dataclass(frozen=True)
class DamBreakParams:
    """A block of water at rest in the left corner of a closed box, released."""

    particles: int = param(400, interval(16, 65536), integer=True)
    """The block's particles, in rows of ``columns`` from the floor up (the top row may be
    short); their spacing is what fills the block with them."""
    water_width_m: float = param(0.2, interval(0.01, 100.0))
    water_height_m: float = param(0.4, interval(0.01, 100.0))
    box_width_m: float = param(0.8, interval(0.02, 200.0))
    box_height_m: float = param(0.6, interval(0.02, 200.0))
    rest_density_kgm3: float = param(1000.0, interval(1.0, 20000.0))
    sound_speed_mps: float = param(15.0, interval(1.0, 1000.0))
    """``c``: the pressure is ``c^2 (rho - rho_0)``. Ten times the fastest flow
    (``sqrt(2 g H)``, 2.8 m/s here) would keep the density within 1% of rest; 15 m/s keeps
    it within a few per cent at half the steps of 30 m/s."""
    viscosity_m2ps: float = param(0.01, interval(0.0, 10.0))
    """``nu``, the kinematic viscosity (Müller's ``mu`` over the density): far above
    water's 1e-6, as SPH at this resolution needs to damp its particle noise."""
    xsph: float = param(0.1, interval(0.0, 1.0))
    """XSPH's ``epsilon``: the share of its neighbours' mean velocity each particle is
    pulled toward every step (Monaghan 1989)."""
    wall_damping_ratio: float = param(1.0, interval(0.0, 1.0))
    """The walls' springs' damping ratio (1: critically damped)."""
    neighbour_search: int = param(GRID, interval(0, 1), integer=True)
    """1 or ``"grid"``: the uniform grid; 0 or ``"all"``: every pair."""
    cell_capacity: int = param(8, interval(4, 64), integer=True)
    """The particles read from each grid cell; at rest a cell holds about 4."""
    courant: float = param(0.4, interval(0.01, 0.4))
    """The time step's share of ``h / c``: at most 0.4, the CFL limit."""

    def __post_init__(self) -> None:
        if isinstance(self.neighbour_search, str):  # "grid" | "all"
            search = check_choice(
                "DamBreakParams.neighbour_search", self.neighbour_search, tuple(SEARCHES)
            )
            object.__setattr__(self, "neighbour_search", SEARCHES[search])
        check_fields(self)
        if self.water_width_m >= self.box_width_m or self.water_height_m >= self.box_height_m:
            raise ValueError(
                "DamBreakParams.water_width_m and water_height_m must be less than "
                "box_width_m and box_height_m (the water starts in the box)"
            )
        if self.columns > self.particles or self.particles // self.columns < 1:
            # A combination of three fields: the error names the other two (the block's
            # shape sets how many particles a row takes).
            ratio = self.water_width_m / self.water_height_m
            raise ValueError(
                f"DamBreakParams.particles: too few to fill one row of the block: "
                f"{self.particles} particles spaced to fill it make rows of {self.columns} "
                f"(water_width_m / water_height_m is {ratio:g}); use about that many "
                f"particles at least, or a taller block"
            )
        if self.neighbour_search == ALL_PAIRS and self.particles > MOST_ALL_PAIRS:
            raise ValueError(
                f"DamBreakParams.neighbour_search: all pairs of more than {MOST_ALL_PAIRS} "
                f"particles would not fit in memory (particles={self.particles}); use the grid"
            )

    @property
    def spacing_m(self) -> float:
        """The particles' spacing: each one's square of water."""
        return math.sqrt(self.water_width_m * self.water_height_m / self.particles)

    @property
    def columns(self) -> int:
        return max(1, round(self.water_width_m / self.spacing_m))

    @property
    def support_m(self) -> float:
        """The kernels' radius ``h``: two spacings (about 12 neighbours at rest)."""
        return 2.0 * self.spacing_m

    @property
    def mass_kg(self) -> float:
        """Each particle's mass (per metre of depth): its square of water."""
        return self.rest_density_kgm3 * self.spacing_m**2

    @property
    def level_m(self) -> float:
        """The hydrostatic level: the water's area spread over the box's floor."""
        return self.particles * self.spacing_m**2 / self.box_width_m

    @property
    def wall_frequency_radps(self) -> float:
        """The walls' springs' angular frequency: ``c / (2 s)``, as stiff as the fluid's
        own sound across a spacing allows while ``omega dt`` stays 0.4 at the CFL limit
        (semi-implicit Euler is stable up to 2)."""
        return self.sound_speed_mps / (2.0 * self.spacing_m)

    @property
    def dt_s(self) -> float:
        """The time step: the least of the CFL limit ``courant h / c``, the viscosity's
        ``0.125 h^2 / nu`` and the gravity's ``0.25 sqrt(h / g)`` (Monaghan 1992)."""
        h = self.support_m
        limits = [self.courant * h / self.sound_speed_mps, 0.25 * math.sqrt(h / GRAVITY_MPS2)]
        if self.viscosity_m2ps > 0.0:
            limits.append(0.125 * h * h / self.viscosity_m2ps)
        return min(limits)

    @property
    def cells(self) -> tuple[int, int]:
        h = self.support_m
        return math.ceil(self.box_width_m / h), math.ceil(self.box_height_m / h)


def poly6(r2: Array, h: float, xp: Any) -> Array:
    """The 2D poly6 kernel ``4 / (pi h^8) (h^2 - r^2)^3`` inside ``h``, at squared distances
    ``r2`` (the density's smoothing)."""
    inside = xp.maximum(h * h - r2, 0.0)
    return 4.0 / (math.pi * h**8) * (inside * inside * inside)


def spiky_gradient(r: Array, h: float, xp: Any) -> Array:
    """The magnitude of the 2D spiky kernel's gradient, ``-30 / (pi h^5) (h - r)^2``, along
    the direction from the neighbour (it repels even as ``r`` goes to 0)."""
    gap = xp.maximum(h - r, 0.0)
    return -30.0 / (math.pi * h**5) * gap * gap


def viscosity_laplacian(r: Array, h: float, xp: Any) -> Array:
    """The 2D viscosity kernel's Laplacian, ``40 / (pi h^5) (h - r)``."""
    return 40.0 / (math.pi * h**5) * xp.maximum(h - r, 0.0)


def grid_candidates(p: DamBreakParams, x: Array, y: Array, xp: Any) -> tuple[Array, Array, Array]:
    """Each particle's candidate neighbours from the uniform grid: indices ``(P, 9 C)``,
    whether each slot holds one, and the fullest cell's count."""
    h = p.support_m
    nx, ny = p.cells
    ix = xp.clip(xp.astype(xp.floor(x / h), xp.int64), 0, nx - 1)
    iy = xp.clip(xp.astype(xp.floor(y / h), xp.int64), 0, ny - 1)
    cell = ix * ny + iy
    order = xp.argsort(cell, stable=True)
    sorted_cells = xp.take(cell, order)
    slots = xp.arange(p.cell_capacity, dtype=xp.int64)
    count = x.shape[0]
    indices, valid = [], []
    fullest = xp.zeros((), dtype=xp.int64)
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            cx, cy = ix + dx, iy + dy
            inside = (cx >= 0) & (cx < nx) & (cy >= 0) & (cy < ny)
            other = xp.clip(cx, 0, nx - 1) * ny + xp.clip(cy, 0, ny - 1)
            start = xp.searchsorted(sorted_cells, other, side="left")
            held = xp.searchsorted(sorted_cells, other, side="right") - start
            fullest = xp.maximum(fullest, xp.max(held))
            position = xp.clip(start[:, None] + slots[None, :], 0, count - 1)
            indices.append(xp.reshape(xp.take(order, xp.reshape(position, (-1,))), (count, -1)))
            valid.append(inside[:, None] & (slots[None, :] < held[:, None]))
    return xp.concat(indices, axis=1), xp.concat(valid, axis=1), fullest


def all_candidates(x: Array, xp: Any) -> tuple[Array, Array, Array]:
    """Every particle as every particle's candidate: ``(P, P)``."""
    count = x.shape[0]
    index = xp.broadcast_to(xp.arange(count, dtype=xp.int64)[None, :], (count, count))
    return index, xp.ones((count, count), dtype=xp.bool), xp.asarray(count, dtype=xp.int64)


def wall_acceleration(p: DamBreakParams, distance_m: Array, speed_in_mps: Array, xp: Any) -> Array:
    """A wall's push on particles ``distance_m`` from it, moving into it at
    ``speed_in_mps``: a spring-damper ``omega^2 (s/2 - d) + 2 zeta omega v_in`` within half a
    spacing ``s/2`` (where the block's outer particles start), never a pull. A damper takes
    energy out of each impact; putting a particle back on the wall by hand put energy in."""
    reach = 0.5 * p.spacing_m
    w = p.wall_frequency_radps
    push = w * w * (reach - distance_m) + 2.0 * p.wall_damping_ratio * w * speed_in_mps
    return xp.where(distance_m < reach, xp.maximum(push, 0.0), 0.0)


def fluid_forces(
    p: DamBreakParams, x: Array, y: Array, vx: Array, vy: Array, xp: Any
) -> tuple[Array, Array, Array, Array]:
    """The velocity change ``(dvx, dvy)`` one step applies at these positions and
    velocities (``(P,)`` each): the forces times the step and the XSPH smoothing; the
    density and the fullest cell."""
    if p.neighbour_search == GRID:
        index, valid, fullest = grid_candidates(p, x, y, xp)
    else:
        index, valid, fullest = all_candidates(x, xp)
    count, slots = index.shape
    flat = xp.reshape(index, (-1,))

    def gather(a: Array) -> Array:
        return xp.reshape(xp.take(a, flat), (count, slots))

    h, m = p.support_m, p.mass_kg
    dx, dy = x[:, None] - gather(x), y[:, None] - gather(y)
    # An empty slot is put at the support's edge, where every kernel is zero: no other mask.
    r2 = xp.where(valid, dx * dx + dy * dy, h * h)
    smooth = poly6(r2, h, xp)
    density = m * xp.sum(smooth, axis=1)
    pressure = p.sound_speed_mps**2 * xp.maximum(density - p.rest_density_kgm3, 0.0)
    # A particle is its own candidate: dx = dy = 0 and v_j - v_i = 0 give it no force. The
    # floor keeps r off 0 there (and between two particles at one point, which get no push).
    r = xp.sqrt(xp.maximum(r2, (1e-6 * h) ** 2))
    rho_j = gather(density)
    # Pressure, symmetric (each pair pushes both alike, so momentum is kept):
    # -sum m (p_i / rho_i^2 + p_j / rho_j^2) grad W, grad W along (x_i - x_j) / r.
    own = pressure / (density * density)
    push = -m * (own[:, None] + gather(own)) * spiky_gradient(r, h, xp) / r
    # Viscosity: nu sum m (v_j - v_i) / rho_j lap W (Müller's mu / rho_i, mu = nu rho).
    drag = p.viscosity_m2ps * m / rho_j * viscosity_laplacian(r, h, xp)
    # XSPH: toward the neighbours' mean velocity, weighted by the kernel, m / mean density.
    blend = p.xsph * 2.0 * m / (rho_j + density[:, None]) * smooth
    dvx_j, dvy_j = gather(vx) - vx[:, None], gather(vy) - vy[:, None]
    ax = xp.sum(push * dx + drag * dvx_j, axis=1)
    ay = xp.sum(push * dy + drag * dvy_j, axis=1) - GRAVITY_MPS2
    ax = ax + wall_acceleration(p, x, -vx, xp) - wall_acceleration(p, p.box_width_m - x, vx, xp)
    ay = ay + wall_acceleration(p, y, -vy, xp) - wall_acceleration(p, p.box_height_m - y, vy, xp)
    dt = p.dt_s
    dvx = dt * ax + xp.sum(blend * dvx_j, axis=1)
    dvy = dt * ay + xp.sum(blend * dvy_j, axis=1)
    return dvx, dvy, density, fullest


def settled(p: DamBreakParams, x: Array, y: Array, vx: Array, vy: Array, xp: Any) -> Fluid:
    """The state at these positions and velocities ``(1, P)``, with its forces."""
    dvx, dvy, density, fullest = fluid_forces(p, x[0, :], y[0, :], vx[0, :], vy[0, :], xp)
    full = xp.reshape(xp.astype(fullest, x.dtype), (1,))
    return Fluid(x, y, vx, vy, dvx[None, :], dvy[None, :], density[None, :], full)


def dam_initial(p: DamBreakParams, xp: Any) -> Fluid:
    """The block: rows of ``columns`` particles from the floor up, half a spacing off the
    walls, at rest."""
    k = np.arange(p.particles)
    x = (k % p.columns + 0.5) * p.spacing_m
    y = (k // p.columns + 0.5) * p.spacing_m
    x, y, still = (xp.asarray(a[None, :], dtype=xp.float64) for a in (x, y, 0.0 * x))
    return settled(p, x, y, still, still, xp)


def dam_step(p: DamBreakParams, s: Fluid, xp: Any) -> Fluid:
    """Semi-implicit Euler: the velocity changes by the forces at the state, then the
    particles move at the new velocity. The walls' springs keep them in; should one still
    cross a wall (a step too coarse for the spring), it is put back on the wall and its
    speed into it taken away (never reversed: that only takes energy out)."""
    vx, vy = s.vx_mps + s.dvx_mps, s.vy_mps + s.dvy_mps
    x, y = s.x_m + p.dt_s * vx, s.y_m + p.dt_s * vy
    w, top = p.box_width_m, p.box_height_m
    vx = xp.where(((x < 0.0) & (vx < 0.0)) | ((x > w) & (vx > 0.0)), 0.0, vx)
    vy = xp.where(((y < 0.0) & (vy < 0.0)) | ((y > top) & (vy > 0.0)), 0.0, vy)
    return settled(p, xp.clip(x, 0.0, w), xp.clip(y, 0.0, top), vx, vy, xp)


def fluid_measures(p: DamBreakParams, s: Fluid, xp: Any) -> dict[str, Array]:
    """The fluid's mass, its kinetic energy (per metre of depth), its mean density, its
    level (twice its centre of mass's height: a flat layer's depth), how far its front has
    run along the floor (its furthest particle in the lowest kernel support) and the
    fullest grid cell."""
    m = p.mass_kg
    count = s.x_m.shape[1]
    kinetic = 0.5 * m * xp.sum(s.vx_mps * s.vx_mps + s.vy_mps * s.vy_mps, axis=1)
    low = s.y_m < p.support_m
    return {
        "mass_kg": xp.ones((1,), dtype=s.x_m.dtype) * (m * count),
        "kinetic_energy_j": kinetic,
        "mean_density_kgm3": xp.mean(s.density_kgm3, axis=1),
        "level_m": 2.0 * xp.mean(s.y_m, axis=1),
        "front_m": xp.max(xp.where(low, s.x_m, 0.0), axis=1),
        "fullest_cell": s.fullest_cell,
    }


def dam_frame(p: DamBreakParams, s: Fluid) -> Frame:
    x, y = np.asarray(s.x_m)[0], np.asarray(s.y_m)[0]
    radius = 0.5 * p.spacing_m
    circles = [Circle(float(a), float(b), radius, WATER) for a, b in zip(x, y, strict=True)]
    w, h = p.box_width_m, p.box_height_m
    walls = [
        Segment(0.0, 0.0, 0.0, h, WALL),
        Segment(w, 0.0, w, h, WALL),
        Segment(0.0, 0.0, w, 0.0, WALL),
        Segment(0.0, h, w, h, WALL),
    ]
    search = "uniform grid" if p.neighbour_search == GRID else "all pairs"
    speed = np.hypot(np.asarray(s.vx_mps)[0], np.asarray(s.vy_mps)[0]).max()
    return Frame(
        circles, walls, [f"{len(x)} particles, neighbours by {search}", f"fastest {speed:.2f} m/s"]
    )


DAM_BREAK = Scene(
    name="dam-break",
    section="§10",
    title="SPH: a dam break",
    claim="released, the block of water surges along the floor to the far wall and "
    "settles: its mass is kept, its kinetic energy dies to under 1% of its peak, its level "
    "comes to the water's area over the box's width and its mean density stays near rest; "
    "the grid's neighbours give the all-pairs trajectory",
    params=DamBreakParams,
    functions=SceneFunctions(dam_initial, dam_step, fluid_measures, dam_frame),
    view_box_m=lambda p: (
        -0.05 * p.box_width_m,
        1.05 * p.box_width_m,
        -0.05 * p.box_height_m,
        1.05 * p.box_height_m,
    ),
    duration_s=lambda p: 2.0,
    bodies=("water",),
    test="test_dam_break_surges_and_settles",
    floor=False,
)

SCENES = (DAM_BREAK,)
