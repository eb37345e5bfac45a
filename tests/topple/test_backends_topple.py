"""BeachballTopple-v0 (and -v2, whose interval is in RK4 steps) on the torch backend runs
the same core as NumPy: equal in float64, close in float32 where it matters (the wall's
state, the hits), compiled equal to eager, each part compiled once. The approach of
``tests/test_backends.py`` (BeachballSail-v0)."""

from __future__ import annotations

import contextlib
import math

import backend_replica
import numpy as np
import pytest

import bbgym  # noqa: F401
from bbgym import backends
from bbgym.envs.functional import InitialNoise
from bbgym.envs.topple import ToppleTask

torch = pytest.importorskip("torch")
pytest.importorskip("array_api_compat")

N = 8
STEPS = 200
# Short intervals with several gust updates keep 200 eager steps quick; near walls and
# winds up to 12 m/s make walls fall or break loose mid-interval (early stops, restarts).
FAST = dict(interval=0.5, gust_dt=0.1, wall_distance_range=(4.0, 5.5), wind_speed_range=(0.0, 12.0))


def make_torch(num_envs: int = N, env_id: str = "BeachballTopple-v0", **kwargs):
    return backend_replica.make_torch(env_id, num_envs, **kwargs)


def throws(rng: np.random.Generator, steps: int, num_envs: int) -> np.ndarray:
    """Throws at the wall (12-18 m/s, 3-20 deg up, aimed within its width), a quarter
    waits and a tenth anywhere (as tests/test_topple_equivalence.py)."""
    n = (steps, num_envs)
    speed = rng.uniform(12.0, 18.0, n) / 18.0
    elevation = np.radians(rng.uniform(3.0, 20.0, n))
    azimuth = rng.uniform(-0.04, 0.04, n)
    velocity = speed[..., None] * np.stack(
        [
            np.cos(elevation) * np.cos(azimuth),
            np.cos(elevation) * np.sin(azimuth),
            np.sin(elevation),
        ],
        axis=-1,
    )
    actions = np.concatenate([velocity, rng.uniform(-0.3, 0.3, (*n, 3))], axis=-1)
    kind = rng.random(n)
    actions[kind < 0.25] = rng.uniform(-0.015, 0.015, (int((kind < 0.25).sum()), 6))
    anywhere = kind > 0.9
    actions[anywhere] = rng.uniform(-1.0, 1.0, (int(anywhere.sum()), 6))
    return actions.astype(np.float32)


def replica_run(
    seed: int, actions: np.ndarray, env_id: str = "BeachballTopple-v0", **kwargs
) -> list[tuple]:
    """(obs, reward, terminated, truncated, wall angle) per step."""
    return backend_replica.replica_run(
        env_id,
        N,
        seed,
        actions,
        extra=lambda state, info: state.wall.angle,
        **kwargs,
    )


@pytest.mark.parametrize(
    ("env_id", "gusts"),
    [("BeachballTopple-v0", True), ("BeachballTopple-v0", False), ("BeachballTopple-v2", True)],
)
def test_torch_float64_equals_numpy_replica(env_id: str, gusts: bool) -> None:
    actions = throws(np.random.default_rng(3), STEPS, N)
    kwargs = {**FAST, "gusts": gusts}
    expected = replica_run(5, actions, env_id, **kwargs)
    venv = make_torch(env_id=env_id, **kwargs)
    venv.reset(seed=5)
    ends = 0
    for a, (obs, reward, term, trunc, angle) in zip(actions, expected, strict=True):
        got = venv.step(a)
        np.testing.assert_allclose(got[0], obs, rtol=0, atol=1e-6)  # float32 observations
        np.testing.assert_allclose(got[1], reward, rtol=0, atol=1e-9)
        np.testing.assert_array_equal(got[2], term)
        np.testing.assert_array_equal(got[3], trunc)
        np.testing.assert_allclose(got[4]["wall_angle"], angle, rtol=0, atol=1e-9)
        ends += int(np.sum(term | trunc))
    assert ends >= 4 * N  # every env restarted several times
    assert venv.unwrapped.state.wall.angle.dtype == torch.float64


@pytest.mark.parametrize("integrator", [{}, {"interval_integrator": "rk4_events", "sim_dt": 0.05}])
def test_host_transition_equals_the_compiled_steps_chunks(integrator: dict) -> None:
    """The host's long chunks (``transition``) and the compiled step's short ones
    (``begin``, ``chunk``..., ``end``) give the same states, on NumPy."""
    task = ToppleTask(**FAST, **integrator)
    assert task.host_interval_params.chunk_substeps != task.interval_params.chunk_substeps
    rng = np.random.default_rng(1)
    keys = backends.env_keys(0, 16, np)
    counter = np.zeros(16, dtype=np.int64)
    noise = InitialNoise(
        backends.uniforms(keys, counter, 1, 3, np.float64, np),
        backends.normals(keys, counter, 2, 2, np.float64, np),
        backends.normals(keys, counter, 3, 2, np.float64, np),
    )
    state = task.initial(noise, {}, np)
    for a in throws(rng, 6, 16):
        step_noise = np.stack(
            backends.normals(keys, counter, 0, 2 * task.step_noise_pairs, np.float64, np)
        )
        a = a.astype(np.float64)
        host, events = task.transition(state, a, step_noise, np)
        carry = task.begin(state, a, step_noise, np)
        for _ in range(task.chunks):
            carry = task.chunk(carry, np)
        short, short_events = task.end(state, carry, np)
        for x, y in zip(_leaves(host), _leaves(short), strict=True):
            np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(events.noise_used, short_events.noise_used)
        np.testing.assert_array_equal(events.samples, short_events.samples)
        state, counter = host, counter + 1


def _leaves(tree):
    if isinstance(tree, tuple):
        return [leaf for t in tree for leaf in _leaves(t)]
    return [np.asarray(tree)]


def test_torch_float32_keeps_the_walls_and_hits_of_float64() -> None:
    """float32's accuracy guard: a fixed set of throws (and waits) in the default 3 s
    intervals hits the same walls the same number of times, leaves every wall in the same
    state, and its final lean within 2e-3 rad of float64's (rewards within 5e-3)."""
    actions = throws(np.random.default_rng(8), 4, 32)
    runs = {}
    for dtype in ("float64", "float32"):
        venv = make_torch(dtype=dtype, num_envs=32, throws_per_episode=4)
        venv.reset(seed=9)
        out = []
        for a in actions:
            _, r, _, _, info = venv.step(a)
            out.append((r, info["hits"], info["wall_state"], info["wall_angle"]))
        runs[dtype] = out
    hits = 0
    for (r64, h64, s64, a64), (r32, h32, s32, a32) in zip(*runs.values(), strict=True):
        np.testing.assert_array_equal(h64, h32)
        np.testing.assert_array_equal(s64, s32)
        assert np.max(np.abs(a64 - a32)) < 2e-3
        assert np.max(np.abs(r64 - r32)) < 5e-3
        hits = max(hits, int(h64.sum()))
    assert hits >= 8  # many throws hit their wall
    assert any((s != "standing").any() for _, _, s, _ in runs["float64"])  # some fell


@pytest.mark.parametrize(
    ("env_id", "step_graph"),
    [("BeachballTopple-v0", "parts"), ("BeachballTopple-v0", "one"), ("BeachballTopple-v2", "one")],
)
def test_compiled_equals_eager_and_compiles_each_graph_once(env_id: str, step_graph: str) -> None:
    """Compiled (its parts, or the whole step as one graph with the interval's chunks in a
    loop) equals eager torch (the parts called one by one)."""
    actions = throws(np.random.default_rng(2), 5, N)
    results = []
    for compile in (False, True):
        with backend_replica.compiles() if compile else contextlib.nullcontext() as counters:
            venv = make_torch(
                compile=compile, throws_per_episode=2, step_graph=step_graph, env_id=env_id, **FAST
            )
            out = [venv.reset(seed=2)[0]]
            out += [venv.step(a)[0] for a in actions]
        results.append(np.array(out))
        if compile:
            # begin, chunk, end, restart, observe: one graph each; or one in all; never
            # recompiled
            graphs = 5 if step_graph == "parts" else 1
            assert counters["stats"]["unique_graphs"] <= graphs, dict(counters["stats"])
            assert not counters["recompiles"], dict(counters["recompiles"])
    np.testing.assert_allclose(results[0], results[1], rtol=0, atol=1e-6)


def test_torch_step_infos() -> None:
    venv = make_torch(output="torch", **FAST)
    obs, info = venv.reset(seed=0)
    assert isinstance(obs, torch.Tensor) and obs.shape == (N, 19)
    obs, reward, term, trunc, info = venv.step(torch.zeros(N, 6))
    assert isinstance(info["wall_angle"], torch.Tensor)
    assert list(info["wall_state"]) == ["standing"] * N or info["_wall_state"].all()
    assert "ball_trajectory" not in info  # the torch backend keeps no samples
    assert math.isfinite(float(reward.sum()))
