"""The conformance kit: one call checks an env family the same way on every backend.

In the spirit of Gymnasium's ``check_env`` and Jumanji's ``testing`` helpers, for a
family's spec rather than one env. :func:`check_family` runs, for each of its ids (or
those asked for):

=========================  =============================================================
``spaces``                 Gymnasium's ``check_env``; observations in the space, float32,
                           of its shape; a float reward, bool ends, a dict info
``determinism``            the same seed and actions give the same episode, and another
                           seed another one
``vector``                 sub-env ``i`` of the native vector env and of Gymnasium's
                           Sync and Async ones equals the single env seeded ``seed + i``,
                           through autoresets (NumPy, float64)
``pickle``                 a pickled env (single and vector) continues identically
``options``                the fuzzer's reset options are accepted; an unknown key and a
                           bad action raise errors that name them
``arguments``              every number argument refuses bad values, naming itself
``fuzz``                   a short random episode of random accepted arguments
``backends``               the step on ``array_api_strict``, torch and JAX, each eager
                           and compiled, equals NumPy's, through autoresets (same keys)
=========================  =============================================================

``python -c "from bbgym.testing import check_family; check_family('sail')"`` checks a
shipped family; the test suite runs it over every registered spec
(``tests/test_conformance.py``). A failed check raises ``AssertionError`` naming the id,
the check and the backend.
"""

from __future__ import annotations

import contextlib
import pickle
import time
from collections.abc import Iterator, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils.env_checker import check_env

from bbgym import backends, fuzz
from bbgym.envs.functional import VectorStep, counter_initial_noise
from bbgym.spec import EnvSpec, register_spec, specs, unregister_spec

CHECKS = ("spaces", "determinism", "vector", "pickle", "options", "arguments", "fuzz", "backends")
"""Every check :func:`check_family` runs, in order."""
BACKENDS = ("array_api_strict", "torch", "torch-compiled", "jax", "jax-compiled")
"""The backends the ``backends`` check compares with NumPy (each where installed)."""


def check_family(
    family: str | EnvSpec,
    *,
    ids: Sequence[str] | None = None,
    checks: Sequence[str] = CHECKS,
    backends_: Sequence[str] = BACKENDS,
    steps: int = 40,
    num_envs: int = 3,
    seed: int = 0,
) -> list[str]:
    """Check an env family (see the module docstring).

    Args:
        family: a registered family's name (``"sail"``) or its spec; a spec that is not
            registered is registered for the checks and removed after.
        ids: which of its ids (default: every version).
        checks: which checks (:data:`CHECKS`).
        backends_: which backends the ``backends`` check compares with NumPy
            (:data:`BACKENDS`); one not installed is skipped and reported.
        steps: steps per episode rollout.
        num_envs: the vector envs' size.
        seed: the seed of the envs and of the actions.

    Returns:
        One line per check run (``"<id> vector: ok in 1.2 s"``), and per
        backend skipped.

    Raises:
        AssertionError: naming the id, the check and the backend that failed.
        ValueError: for an unknown check or backend.
    """
    unknown = [c for c in checks if c not in CHECKS] + [b for b in backends_ if b not in BACKENDS]
    if unknown:
        raise ValueError(f"unknown checks or backends: {unknown}; known: {CHECKS}, {BACKENDS}")
    report: list[str] = []
    with _registered(family) as spec:
        for env_id in ids or spec.ids:
            for check in checks:
                if check == "backends":
                    for backend in backends_:
                        start = time.perf_counter()
                        line = _check_backend(env_id, backend, steps, num_envs, seed)
                        report.append(f"{line} in {time.perf_counter() - start:.1f} s")
                    continue
                start = time.perf_counter()
                _CHECKS[check](env_id, steps, num_envs, seed)
                report.append(f"{env_id} {check}: ok in {time.perf_counter() - start:.1f} s")
    return report


@contextlib.contextmanager
def _registered(family: str | EnvSpec) -> Iterator[EnvSpec]:
    """The family's spec, registered for the block (and removed after if it was not)."""
    if isinstance(family, str):
        yield next(s for s in specs() if s.family == family)
        return
    known = any(s is family for s in specs())
    if not known:
        register_spec(family)
    try:
        yield family
    finally:
        if not known:
            unregister_spec(family.family)


def _actions(env_id: str, steps: int, num_envs: int, seed: int) -> np.ndarray:
    """Seeded random actions ``(steps, num_envs, size)`` in the action box."""
    env = gym.make(env_id)
    shape = env.action_space.shape
    env.close()
    return np.random.default_rng(seed).uniform(-1.0, 1.0, (steps, num_envs, *shape))


def _rollout_single(env: gym.Env, seed: int, actions: np.ndarray) -> list[tuple]:
    """(obs, reward, terminated, truncated) per step, next-step resets as a vector env
    makes them (the step after an end returns the reset's observation, reward 0)."""
    obs, _ = env.reset(seed=seed)
    out, done = [(obs, 0.0, False, False)], False
    for a in actions:
        if done:
            obs, _ = env.reset()
            out.append((obs, 0.0, False, False))
            done = False
            continue
        obs, reward, terminated, truncated, _ = env.step(a.astype(np.float32))
        out.append((obs, float(reward), bool(terminated), bool(truncated)))
        done = terminated or truncated
    return out


def _rollout_vector(env: Any, seed: int, actions: np.ndarray) -> list[tuple]:
    """:func:`_rollout_single` for a vector env (its autoreset makes the restarts)."""
    obs, _ = env.reset(seed=seed)
    start = np.zeros(env.num_envs, bool)
    out = [(_np(obs), np.zeros(env.num_envs), start, start)]
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a.astype(np.float32))
        out.append((_np(obs), _np(reward), _np(terminated), _np(truncated)))
    return out


def _np(x: Any) -> np.ndarray:
    return np.asarray(backends.to_numpy(x))


def _check_spaces(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    env = gym.make(env_id)
    check_env(env.unwrapped, skip_render_check=True)
    obs, info = env.reset(seed=seed)
    for a in _actions(env_id, steps, 1, seed)[:, 0]:
        assert obs in env.observation_space, f"{env_id} spaces: {obs} outside the space"
        assert obs.dtype == np.float32 and obs.shape == env.observation_space.shape, env_id
        assert isinstance(info, dict), f"{env_id} spaces: info is {type(info)}"
        obs, reward, terminated, truncated, info = env.step(a.astype(np.float32))
        assert isinstance(reward, float) and np.isfinite(reward), f"{env_id}: reward {reward!r}"
        assert isinstance(terminated, bool) and isinstance(truncated, bool), env_id
        if terminated or truncated:
            obs, info = env.reset()
    env.close()


def _check_determinism(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    actions = _actions(env_id, steps, 1, seed)[:, 0]
    runs = [_rollout_single(gym.make(env_id), s, actions) for s in (seed, seed, seed + 1)]
    for t, (a, b) in enumerate(zip(*runs[:2], strict=True)):
        np.testing.assert_array_equal(a[0], b[0], err_msg=f"{env_id} determinism: step {t}")
        assert a[1:] == b[1:], f"{env_id} determinism: step {t}: {a[1:]} != {b[1:]}"
    observed = [np.array([step[0] for step in run]) for run in (runs[0], runs[2])]
    assert not np.array_equal(*observed), f"{env_id} determinism: seed {seed + 1} is seed {seed}"


def _check_vector(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    actions = _actions(env_id, steps, num_envs, seed)
    singles = [_rollout_single(gym.make(env_id), seed + i, actions[:, i]) for i in range(num_envs)]
    for mode in ("vector_entry_point", "sync", "async"):
        vec = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode=mode)
        batch = _rollout_vector(vec, seed, actions)
        vec.close()
        for i, single in enumerate(singles):
            for t, (one, many) in enumerate(zip(single, batch, strict=True)):
                where = f"{env_id} vector ({mode}): sub-env {i} step {t}"
                np.testing.assert_allclose(one[0], many[0][i], 1e-6, 1e-6, err_msg=where)
                np.testing.assert_allclose(one[1], many[1][i], 1e-6, 1e-9, err_msg=where)
                assert (one[2], one[3]) == (bool(many[2][i]), bool(many[3][i])), where


def _check_pickle(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    actions = _actions(env_id, 2 * steps, num_envs, seed)
    for env in (
        gym.make(env_id),
        gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point"),
    ):
        vector = isinstance(env, gym.vector.VectorEnv)
        env.reset(seed=seed)
        for a in actions[:steps]:
            _, _, terminated, truncated, _ = env.step(a if vector else a[0])
            if not vector and (terminated or truncated):
                env.reset()
        clone = pickle.loads(pickle.dumps(env))
        for t, a in enumerate(actions[steps:]):
            one, two = env.step(a if vector else a[0]), clone.step(a if vector else a[0])
            np.testing.assert_array_equal(one[0], two[0], err_msg=f"{env_id} pickle: step {t}")
            if not vector and (one[2] or one[3]):
                np.testing.assert_array_equal(env.reset()[0], clone.reset()[0])
        env.close()


def _check_options(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    env = gym.make(env_id)
    draw = fuzz.numpy_draw(np.random.default_rng(seed))
    options = fuzz.sample_options(env_id, env.unwrapped, draw)
    obs, _ = env.reset(seed=seed, options=options)
    assert obs in env.observation_space, f"{env_id} options: {options} gave {obs}"
    try:
        env.reset(options={"no_such_option": 1.0})
    except TypeError as error:
        assert "no_such_option" in str(error), f"{env_id} options: {error} names no key"
    else:
        raise AssertionError(f"{env_id} options: an unknown key was accepted")
    bad = np.full(env.action_space.shape, np.nan, dtype=np.float32)
    try:
        env.step(bad)
    except ValueError as error:
        assert "action" in str(error), f"{env_id} options: {error} does not name the action"
    else:
        raise AssertionError(f"{env_id} options: a NaN action was accepted")
    env.close()


def _check_arguments(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    expected = len(fuzz.numeric_arguments(env_id)) * len(fuzz.BAD_NUMBERS)
    checked = fuzz.check_rejections(env_id)
    assert checked == expected, f"{env_id} arguments: {checked} refusals checked of {expected}"


def _check_fuzz(env_id: str, steps: int, num_envs: int, seed: int) -> None:
    draw = fuzz.numpy_draw(np.random.default_rng(seed))
    kwargs = fuzz.sample_kwargs(env_id, draw)
    probe = gym.make(env_id, **kwargs)
    options = fuzz.sample_options(env_id, probe.unwrapped, draw)
    probe.close()
    for n in (0, num_envs):
        fuzz.check_episode(env_id, kwargs, options, steps, seed, n)


def _keyed_rollout(
    env_id: str,
    xp: Any,
    dtype: Any,
    seed: int,
    actions: np.ndarray,
    max_episode_steps: int | None = None,
    parts: bool = False,
    with_state: bool = False,
) -> list:
    """The vector step run as pure functions on namespace ``xp`` (what the torch backend
    compiles), from the counter-based keys: (obs, reward, terminated, truncated) per step,
    and the state after it where ``with_state``. A ``"generator"`` task on NumPy draws from
    its generators; this is how its torch and JAX backends are checked against NumPy.
    ``parts`` runs the step's parts (as the compiled backends do) rather than a host
    transition, which a task may fly its own way (the same physics, other rounding)."""
    num_envs = actions.shape[1]
    vec = gym.make_vec(env_id, num_envs=1, vectorization_mode="vector_entry_point")
    task, max_steps = vec.unwrapped.task, vec.unwrapped.max_episode_steps
    vec.close()
    step = VectorStep(task, max_episode_steps or max_steps, xp, dtype)
    step_parts = (step.begin, step.chunk, step.end, step.restart, step.observe) if parts else None

    def to_xp(x: np.ndarray) -> Any:
        return xp.asarray(x)

    keys = to_xp(np.array([backends.env_keys(seed + i, 1, np)[0] for i in range(num_envs)]))
    counter = to_xp(np.zeros(num_envs, dtype=np.int64))
    state = task.initial(counter_initial_noise(task, keys, counter, dtype, xp), {}, xp)
    counter = counter + 1
    steps = to_xp(np.zeros(num_envs, dtype=np.int64))
    restarting = to_xp(np.zeros(num_envs, dtype=bool))
    out = []
    for a in actions:
        state, obs, reward, term, trunc, _, counter, steps = step(
            state, xp.asarray(a, dtype=dtype), keys, counter, steps, restarting, step_parts
        )
        restarting = term | trunc
        out.append(tuple(_np(x) for x in (obs, reward, term, trunc)))
        if with_state:
            out[-1] += (state,)
    return out


def _check_backend(env_id: str, backend: str, steps: int, num_envs: int, seed: int) -> str:
    """One backend's steps against NumPy's (the same functions on NumPy, same keys)."""
    where = f"{env_id} backends ({backend})"
    actions = _actions(env_id, steps, num_envs, seed)
    try:
        if backend == "array_api_strict":
            import array_api_strict as xp

            dtype: Any = xp.float64
        else:
            __import__(backend.split("-")[0])
    except ImportError:
        return f"{where}: skipped, not installed"
    reference = _keyed_rollout(env_id, np, np.float64, seed, actions)
    if backend == "array_api_strict":
        got = _keyed_rollout(env_id, xp, dtype, seed, actions)
    else:
        vec = gym.make_vec(
            env_id,
            num_envs=num_envs,
            vectorization_mode="vector_entry_point",
            backend=backend.split("-")[0],
            dtype="float64",
            compile=backend.endswith("-compiled"),
        )
        got = _rollout_vector(vec, seed, actions)[1:]
        vec.close()
    # Rounding differs (a fused kernel, another libm); a trajectory that takes another
    # branch (a ball just touching the ground) would show as a large difference.
    for t, (ref, out) in enumerate(zip(reference, got, strict=True)):
        for name, a, b in zip(("obs", "reward", "terminated", "truncated"), ref, out, strict=True):
            if a.dtype == bool:
                assert np.array_equal(a, b), f"{where}: {name} at step {t}: {b} != {a}"
            else:
                np.testing.assert_allclose(
                    b, a, rtol=1e-5, atol=1e-6, err_msg=f"{where}: {name} at step {t}"
                )
    return f"{where}: ok"


_CHECKS = {
    "spaces": _check_spaces,
    "determinism": _check_determinism,
    "vector": _check_vector,
    "pickle": _check_pickle,
    "options": _check_options,
    "arguments": _check_arguments,
    "fuzz": _check_fuzz,
}

__all__ = ["BACKENDS", "CHECKS", "check_family"]
