"""The ball physics is array-API clean: it runs unchanged on ``array_api_strict`` (the
standard and nothing more: a non-standard name, a bool used as a number, two Python scalars
in ``where`` all raise there), on torch through ``array_api_compat`` and on Python floats,
and gives NumPy's numbers (DESIGN §2, :mod:`bbgym.physics.namespace`)."""

from __future__ import annotations

import numpy as np
import pytest

from bbgym.physics.ball import (
    BallParams,
    BallState,
    air_force,
    ball_at,
    collide_balls,
    ground_contact,
    magnus_force,
    panel_contact,
    substep,
)
from bbgym.physics.flight import (
    BallPose,
    Screen,
    flight_chunk,
    flight_record_every,
    flight_start,
    fly,
    recorded_poses,
    simulate_throw,
)
from bbgym.physics.namespace import floats

xs = pytest.importorskip("array_api_strict")

BALL = BallParams()
N = 16
DT = 0.01
FIELD_M = 10.0
TOL = {"rtol": 1e-12, "atol": 1e-12}


def _launches() -> dict[str, np.ndarray]:
    """16 varied throws: lobs, flat throws, backspin, topspin, side spin, a drop, a calm."""
    rng = np.random.default_rng(3)
    v = rng.uniform(-1.0, 1.0, (N, 3)) * 14.0
    v[:, 2] = np.abs(v[:, 2])
    w = rng.uniform(-1.0, 1.0, (N, 3)) * 40.0
    v[0], w[0] = (6.0, 0.5, 5.0), (0.0, -30.0, 0.0)  # toward the screen, backspin
    v[1], w[1] = (3.0, 0.0, 12.0), (0.0, 0.0, 0.0)  # a lob
    v[2], w[2] = (9.0, 0.0, 3.0), (0.0, 40.0, 0.0)  # topspin
    v[3], w[3] = (8.0, 1.0, 4.0), (0.0, -60.0, 0.0)  # heavy backspin: comes back
    v[4], w[4] = (7.0, 0.0, 6.0), (0.0, 0.0, 50.0)  # side spin: curves
    v[5], w[5] = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)  # dropped
    v[6] = (25.0, 0.0, 2.0)  # leaves the field (of 10 m)
    wind = rng.uniform(-3.0, 3.0, (N, 2))
    wind[1] = wind[5] = 0.0  # calm
    return {"v": v, "w": w, "wind": wind, "screen": np.arange(N) % 2 == 0}


def _states() -> np.ndarray:
    """``(13, N)`` states for the single-substep functions: half in the air, half on or
    into the ground (bouncing, resting, rolling, spinning)."""
    rng = np.random.default_rng(5)
    r = BALL.radius_m
    s = np.empty((13, N))
    s[0:2] = rng.uniform(-3.0, 3.0, (2, N))
    s[2] = np.where(np.arange(N) < N // 2, rng.uniform(1.0, 4.0, N), r * rng.uniform(0.9, 1.0, N))
    s[3:6] = rng.uniform(-6.0, 6.0, (3, N))
    s[5, N // 2 : N // 2 + 3] = (-0.1, 0.0, 0.1)  # slow: resting contact, and rising
    s[6:9] = rng.uniform(-30.0, 30.0, (3, N))
    q = rng.normal(size=(4, N))
    s[9:13] = q / np.linalg.norm(q, axis=0)
    return s


def _to(xp, a: np.ndarray, dtype=None):
    if xp is np:
        return a
    if xp is xs:
        return xs.asarray(a)
    import torch

    return torch.asarray(a, dtype=dtype)


def _state(xp, s: np.ndarray, dtype=None) -> BallState:
    return BallState(*(_to(xp, row, dtype) for row in s))


def _close(got, want) -> None:
    """Every field (nested tuples too) equal to NumPy's to 1e-12; bools and ints exactly."""
    if isinstance(want, (tuple, list)):
        assert len(got) == len(want)
        for g, w in zip(got, want, strict=True):
            _close(g, w)
        return
    g, w = np.asarray(got), np.asarray(want)
    assert g.shape == w.shape
    if w.dtype.kind in "bi":
        assert g.dtype.kind == w.dtype.kind
        np.testing.assert_array_equal(g, w)
    else:
        np.testing.assert_allclose(g, w, **TOL)


def _namespaces() -> list:
    out = [pytest.param(xs, id="array_api_strict")]
    try:
        import array_api_compat.torch as xt  # noqa: F401
        import torch  # noqa: F401
    except ImportError:
        return out
    return [*out, pytest.param(xt, id="torch")]


NAMESPACES = _namespaces()


def _throw(xp, screen: bool = True, dtype=None, **kwargs):
    d = _launches()
    z = np.zeros(N)
    start = ball_at(*(_to(xp, a, dtype) for a in (z, z, z + 1.5, *d["v"].T, *d["w"].T)), xp=xp)
    wall = None
    if screen:
        wall = Screen(
            _to(xp, z + 4.0, dtype),
            _to(xp, z + 0.5, dtype),
            _to(xp, z, dtype),
            _to(xp, z + 1.0, dtype),
            1.5,
            2.5,
            _to(xp, d["screen"]),
        )
    wind = d["wind"]
    return simulate_throw(
        BALL,
        start,
        _to(xp, wind[:, 0], dtype),
        _to(xp, wind[:, 1], dtype),
        wall,
        xp=xp,
        max_roll_s=1.0,
        field_radius_m=FIELD_M,
        **kwargs,
    )


@pytest.mark.parametrize("xp", NAMESPACES)
def test_single_substep_functions_match_numpy(xp):
    s = _states()
    wind = np.random.default_rng(6).uniform(-3.0, 3.0, (2, N))
    ref, got = _state(np, s), _state(xp, s)
    wx, wy = _to(xp, wind[0]), _to(xp, wind[1])
    _close(substep(BALL, got, wx, wy, DT, xp), substep(BALL, ref, wind[0], wind[1], DT, np))
    _close(ground_contact(BALL, got, DT, xp), ground_contact(BALL, ref, DT, np))
    assert np.asarray(ground_contact(BALL, got, DT, xp)[1]).any()  # some touch
    _close(air_force(BALL, got, wx, wy, xp), air_force(BALL, ref, wind[0], wind[1], np))
    _close(
        magnus_force(BALL, got.vx, got.vy, got.vz, got.wx, got.wy, got.wz, xp),
        magnus_force(BALL, ref.vx, ref.vy, ref.vz, ref.wx, ref.wy, ref.wz, np),
    )
    # A panel across x = 0 (along +y) that half of the balls face.
    enabled = np.arange(N) % 3 != 0
    panel = (0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 0.5)
    near = s.copy()
    near[0] = np.linspace(-0.3, 0.3, N)
    ref_hit = panel_contact(_state(np, near), BALL.radius_m, *panel, enabled, np)
    got_hit = panel_contact(_state(xp, near), BALL.radius_m, *panel, _to(xp, enabled), xp)
    _close(got_hit, ref_hit)
    assert ref_hit[1].any() and not ref_hit[1].all()
    # Ball-ball collisions: each ball against the next one.
    p1, p2 = tuple(s[0:3]), tuple(np.roll(s[0:3], 1, axis=1))
    v1, v2 = tuple(s[3:6]), tuple(np.roll(s[3:6], 1, axis=1))

    def on(xp_, vectors):
        return tuple(_to(xp_, c) for c in vectors)

    _close(
        collide_balls(0.25, on(xp, v1), on(xp, p1), 0.4, on(xp, v2), on(xp, p2), 0.7, xp),
        collide_balls(0.25, v1, p1, 0.4, v2, p2, 0.7, np),
    )


def _result_close(got, want) -> None:
    for name in (
        "landing_x",
        "landing_y",
        "flight_time_s",
        "apex_height_m",
        "spin_parameter",
        "hit_screen",
        "steps",
    ):
        _close(getattr(got, name), getattr(want, name))
    _close(tuple(got.final), tuple(want.final))
    assert len(got.trajectory) == len(want.trajectory)
    _close([tuple(p) for p in got.trajectory], [tuple(p) for p in want.trajectory])


@pytest.mark.parametrize("xp", NAMESPACES)
def test_simulate_throw_matches_numpy(xp):
    want = _throw(np)
    # The batch is varied: it bounces, hits the screen, rolls and leaves the field.
    assert want.hit_screen.any() and not want.hit_screen.all()
    assert (np.hypot(want.final.x, want.final.y) > FIELD_M).any()
    assert len(set(want.steps.tolist())) > 5
    _result_close(_throw(xp), want)


@pytest.mark.parametrize("check_every", [1, 3, 16, 1000])
def test_results_and_record_do_not_depend_on_the_check_interval(check_every):
    want = _throw(np, check_every=7)
    _result_close(_throw(np, check_every=check_every), want)
    assert len(want.trajectory) == want.steps.max()
    unrecorded = _throw(np, check_every=check_every, record=False)
    assert unrecorded.trajectory == []
    _close(unrecorded.steps, want.steps)
    _close(tuple(unrecorded.final), tuple(want.final))


def test_python_floats_fly_like_element_0_of_the_numpy_batch():
    batch = _throw(np)
    d = _launches()
    start = ball_at(0.0, 0.0, 1.5, *map(float, d["v"][0]), *map(float, d["w"][0]))
    screen = Screen(4.0, 0.5, 0.0, 1.0, 1.5, 2.5, bool(d["screen"][0]))
    one = simulate_throw(
        BALL,
        start,
        float(d["wind"][0, 0]),
        float(d["wind"][0, 1]),
        screen,
        xp=floats,
        max_roll_s=1.0,
        field_radius_m=FIELD_M,
    )
    assert isinstance(one.landing_x, float) and isinstance(one.steps, int)
    assert one.hit_screen is True and batch.hit_screen[0]
    for name in ("landing_x", "landing_y", "flight_time_s", "apex_height_m", "spin_parameter"):
        assert getattr(one, name) == getattr(batch, name)[0], name  # the same bits
    assert one.steps == batch.steps[0]
    assert list(one.final) == [c[0] for c in batch.final]
    assert len(one.trajectory) == one.steps
    for k, pose in enumerate(one.trajectory):
        assert isinstance(pose, BallPose)
        assert list(pose) == [c[0] for c in batch.trajectory[k]]


def test_torch_float32_stays_float32():
    torch = pytest.importorskip("torch")
    xt = pytest.importorskip("array_api_compat.torch")
    result = _throw(xt, dtype=torch.float32)
    assert result.landing_x.dtype == torch.float32
    assert all(c.dtype == torch.float32 for c in result.final)
    assert result.steps.dtype == torch.int64 and result.hit_screen.dtype == torch.bool
    want = _throw(np)
    np.testing.assert_allclose(result.flight_time_s.numpy(), want.flight_time_s, atol=0.05)


def _exact(got, want) -> None:
    """The same bits (nested tuples too)."""
    if isinstance(want, (tuple, list)):
        assert len(got) == len(want)
        for g, w in zip(got, want, strict=True):
            _exact(g, w)
        return
    g, w = np.asarray(got), np.asarray(want)
    assert g.shape == w.shape and g.dtype == w.dtype
    assert np.array_equal(g, w), (g, w)


def test_numpy_host_flight_drops_finished_balls_with_the_masked_loops_bits():
    """``fly`` on NumPy flies only the balls still in the air; every field of the flight
    (the batch-wide counters included) and every recorded pose equal those of the plain
    masked loop of ``flight_chunk`` over the whole batch."""
    d = _launches()
    z = np.zeros(N)
    start = ball_at(z, z, z + 1.5, *d["v"].T, *d["w"].T)
    screen = Screen(z + 4.0, z + 0.5, z, z + 1.0, 1.5, 2.5, d["screen"])
    wx, wy = d["wind"].T.copy()
    last, every = 600, flight_record_every(DT)
    args = (BALL, flight_start(BALL, start), wx, wy, screen, DT)
    got, got_poses = fly(*args, last, every, True, np, 1.0, FIELD_M, check_every=4)
    want, poses, i = args[1], [], 1
    while i <= last and not want.done.all():
        want, chunk = flight_chunk(
            *args[:1], want, *args[2:], 4, last, every, True, np, 1.0, FIELD_M
        )
        poses += recorded_poses(chunk, i, every, last)
        i += 4
    del poses[int(want.samples.max()) - 1 :]
    assert len(set(want.end_time_s.tolist())) > 5  # flights of many lengths: drops happen
    _exact(tuple(got), tuple(want))
    _exact([tuple(q) for q in got_poses], [tuple(q) for q in poses])


def test_host_shortcuts_give_the_masked_updates_bits():
    """Where no ball touches the ground or a panel, NumPy skips the masked update
    (``backend.skippable``); array_api_strict never skips: the same bits either way."""
    s = _states()
    s[2] = np.linspace(1.0, 4.0, N)  # every ball in the air
    panel = (0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 0.5)
    enabled = np.arange(N) % 3 != 0
    for fn in (
        lambda xp, st: ground_contact(BALL, st, DT, xp),
        lambda xp, st: panel_contact(st, BALL.radius_m, *panel, _to(xp, enabled), xp),
    ):
        ref = fn(np, _state(np, s))
        assert not np.asarray(ref[1]).any()
        _exact([np.asarray(a) for a in fn(xs, _state(xs, s))[0]], list(ref[0]))
