"""A new env family through its spec alone (``docs/new-env.md``).

The template family, the puck (``bbgym/envs/puck/``), ships unregistered: registering its
spec gives it ``gym.make`` / ``gym.make_vec``, ``check_env``,
Gymnasium's Sync/Async vector envs, the fuzzer, ``bbgym evaluate``, ``bbgym bench`` and
an RL Zoo hyperparameter block, with no edit to any module of the package.
"""

from __future__ import annotations

import dataclasses
import json
import math

import gymnasium as gym
import numpy as np
import pytest

from bbgym import fuzz
from bbgym.envs import puck
from bbgym.spec import base_ids, env_ids, register_spec, spec_of, unregister_spec

ENV_ID = puck.ENV_ID
PRESET = """\
env_id: BeachballPuck-v0
env: {mass_kg: 0.5, drag_area_m2: 0.05}
algo: ppo
ppo: {n_steps: 32, batch_size: 64, learning_rate: 0.001}
train: {n_envs: 4, total_timesteps: 256}
"""


@pytest.fixture(scope="module", autouse=True)
def registered(tmp_path_factory):
    """The puck's spec with a training preset (the template ships none), registered for
    this module only."""
    preset = tmp_path_factory.mktemp("presets") / "puck.yaml"
    preset.write_text(PRESET)
    version = dataclasses.replace(puck.SPEC.versions[0], preset=preset)
    spec = register_spec(dataclasses.replace(puck.SPEC, versions=(version,)))
    yield spec
    unregister_spec("puck")
    assert ENV_ID not in env_ids() and ENV_ID not in gym.registry


def test_the_spec_registers_its_id():
    assert ENV_ID in env_ids() and ENV_ID in base_ids()
    assert spec_of(ENV_ID).family == "puck"
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


def test_its_argument_table_comes_from_its_params_fields():
    """A ``params_class`` task declares no table: the docs' rows are its fields, each with
    the interval the validation checks (one source), in the order of the dataclass."""
    import dataclasses

    from bbgym.envs.puck.task import PuckParams
    from bbgym.physics.validation import accepted_interval

    spec = spec_of(puck.ENV_ID)
    assert spec.argument_table == ()
    names = [f.name for f in dataclasses.fields(PuckParams)]
    assert [row[0] for row in spec.argument_rows()] == [f"`{n}`" for n in names]
    for (_, accepted), name in zip(spec.argument_rows(), names, strict=True):
        assert accepted == str(accepted_interval(PuckParams, name))
    assert ("`max_jet_speed_mps`", "(0, 50]") in spec.argument_rows()  # an open end shown


def test_the_jet_drags_the_puck_implicitly():
    """One step from rest in a steady jet w (no gusts): the implicit drag step gives
    v = (h k / m) w / (1 + h k / m), k = C_d A rho |w| / 2, and the puck never outruns the
    jet, however large the step."""
    kwargs = dict(mass_kg=0.5, drag_area_m2=0.05, air_density_kgm3=1.2, jet_noise_mps=0.0)
    env = gym.make(ENV_ID, dt_s=0.1, **kwargs)
    obs, _ = env.reset(seed=0, options={"distance": 5.0})
    obs, *_ = env.step(np.array([1.0, 0.0], np.float32))
    rate = 0.1 * 0.5 * 0.05 * 1.2 * 10.0 / 0.5
    np.testing.assert_allclose(obs[2] * 10.0, rate * 10.0 / (1.0 + rate), rtol=1e-6)
    fast = gym.make(ENV_ID, dt_s=0.5, **{**kwargs, "mass_kg": 0.01})
    fast.reset(seed=0, options={"distance": 5.0})
    for _ in range(20):
        obs, *_ = fast.step(np.array([1.0, 0.0], np.float32))
        assert 0.0 < obs[2] <= 1.0  # velocity / jet speed: never beyond the jet


def test_the_start_is_drawn_on_a_ring():
    env = gym.make(ENV_ID)
    for seed in range(20):
        _, info = env.reset(seed=seed)
        assert 2.0 <= info["distance_m"] <= 4.0
    _, info = env.reset(seed=0, options={"distance": 7.5})
    assert info["distance_m"] == pytest.approx(7.5)
    assert math.isfinite(info["distance_m"])


def test_the_fuzzer_serves_it():
    rng = np.random.default_rng(0)
    draw = fuzz.numpy_draw(rng)
    for num_envs in (0, 4):
        kwargs = fuzz.sample_kwargs(ENV_ID, draw)
        probe = gym.make(ENV_ID, **kwargs)
        options = fuzz.sample_options(ENV_ID, probe, draw)
        assert fuzz.check_episode(ENV_ID, kwargs, options, 30, 1, num_envs) == 30 * max(num_envs, 1)
    names = fuzz.numeric_arguments(ENV_ID)
    assert names == list(puck.task.PuckParams.__dataclass_fields__)
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
    assert params["n_steps"] == 32
    assert params["env_kwargs"] == {"mass_kg": 0.5, "drag_area_m2": 0.05}


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
