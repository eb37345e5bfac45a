"""A new env family through its spec alone (``docs/new-env.md``).

The point-mass family of ``tests/point_mass.py`` is declared in the test suite, outside
the package: registering its spec gives it ``gym.make`` / ``gym.make_vec``, ``check_env``,
Gymnasium's Sync/Async vector envs, the fuzzer, ``bbgym evaluate``, ``bbgym bench`` and
an RL Zoo hyperparameter block, with no edit to any module of the package.
"""

from __future__ import annotations

import json

import gymnasium as gym
import numpy as np
import point_mass
import pytest
from gymnasium.utils.env_checker import check_env

from bbgym import fuzz
from bbgym.spec import base_ids, env_ids, spec_of

ENV_ID = point_mass.ENV_ID


@pytest.fixture(scope="module", autouse=True)
def registered(tmp_path_factory):
    spec = point_mass.register(tmp_path_factory.mktemp("presets"))
    yield spec
    point_mass.unregister()
    assert ENV_ID not in env_ids() and ENV_ID not in gym.registry


def test_the_spec_registers_its_id():
    assert ENV_ID in env_ids() and ENV_ID in base_ids()
    assert spec_of(ENV_ID).family == "point_mass"
    assert gym.spec(ENV_ID).max_episode_steps == 200


def test_the_time_limit_has_one_source_the_spec():
    """The native vector env made directly (no gym.make) truncates where gym.make's
    TimeLimit does: at the spec's max_episode_steps, for every family."""
    import importlib

    from bbgym.spec import spec_of_class, specs

    for spec in specs():
        module = importlib.import_module(spec.module)
        vector_class = getattr(module, spec.vector_env_class)
        assert spec_of_class(vector_class) is spec
        vec = vector_class(num_envs=1)
        assert vec.max_episode_steps == spec.max_episode_steps, spec.family
        vec.close()
    with pytest.raises(LookupError, match="no registered bbgym family"):
        spec_of_class(dict)


def test_check_env_and_determinism():
    env = gym.make(ENV_ID)
    check_env(env.unwrapped, skip_render_check=True)
    a = [env.reset(seed=3)[0]] + [env.step(np.array([0.3], np.float32))[0] for _ in range(5)]
    b = [env.reset(seed=3)[0]] + [env.step(np.array([0.3], np.float32))[0] for _ in range(5)]
    np.testing.assert_array_equal(a, b)


def test_the_physics_is_semi_implicit_euler():
    """One step of force F from rest: v = F/m dt, x = x0 + v dt."""
    env = gym.make(ENV_ID, mass_kg=2.0, max_force_n=4.0, dt=0.5)
    obs, _ = env.reset(seed=0, options={"x": 5.0})
    obs, *_ = env.step(np.array([1.0], np.float32))
    v = 4.0 / 2.0 * 0.5
    np.testing.assert_allclose(obs, [(5.0 + v * 0.5) / 10.0, v / 10.0], rtol=1e-6)


@pytest.mark.parametrize("mode", ["sync", "async", "vector_entry_point"])
def test_vector_envs_equal_the_single_env(mode):
    """Gymnasium's Sync/Async vector envs and the native one: sub-env i equals the single
    env seeded 7 + i."""
    vec = gym.make_vec(ENV_ID, num_envs=3, vectorization_mode=mode)
    obs, _ = vec.reset(seed=7)
    actions = np.linspace(-1, 1, 3, dtype=np.float32)[:, None]
    obs2, *_ = vec.step(actions)
    vec.close()
    for i in range(3):
        env = gym.make(ENV_ID)
        first, _ = env.reset(seed=7 + i)
        np.testing.assert_array_equal(first, obs[i])
        np.testing.assert_allclose(env.step(actions[i])[0], obs2[i], rtol=1e-6)


def test_the_fuzzer_serves_it():
    rng = np.random.default_rng(0)
    draw = fuzz.numpy_draw(rng)
    for num_envs in (0, 4):
        kwargs = fuzz.sample_kwargs(ENV_ID, draw)
        probe = gym.make(ENV_ID, **kwargs)
        options = fuzz.sample_options(ENV_ID, probe, draw)
        assert fuzz.check_episode(ENV_ID, kwargs, options, 30, 1, num_envs) == 30 * max(num_envs, 1)
    names = fuzz.numeric_arguments(ENV_ID)
    assert names == ["mass_kg", "max_force_n", "dt"]
    assert fuzz.check_rejections(ENV_ID) == len(names) * len(fuzz.BAD_NUMBERS)


def test_bbgym_evaluate_runs_its_policies(tmp_path):
    from bbgym.cli import main

    status = main(
        [
            "evaluate",
            "--env",
            ENV_ID,
            "--policies",
            "random,scripted",
            "--episodes",
            "5",
            "--out",
            str(tmp_path),
        ]
    )
    assert status == 0
    results = {r["policy"]: r for r in json.loads((tmp_path / f"{ENV_ID}.json").read_text())}
    assert results["scripted"]["success_rate"] == 1.0  # a PD controller always arrives
    assert results["random"]["success_rate"] < 1.0
    assert set(results["scripted"]["outcomes"]) == {"success"}


def test_bbgym_evaluate_refuses_a_policy_the_family_lacks(tmp_path, capsys):
    from bbgym.cli import main

    with pytest.raises(SystemExit):
        main(
            [
                "evaluate",
                "--env",
                ENV_ID,
                "--policies",
                "planner",
                "--episodes",
                "1",
                "--out",
                str(tmp_path),
            ]
        )
    assert "has no 'planner' policy" in capsys.readouterr().err


def test_bbgym_bench_times_it(tmp_path):
    from bbgym.cli import main

    assert main(["bench", "--quick", "--envs", ENV_ID, "--out", str(tmp_path)]) == 0
    result = json.loads((tmp_path / "bench.json").read_text())
    rows = [r for r in result["rows"] if r["env"] == ENV_ID]
    assert rows and all(r["rate"] > 0 for r in rows)


def test_rl_zoo_hyperparameters_come_from_its_preset():
    from bbgym.zoo import zoo_hyperparams

    params = zoo_hyperparams("ppo")[ENV_ID]
    assert params["n_envs"] == 4 and params["n_timesteps"] == 256
    assert params["n_steps"] == 32 and params["env_kwargs"] == {
        "mass_kg": 1.0,
        "max_force_n": 1.0,
        "dt": 0.1,
    }


def test_no_module_of_the_package_names_an_env_id():
    """Outside each family's folder, no module of the package spells out one of its ids
    (the registry, the command and the tools read them from the specs)."""
    from pathlib import Path

    import bbgym

    root = Path(bbgym.__file__).parent
    ids = [i for i in env_ids() if i != ENV_ID]
    offenders = []
    for path in root.rglob("*.py"):
        relative = path.relative_to(root)
        if relative.parts[0] == "envs" and len(relative.parts) > 2:
            continue  # a family's own folder
        text = path.read_text(encoding="utf-8")
        offenders += [f"{relative}: {i}" for i in ids if i in text]
    assert not offenders, offenders
