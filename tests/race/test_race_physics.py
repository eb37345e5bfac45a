"""BeachballRace's laws, each against a number: the wind shadow (momentum conserved, inside
and outside its cone), the hull collisions (momentum, energy, no overlap), the course's
crossings and the right-of-way rules on built encounters."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bbgym.envs.race import course as rc
from bbgym.envs.race import rules
from bbgym.physics.collision import collide, hull_contacts, hulls
from bbgym.physics.common import AIR_DENSITY_KGM3
from bbgym.physics.shadow import (
    ShadowParams,
    cone_profile,
    profile_area_m2,
    shadow_velocity,
    shadowed_wind,
)

P = ShadowParams()
HULLS = hulls(4.2, 1.4, 135.0, 180.0)


def test_shadow_conserves_momentum_over_its_cone() -> None:
    """The air of the cone carries exactly -F t: the velocity change summed over a fine
    grid of the cone, times the air's mass per area, is the sail's impulse reversed (the
    pairwise function is the same law: the next test)."""
    force = np.array([-120.0, 200.0])
    flow = np.array([4.0, -1.0]) / math.hypot(4.0, -1.0)
    along = np.linspace(0.0, P.length_m, 801)
    across = np.linspace(-P.end_width_m, P.end_width_m, 801)
    u, v = np.meshgrid(along, across, indexing="ij")
    px = u * flow[0] - v * flow[1]
    py = u * flow[1] + v * flow[0]
    dvx, dvy = _field(force, flow, px, py)
    cell = (along[1] - along[0]) * (across[1] - across[0])
    air = AIR_DENSITY_KGM3 * P.air_height_m * cell
    total = np.array([np.sum(dvx) * air, np.sum(dvy) * air])
    np.testing.assert_allclose(total, -force * P.acting_time_s, rtol=2e-3)


def _field(force: np.ndarray, flow: np.ndarray, px: np.ndarray, py: np.ndarray) -> tuple:
    """The shadow of one boat at the origin at the points ``(px, py)``, through the law's
    own profile (the pairwise function is checked against it below)."""
    along = px * flow[0] + py * flow[1]
    across = -px * flow[1] + py * flow[0]
    scale = -P.acting_time_s / (AIR_DENSITY_KGM3 * P.air_height_m * profile_area_m2(P))
    profile = cone_profile(P, along, across, np)
    return scale * profile * force[0], scale * profile * force[1]


def test_pairwise_shadow_matches_the_profile_and_skips_itself_and_the_upwind_boat() -> None:
    """Three boats in a line downwind: the first shadows the second (as the profile
    says) and the third; nobody shadows itself, the boats upwind get nothing, a boat that
    casts none (``casts`` false) gives nothing."""
    x = np.array([[0.0, 5.0, 12.0]])
    y = np.array([[0.0, 0.5, -1.0]])
    flow_x, flow_y = np.full((1, 3), 5.0), np.zeros((1, 3))  # air moving to +x
    fx, fy = np.array([[30.0, 30.0, 30.0]]), np.array([[200.0, 200.0, 200.0]])
    casts = np.array([[True, True, True]])
    dvx, dvy = shadow_velocity(P, x, y, fx, fy, flow_x, flow_y, casts, x, y, np)
    assert dvx[0, 0] == 0.0 and dvy[0, 0] == 0.0  # the first is upwind of all
    ex, ey = _field(np.array([30.0, 200.0]), np.array([1.0, 0.0]), x[0, 1], y[0, 1])
    np.testing.assert_allclose([dvx[0, 1], dvy[0, 1]], [ex, ey], rtol=1e-12)
    assert dvx[0, 1] < 0.0  # slowed: the sail's drag reversed
    assert dvy[0, 1] < 0.0  # bent away from the side the sail pulls to
    dvx2, _ = shadow_velocity(
        P, x, y, fx, fy, flow_x, flow_y, np.array([[False, True, True]]), x, y, np
    )
    assert dvx2[0, 1] == 0.0


def test_shadow_is_zero_outside_the_cone() -> None:
    force, flow = np.array([50.0, 250.0]), np.array([1.0, 0.0])
    for px, py in ((-3.0, 0.0), (P.length_m + 0.1, 0.0), (10.0, 9.0), (0.0, 3.0)):
        dvx, dvy = _field(force, flow, np.array(px), np.array(py))
        assert dvx == 0.0 and dvy == 0.0, (px, py)
    dvx, _ = _field(force, flow, np.array(2.0), np.array(0.0))
    assert dvx != 0.0


def test_a_beating_dinghys_shadow_is_a_deficit_of_tens_of_percent_that_fades() -> None:
    """The module docstring's figures: 250 N of sail force against 5 m/s of wind takes a
    third of it just behind the sail, a fifth two boat lengths on, under a tenth four
    boat lengths on."""
    force, flow = np.array([250.0, 0.0]), np.array([1.0, 0.0])  # all drag, downwind
    deficit = [-_field(force, flow, np.array(u), np.array(0.0))[0] / 5.0 for u in (1.0, 8.4, 16.8)]
    assert 0.28 < deficit[0] < 0.36 and 0.18 < deficit[1] < 0.26 and deficit[2] < 0.1


def test_shadowed_wind_is_never_faster_than_the_wind() -> None:
    rng = np.random.default_rng(0)
    wx, wy = rng.normal(size=200) * 5, rng.normal(size=200) * 5
    dvx, dvy = rng.normal(size=200) * 3, rng.normal(size=200) * 3
    nx, ny = shadowed_wind(wx, wy, dvx, dvy, np)
    assert np.all(np.hypot(nx, ny) <= np.hypot(wx, wy) * (1 + 1e-12))
    same = np.hypot(wx + dvx, wy + dvy) <= np.hypot(wx, wy)
    np.testing.assert_array_equal(nx[same], (wx + dvx)[same])


def test_profile_area_agrees_with_a_fine_grid() -> None:
    along = np.linspace(0.0, P.length_m, 2001)
    across = np.linspace(-P.end_width_m, P.end_width_m, 2001)
    u, v = np.meshgrid(along, across, indexing="ij")
    grid = np.sum(cone_profile(P, u, v, np)) * (along[1] - along[0]) * (across[1] - across[0])
    assert profile_area_m2(P) == pytest.approx(grid, rel=2e-3)


# -- collisions ------------------------------------------------------------------------------


def _two_boats(x2: float, y2: float, h2: float, v1: tuple, v2: tuple, w: tuple = (0.0, 0.0)):
    x, y = np.array([[0.0, x2]]), np.array([[0.0, y2]])
    heading = np.array([[0.0, h2]])
    vx, vy = np.array([[v1[0], v2[0]]]), np.array([[v1[1], v2[1]]])
    return x, y, heading, vx, vy, np.array([list(w)])


@pytest.mark.parametrize("restitution", [0.0, 0.3, 1.0])
def test_collision_conserves_momentum_and_never_gains_energy(restitution: float) -> None:
    """A T-bone (boat 2 sailing into boat 1's side, off centre): linear and angular
    momentum conserved, kinetic energy kept at e = 1 and lost below, the hulls leave
    apart at e times their approach."""
    x, y, heading, vx, vy, w = _two_boats(1.0, -1.6, math.pi / 2, (0.5, 0.0), (0.0, 2.0))
    m, inertia = HULLS.mass_kg, HULLS.yaw_inertia_kgm2
    contacts = hull_contacts(HULLS, x, y, heading, np)
    assert contacts.gap_m[0, 0, 1] < 0.0
    nx, ny = contacts.normal_x[0, 0, 1], contacts.normal_y[0, 0, 1]
    px, py = contacts.point_x_m[0, 0, 1], contacts.point_y_m[0, 0, 1]

    def point_velocity(vx, vy, w, i):
        rx, ry = px - x[0, i], py - y[0, i]
        return vx[0, i] - w[0, i] * ry, vy[0, i] + w[0, i] * rx

    def approach(vx, vy, w):
        a, b = point_velocity(vx, vy, w, 0), point_velocity(vx, vy, w, 1)
        return (a[0] - b[0]) * nx + (a[1] - b[1]) * ny

    before = approach(vx, vy, w)
    assert before < 0.0
    _, _, nvx, nvy, nw, touching = collide(
        HULLS, restitution, x, y, heading, vx, vy, w, np.array([[True, True]]), np
    )
    assert touching[0, 0, 1] and touching[0, 1, 0]
    np.testing.assert_allclose(nvx.sum(), vx.sum(), atol=1e-9)
    np.testing.assert_allclose(nvy.sum(), vy.sum(), atol=1e-9)

    def angular(vx, vy, w):  # about the origin
        return float(np.sum(m * (x * vy - y * vx) + inertia * w))

    assert angular(nvx, nvy, nw) == pytest.approx(angular(vx, vy, w), abs=1e-6)
    energy = lambda vx, vy, w: float(np.sum(0.5 * m * (vx**2 + vy**2) + 0.5 * inertia * w**2))  # noqa: E731
    if restitution == 1.0:
        assert energy(nvx, nvy, nw) == pytest.approx(energy(vx, vy, w), rel=1e-9)
    else:
        assert energy(nvx, nvy, nw) < energy(vx, vy, w)
    assert approach(nvx, nvy, nw) == pytest.approx(-restitution * before, abs=1e-9)


def test_collision_leaves_no_overlap_even_in_a_heap() -> None:
    """Eight hulls dropped on top of each other in random headings in a 12 m square:
    after a step's five resolutions no two overlap by more than a centimetre, and hulls
    not touching are not moved."""
    rng = np.random.default_rng(3)
    for trial in range(20):
        x, y = rng.uniform(-6, 6, (1, 8)), rng.uniform(-6, 6, (1, 8))
        heading = rng.uniform(-math.pi, math.pi, (1, 8))
        zero = np.zeros((1, 8))
        for _ in range(5):  # the substeps of one step
            x, y, *_ = collide(
                HULLS, 0.3, x, y, heading, zero, zero, zero, np.ones((1, 8), dtype=bool), np
            )
        gap = hull_contacts(HULLS, x, y, heading, np).gap_m[0]
        off = ~np.eye(8, dtype=bool)
        assert gap[off].min() > -0.01, trial
    far_x, far_y = np.array([[0.0, 30.0]]), np.array([[0.0, 0.0]])
    out = collide(
        HULLS,
        0.3,
        far_x,
        far_y,
        np.zeros((1, 2)),
        np.ones((1, 2)),
        np.zeros((1, 2)),
        np.zeros((1, 2)),
        np.ones((1, 2), dtype=bool),
        np,
    )
    np.testing.assert_array_equal(out[0], far_x)
    assert not out[5].any()


def test_inactive_hulls_pass_through() -> None:
    x, y, heading, vx, vy, w = _two_boats(0.5, 0.0, 0.0, (1.0, 0.0), (-1.0, 0.0))
    out = collide(HULLS, 0.3, x, y, heading, vx, vy, w, np.array([[True, False]]), np)
    np.testing.assert_array_equal(out[2], vx)
    assert not out[5].any()


# -- the course ------------------------------------------------------------------------------


def _course(wind_from: float = math.pi / 2) -> rc.Course:
    """Wind from the north: upwind +y, the line along x, the pin at -x (port end)."""
    return rc.lay_course(np.array([wind_from]), 60.0, 120.0, 15.0, 30.0, np)


def test_the_course_is_laid_square_to_the_wind() -> None:
    c = _course()
    (cx, cy), (px, py) = c.ends()
    np.testing.assert_allclose(
        [cx[0, 0], cy[0, 0], px[0, 0], py[0, 0]], [30, 0, -30, 0], atol=1e-12
    )
    np.testing.assert_allclose([c.windward_x_m[0, 0], c.windward_y_m[0, 0]], [0, 120], atol=1e-12)
    np.testing.assert_allclose([c.gate_x_m[0, 0], c.gate_y_m[0, 0]], [0, -15], atol=1e-12)


@pytest.mark.parametrize(
    ("kind", "start", "end", "passed"),
    [
        (rc.START, (0, -1), (0, 1), True),  # through the line, upwind
        (rc.START, (0, 1), (0, -1), False),  # the wrong way
        (rc.START, (31, -1), (31, 1), False),  # outside the committee boat
        (rc.FINISH, (10, 1), (10, -1), True),  # downwind through the line
        (rc.FINISH, (10, -1), (10, 1), False),
        (rc.GATE, (14, -14), (14, -16), True),
        (rc.GATE, (16, -14), (16, -16), False),  # outside the gate
        (rc.WINDWARD, (2, 125), (-2, 125), True),  # above the mark, to port
        (rc.WINDWARD, (-2, 125), (2, 125), False),  # the wrong way round
        (rc.WINDWARD, (2, 115), (-2, 115), False),  # below the mark
    ],
)
def test_waypoints_are_passed_only_the_right_way(kind, start, end, passed) -> None:
    c = _course()
    a = lambda v: np.array([[float(v)]])  # noqa: E731
    got, _ = rc.passed_waypoint(
        c, np.array([[kind]]), a(start[0]), a(start[1]), a(end[0]), a(end[1]), np
    )
    assert bool(got[0, 0]) is passed


def test_steering_for_the_targets_rounds_the_windward_mark_to_port() -> None:
    """From either side below the mark, steering straight for the point the observation
    names (a step of 1 m at a time) rounds the mark the right way within 60 m."""
    for side in (-20.0, 20.0):
        assert _steer(rc.WINDWARD, side, 100.0, steps=60) is not None, side


def _steer(kind: int, x: float, y: float, steps: int = 100) -> int | None:
    """Steer straight for the point the observation names, 1 m a step, from ``(x, y)`` on
    ``_course()``; the step the waypoint of ``kind`` is passed at, or None."""
    c = _course()
    x, y = np.array([[x]]), np.array([[y]])
    kinds = np.array([[kind]])
    for step in range(steps):
        tx, ty = rc.steer_target(c, kinds, x, y, np)
        d = max(math.hypot(tx[0, 0] - x[0, 0], ty[0, 0] - y[0, 0]), 1e-9)
        nx, ny = x + (tx - x) / d, y + (ty - y) / d
        done, _ = rc.passed_waypoint(c, kinds, x, y, nx, ny, np)
        x, y = nx, ny
        if done[0, 0]:
            return step
    return None


@pytest.mark.parametrize(
    "x, y, most",
    [
        (0.0, -20.0, 25),  # below the line, between its ends: straight up, 20 m
        (-45.0, -3.0, 30),  # below and beyond the pin: inside the end, then up
        (48.0, -1.0, 30),  # below and beyond the committee boat
        (-40.0, 6.0, 60),  # came round the pin onto the course side: back, then up
        (10.0, 4.0, 40),  # over early: back below the line, then up
    ],
)
def test_steering_for_the_start_target_starts(x, y, most) -> None:
    """From below the line, beyond its ends or over it, steering for the point the
    observation names crosses the line upwind between its ends (a start) within ``most``
    metres: the target never leads a boat across the line's extension, which does not
    count, or to a point on the course side it cannot start from."""
    step = _steer(rc.START, x, y)
    assert step is not None and step < most, step


# -- right of way ----------------------------------------------------------------------------


def _must(x, y, heading, kind=rc.START, wind_from=math.pi / 2) -> np.ndarray:
    x, y, heading = (np.array([v], dtype=float) for v in (x, y, heading))
    k = x.shape[1]
    return rules.keeps_clear(
        4.2,
        _course(wind_from),
        np.full((1, k), wind_from),
        np.full((1, k), kind),
        x,
        y,
        heading,
        np,
    )[0]


def test_port_gives_way_to_starboard() -> None:
    """Wind from the north: heading north-east (45 deg) the wind comes over the port side
    (port tack), heading north-west the starboard side. Rule 10, whoever is where."""
    port, starboard = math.radians(45.0), math.radians(135.0)
    must = _must([0.0, 5.0], [0.0, 5.0], [port, starboard])
    assert must[0, 1] and not must[1, 0]


def test_windward_gives_way_to_leeward_when_overlapped() -> None:
    """Two boats on starboard tack (heading north-west), side by side: the one to the
    north-east (upwind side) keeps clear (Rule 11)."""
    h = math.radians(135.0)
    # boat 1 abeam to port of boat 0 (leeward side on starboard tack is the port side)
    left_x, left_y = -math.sin(h) * 3.0, math.cos(h) * 3.0
    must = _must([0.0, left_x], [0.0, left_y], [h, h])
    assert must[0, 1] and not must[1, 0]


def test_clear_astern_gives_way() -> None:
    """Same tack, one 8 m behind the other on the same heading: the one astern keeps
    clear (Rule 12), even on the windward side."""
    h = math.radians(135.0)
    back_x, back_y = -math.cos(h) * 8.0, -math.sin(h) * 8.0
    must = _must([0.0, back_x], [0.0, back_y], [h, h])
    assert must[1, 0] and not must[0, 1]


def test_inside_boat_gets_mark_room() -> None:
    """Two boats on starboard tack overlapped within the windward mark's zone, the inside
    one (nearer the mark) to windward: the outside, leeward one keeps clear (Rule 18),
    where far from the mark the windward one would (Rule 11)."""
    h = math.radians(135.0)  # heading north-west: the port side (south-west) is leeward
    mark = (0.0, 120.0)
    inside = (mark[0] - 3.0, mark[1] - 3.0)
    port_x, port_y = -math.sin(h), math.cos(h)
    outside = (inside[0] + 3.0 * port_x, inside[1] + 3.0 * port_y)  # abeam to leeward
    assert math.dist(inside, mark) < math.dist(outside, mark)
    xs, ys = [inside[0], outside[0]], [inside[1], outside[1]]
    must = _must(xs, ys, [h, h], kind=rc.WINDWARD)
    assert must[1, 0] and not must[0, 1]
    far = _must(xs, [ys[0] - 60.0, ys[1] - 60.0], [h, h], kind=rc.WINDWARD)
    assert far[0, 1] and not far[1, 0]


def test_races_resolve_alone_as_in_a_batch() -> None:
    """A batch of races where only some have hulls close: each race's result is the one it
    gets resolved alone (NumPy resolves the close races only), bit for bit."""
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-4, 4, (6, 4)), rng.uniform(-4, 4, (6, 4))
    x[1::2] *= 40.0  # every other race spread out: no hulls near
    heading = rng.uniform(-3, 3, (6, 4))
    vx, vy, w = rng.normal(size=(6, 4)), rng.normal(size=(6, 4)), rng.normal(size=(6, 4))
    active = np.ones((6, 4), dtype=bool)
    batch = collide(HULLS, 0.3, x, y, heading, vx, vy, w, active, np)
    assert batch[5][0::2].any() and not batch[5][1::2].any()
    for r in range(6):
        one = slice(r, r + 1)
        alone = collide(
            HULLS, 0.3, x[one], y[one], heading[one], vx[one], vy[one], w[one], active[one], np
        )
        for got, want in zip(batch, alone, strict=True):
            np.testing.assert_array_equal(got[r], want[0])
