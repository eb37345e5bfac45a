"""Train PPO on BeachballThrow-v1 inside one jax.jit program: five seeds at once.

    pip install -e ".[rejax]"
    python docs/examples/rejax_ppo.py

The env (bbgym.jax_env, gymnax's interface) and rejax's PPO compile together: collecting,
learning and evaluating run with no Python between steps, and jax.vmap trains the seeds
side by side. `bbgym train --engine rejax` does the same from a preset and saves the policy.
"""

import time

import jax
import rejax

from bbgym import jax_env


def main(total_timesteps: int = 500_000, seeds: int = 5) -> jax.Array:
    env, params = jax_env.make("BeachballThrow-v1", vary=())  # every argument a constant
    algo = rejax.PPO.create(
        env=env,
        env_params=params,
        total_timesteps=total_timesteps,
        eval_freq=total_timesteps // 5,
        num_envs=256,
        num_steps=16,
        num_epochs=8,
        num_minibatches=4,
        learning_rate=1e-3,
        gamma=0.95,
        ent_coef=0.0,
        max_grad_norm=0.5,
        agent_kwargs={"hidden_layer_sizes": (128, 128), "activation": "tanh"},
    )
    train = jax.jit(jax.vmap(algo.train))  # one program: every seed, every step
    keys = jax.random.split(jax.random.PRNGKey(0), seeds)
    start = time.perf_counter()
    _, (lengths, returns) = jax.block_until_ready(train(keys))
    # rejax evaluates its (sampling) policy on 128 episodes at each eval_freq.
    print(f"{seeds} seeds x {total_timesteps} throws in {time.perf_counter() - start:.0f} s")
    print("mean return by seed, at each evaluation:")
    print(returns.mean(axis=-1).round(2))
    return returns


if __name__ == "__main__":
    main()
