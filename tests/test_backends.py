"""The torch backend runs the same core as NumPy: equal in float64, close in float32,
compiled equal to eager, and the counter-based generator gives the same bits everywhere.
Written for BeachballSail-v0; the ball envs have their own files
(``test_backends_throw.py``, ``test_backends_topple.py``) on the same pattern."""

from __future__ import annotations

import contextlib
import logging
import math
import re

import backend_replica
import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401
import bbgym.spec
from bbgym import backends
from bbgym.envs.functional import task_info_names

torch = pytest.importorskip("torch")
pytest.importorskip("array_api_compat")

N = 16
STEPS = 200


def make_torch(env_id: str, **kwargs):
    return backend_replica.make_torch(env_id, N, **kwargs)


def replica_run(env_id: str, seed: int, actions: np.ndarray, **kwargs) -> list[tuple]:
    return backend_replica.replica_run(env_id, N, seed, actions, **kwargs)


def actions_for(env_id: str, steps: int = STEPS) -> np.ndarray:
    space = gym.make(env_id).action_space
    return np.random.default_rng(3).uniform(-1, 1, (steps, N, *space.shape)).astype(np.float32)


@pytest.mark.parametrize("gusts", [True, False])
def test_torch_float64_equals_numpy_replica(gusts: bool) -> None:
    env_id = "BeachballSail-v0"
    actions = actions_for(env_id)
    # short episodes, so autoresets happen inside the run
    kwargs = {"gusts": gusts, "max_episode_steps": 60}
    expected = replica_run(env_id, 5, actions, **kwargs)
    venv = make_torch(env_id, **kwargs)
    venv.reset(seed=5)
    resets = 0
    for a, (obs, reward, term, trunc) in zip(actions, expected, strict=True):
        got = venv.step(a)
        np.testing.assert_allclose(got[0], obs, rtol=0, atol=1e-6)  # float32 observations
        np.testing.assert_allclose(got[1], reward, rtol=0, atol=1e-9)
        np.testing.assert_array_equal(got[2], term)
        np.testing.assert_array_equal(got[3], trunc)
        resets += int(np.sum(term | trunc))
    assert resets >= N  # every env restarted at least once
    state = venv.unwrapped.state
    assert state.boat.x_m.dtype == torch.float64


def test_torch_float32_tracks_float64() -> None:
    """float32's accuracy guard: the same boats (same noise, same actions) sail tracks
    that stay within 0.5 m of float64's over 100 steps (25 s, about 50 m sailed), with
    rewards within 1e-3 per step."""
    env_id = "BeachballSail-v0"
    actions = actions_for(env_id, 100)
    runs = {}
    for dtype in ("float64", "float32"):
        venv = make_torch(env_id, dtype=dtype, max_episode_steps=1000)
        venv.reset(seed=9)
        rewards, positions = [], []
        for a in actions:
            _, r, term, trunc, info = venv.step(a)
            rewards.append(r)
            positions.append(info["position"])
        runs[dtype] = np.array(rewards), np.array(positions)
    r64, p64 = runs["float64"]
    r32, p32 = runs["float32"]
    assert np.max(np.abs(p64 - p32)) < 0.5
    assert np.max(np.abs(r64 - r32)) < 1e-3
    assert np.max(np.abs(p64)) > 10.0  # the boats did sail


def compile_lines(caplog) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == "bbgym.backends"]


def test_compiled_equals_eager(caplog) -> None:
    """... and the compiled env says so on its first step (and on no later one)."""
    caplog.set_level(logging.INFO, logger="bbgym")
    env_id = "BeachballSail-v0"
    actions = actions_for(env_id, 12)
    results = []
    for compile in (False, True):
        with backend_replica.compiles() if compile else contextlib.nullcontext():
            venv = make_torch(env_id, compile=compile, max_episode_steps=5)
            out = [venv.reset(seed=2)[0]]
            out.append(venv.step(actions[0])[0])
            first = compile_lines(caplog)
            caplog.clear()
            out += [venv.step(a)[0] for a in actions[1:]]
        results.append(np.array(out))
        if compile:
            assert len(first) == 2, first
            assert first[0].startswith(
                f"compiling the {env_id} step for torch (cpu, float64, batch {N})"
            ), first
            assert re.fullmatch(
                r"compiled the .* step in [0-9.]+ s \([1-9][0-9]* new graphs\)", first[1]
            ), first
        else:
            assert first == []  # eager torch compiles nothing, so says nothing
        assert compile_lines(caplog) == []  # later steps reuse the graphs
    np.testing.assert_allclose(results[0], results[1], rtol=0, atol=1e-6)


def test_compile_logged_names_the_shape_and_the_cache(caplog, monkeypatch, tmp_path) -> None:
    """The two lines around a compile: what, where, which dtype and batch, the cache folder
    (torch's, moved by ``TORCHINDUCTOR_CACHE_DIR``) and how long it took."""
    monkeypatch.setenv("TORCHINDUCTOR_CACHE_DIR", str(tmp_path / "inductor"))
    caplog.set_level(logging.INFO, logger="bbgym")
    backend = backends.Backend("torch", dtype="float32")
    step = backends.compiled(lambda x: x * 2.0 + 1.0, backend)
    with backend_replica.compiles(), backends.compile_logged("tiny", backend, 3):
        step(torch.ones(3))
    start, end = compile_lines(caplog)
    assert start.startswith("compiling tiny for torch (cpu, float32, batch 3): ")
    assert start.endswith(f"reuse the compile cache ({tmp_path / 'inductor'})")
    assert re.fullmatch(r"compiled tiny in [0-9.]+ s \(1 new graphs\)", end), end


def test_a_failing_compile_raises_and_names_the_eager_switch(monkeypatch) -> None:
    """No silent fallback to eager torch: a compiler that fails (here a backend that raises,
    as a missing C++ compiler makes inductor do) fails the call, naming ``compile=False``."""
    real_compile = torch.compile

    def broken(gm, example_inputs):
        raise RuntimeError("no C++ compiler on this machine")

    monkeypatch.setattr(torch, "compile", lambda fn, **kw: real_compile(fn, backend=broken, **kw))
    step = backends.compiled(lambda x: x * 2.0 + 1.0, backends.Backend("torch"))
    with pytest.raises(RuntimeError, match=r"(?s)torch.compile failed .*compile=False") as error:
        step(torch.ones(3, dtype=torch.float64))
    assert "no C++ compiler" in str(error.value)
    eager = backends.compiled(abs, backends.Backend("torch", compile=False))
    assert eager is abs


def test_tensor_output_stays_on_the_device() -> None:
    venv = make_torch("BeachballSail-v0", output="torch")
    obs, info = venv.reset(seed=0)
    assert isinstance(obs, torch.Tensor) and obs.dtype == torch.float32
    obs, reward, term, trunc, info = venv.step(torch.zeros(N, 2))
    assert isinstance(reward, torch.Tensor) and isinstance(info["boat_speed"], torch.Tensor)
    assert obs.shape == (N, 16)


def test_torch_runs_are_deterministic_under_a_seed() -> None:
    actions = actions_for("BeachballSail-v0", 30)
    runs = []
    for _ in range(2):
        venv = make_torch("BeachballSail-v0")
        out = [venv.reset(seed=4)[0]] + [venv.step(a)[0] for a in actions]
        runs.append(np.array(out))
    np.testing.assert_array_equal(runs[0], runs[1])
    venv = make_torch("BeachballSail-v0")
    other = np.array([venv.reset(seed=5)[0]] + [venv.step(a)[0] for a in actions])
    assert not np.array_equal(runs[0], other)


def test_backend_arguments_are_checked() -> None:
    with pytest.raises(ValueError, match="backend"):
        gym.make_vec(
            "BeachballSail-v0", num_envs=2, vectorization_mode="vector_entry_point", backend="mlx"
        )
    with pytest.raises(ValueError, match="dtype"):
        make_torch("BeachballSail-v0", dtype="float16")
    with pytest.raises(ValueError, match="device"):
        make_torch("BeachballSail-v0", device="tpu")
    with pytest.raises(ValueError, match="dtype"):
        gym.make_vec(
            "BeachballSail-v0", num_envs=2, vectorization_mode="vector_entry_point", dtype="float32"
        )


@pytest.mark.skipif(not torch.cuda.is_available(), reason="needs CUDA")
def test_cuda_equals_cpu() -> None:
    actions = actions_for("BeachballSail-v0", 50)
    out = {}
    for device in ("cpu", "cuda"):
        venv = make_torch("BeachballSail-v0", device=device, compile=True)
        out[device] = np.array([venv.reset(seed=1)[0]] + [venv.step(a)[0] for a in actions])
    np.testing.assert_allclose(out["cpu"], out["cuda"], rtol=0, atol=1e-5)


def test_counter_rng_agrees_on_numpy_torch_and_strict() -> None:
    strict = pytest.importorskip("array_api_strict")
    from array_api_compat import torch as tx

    keys = backends.env_keys(123, 64, np)
    counter = np.arange(64, dtype=np.int64) * 7
    ref = backends.normals(keys, counter, 2, 4, np.float64, np)
    got_t = backends.normals(
        torch.as_tensor(keys), torch.as_tensor(counter), 2, 4, torch.float64, tx
    )
    got_s = backends.normals(
        strict.asarray(keys), strict.asarray(counter), 2, 4, strict.float64, strict
    )
    for r, t, s in zip(ref, got_t, got_s, strict=True):  # log and cos may round differently
        np.testing.assert_allclose(t.numpy(), r, rtol=1e-15, atol=1e-15)
        np.testing.assert_array_equal(r, np.asarray(s))  # strict wraps NumPy itself
    ref_u = backends.uniforms(keys, counter, 2, 4, np.float64, np)
    got_u = backends.uniforms(
        torch.as_tensor(keys), torch.as_tensor(counter), 2, 4, torch.float64, tx
    )
    for r, t in zip(ref_u, got_u, strict=True):  # integer hashing: the same bits
        np.testing.assert_array_equal(r, t.numpy())
    # and they are standard normals
    big = backends.normals(
        backends.env_keys(0, 100_000, np), np.zeros(100_000, dtype=np.int64), 0, 2, np.float64, np
    )
    for z in big:
        assert abs(np.mean(z)) < 0.02 and abs(np.std(z) - 1.0) < 0.02
    assert abs(np.corrcoef(big[0], big[1])[0, 1]) < 0.02
    u = backends.uniforms(
        backends.env_keys(1, 100_000, np), np.zeros(100_000, dtype=np.int64), 0, 1, np.float64, np
    )[0]
    assert 0.0 < u.min() and u.max() < 1.0
    hist, _ = np.histogram(u, 10, (0.0, 1.0))
    assert np.all(np.abs(hist - 10_000) < 5 * math.sqrt(10_000))


def test_replaced_is_replace_spelled_as_a_constructor() -> None:
    """``replaced`` gives ``_replace``'s record (torch 2.11's Dynamo returned an empty tuple
    from a compiled ``_replace``), names a field the record lacks, and the package calls
    it and ``select`` instead of ``_replace`` and ``_make`` everywhere."""
    from pathlib import Path

    from bbgym.physics.namespace import replaced, select
    from bbgym.physics.sailing_step import StepCarry

    carry = StepCarry(*range(7))
    assert replaced(carry, wind_x=10, sea="calm") == carry._replace(wind_x=10, sea="calm")
    with pytest.raises(ValueError, match=r"StepCarry has no field \['wind_z'\]"):
        replaced(carry, wind_z=1.0)
    compiled = torch.compile(lambda c: replaced(c, jibes=c.jibes + 1), fullgraph=True)
    out = compiled(StepCarry(*(torch.zeros(2) for _ in range(7))))
    assert len(out) == len(StepCarry._fields) and torch.equal(out.jibes, torch.ones(2))
    mixed = select(
        np.array([True, False]), StepCarry(*([1, 1],) * 9), StepCarry(*([2, 2],) * 9), np
    )
    assert type(mixed) is StepCarry and all(list(field) == [1, 2] for field in mixed)
    package = Path(bbgym.__file__).parent
    calls = [
        f"{path.relative_to(package)}:{number}"
        for path in sorted(package.rglob("*.py"))
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if "._replace(" in line or "._make(" in line
    ]
    assert calls == [], calls


@pytest.mark.parametrize("env_id", ["BeachballSail-v1", "BeachballThrow-v0", "BeachballTopple-v1"])
@pytest.mark.parametrize("backend", ["numpy", "torch"])
def test_info_keys_keeps_those_infos_with_the_same_values(env_id: str, backend: str) -> None:
    """``info_keys`` keeps the named infos (each with its ``_key`` mask), their values
    those of an env that computes them all; observations and rewards are unchanged."""
    other = {
        "BeachballSail-v1": "distance_to_mark",
        "BeachballThrow-v0": "miss_distance",
        "BeachballTopple-v1": "wall_angle",
    }[env_id]
    keep = ["is_success", other]
    kwargs = {"backend": backend, "max_episode_steps": 3}
    if backend == "torch":
        kwargs["compile"] = False
    runs = []
    for info_keys in (None, keep):
        venv = gym.make_vec(
            env_id,
            num_envs=4,
            vectorization_mode="vector_entry_point",
            info_keys=info_keys,
            **kwargs,
        )
        out = [venv.reset(seed=1)]
        actions = np.random.default_rng(0).uniform(-1, 1, (5, *venv.action_space.shape))
        out += [venv.step(a.astype(np.float32)) for a in actions]
        runs.append(out)
    names = set(task_info_names(venv.unwrapped.task))
    for full, kept in zip(*runs, strict=True):
        info = kept[-1]
        assert {k for k in info if k in names} == set(keep)
        # the host's records (a NumPy throw's trajectory, a wall's state by name) stay
        records = {k for k in full[-1] if k not in names and f"_{k}" in full[-1]}
        assert {k for k in info if k not in names and f"_{k}" in info} == records
        for key in keep:
            np.testing.assert_array_equal(np.asarray(info[key]), np.asarray(full[-1][key]))
            assert info[f"_{key}"].all()
        np.testing.assert_array_equal(kept[0], full[0])  # the observations
    assert any(np.asarray(step[1]).any() for step in runs[1][1:])  # some reward was paid


def test_info_keys_that_are_no_infos_are_named() -> None:
    def make(keys):
        return gym.make_vec(
            "BeachballSail-v1", num_envs=2, vectorization_mode="vector_entry_point", info_keys=keys
        )

    with pytest.raises(ValueError, match=r"info_keys: \['speed'\] are not infos .*is_success"):
        make(["is_success", "speed"])
    with pytest.raises(TypeError, match="info_keys must be a list or tuple"):
        make("is_success")


@pytest.mark.parametrize("env_id", bbgym.spec.env_ids())
def test_the_one_graph_step_equals_its_parts(env_id: str) -> None:
    """``VectorStep.fused`` (what ``step_graph="one"`` compiles: the chunks after the first
    in a ``while_loop``, the restart for every env) gives the parts' results exactly, run
    eagerly over steps with restarts (episodes of 3 steps), float64."""
    from bbgym.envs.functional import VectorStep, tree_leaves

    venv = make_torch(env_id, max_episode_steps=3)
    core = venv.unwrapped
    core.reset(seed=1)
    step = VectorStep(core.task, core.max_episode_steps, core.xp, core.backend.float_dtype)
    state, counter, steps, restarting = core.state, core._counter, core._steps, core._autoreset
    rng = np.random.default_rng(0)
    restarts = 0
    for _ in range(7):
        action = torch.as_tensor(rng.uniform(-1, 1, (N, *core.single_action_space.shape)))
        parts = step(state, action, core._keys, counter, steps, restarting)
        one = step.fused(state, action, core._keys, counter, steps, restarting)
        for a, b in zip(tree_leaves(parts), tree_leaves(one), strict=True):
            if isinstance(a, torch.Tensor):
                assert torch.equal(a, b)
        state, counter, steps = parts[0], parts[6], parts[7]
        restarting = parts[3] | parts[4]
        restarts += int(restarting.sum())
    assert restarts >= N


def test_the_eager_one_graph_runs_tasks_of_different_sizes_in_one_process() -> None:
    """Run eagerly, ``while_loop`` traces its functions itself, where Dynamo makes an int it
    saw change (a task's chunk count: 300, then 60, then 50) symbolic, which the loop cannot
    carry; each task's ints stay its constants (Topple-v2 after v1 failed so)."""
    throw = np.tile(np.array([0.6, 0.0, 0.2, 0.0, 0.0, 0.0], np.float32), (N, 1))
    for env_id, kwargs in (
        ("BeachballTopple-v1", {}),
        ("BeachballTopple-v2", {}),
        ("BeachballTopple-v1", {"interval": 0.5}),
    ):
        venv = make_torch(env_id, step_graph="one", **kwargs)
        venv.reset(seed=0)
        assert np.isfinite(venv.step(throw)[0]).all()


def test_step_graph_is_checked() -> None:
    with pytest.raises(ValueError, match="step_graph must be one of"):
        make_torch("BeachballSail-v1", step_graph="fused")
    with pytest.raises(ValueError, match="step_graph='one' needs backend='torch'"):
        gym.make_vec(
            "BeachballSail-v1",
            num_envs=2,
            vectorization_mode="vector_entry_point",
            step_graph="one",
        )
