"""The wall and Topple's interval run unchanged on every array API namespace.

A batch of 12 varied walls and balls (standing, rocking and toppling either way, breaking
loose, loose panels in flight and landed, fallen walls, hits high and low, misses, gusts on
and off with a noise window, envs stopped from the start) runs through ``wall_torques``,
``wall_step``, ``loose_step``, ``ball_hits_wall`` and ``run_interval`` on NumPy (the
reference), on ``array_api_strict`` (the standard and nothing more: a non-standard name, a
bool used as a number, two scalars in ``where`` raise there) and on torch float64 through
``array_api_compat.torch``. Every output field agrees with NumPy to 1e-12; on Python floats
env 0 of the batch agrees with element 0 of NumPy's.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from bbgym.physics.ball import BallParams, ball_at
from bbgym.physics.namespace import floats
from bbgym.physics.toppling import IntervalParams, interval_start, run_interval
from bbgym.physics.wall import (
    FALLEN_AWAY,
    FALLEN_TOWARD,
    LOOSE,
    STANDING,
    WallParams,
    WallState,
    ball_hits_wall,
    loose_step,
    wall_at,
    wall_step,
    wall_torques,
)
from bbgym.physics.wind import GustParams, GustState

TOL = 1e-12
N = 12
P = WallParams()
BALL = BallParams()
DT = 0.01


def _strict() -> Any:
    return pytest.importorskip("array_api_strict")


def _torch() -> Any:
    pytest.importorskip("torch")
    return pytest.importorskip("array_api_compat.torch")


NAMESPACES = [pytest.param(_strict, id="array_api_strict"), pytest.param(_torch, id="torch")]


def to_xp(xp: Any, tree: Any) -> Any:
    """NumPy arrays (in NamedTuples, tuples, lists) as arrays of ``xp``; the rest as is."""
    if isinstance(tree, np.ndarray):
        return xp.asarray(tree)
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(to_xp(xp, v) for v in tree))
    if isinstance(tree, (tuple, list)):
        return type(tree)(to_xp(xp, v) for v in tree)
    return tree


def to_float(tree: Any, i: int = 0) -> Any:
    """Element ``i`` of NumPy arrays as Python scalars."""
    if isinstance(tree, np.ndarray):
        return tree[i].item()
    if isinstance(tree, tuple) and hasattr(tree, "_fields"):
        return type(tree)(*(to_float(v, i) for v in tree))
    if isinstance(tree, (tuple, list)):
        return type(tree)(to_float(v, i) for v in tree)
    if isinstance(tree, dict):
        return {k: to_float(v, i) for k, v in tree.items()}
    return tree


def to_numpy(x: Any) -> np.ndarray:
    if isinstance(x, (bool, int, float, np.ndarray)):
        return np.asarray(x)
    if hasattr(x, "detach"):  # a torch tensor
        return x.detach().cpu().numpy()
    return np.from_dlpack(x)


def assert_same(got: Any, want: Any, path: str = "") -> None:
    """Every leaf of ``got`` (any namespace) equals ``want`` (NumPy) to ``TOL``, with the
    same kind (float, int, bool)."""
    if isinstance(want, tuple):
        assert isinstance(got, tuple) and len(got) == len(want), path
        names = getattr(want, "_fields", range(len(want)))
        for name, g, w in zip(names, got, want, strict=True):
            assert_same(g, w, f"{path}.{name}")
        return
    if isinstance(want, dict):
        assert isinstance(got, dict) and set(got) == set(want), path
        for key in want:
            assert_same(got[key], want[key], f"{path}.{key}")
        return
    if isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), path
        for k, (g, w) in enumerate(zip(got, want, strict=True)):
            assert_same(g, w, f"{path}[{k}]")
        return
    if isinstance(want, int) and not isinstance(want, (bool, np.ndarray)):
        assert got == want, path
        return
    g, w = to_numpy(got), np.asarray(want)
    assert g.shape == w.shape, f"{path}: shape {g.shape} != {w.shape}"
    kind = {"b": "b", "i": "i", "u": "i", "f": "f"}
    assert kind[g.dtype.kind] == kind[w.dtype.kind], f"{path}: dtype {g.dtype} != {w.dtype}"
    if w.dtype.kind == "f":
        np.testing.assert_allclose(g, w, rtol=TOL, atol=TOL, err_msg=path)
    else:
        np.testing.assert_array_equal(g, w, err_msg=path)


def walls() -> WallState:
    """Twelve walls: upright (0, 1, 10), rocking away (2) and toward (3), about to fall (4),
    leaning back onto the foot (5), fallen away (6) and toward (7), loose in flight (8, 9:
    about to touch down), loose and landed (11)."""
    base = np.array([6.0, 5.0, 4.5, 7.0, 6.0, 5.5, 6.0, 6.0, 6.0, 8.0, 4.0, 5.0])
    s = wall_at(base)
    angle = np.array(
        [0.0, 0.0, 0.2, -0.15, 1.4, 0.02, 0.5 * math.pi, -0.5 * math.pi, 0.0, 0.0, 0.0, 0.0]
    )
    rate = np.array([0.0, 0.0, 0.6, -0.5, 2.0, -0.8, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    pivot = np.array([0.0, 0.0, 1.0, -1.0, 1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 0.0, 1.0])
    status = np.array(
        [STANDING] * 6 + [FALLEN_AWAY, FALLEN_TOWARD, LOOSE, LOOSE, STANDING, LOOSE],
        dtype=np.float64,
    )
    loose_x = np.array([0.0] * 8 + [6.5, 9.0, 0.0, 7.0])
    loose_z = np.array([0.0] * 8 + [1.5, 1.21, 0.0, 0.015])
    loose_angle = np.array([0.0] * 8 + [0.3, -0.1, 0.0, 0.5 * math.pi])
    loose_vx = np.array([0.0] * 8 + [3.0, 1.0, 0.0, 0.0])
    loose_vz = np.array([0.0] * 8 + [1.0, -2.0, 0.0, 0.0])
    loose_rate = np.array([0.0] * 8 + [1.5, -0.7, 0.0, 0.0])
    landed = np.array([False] * 11 + [True])
    stress = np.array([0.0, 0.3, 0.5, 0.1, 0.2, 0.0, 0.9, 0.4, 1.1, 1.2, 0.0, 1.3])
    return s._replace(
        angle=angle,
        rate=rate,
        pivot=pivot,
        status=status,
        stress=stress,
        loose_x=loose_x,
        loose_z=loose_z,
        loose_angle=loose_angle,
        loose_vx=loose_vx,
        loose_vz=loose_vz,
        loose_rate=loose_rate,
        landed=landed,
    )


WIND = np.array([0.0, 3.5, -2.0, 4.0, 1.0, 0.0, 5.0, -5.0, 8.0, 3.0, 12.0, 2.0])


def balls_at_the_face(s: WallState) -> tuple[np.ndarray, ...]:
    """Ball centres touching the near face of each wall (some off its width, some moving
    away, some below or above the face): ``(x, y, z, vx, vz)``."""
    x = s.base_x - P.thickness_m / 2 - 0.15
    y = np.array([0.0, 0.1, -0.2, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3])
    z = np.array([1.8, 0.5, 2.2, 1.0, 1.2, 2.5, 1.0, 1.0, 1.0, 1.0, 0.1, 1.0])
    vx = np.array([10.0, 6.0, 8.0, -3.0, 9.0, 4.0, 5.0, 5.0, 5.0, 5.0, 12.0, 5.0])
    vz = np.array([0.0, -1.0, 2.0, 0.0, 0.5, -3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    return x, y, z, vx, vz


def wall_cases(xp: Any, s: WallState, wind: Any, balls: tuple) -> dict[str, Any]:
    out: dict[str, Any] = {}
    out["torques"] = wall_torques(P, s.angle, s.pivot, wind, xp)
    stepped = s
    for k in range(40):
        stepped = wall_step(P, stepped, wind, 0.02, xp)
        if k in (0, 9, 39):
            out[f"wall_step_{k}"] = stepped
    out["wall_step_storm"] = wall_step(P, s, 3.0 * wind, 0.02, xp)
    loose = (s.loose_x, s.loose_z, s.loose_angle, s.loose_vx, s.loose_vz, s.loose_rate)
    out["loose_step"] = loose_step(P, *loose, wind, 0.05, xp)
    out["ball_hits_wall"] = ball_hits_wall(P, s, BALL.mass_kg, BALL.radius_m, *balls, xp)
    return out


def test_wall_functions_on_every_namespace_match_numpy_to_1e12():
    s, balls = walls(), balls_at_the_face(walls())
    want = wall_cases(np, s, WIND, balls)
    # The batch covers what it claims: hits and misses, breaking loose, landing, falling.
    height = want["ball_hits_wall"][3]
    assert 3 <= np.sum(height >= 0.0) < N
    final = want["wall_step_39"]
    assert {STANDING, FALLEN_AWAY, FALLEN_TOWARD, LOOSE} <= set(final.status.tolist())
    assert np.any(final.landed & ~s.landed)
    for make in (_strict, _torch):
        try:
            xp = make()
        except pytest.skip.Exception:
            continue
        got = wall_cases(xp, to_xp(xp, s), xp.asarray(WIND), to_xp(xp, balls))
        for key in want:
            assert_same(got[key], want[key], f"{xp.__name__}:{key}")
    got = wall_cases(floats, to_float(s), float(WIND[0]), to_float(balls))
    assert_same(got, to_float(want), "floats")


INTERVAL = IntervalParams(
    wall=P,
    ball=BALL,
    gust=GustParams(speed_std=0.4, shift_std_rad=0.3, time_constant_s=2.0),
    sim_dt=DT,
    gust_dt=0.1,
    n_substeps=150,
    gust_every=10,
    record_every=5,
)


def interval_inputs() -> tuple:
    """The interval's inputs for the 12 envs: balls thrown at the walls (some waits), gusts
    on for some, two envs stopped from the start (10, 11)."""
    s = walls()
    rng = np.random.default_rng(5)
    launch = np.array(
        [
            [9.0, 0.0, 4.0],
            [7.0, 0.5, 3.0],
            [8.0, -0.3, 5.0],
            [6.0, 0.0, 4.0],
            [10.0, 0.0, 2.0],
            [0.0, 0.0, 0.0],
            [6.0, 0.0, 3.0],
            [5.0, 0.0, 3.0],
            [8.0, 0.0, 4.0],
            [0.0, 0.0, 0.0],
            [12.0, 0.0, 1.0],
            [4.0, 0.0, 2.0],
        ]
    ).T
    spin = rng.normal(0.0, 20.0, (3, N))
    zero = np.zeros(N)
    ball = ball_at(zero, zero, zero + 1.5, *launch, *spin)
    gust = GustState(*(rng.normal(0.0, 0.2, N) for _ in range(4)))
    wind_speed = np.abs(WIND) * 0.5
    wind_from = np.where(WIND >= 0.0, math.pi, 0.0) + rng.normal(0.0, 0.3, N)
    gusts = np.array([True, False] * 6)
    flying = np.array([True] * 5 + [False] + [True] * 3 + [False] + [True] * 2)
    running = np.array([True] * 10 + [False] * 2)
    noise = rng.standard_normal((INTERVAL.n_gust_updates, 2, N))
    noise = np.where(gusts & running, noise, 0.0)  # as NormalStreams.peek gives it
    # The window's rows: pair j is rows 2j, 2j + 1.
    return s, ball, gust, wind_speed, wind_from, gusts, flying, running, noise.reshape(-1, N)


def interval(xp: Any, inputs: tuple, stop_early: bool) -> tuple:
    """The interval's carry (without its samples) and its samples."""
    s, ball, gust, wind_speed, wind_from, gusts, flying, running, noise = inputs
    carry = interval_start(
        INTERVAL, ball, s, gust, wind_speed, wind_from, flying, running, xp, record=True
    )
    carry = run_interval(
        INTERVAL, carry, wind_speed, wind_from, gusts, noise, xp, stop_early=stop_early
    )
    return carry._replace(taken=()), list(carry.taken)


def _cut(samples: list, n_taken: np.ndarray) -> list:
    """Env ``i``'s first ``n_taken[i]`` samples, as ``(K_i, 12)`` arrays."""
    rows = np.array([[to_numpy(v) for v in sample] for sample in samples])  # (K, 12, N)
    return [rows[: n_taken[i], :, i] for i in range(rows.shape[2])]


def test_interval_numpy_batch_is_what_it_claims():
    carry, samples = interval(np, interval_inputs(), True)
    assert np.all(carry.substep <= INTERVAL.n_substeps) and carry.substep.dtype == np.int64
    assert carry.hits.dtype == np.int64 and carry.samples.dtype == np.int64
    assert carry.hits.sum() >= 2  # some balls hit their wall
    assert np.all(carry.noise_used[~interval_inputs()[5]] == 0)  # no gusts, no pairs
    assert carry.noise_used.max() > 0
    assert not carry.running[10] and carry.samples[10] == 0  # stopped from the start
    # A stopped env keeps exactly its state.
    s = walls()
    for name in s._fields:
        np.testing.assert_array_equal(getattr(carry.wall, name)[10:], getattr(s, name)[10:])
    # Results and each env's samples do not depend on whether the driver stops early.
    other, other_samples = interval(np, interval_inputs(), False)
    assert np.all(other.substep == INTERVAL.n_chunks * INTERVAL.chunk_substeps)
    assert_same(other._replace(substep=carry.substep), carry, "stop_early")
    for a, b in zip(_cut(other_samples, other.samples), _cut(samples, carry.samples), strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("make", NAMESPACES)
def test_interval_on_every_namespace_matches_numpy_to_1e12(make):
    xp = make()
    inputs = interval_inputs()
    want, want_samples = interval(np, inputs, True)
    got, got_samples = interval(xp, to_xp(xp, inputs), True)
    assert_same(got, want, xp.__name__)
    assert_same(got_samples, want_samples, f"{xp.__name__}:samples")


def test_interval_on_floats_matches_element_0_of_numpy():
    inputs = interval_inputs()
    want, want_samples = interval(np, inputs, True)
    floats_inputs = to_float(inputs[:-1]) + (inputs[-1][:, 0].tolist(),)
    got, got_samples = interval(floats, floats_inputs, True)
    n0 = int(want.samples[0])
    assert got.samples == n0 and len(got_samples) >= n0
    assert_same(got._replace(substep=0), to_float(want._replace(substep=0)), "floats")
    np.testing.assert_allclose(
        np.array(got_samples[:n0], dtype=np.float64),
        _cut(want_samples, want.samples)[0],
        rtol=TOL,
        atol=TOL,
    )


def _float_dtypes(tree: Any) -> set:
    if isinstance(tree, tuple):
        return set().union(*(_float_dtypes(v) for v in tree)) if tree else set()
    if isinstance(tree, list):
        return set().union(*(_float_dtypes(v) for v in tree)) if tree else set()
    if hasattr(tree, "dtype") and tree.dtype.is_floating_point:
        return {tree.dtype}
    return set()


def test_float32_stays_float32_on_torch():
    # No float64 is hard-coded: a float32 batch computes in float32 throughout.
    torch = pytest.importorskip("torch")
    xp = _torch()

    def f32(tree: Any) -> Any:
        tree = to_xp(xp, tree)
        if isinstance(tree, tuple) and hasattr(tree, "_fields"):
            return type(tree)(*(f32(v) for v in tree))
        if isinstance(tree, (tuple, list)):
            return type(tree)(f32(v) for v in tree)
        if hasattr(tree, "dtype") and tree.dtype == torch.float64:
            return tree.to(torch.float32)
        return tree

    s, balls = f32(walls()), f32(balls_at_the_face(walls()))
    out = wall_cases(xp, s, f32(WIND), balls)
    assert _float_dtypes(tuple(out.values())) == {torch.float32}
    carry, samples = interval(xp, f32(interval_inputs()), True)
    assert _float_dtypes((carry, samples)) == {torch.float32}
    assert carry.hits.dtype == torch.int64 and carry.wall.landed.dtype == torch.bool
