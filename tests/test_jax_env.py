"""The gymnax-style interface (:mod:`bbgym.jax_env`): an episode equals the Gymnasium id's
(sub-env ``i`` of the vector env), under ``jit``, ``vmap`` and ``lax.scan`` and in a
PureJaxRL-style rollout; params batch under ``vmap`` and each traced value steps as a task
built with it; concrete params are checked by name."""

from __future__ import annotations

import numpy as np
import pytest

from bbgym import testing
from bbgym.spec import specs

jax = pytest.importorskip("jax")
jnp = pytest.importorskip("jax.numpy")
jax_env = pytest.importorskip("bbgym.jax_env")

SEED, NUM_ENVS, STEPS, EPISODE_STEPS = 3, 3, 16, 5
TRAINED_IDS = ("BeachballSail-v1", "BeachballThrow-v1")
NEWEST = tuple(s.ids[-1] for s in specs())


@pytest.mark.parametrize("env_id", sorted(set(TRAINED_IDS + NEWEST)))
def test_an_episode_is_the_vector_envs_sub_env_without_its_restart_steps(env_id):
    """Same observations, rewards and ends as the Gymnasium id's vector step (NumPy,
    float64, the same keys) to float32's rounding: the vector env spends a step on each
    restart, this env restarts on the step that ends an episode."""
    env = jax_env.JaxEnv(env_id)
    params = env.default_params._replace(max_steps_in_episode=EPISODE_STEPS)
    probe_shape = (STEPS, NUM_ENVS, env.num_actions)
    actions = np.random.default_rng(SEED).uniform(-1, 1, size=probe_shape)
    reference = testing._keyed_rollout(env_id, np, np.float64, SEED, actions, EPISODE_STEPS)
    reset, step = jax.jit(env.reset_from_key), jax.jit(env.step)
    keys = jax_env.vector_keys(SEED, NUM_ENVS)
    key = jax.random.PRNGKey(0)
    for i in range(NUM_ENVS):
        _, state = reset(keys[i], params)
        restarting, ends = False, 0
        for t in range(STEPS):
            ref_obs, ref_reward, ref_term, ref_trunc = (row[i] for row in reference[t])
            if restarting:  # the vector env's restart step: done here on the step before
                restarting = False
                continue
            obs, state, reward, done, info = step(key, state, actions[t, i], params)
            where = f"{env_id} env {i} step {t}"
            assert abs(float(reward) - ref_reward) <= 1e-4 * max(1.0, abs(ref_reward)), where
            assert bool(info["terminated"]) == ref_term and bool(info["truncated"]) == ref_trunc
            assert bool(done) == (ref_term or ref_trunc), where
            if done:  # the next episode's first observation: the vector env's next one
                ends += 1
                restarting = True
                np.testing.assert_allclose(obs, reference[t + 1][0][i], atol=2e-4, err_msg=where)
            else:
                np.testing.assert_allclose(obs, ref_obs, atol=2e-4, err_msg=where)
        assert ends >= 2, f"{env_id} env {i}: the rollout should cross autoresets"


def test_a_purejaxrl_style_rollout_under_jit_vmap_and_scan():
    """Envs vmapped, steps scanned, the whole rollout one jitted function: the same
    result as stepping the jitted step in a Python loop."""
    env, params = jax_env.make("BeachballThrow-v1")
    num_envs, steps = 8, 12

    def rollout(key):
        reset_keys = jax.random.split(key, num_envs)
        obs, state = jax.vmap(env.reset, in_axes=(0, None))(reset_keys, params)

        def one_step(carry, key):
            obs, state = carry
            action_keys = jax.random.split(key, num_envs)
            actions = jax.vmap(lambda k: env.action_space(params).sample(k))(action_keys)
            obs, state, reward, done, info = jax.vmap(env.step, in_axes=(0, 0, 0, None))(
                action_keys, state, actions, params
            )
            return (obs, state), (reward, done, actions)

        _, (rewards, dones, actions) = jax.lax.scan(
            one_step, (obs, state), jax.random.split(key, steps)
        )
        return rewards, dones, actions

    rewards, dones, actions = jax.jit(rollout)(jax.random.PRNGKey(7))
    assert rewards.shape == dones.shape == (steps, num_envs)
    assert np.all(np.isfinite(rewards)) and int(dones.sum()) >= num_envs
    # the same steps one by one
    reset_keys = jax.random.split(jax.random.PRNGKey(7), num_envs)
    _, state = jax.vmap(env.reset, in_axes=(0, None))(reset_keys, params)
    step = jax.jit(jax.vmap(env.step, in_axes=(0, 0, 0, None)))
    for t in range(steps):
        _, state, reward, done, _ = step(reset_keys, state, actions[t], params)
        np.testing.assert_allclose(reward, rewards[t], rtol=1e-6, atol=1e-6)
        assert np.array_equal(done, dones[t])


@pytest.mark.parametrize("env_id", NEWEST)
def test_each_varying_argument_traced_steps_as_a_task_built_with_it(env_id):
    """Domain randomization: params batched under vmap, each env's value of every varying
    argument (its spec's ``jax_params``) changed by a tenth; each env then steps as the
    env made with that value (``JaxEnv(id, **that)``), and differs from the default."""
    env, params = jax_env.make(env_id)
    flat = jax_env.JaxEnv._flat(params.arguments)
    assert set(flat) == set(env.varying) and env.varying
    key = jax.random.PRNGKey(0)
    steps = 6
    for path, value in flat.items():
        changed = tuple(v * 1.1 for v in value) if isinstance(value, tuple) else value * 1.1
        custom = jax_env._merge(params.arguments, jax_env._nest({path: changed}))
        batched = jax.tree.map(lambda *xs: jnp.stack(xs), params.arguments, custom)
        both = jax_env.EnvParams(params.max_steps_in_episode, batched)
        env.check_params(both)
        in_axes = jax_env.EnvParams(None, 0)
        _, state = jax.vmap(env.reset, in_axes=(None, in_axes))(key, both)
        step = jax.jit(jax.vmap(env.step, in_axes=(None, 0, None, in_axes)))
        # the whole parameter group, as the task has it, with the one field changed
        built_kwargs = jax_env._merge(env._base_arguments(), jax_env._nest({path: changed}))
        built, built_params = jax_env.make(env_id, vary=(), **built_kwargs)
        _, built_state = jax.jit(built.reset)(key, built_params)
        built_step = jax.jit(built.step)
        rewards, built_rewards, observations = [], [], []
        for t in range(steps):
            action = jnp.full(env.num_actions, 0.5 * np.sin(t))
            obs, state, reward, _, _ = step(key, state, action, both)
            observations.append(np.asarray(obs))
            _, built_state, built_reward, _, _ = built_step(key, built_state, action, built_params)
            rewards.append(np.asarray(reward))
            built_rewards.append(float(built_reward))
        rewards = np.array(rewards)
        np.testing.assert_allclose(rewards[:, 1], built_rewards, rtol=1e-5, atol=1e-5)
        traced_state = jax.tree.map(lambda x: x[1], state)
        for a, b in zip(jax.tree.leaves(traced_state), jax.tree.leaves(built_state), strict=True):
            # float32: a constant folded at compile time rounds unlike the traced one
            np.testing.assert_allclose(np.asarray(a, float), np.asarray(b, float), 1e-4, 1e-6)
        moved = [
            not np.allclose(np.asarray(a)[:, 0], np.asarray(a)[:, 1])
            for a in [rewards, np.array(observations)]
        ]
        moved += [
            not np.allclose(np.asarray(a)[0], np.asarray(a)[1]) for a in jax.tree.leaves(state.task)
        ]
        assert any(moved), f"{env_id}: {path} changed nothing"


def test_concrete_params_are_checked_naming_the_argument_and_the_entry():
    env, params = jax_env.make("BeachballSail-v1")
    masses = jnp.array([135.0, -1.0])
    batched = params._replace(
        arguments=jax_env._merge(params.arguments, {"dinghy": {"mass_kg": masses}})
    )
    with pytest.raises(ValueError, match=r"dinghy\.mass_kg must be in .*batch entry 1"):
        env.check_params(batched)
    with pytest.raises(TypeError, match="do not vary"):
        env.check_params(params._replace(arguments={"mark_radius": 3.0}))
    with pytest.raises(ValueError, match="max_steps_in_episode"):
        env.check_params(params._replace(max_steps_in_episode=0))
    assert env.check_params(params) is params


def test_spaces_and_dtypes():
    env, params = jax_env.make("BeachballSail-v2")
    space = env.action_space(params)
    assert space.shape == (env.num_actions,) and env.num_actions == 3
    sample = space.sample(jax.random.PRNGKey(0))
    assert bool(space.contains(sample)) and not bool(space.contains(sample + 3.0))
    obs, state = env.reset(jax.random.PRNGKey(0), params)
    assert obs.shape == env.observation_space(params).shape and obs.dtype == jnp.float32
    assert bool(env.observation_space(params).contains(obs))
    with pytest.raises(ValueError, match="dtype='float64' needs jax_enable_x64"):
        jax_env.JaxEnv("BeachballSail-v2", dtype="float64").reset(jax.random.PRNGKey(0))
    with pytest.raises(ValueError, match="dtype must be one of"):
        jax_env.JaxEnv("BeachballSail-v2", dtype="float16")
