"""Training inside one JAX program (``--engine rejax``, :mod:`bbgym.rejax`): the exported
NumPy policy acts as the learner's deterministic policy; a two-seed program writes each
seed's run folder; its in-program evaluations are the Gymnasium env's episodes for the
evaluation seeds, played by the exported policy; the settings are checked by name."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("jax")
pytest.importorskip("rejax")

import jax  # noqa: E402

from bbgym import rejax as bbgym_rejax  # noqa: E402
from bbgym.cli import UsageError  # noqa: E402
from bbgym.cli.train import train_rejax  # noqa: E402
from bbgym.config import REJAX_DEFAULTS, load_rejax  # noqa: E402
from bbgym.mlp_policy import MLPPolicy  # noqa: E402

ENV_ID = "BeachballThrow-v1"
EPISODES = 6
TINY_PPO = {
    "algo": "ppo",
    "total_timesteps": 1024,
    "eval_every_timesteps": 512,
    "eval_episodes": EPISODES,
    "num_envs": 16,
    "num_steps": 16,
    "num_epochs": 2,
    "num_minibatches": 2,
    "learning_rate": 0.003,
    "agent_kwargs": {"hidden_layer_sizes": [16, 16], "activation": "tanh"},
}


def _preset(tmp_path, section: dict) -> str:
    """A preset file for ``ENV_ID`` whose ``rejax`` section is ``section``."""
    import yaml

    path = tmp_path / "tiny.yaml"
    path.write_text(yaml.safe_dump({"env_id": ENV_ID, "env": {}, "rejax": section}))
    return str(path)


@pytest.mark.parametrize(
    ("algo", "env_id", "extra"),
    [
        ("sac", "BeachballSail-v1", {"hidden_layer_sizes": [8, 8]}),
        ("ppo", ENV_ID, {"agent_kwargs": {"hidden_layer_sizes": [8], "activation": "tanh"}}),
        ("ppo", ENV_ID, {"normalize_observations": True}),
    ],
)
def test_the_exported_policy_is_the_learners_deterministic_action(algo, env_id, extra):
    """SAC's squashed mean and PPO's clipped mean, with and without the observation
    normalizer, through a file: NumPy float64 against the JAX network to float32's
    rounding."""
    settings = {**REJAX_DEFAULTS, "algo": algo, "total_timesteps": 64, **extra}
    algo_ = bbgym_rejax.make_algorithm(env_id, settings)
    state = algo_.init_state(jax.random.PRNGKey(1))
    size = algo_.obs_space.shape[0]
    rng = np.random.default_rng(0)
    if extra.get("normalize_observations"):
        rms = state.obs_rms_state.replace(
            mean=rng.normal(size=size).astype(np.float32),
            var=rng.uniform(0.2, 3.0, size=size).astype(np.float32),
        )
        state = state.replace(obs_rms_state=rms)
    # Inputs large enough to push some actions into the squash's and the clip's bounds.
    obs = rng.uniform(-1, 1, size=(32, size)).astype(np.float32) * 30.0
    expected = np.stack(
        [np.asarray(bbgym_rejax.deterministic_action(algo_, state)(o)) for o in obs]
    )
    policy = bbgym_rejax.export_policy(algo_, state, {"algo": algo})
    assert policy.squash == (algo == "sac")
    assert (policy.obs_mean is not None) == bool(extra.get("normalize_observations"))
    assert np.abs(expected).max() > 0.5  # a real action, not all zeros
    np.testing.assert_allclose(policy(obs), expected, atol=2e-5)
    np.testing.assert_allclose(policy(obs[3]), expected[3], atol=2e-5)  # one observation
    path = _tmp_file(algo, extra)
    policy.save(path)
    loaded = MLPPolicy.load(path)
    np.testing.assert_array_equal(loaded(obs), policy(obs))
    assert loaded.meta == {"algo": algo}


def _tmp_file(algo: str, extra: dict) -> str:
    import tempfile

    return tempfile.mkstemp(suffix=f"-{algo}-{len(extra)}.npz")[1]


@pytest.fixture(scope="module")
def two_seeds(tmp_path_factory):
    """``bbgym train --engine rejax``'s trainer: seeds 3 and 4 in one program."""
    tmp = tmp_path_factory.mktemp("rejax")
    folders = {3: tmp / "seed3", 4: tmp / "seed4"}
    summaries = train_rejax(ENV_ID, folders=folders, preset=_preset(tmp, TINY_PPO))
    return folders, summaries


def test_one_program_writes_each_seeds_run_folder(two_seeds):
    folders, summaries = two_seeds
    for seed, folder in folders.items():
        assert sorted(p.name for p in folder.iterdir()) == [
            "best_model.npz",
            "config.yaml",
            "eval",
            "model.npz",
            "train.json",
        ]
        log = json.loads((folder / "train.json").read_text())
        assert log == summaries[seed]
        assert (log["engine"], log["algo"], log["seed"]) == ("rejax", "ppo", seed)
        assert log["seeds_in_program"] == [3, 4]
        # 1024 timesteps in batches of 16 envs x 16 steps, two evaluations.
        assert log["timesteps_trained"] == 1024 and log["evaluations"] == 2
        assert log["versions"]["rejax"] == "0.1.3"
        with np.load(folder / "eval" / "evaluations.npz") as curve:
            assert curve["timesteps"].tolist() == [512, 1024]
            assert curve["results"].shape == curve["successes"].shape == (2, EPISODES)
            assert np.all(curve["ep_lengths"] >= 1)
        final = MLPPolicy.load(folder / "model.npz")
        best = MLPPolicy.load(folder / "best_model.npz")
        assert final.meta["seed"] == best.meta["seed"] == seed
        assert final.meta["timesteps"] == 1024
        with np.load(folder / "eval" / "evaluations.npz") as curve:
            # The best is the first evaluation with the highest mean return.
            best_step = curve["timesteps"][np.argmax(curve["results"].mean(axis=1))]
        assert best.meta["timesteps"] == log["best_model_timesteps"] == best_step
        same = all(np.array_equal(a, b) for a, b in zip(final.kernels, best.kernels, strict=True))
        assert same == (best_step == 1024)  # the final policy only where it was the best
    # Two seeds learn differently.
    first, second = (MLPPolicy.load(f / "model.npz") for f in folders.values())
    assert not np.allclose(first.kernels[0], second.kernels[0])


def test_the_programs_evaluation_is_the_gym_envs_episodes_under_the_exported_policy(two_seeds):
    """The last in-program evaluation of each seed equals its saved policy (NumPy) playing
    the episodes that the Gymnasium id's vector env starts for ``reset(seed=10000 +
    seed)`` on ``EPISODES`` envs (the JAX backend, float32: the program's arithmetic)."""
    folders, _ = two_seeds
    for seed, folder in folders.items():
        policy = MLPPolicy.load(folder / "model.npz")
        env = gym.make_vec(
            ENV_ID,
            num_envs=EPISODES,
            vectorization_mode="vector_entry_point",
            backend="jax",
            dtype="float32",
        )
        obs, _ = env.reset(seed=10_000 + seed)
        returns, lengths = np.zeros(EPISODES), np.zeros(EPISODES, int)
        success, running = np.zeros(EPISODES, bool), np.ones(EPISODES, bool)
        while running.any():
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            returns += np.where(running, reward, 0.0)
            lengths += running
            ended = running & (terminated | truncated)
            success[ended] = np.asarray(info["is_success"])[ended]
            running &= ~ended
        env.close()
        with np.load(folder / "eval" / "evaluations.npz") as curve:
            np.testing.assert_allclose(curve["results"][-1], returns, rtol=1e-3, atol=1e-3)
            np.testing.assert_array_equal(curve["ep_lengths"][-1], lengths)
            np.testing.assert_array_equal(curve["successes"][-1], success)


def test_evaluate_reads_the_npz_policy_with_numpy_alone(two_seeds):
    """``bbgym evaluate --model model.npz`` in a process where JAX cannot be imported."""
    folders, _ = two_seeds
    model = folders[3] / "model.npz"
    script = textwrap.dedent(
        f"""
        import sys
        sys.modules["jax"] = None  # importing jax now fails
        from bbgym.cli import evaluate
        result = evaluate.evaluate({ENV_ID!r}, "ppo", 2, 0, {str(model)!r})
        print(result["episodes"], "jax" in sys.modules and sys.modules["jax"] is not None)
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    )
    assert done.stdout.split() == ["2", "False"]
    from bbgym.cli import evaluate

    with pytest.raises(ValueError, match=r"--model .*model\.npz: a policy of ppo"):
        evaluate.evaluate(ENV_ID, "sac", 1, 0, model)


def test_settings_are_checked_by_name(tmp_path):
    with pytest.raises(ValueError, match=r"rejax\.algo must be one of"):
        load_rejax(_preset(tmp_path, {**TINY_PPO, "algo": "dqn"}))
    with pytest.raises(ValueError, match=r"rejax\.eval_episodes must be a positive int"):
        load_rejax(_preset(tmp_path, {**TINY_PPO, "eval_episodes": 0}))
    with pytest.raises(ValueError, match="no rejax section"):
        load_rejax("BeachballTopple-v2")
    with pytest.raises(UsageError, match=r"rejax\.num_env: not a setting of rejax's PPO"):
        train_rejax(
            ENV_ID,
            folders={0: tmp_path / "x"},
            preset=_preset(tmp_path, {**TINY_PPO, "num_env": 8}),
        )
    assert not (tmp_path / "x").exists()  # refused before anything was written


@pytest.mark.parametrize("preset", ["BeachballSail-v1", "BeachballThrow-v1"])
def test_the_shipped_rejax_sections_load(preset):
    settings = load_rejax(preset)
    assert bbgym_rejax.algorithm_settings(settings)  # every name is rejax's


def test_the_training_pages_example_trains_seeds_in_one_program():
    """``docs/examples/rejax_ppo.py`` (included whole on the Training page), on a budget of
    two iterations a seed: one evaluation row per eval period and seed."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "docs" / "examples" / "rejax_ppo.py"
    spec = importlib.util.spec_from_file_location("rejax_ppo_example", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    returns = example.main(total_timesteps=5 * 4096, seeds=2)
    # rejax evaluates before training and at each of the 5 periods, 128 episodes each.
    assert returns.shape == (2, 6, 128)
    assert np.isfinite(np.asarray(returns)).all()


def test_sacs_replay_buffer_samples_stored_transitions_uniformly_with_replacement():
    """``bbgym.rejax._UniformReplayBuffer``: only stored entries, each about equally
    often (stable-baselines3's sampling, without rejax's sort over the whole buffer)."""
    settings = {**load_rejax("BeachballSail-v1"), "buffer_size": 1000, "total_timesteps": 64}
    algo = bbgym_rejax.make_algorithm("BeachballSail-v1", settings)
    buffer = algo.init_state(jax.random.PRNGKey(0)).replay_buffer
    assert isinstance(buffer, bbgym_rejax._UniformReplayBuffer)
    stored = 40
    batch = buffer.data._replace(
        reward=np.arange(stored, dtype=np.float32),
        obs=buffer.data.obs[:stored],
        action=buffer.data.action[:stored],
        done=buffer.data.done[:stored],
        next_obs=buffer.data.next_obs[:stored],
    )
    buffer = buffer.extend(batch)
    drawn = np.asarray(buffer.sample(4000, jax.random.PRNGKey(1)).reward)
    assert set(np.unique(drawn)) == set(range(stored))  # every stored one, none other
    counts = np.bincount(drawn.astype(int), minlength=stored)
    assert counts.min() > 50 and counts.max() < 150  # 100 expected each
