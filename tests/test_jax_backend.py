"""The JAX backend of the native vector envs (``backend="jax"``): every id's jitted step
equals the same functions on NumPy (float64, the counter-based draws) to 1e-9 through
autoresets, float32 stays within stated tolerances, the random bits need no
``jax_enable_x64``, and the keywords, outputs and actions behave as on torch."""

from __future__ import annotations

import subprocess
import sys

import gymnasium as gym
import numpy as np
import pytest

import bbgym  # noqa: F401 (registers the ids)
from bbgym import backends, testing
from bbgym.envs.functional import tree_leaves
from bbgym.spec import env_ids, specs

jax = pytest.importorskip("jax")
jnp = pytest.importorskip("jax.numpy")

STEPS, NUM_ENVS, EPISODE_STEPS, SEED = 14, 3, 6, 5
"""Short episodes (a time limit of 6 steps) so that every env restarts twice."""


def _actions(env_id: str) -> np.ndarray:
    probe = gym.make_vec(env_id, num_envs=NUM_ENVS, vectorization_mode="vector_entry_point")
    shape = probe.action_space.shape
    probe.close()
    return np.random.default_rng(SEED).uniform(-1.0, 1.0, size=(STEPS, *shape))


def _numpy_rollout(env_id: str, actions: np.ndarray) -> list[tuple]:
    """The vector step's parts run on NumPy float64 from the counter-based keys: what the
    torch and JAX backends compile. Per step: (state leaves, obs, reward, terminated,
    truncated)."""
    rows = testing._keyed_rollout(
        env_id, np, np.float64, SEED, actions, EPISODE_STEPS, parts=True, with_state=True
    )
    return [(_leaves(state), *row) for *row, state in rows]


def _leaves(state) -> list[np.ndarray]:
    return [np.asarray(backends.to_numpy(x), dtype=float) for x in tree_leaves(state)]


def _jax_vec(env_id: str, num_envs: int = NUM_ENVS, **kwargs) -> gym.vector.VectorEnv:
    return gym.make_vec(
        env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", backend="jax", **kwargs
    )


def _jax_rollout(env_id: str, actions: np.ndarray, dtype: str) -> list[tuple]:
    vec = _jax_vec(env_id, dtype=dtype, max_episode_steps=EPISODE_STEPS)
    vec.reset(seed=SEED)
    out = []
    for a in actions:
        obs, reward, term, trunc, _ = vec.step(a)
        out.append((_leaves(vec.unwrapped.state), obs, reward, term, trunc))
    vec.close()
    return out


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    """The largest difference relative to max(1, |b|); equal values (infinities too) 0."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    with np.errstate(invalid="ignore"):
        gap = np.where(a == b, 0.0, np.abs(a - b) / np.maximum(1.0, np.abs(b)))
    return float(np.max(np.where(np.isnan(gap), np.inf, gap), initial=0.0))


@pytest.mark.parametrize("env_id", env_ids())
def test_every_id_steps_as_numpy_does_to_1e9_in_float64(env_id):
    """The whole jitted step (draws, transition and its rolled loop, autoreset,
    observation, reward, ends) against NumPy: every state leaf and reward to 1e-9
    relative (measured: at most about 1e-13), the ends exactly, through two autoresets."""
    actions = _actions(env_id)
    reference = _numpy_rollout(env_id, actions)
    got = _jax_rollout(env_id, actions, "float64")
    restarts = 0
    for t, ((ref_leaves, *ref), (leaves, *out)) in enumerate(zip(reference, got, strict=True)):
        worst = max(_relative(a, b) for a, b in zip(leaves, ref_leaves, strict=True))
        assert worst < 1e-9, f"{env_id}: state at step {t} differs by {worst:.1e}"
        np.testing.assert_allclose(out[0], ref[0], atol=1e-6, err_msg=f"{env_id} obs, step {t}")
        assert _relative(out[1], ref[1]) < 1e-9, f"{env_id}: reward at step {t}"
        assert np.array_equal(out[2], ref[2]) and np.array_equal(out[3], ref[3]), (env_id, t)
        restarts += int(np.sum(ref[2] | ref[3]))
    assert restarts >= NUM_ENVS, f"{env_id}: the rollout should cross autoresets"


FLOAT32_TOLERANCE = {"obs": 2e-4, "reward": 1e-4}
"""float32 against float64 NumPy over the rollout above (absolute on observations in
[-1, 1], relative on rewards; measured at most 5e-5 and 1e-5 over 60 steps)."""


@pytest.mark.parametrize("family", [s.family for s in specs()])
def test_float32_stays_within_its_tolerances(family):
    env_id = next(s for s in specs() if s.family == family).ids[-1]
    actions = _actions(env_id)
    reference = _numpy_rollout(env_id, actions)
    got = _jax_rollout(env_id, actions, "float32")
    for t, ((_, *ref), (_, *out)) in enumerate(zip(reference, got, strict=True)):
        np.testing.assert_allclose(
            out[0], ref[0], atol=FLOAT32_TOLERANCE["obs"], err_msg=f"{env_id} obs, step {t}"
        )
        assert _relative(out[1], ref[1]) < FLOAT32_TOLERANCE["reward"], (env_id, t)


def test_the_counter_hash_gives_the_same_bits_in_uint32_without_x64():
    """JAX holds the keys as uint32 and needs no 64-bit types: the same uniform bits as
    NumPy's int64 arithmetic (float32 and, under the x64 context, float64), the normals to
    the rounding of log and cos."""
    assert not jax.config.jax_enable_x64
    keys = backends.env_keys(11, 64, np)
    counter = np.arange(64, dtype=np.int64) * 7
    xp32 = backends.jax_namespace(False)
    jkeys, jcounter = jnp.asarray(keys.astype(np.uint32)), jnp.asarray(counter.astype(np.uint32))
    for stream in (0, 1, 4):
        u_np = backends.uniforms(keys, counter, stream, 5, np.float32, np)
        u_jax = jax.jit(lambda k, c, s=stream: backends.uniforms(k, c, s, 5, xp32.float32, xp32))(
            jkeys, jcounter
        )
        for a, b in zip(u_np, u_jax, strict=True):
            assert np.array_equal(np.asarray(b), a)
        n_np = backends.normals(keys, counter, stream, 3, np.float32, np)
        n_jax = backends.normals(jkeys, jcounter, stream, 3, xp32.float32, xp32)
        for a, b in zip(n_np, n_jax, strict=True):
            np.testing.assert_allclose(np.asarray(b), a, rtol=2e-6, atol=2e-6)
    with backends.jax_x64(True):
        xp64 = backends.jax_namespace(True)
        u64 = backends.uniforms(jkeys, jcounter, 4, 3, xp64.float64, xp64)
        for a, b in zip(backends.uniforms(keys, counter, 4, 3, np.float64, np), u64, strict=True):
            assert np.array_equal(np.asarray(b), a)
    assert not jax.config.jax_enable_x64


def test_float64_leaves_the_processes_x64_setting_alone_and_float32_uses_no_64_bit_type():
    assert not jax.config.jax_enable_x64
    vec = _jax_vec("BeachballThrow-v1", 2)
    vec.reset(seed=0)
    vec.step(np.zeros(vec.action_space.shape))
    assert not jax.config.jax_enable_x64
    assert {str(x.dtype) for x in tree_leaves(vec.unwrapped.state)} >= {"float64"}
    vec32 = _jax_vec("BeachballThrow-v1", 2, dtype="float32")
    vec32.reset(seed=0)
    vec32.step(np.zeros(vec32.action_space.shape))
    kinds = {str(x.dtype) for x in tree_leaves(vec32.unwrapped.state)}
    kinds |= {str(vec32.unwrapped._keys.dtype), str(vec32.unwrapped._counter.dtype)}
    assert not any("64" in kind for kind in kinds), kinds


def test_jax_outputs_and_actions_and_the_errors_that_name_their_argument():
    vec = _jax_vec("BeachballSail-v2", 4, dtype="float32", output="jax")
    obs, info = vec.reset(seed=1)
    assert isinstance(obs, jax.Array) and obs.shape == (4, vec.single_observation_space.shape[0])
    actions = jnp.zeros(vec.action_space.shape, dtype=jnp.float32)
    obs, reward, terminated, truncated, info = vec.step(actions)
    assert all(isinstance(x, jax.Array) for x in (obs, reward, terminated, truncated))
    bad = actions.at[2, 0].set(jnp.nan)
    with pytest.raises(ValueError, match=r"rows \[2\] hold NaN"):
        vec.step(bad)
    with pytest.raises(ValueError, match="actions must have shape"):
        vec.step(jnp.zeros((3, 2)))
    with pytest.raises(ValueError, match="step_graph='parts' needs backend='torch'"):
        backends.resolve_backend("jax", step_graph="parts")
    with pytest.raises(ValueError, match="output='torch' needs backend='torch'"):
        backends.resolve_backend("jax", output="torch")
    with pytest.raises(ValueError, match="output='jax' needs backend='jax'"):
        backends.resolve_backend("numpy", output="jax")
    with pytest.raises(ValueError, match="device must be 'cpu' or 'cuda'"):
        backends.resolve_backend("jax", device="tpu")
    with pytest.raises(ValueError, match="jax finds no such device"):
        backends.resolve_backend("jax", device="cuda:7")


def test_the_race_fleet_sails_on_jax_as_on_numpy():
    from bbgym.envs.race.fleet import BeachballRaceFleetEnv

    rewards = {}
    for kwargs in ({}, {"backend": "jax"}):
        env = BeachballRaceFleetEnv(2, **kwargs)
        env.reset(seed=3)
        rng = np.random.default_rng(0)
        got = []
        for _ in range(30):
            obs, reward, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
            got.append((obs, reward, _leaves(env.state)))
        rewards[bool(kwargs)] = got
    for (obs, reward, leaves), (obs_ref, reward_ref, ref) in zip(
        rewards[True], rewards[False], strict=True
    ):
        assert max(_relative(a, b) for a, b in zip(leaves, ref, strict=True)) < 1e-9
        assert _relative(reward, reward_ref) < 1e-9
        np.testing.assert_allclose(obs, obs_ref, atol=1e-6)


def test_jax_is_imported_only_when_asked_for():
    code = (
        "import sys, gymnasium as gym, bbgym\n"
        "v = gym.make_vec('BeachballSail-v2', num_envs=2,\n"
        "                 vectorization_mode='vector_entry_point')\n"
        "v.reset(seed=0); v.step(v.action_space.sample())\n"
        "assert 'jax' not in sys.modules, 'jax was imported'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_a_missing_jax_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "jax", None)
    with pytest.raises(ImportError, match="the 'jax' extra"):
        backends.resolve_backend("jax")


def test_the_first_step_says_it_compiles_for_jax(capsys, monkeypatch):
    monkeypatch.delenv(backends.QUIET_VARIABLE, raising=False)
    vec = _jax_vec("BeachballCurve-v2", 7, dtype="float32")
    vec.reset(seed=0)
    vec.step(np.zeros(vec.action_space.shape))
    err = capsys.readouterr().err
    assert "compiling the BeachballCurve-v2 step for jax (cpu, float32, batch 7)" in err
    assert "compiled the BeachballCurve-v2 step in" in err


def test_a_gpu_step_equals_the_cpu_step():
    """Runs where JAX finds a GPU (a lent machine); skipped elsewhere."""
    try:
        jax.devices("gpu")
    except RuntimeError:
        pytest.skip("no GPU for JAX on this machine")
    actions = _actions("BeachballSail-v2")
    runs = []
    for device in ("cpu", "cuda"):
        vec = _jax_vec("BeachballSail-v2", device=device)
        vec.reset(seed=SEED)
        runs.append([vec.step(a)[1] for a in actions])
    for a, b in zip(*runs, strict=True):
        assert _relative(a, b) < 1e-9
