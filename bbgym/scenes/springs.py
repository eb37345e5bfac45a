"""Spring systems (§7): "Sproing", a grid of beach balls joined by springs to their nearest
neighbours (8 in 2D, or 4 or 6 as options; 26 in 3D), and "Sproing cloth", a grid hanging
from its anchored top row.

The text's claims are about stability: the integrator and the damping decide it, and a
stiff spring makes the system explode. So each scene runs the same grid three times side
by side, one row of the batch per integrator (explicit Euler, semi-implicit Euler, velocity
Verlet), from the same seeded start, and measures each one's energy.

Each spring pulls by Hooke's law along its length, ``k (|d| - L)``, and is damped along its
length, ``c (v_j - v_i) . u`` (:func:`spring_forces`). A particle's springs are the slots of
a fixed neighbour table (particle, slot) -> other particle, so the forces are gathered,
never scattered: every spring is seen from both ends, the same source runs on every array
namespace, and the cost is linear in the particles. A row whose particles fly further than
:data:`EXPLODED_SPANS` grid spans from the start is stopped where it was and reported as
exploded (its energy stays finite, and huge).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.physics.namespace import Array
from bbgym.physics.validation import check_fields, interval, param
from bbgym.scenes.projectiles import BALL_COLORS
from bbgym.scenes.scene import Circle, Frame, Scene, SceneFunctions, Segment

EXPLICIT, SEMI_IMPLICIT, VERLET = 0.0, 1.0, 2.0
"""The integrator of each row of the batch, in that order."""
INTEGRATORS = ("explicit Euler", "semi-implicit Euler", "velocity Verlet")
EXPLODED_SPANS = 100.0
"""A row whose particles get further than this many grid spans from where they started
has exploded: it is stopped there."""
SPRING_COLOR = (150, 150, 150)


class Lattice(NamedTuple):
    """Particles ``(rows, particles, dims)`` of each integrator's copy, and the constant
    neighbour table ``(particles, slots)`` they share."""

    x_m: Array
    v_mps: Array
    start_m: Array
    exploded: Array
    """``(rows,)``: the row was stopped (1.0) or runs (0.0)."""
    neighbour: Array
    """Index of each slot's particle (the particle itself where the slot has no spring)."""
    linked: Array
    """1.0 where the slot holds a spring, else 0.0."""
    rest_m: Array
    free: Array
    """``(particles, 1)``: 1.0 for a free particle, 0.0 for an anchored one."""


def neighbour_counts(dims: int) -> tuple[int, ...]:
    """The springs a particle of a ``dims``-dimensional grid can have (:func:`grid_offsets`):
    4, 6 or 8 in 2D; 6 or 26 in 3D."""
    return tuple(sorted({2 * dims, 3**dims - 1} | ({6} if dims == 2 else set())))


def grid_offsets(dims: int, neighbours: int) -> list[tuple[int, ...]]:
    """The neighbour offsets of a particle of a ``dims``-dimensional grid: every cell of
    the surrounding layer (8 in 2D, 26 in 3D), the axes alone (4 in 2D), or the axes and
    one diagonal (6 in 2D: a triangulated grid)."""
    every = [o for o in itertools.product((-1, 0, 1), repeat=dims) if any(o)]
    if neighbours == len(every):
        return every
    axes = [o for o in every if sum(map(abs, o)) == 1]
    if neighbours == 2 * dims:
        return axes
    if dims == 2 and neighbours == 6:
        return [*axes, (1, 1), (-1, -1)]
    counts = ", ".join(map(str, neighbour_counts(dims)))
    raise ValueError(f"neighbours must be one of {counts} in {dims}D, got {neighbours}")


def neighbour_table(
    shape: tuple[int, ...], offsets: list[tuple[int, ...]], spacing_m: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(neighbour, linked, rest_m)`` of a grid of ``shape`` (row-major particle order)."""
    cells = list(itertools.product(*(range(n) for n in shape)))
    index = {cell: i for i, cell in enumerate(cells)}
    neighbour = np.zeros((len(cells), len(offsets)), dtype=np.int64)
    linked = np.zeros((len(cells), len(offsets)))
    rest = np.ones((len(cells), len(offsets)))
    for i, cell in enumerate(cells):
        for k, offset in enumerate(offsets):
            other = tuple(c + o for c, o in zip(cell, offset, strict=True))
            neighbour[i, k] = index.get(other, i)
            if other in index:
                linked[i, k] = 1.0
                rest[i, k] = spacing_m * math.sqrt(sum(o * o for o in offset))
    return neighbour, linked, rest


def spring_forces(
    s: Lattice, x: Array, v: Array, stiffness: float, damping: float, xp: Any
) -> tuple[Array, Array]:
    """Each particle's force from its springs ``(rows, particles, dims)`` (Hooke's law
    along each spring plus damping along it), and each row's spring energy (each spring
    seen from both ends, so half of the sum of ``k s^2 / 2``)."""
    rows, count, dims = x.shape
    slots = s.neighbour.shape[1]
    flat = xp.reshape(s.neighbour, (-1,))
    x_other = xp.reshape(xp.take(x, flat, axis=1), (rows, count, slots, dims))
    v_other = xp.reshape(xp.take(v, flat, axis=1), (rows, count, slots, dims))
    d = x_other - x[:, :, None, :]
    length = xp.sqrt(xp.sum(d * d, axis=3))
    unit = d / xp.maximum(length, 1e-12)[..., None]
    stretch = (length - s.rest_m) * s.linked
    closing = xp.sum((v_other - v[:, :, None, :]) * unit, axis=3) * s.linked
    pull = stiffness * stretch + damping * closing
    force = xp.sum(pull[..., None] * unit, axis=2)
    energy = 0.25 * stiffness * xp.sum(xp.sum(stretch * stretch, axis=2), axis=1)
    return force, energy


@dataclass(frozen=True)
class SproingParams:
    """A square grid of beach balls joined by springs, jostled from rest; each row of the
    batch integrates it its own way."""

    size: int = param(8, interval(2, 128), integer=True)
    """Particles along each side (2D: size^2 of them, up to 16,384: ``bbgym bench
    --scenes``'s largest; 3D: size^3)."""
    neighbours: int = param(8, interval(4, 8), integer=True)
    """Springs per particle: 4, 6 or 8 (5 and 7 are refused: no grid has them)."""
    spacing_m: float = param(0.5, interval(0.05, 10.0))
    mass_kg: float = param(0.25, interval(0.01, 100.0))
    stiffness_npm: float = param(50.0, interval(0.0, 1e6))
    damping_nspm: float = param(1.0, interval(0.0, 1e4))
    """Along each spring; 0 leaves the system to its integrator alone."""
    jitter_m: float = param(0.05, interval(0.0, 1.0))
    """The standard deviation of each particle's random displacement at the start."""
    seed: int = param(0, interval(0, 2**31 - 1), integer=True)
    dt_s: float = param(1.0 / 60.0, interval(1e-4, 0.1))

    def __post_init__(self) -> None:
        check_fields(self)
        try:
            grid_offsets(self.shape_dims, self.neighbours)
        except ValueError as error:
            # Named as the fields are, so the scene's error names the scene.
            raise ValueError(f"{type(self).__name__}.{error}") from None
        if self.jitter_m >= 0.5 * self.spacing_m:
            raise ValueError(
                f"{type(self).__name__}.jitter_m must be under half spacing_m "
                f"({0.5 * self.spacing_m}), got {self.jitter_m}: particles could swap places"
            )

    dims = 2
    shape_dims = 2
    anchored_top = False
    gravity = False


@dataclass(frozen=True)
class Sproing3DParams(SproingParams):
    """The grid in 3D: a cube of beach balls, each joined to all 26 around it."""

    size: int = param(5, interval(2, 16), integer=True)
    neighbours: int = param(26, interval(26, 26), integer=True)
    """Springs per particle: every cell around (the scene is about that one layer)."""

    dims = 3
    shape_dims = 3


@dataclass(frozen=True)
class ClothParams(SproingParams):
    """A square grid hanging from its anchored top row: it starts raised above that row
    and falls under gravity (in 3D; the picture is its side view)."""

    size: int = param(10, interval(2, 40), integer=True)
    stiffness_npm: float = param(200.0, interval(0.0, 1e6))
    damping_nspm: float = param(1.0, interval(0.0, 1e4))

    dims = 3
    shape_dims = 2
    anchored_top = True
    gravity = True


def lattice_initial(p: SproingParams, xp: Any) -> Lattice:
    """The grid at rest, each particle displaced by seeded noise, copied into each
    integrator's row. The cloth's rows stand upward from its anchored row (row 0)."""
    shape = (p.size,) * p.shape_dims
    offsets = grid_offsets(p.shape_dims, p.neighbours)
    neighbour, linked, rest = neighbour_table(shape, offsets, p.spacing_m)
    cells = np.array(list(itertools.product(*(range(n) for n in shape))), dtype=np.float64)
    centred = (cells - 0.5 * (p.size - 1)) * p.spacing_m
    if p.anchored_top:  # x along the anchored row, y up from it, z out of the picture
        position = np.stack([centred[:, 1], cells[:, 0] * p.spacing_m, 0.0 * centred[:, 0]], 1)
    else:
        position = centred
    noise = np.random.default_rng(p.seed).normal(0.0, p.jitter_m, position.shape)
    free = np.ones((len(cells), 1))
    if p.anchored_top:
        free[cells[:, 0] == 0] = 0.0
    position = position + noise * free
    rows = len(INTEGRATORS)
    x = np.broadcast_to(position, (rows, *position.shape)).copy()

    def to(a: np.ndarray, dtype: Any = None) -> Array:
        return xp.asarray(a, dtype=xp.float64 if dtype is None else dtype)

    return Lattice(
        x_m=to(x),
        v_mps=to(0.0 * x),
        start_m=to(x),
        exploded=to(np.zeros(rows)),
        neighbour=to(neighbour, xp.int64),
        linked=to(linked),
        rest_m=to(rest),
        free=to(free),
    )


def lattice_step(p: SproingParams, s: Lattice, xp: Any) -> Lattice:
    """One step of each row by its integrator: explicit Euler (position with the old
    velocity), semi-implicit Euler (velocity first) or velocity Verlet (a half kick, the
    drift, a half kick with the new forces). Anchored particles stay put."""
    dt = p.dt_s

    def accel(x: Array, v: Array) -> Array:
        force, _ = spring_forces(s, x, v, p.stiffness_npm, p.damping_nspm, xp)
        a = force / p.mass_kg
        if p.gravity:
            down = xp.asarray([0.0, 1.0, 0.0], dtype=x.dtype) * GRAVITY_MPS2
            a = a - down
        return a * s.free

    code = xp.asarray([EXPLICIT, SEMI_IMPLICIT, VERLET], dtype=s.x_m.dtype)[:, None, None]
    a0 = accel(s.x_m, s.v_mps)
    half = s.v_mps + 0.5 * dt * a0
    kicked = s.v_mps + dt * a0
    x1 = s.x_m + dt * xp.where(code == EXPLICIT, s.v_mps, xp.where(code == VERLET, half, kicked))
    v1 = xp.where(code == VERLET, half + 0.5 * dt * accel(x1, half), kicked)
    span = p.spacing_m * p.size
    far = xp.max(xp.reshape(xp.abs(x1 - s.start_m), (x1.shape[0], -1)), axis=1)
    exploded = xp.where(far > EXPLODED_SPANS * span, 1.0, s.exploded)
    stop = (exploded > 0.5)[:, None, None]
    return Lattice(
        xp.where(stop, s.x_m, x1),
        xp.where(stop, s.v_mps, v1),
        s.start_m,
        exploded,
        s.neighbour,
        s.linked,
        s.rest_m,
        s.free,
    )


def lattice_measures(p: SproingParams, s: Lattice, xp: Any) -> dict[str, Array]:
    """Each row's energy: kinetic plus the springs' (plus gravity's, above the anchored
    row, for the cloth), and whether it exploded."""
    _, springs = spring_forces(s, s.x_m, s.v_mps, p.stiffness_npm, p.damping_nspm, xp)
    kinetic = 0.5 * p.mass_kg * xp.sum(xp.sum(s.v_mps * s.v_mps, axis=2) * s.free[:, 0], axis=1)
    energy = kinetic + springs
    if p.gravity:
        energy = energy + p.mass_kg * GRAVITY_MPS2 * xp.sum(s.x_m[:, :, 1] * s.free[:, 0], axis=1)
    lowest = xp.min(s.x_m[:, :, 1], axis=1)
    measures = {"energy_j": energy, "exploded": s.exploded, "lowest_m": lowest}
    if p.dims == 2:
        measures["shear"] = grid_shear(p, s.x_m, xp)
    return measures


def grid_shear(p: SproingParams, x: Array, xp: Any) -> Array:
    """How far a 2D grid's cells are from squares: the mean difference of each cell's two
    diagonals, over the spacing (0 for squares; about 1.4 for a cell flattened to a line)."""
    g = xp.reshape(x, (x.shape[0], p.size, p.size, 2))

    def length(d: Array) -> Array:
        return xp.sqrt(xp.sum(d * d, axis=3))

    one = length(g[:, 1:, 1:, :] - g[:, :-1, :-1, :])
    other = length(g[:, 1:, :-1, :] - g[:, :-1, 1:, :])
    return xp.mean(xp.reshape(xp.abs(one - other), (x.shape[0], -1)), axis=1) / p.spacing_m


def lattice_frame(p: SproingParams, s: Lattice, row: int = 1) -> Frame:
    """The semi-implicit row's particles and springs (side view: x and y)."""
    x = np.asarray(s.x_m)[row]
    neighbour, linked = np.asarray(s.neighbour), np.asarray(s.linked)
    segments = [
        Segment(x[i, 0], x[i, 1], x[j, 0], x[j, 1], SPRING_COLOR, 1)
        for i, k in zip(*np.nonzero(linked), strict=True)
        if (j := int(neighbour[i, k])) > i
    ]
    radius = 0.15 * p.spacing_m
    circles = [Circle(x[i, 0], x[i, 1], radius, BALL_COLORS[1]) for i in range(len(x))]
    state = ", ".join(
        f"{name} {'exploded' if float(np.asarray(s.exploded)[r]) else 'runs'}"
        for r, name in enumerate(INTEGRATORS)
    )
    return Frame(circles, segments, [f"drawn: {INTEGRATORS[row]}; {state}"])


def lattice_box(p: SproingParams) -> tuple[float, float, float, float]:
    half = 0.5 * p.size * p.spacing_m + 2.0 * p.spacing_m
    if p.anchored_top:
        return (-2.0 * half, 2.0 * half, -p.size * p.spacing_m - half, p.size * p.spacing_m)
    return (-2.0 * half, 2.0 * half, -half, half)


def lattice_scene(
    name: str, title: str, claim: str, params: type, seconds: float, test: str
) -> Scene:
    return Scene(
        name=name,
        section="§7",
        title=title,
        claim=claim,
        params=params,
        functions=SceneFunctions(lattice_initial, lattice_step, lattice_measures, lattice_frame),
        view_box_m=lattice_box,
        duration_s=lambda p: seconds,
        bodies=INTEGRATORS,
        test=test,
        floor=False,
    )


SPROING = lattice_scene(
    "sproing",
    "Sproing: a 2D spring system and three integrators",
    "undamped, explicit Euler gains energy until it explodes while semi-implicit Euler and "
    "velocity Verlet keep it bounded; damped, all three settle; a stiff spring makes all "
    "three explode; with 4 springs a particle (no diagonals) the grid has no shear "
    "stiffness and stays collapsed",
    SproingParams,
    10.0,
    "test_sproing_the_integrator_and_the_damping_decide_stability",
)
SPROING_3D = lattice_scene(
    "sproing-3d",
    "Sproing 3D: 26 springs a particle",
    "the same in 3D: stable with semi-implicit Euler or Verlet, explicit Euler explodes undamped",
    Sproing3DParams,
    10.0,
    "test_sproing_3d_is_stable_with_one_layer_of_springs",
)
SPROING_CLOTH = lattice_scene(
    "sproing-cloth",
    "Sproing cloth: a grid hanging from its top row",
    "the cloth, raised above its anchored row, falls and hangs below it at about its own "
    "length, losing energy to the damping (semi-implicit Euler and Verlet; explicit Euler "
    "explodes)",
    ClothParams,
    8.0,
    "test_sproing_cloth_falls_and_hangs_below_its_anchored_row",
)

SCENES = (SPROING, SPROING_3D, SPROING_CLOTH)
