"""The torch backend runs the throw envs' core as NumPy does: equal in float64, close in
float32 (landing points), compiled equal to eager. The pattern of ``test_backends.py``
(BeachballSail-v0), for the throwing family in both flights (substeps and RK4 steps)."""

from __future__ import annotations

import contextlib

import backend_replica
import numpy as np
import pytest

import bbgym  # noqa: F401

torch = pytest.importorskip("torch")
pytest.importorskip("array_api_compat")

N = 16
STEPS = 200
ENV_IDS = ("BeachballThrow-v0", "BeachballCurve-v0", "BeachballThrow-v1", "BeachballCurve-v2")
# Coarse, short flights keep 200 eager torch steps quick (about 10 s); the code run is
# the default flight's.
QUICK = {"sim_dt": 0.05, "max_flight_time": 2.0, "max_roll_time": 0.25}


def make_torch(env_id: str, **kwargs):
    return backend_replica.make_torch(env_id, N, **kwargs)


def replica_run(env_id: str, seed: int, actions: np.ndarray, **kwargs) -> list[tuple]:
    """(obs, reward, terminated, truncated, landing point) per step."""
    return backend_replica.replica_run(
        env_id, N, seed, actions, extra=lambda state, info: info["landing_point"], **kwargs
    )


def actions_for(steps: int = STEPS) -> np.ndarray:
    return np.random.default_rng(3).uniform(-1, 1, (steps, N, 6)).astype(np.float32)


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("gusts", [True, False])
def test_torch_float64_equals_numpy_replica(env_id: str, gusts: bool) -> None:
    # The RK4 flight's eager torch step is many small operations: fewer steps (still about
    # 30 episodes an env)
    actions = actions_for(STEPS if env_id.endswith("-v0") else 60)
    # short episodes, so autoresets happen inside the run
    kwargs = {"gusts": gusts, "max_episode_steps": 2, **QUICK}
    expected = replica_run(env_id, 5, actions, **kwargs)
    venv = make_torch(env_id, **kwargs)
    venv.reset(seed=5)
    resets = hits = 0
    for a, (obs, reward, term, trunc, landing) in zip(actions, expected, strict=True):
        got = venv.step(a)
        np.testing.assert_allclose(got[0], obs, rtol=0, atol=1e-6)  # float32 observations
        np.testing.assert_allclose(got[1], reward, rtol=0, atol=1e-9)
        np.testing.assert_array_equal(got[2], term)
        np.testing.assert_array_equal(got[3], trunc)
        np.testing.assert_allclose(got[4]["landing_point"], landing, rtol=0, atol=1e-9)
        resets += int(np.sum(term | trunc))
        hits += int(np.sum(got[4]["is_success"]))
    assert resets >= N  # every env restarted at least once
    assert venv.unwrapped.state.landing_x.dtype == torch.float64
    if env_id.startswith("BeachballCurve"):
        assert venv.unwrapped.state.scenario.screen.all()


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_torch_float32_lands_where_float64_does(env_id: str) -> None:
    """float32's accuracy guard: the same launches (same seed, same actions, calm air so
    the float32 draws cannot move the wind) land within 2 cm of float64's, over 10 throws
    per env of the default flight (sim_dt 0.01 s, up to 6 s)."""
    actions = actions_for(10)
    kwargs = {
        "gusts": False,
        "throws_per_episode": 100,
        "target_radius": 0.01,
        "wind_speed_range": (0.0, 0.0),
    }
    runs = {}
    for dtype in ("float64", "float32"):
        venv = make_torch(env_id, dtype=dtype, **kwargs)
        venv.reset(seed=9)
        landings, ends = [], []
        for a in actions:
            _, _, term, trunc, info = venv.step(a)
            landings.append(info["landing_point"])
            ends.append(term | trunc)
        assert venv.unwrapped.state.landing_x.dtype == getattr(torch, dtype)
        runs[dtype] = np.array(landings, dtype=np.float64), np.array(ends)
    (l64, e64), (l32, e32) = runs["float64"], runs["float32"]
    np.testing.assert_array_equal(e64, e32)
    assert not e64.any()  # one episode: every step is a throw of the same launches
    assert np.max(np.abs(l64 - l32)) < 0.02
    assert np.max(np.hypot(*l64.reshape(-1, 2).T)) > 3.0  # the balls did fly


@pytest.mark.slow  # a cold compile takes over a minute on two CPU cores
# (Curve-v2 stands for Throw-v1 too: the same RK4 flight, its screen cuts included)
@pytest.mark.parametrize("env_id", ("BeachballThrow-v0", "BeachballCurve-v0", "BeachballCurve-v2"))
def test_compiled_equals_eager(env_id: str) -> None:
    actions = actions_for(4)
    results = []
    for compile in (False, True):
        with backend_replica.compiles() if compile else contextlib.nullcontext():
            venv = make_torch(env_id, compile=compile, max_episode_steps=2)
            out = [venv.reset(seed=2)[0]]
            out += [venv.step(a)[0] for a in actions]
        results.append(np.array(out))
    np.testing.assert_allclose(results[0], results[1], rtol=0, atol=1e-6)


def test_tensor_output_and_no_records_on_torch() -> None:
    venv = make_torch("BeachballThrow-v0", output="torch")
    obs, info = venv.reset(seed=0)
    assert isinstance(obs, torch.Tensor) and obs.dtype == torch.float32
    obs, reward, term, trunc, info = venv.step(torch.zeros(N, 6))
    assert isinstance(reward, torch.Tensor) and isinstance(info["miss_distance"], torch.Tensor)
    assert obs.shape == (N, 19) and "trajectory" not in info
