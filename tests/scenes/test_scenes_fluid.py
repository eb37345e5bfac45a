"""The SPH dam break (§10): the water surges, settles at its hydrostatic level and keeps
its mass, and the uniform grid finds the same neighbours as testing every pair."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.physics.common import GRAVITY_MPS2
from bbgym.scenes import get_scene, simulate
from bbgym.scenes.fluid import ALL_PAIRS, GRID, fluid_forces


def test_dam_break_surges_and_settles() -> None:
    """§10, 400 particles for 2 s: the particle count and the mass never change; the front
    reaches the far wall no sooner than Ritter's frictionless dam-break front (2 sqrt(g H))
    would, and within three times that (measured 2.4: the column first has to fall); the
    kinetic energy then dies to under 1% of its peak (measured 1e-5); the level (twice the
    centre of mass's height) ends within one particle spacing of the water's area over the
    box's width (measured 0.76 spacings under: the free surface's particles lack neighbours
    above, read a low density and pack closer, an error of the order of a spacing that
    shrinks with it); the mean density stays within 10% of rest all along (within 1% at
    the end, measured 0.6%); no particle leaves the box and no grid cell overflows its capacity."""
    scene = get_scene("dam-break")
    lows, highs = [], []

    def bounds(p, state) -> None:
        lows.append((state.x_m.min(), state.y_m.min()))
        highs.append((state.x_m.max(), state.y_m.max()))

    run = simulate(scene, on_step=bounds)
    p, m = run.params, run.measures
    assert run.state.x_m.shape == (1, p.particles) == (1, 400)
    np.testing.assert_array_equal(m["mass_kg"], p.particles * p.mass_kg)

    front, ke = m["front_m"][:, 0], m["kinetic_energy_j"][:, 0]
    arrival = run.times_s[np.argmax(front > p.box_width_m - p.spacing_m)]
    ritter = (p.box_width_m - p.water_width_m) / (2.0 * math.sqrt(GRAVITY_MPS2 * p.water_height_m))
    assert ritter < arrival < 3.0 * ritter, (arrival, ritter)
    assert arrival < 0.25 * run.times_s[-1]  # early: the surge first, then the settling

    assert ke.max() > 10.0  # it surged: a peak of tens of joules (measured 73)
    assert ke[-1] < 0.01 * ke.max()
    assert np.all(ke[-int(0.25 / p.dt_s) :] < 0.01 * ke.max())

    level = m["level_m"][-1, 0]
    assert abs(level - p.level_m) < p.spacing_m, (level, p.level_m)
    assert m["level_m"][0, 0] == pytest.approx(p.water_height_m, abs=p.spacing_m)

    density = m["mean_density_kgm3"][:, 0]
    # The mean counts the surface's particles, short of neighbours above: it dips most
    # (7.7% under rest) as the collapsing column spreads its surface out.
    assert np.all(np.abs(density / p.rest_density_kgm3 - 1.0) < 0.1)
    assert abs(density[-1] / p.rest_density_kgm3 - 1.0) < 0.01

    assert np.min(lows) >= 0.0 and np.max(np.array(highs)[:, 0]) <= p.box_width_m
    assert np.max(np.array(highs)[:, 1]) <= p.box_height_m
    assert m["fullest_cell"].max() <= p.cell_capacity


def test_grid_neighbours_give_the_all_pairs_forces_and_trajectory() -> None:
    """The uniform grid (argsort by cell, each cell's range by searchsorted, up to
    cell_capacity from each of 9 cells) gives every particle the forces and densities
    testing every pair gives (to 1e-12 relative), and 150 steps (through the column's
    collapse) the same trajectory to 1e-9: only the summation order differs."""
    scene = get_scene("dam-break")
    grid = scene.make_params({"neighbour_search": "grid"})
    every = scene.make_params({"neighbour_search": "all"})
    assert (grid.neighbour_search, every.neighbour_search) == (GRID, ALL_PAIRS)
    state = simulate(scene, grid, steps=60).state  # a moving, jumbled state
    x, y, vx, vy = (np.asarray(a)[0] for a in state[:4])
    ours = fluid_forces(grid, x, y, vx, vy, np)
    theirs = fluid_forces(every, x, y, vx, vy, np)
    for a, b in zip(ours[:3], theirs[:3], strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max())
    assert ours[3] < grid.cell_capacity  # no cell overflowed: none lost a neighbour
    runs = [simulate(scene, p, steps=150) for p in (grid, every)]
    for key, values in runs[0].measures.items():
        if key != "fullest_cell":
            np.testing.assert_allclose(values, runs[1].measures[key], rtol=1e-9, atol=1e-9)
    for a, b in zip(runs[0].state[:4], runs[1].state[:4], strict=True):
        np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-9)
    assert np.abs(runs[0].state.vy_mps).max() > 0.5  # the column was falling


def test_dam_break_refuses_what_cannot_run() -> None:
    scene = get_scene("dam-break")
    with pytest.raises(ValueError, match="neighbour_search"):
        scene.make_params({"neighbour_search": "all", "particles": 8192})
    with pytest.raises(ValueError, match="neighbour_search"):
        scene.make_params({"neighbour_search": "hash"})
    with pytest.raises(ValueError, match="water_width_m"):
        scene.make_params({"water_width_m": 1.0})
    p = scene.make_params({"particles": 65536})
    assert p.dt_s <= 0.4 * p.support_m / p.sound_speed_mps  # the CFL limit at any size
