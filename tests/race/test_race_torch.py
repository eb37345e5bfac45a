"""BeachballRace's batch on the torch backend: the same races as on NumPy (the same core,
the same random draws), float32 finite, tensors out when asked, and the step one compiled
graph (no break on the data, which would split it)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pettingzoo")
torch = pytest.importorskip("torch")

from bbgym.envs.race import BeachballRaceFleetEnv, BeachballRaceMatchEnv  # noqa: E402

SHORT = {"num_boats": 3, "countdown_s": 2.0, "max_race_time_s": 10.0}
"""Races of 40 steps, so 60 steps run through every race's restart."""


def _run(env, steps: int = 60, seed: int = 5) -> list[tuple]:
    actions = np.random.default_rng(1).uniform(-1, 1, (steps, env.num_envs, 3))
    out = [(env.reset(seed=seed)[0],)]
    for a in actions:
        obs, reward, terminated, truncated, info = env.step(a)
        out.append((obs, reward, terminated, truncated, info["place"], info["fouls"]))
    return out


def test_the_torch_fleet_races_as_the_numpy_one() -> None:
    """float64 on torch: every observation and reward within 1e-9 of NumPy's, the same
    ends, places and fouls, through each race's end and restart."""
    reference = _run(BeachballRaceFleetEnv(3, **SHORT))
    got = _run(BeachballRaceFleetEnv(3, backend="torch", compile=False, **SHORT))
    ended = 0
    for step, (want, have) in enumerate(zip(reference, got, strict=True)):
        np.testing.assert_allclose(have[0], want[0], rtol=0, atol=1e-9, err_msg=f"step {step}")
        if step:
            np.testing.assert_allclose(have[1], want[1], rtol=0, atol=1e-9)
            for a, b in zip(have[2:], want[2:], strict=True):
                np.testing.assert_array_equal(a, b)
            ended += int(want[3].sum())
    assert ended == 9  # every race's time ran out once (each boat truncated), then restarted


def test_float32_stays_finite_and_near_float64() -> None:
    """float32 on torch: finite and in bounds throughout; the first second of racing within
    1e-3 of float64 (later the races drift apart, as chaotic dynamics do in any precision)."""
    reference = _run(BeachballRaceFleetEnv(2, **SHORT), steps=40)
    got = _run(
        BeachballRaceFleetEnv(2, backend="torch", dtype="float32", compile=False, **SHORT), steps=40
    )
    for step, (want, have) in enumerate(zip(reference, got, strict=True)):
        assert np.isfinite(have[0]).all() and np.abs(have[0]).max() <= 1.0
        if step <= 4:
            np.testing.assert_allclose(have[0], want[0], rtol=0, atol=1e-3)


def test_output_torch_returns_tensors_on_the_device() -> None:
    fleet = BeachballRaceFleetEnv(2, backend="torch", output="torch", compile=False, **SHORT)
    obs, info = fleet.reset(seed=0)
    assert isinstance(obs, torch.Tensor) and obs.shape == (
        6,
        fleet.single_observation_space.shape[0],
    )
    obs, reward, terminated, truncated, info = fleet.step(torch.zeros((6, 3)))
    assert all(isinstance(x, torch.Tensor) for x in (obs, reward, terminated, truncated))
    assert reward.dtype == torch.float64 and terminated.dtype == torch.bool
    assert isinstance(info["place"], np.ndarray)  # infos stay NumPy


def test_the_race_step_is_one_graph() -> None:
    """What ``compile=True`` compiles traces as one graph with no break: a branch on the
    data (such as skipping collisions when no hulls are near) would split the step and
    cost a host sync on a GPU."""
    import torch._dynamo

    fleet = BeachballRaceFleetEnv(2, backend="torch", compile=False, **SHORT)
    fleet.reset(seed=0)
    action = torch.zeros((fleet.num_envs, 3), dtype=torch.float64)
    noise = torch.zeros((2, 2), dtype=torch.float64)
    for fn, args in (
        (fleet._advance_races, (fleet.state, action, noise)),
        (fleet._observation_of, (fleet.state,)),
    ):
        explained = torch._dynamo.explain(fn)(*args)
        assert (explained.graph_count, explained.graph_break_count) == (1, 0), (
            explained.break_reasons
        )


def test_a_match_on_torch_equals_one_on_numpy() -> None:
    """The learning boats against racers, the races stepped on torch: the same
    observations and rewards as on NumPy."""
    reference = _run(BeachballRaceMatchEnv(2, learners=1, **SHORT), steps=30)
    got = _run(
        BeachballRaceMatchEnv(2, learners=1, backend="torch", compile=False, **SHORT), steps=30
    )
    for want, have in zip(reference, got, strict=True):
        np.testing.assert_allclose(have[0], want[0], rtol=0, atol=1e-9)


@pytest.mark.parametrize(
    "kwargs, names",
    [
        ({"backend": "mlx"}, "backend"),
        ({"backend": "torch", "dtype": "float16"}, "dtype"),
        ({"backend": "torch", "device": "tpu"}, "device"),
        ({"dtype": "float32"}, "dtype"),
        ({"output": "torch"}, "output"),
    ],
)
def test_backend_arguments_name_themselves(kwargs, names) -> None:
    with pytest.raises(ValueError, match=names):
        BeachballRaceFleetEnv(2, **kwargs)


def test_a_match_refuses_tensor_outputs() -> None:
    """The scripted racer reads NumPy observations."""
    with pytest.raises(ValueError, match="output"):
        BeachballRaceMatchEnv(2, backend="torch", output="torch", compile=False)
