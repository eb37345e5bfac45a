"""RL Baselines3 Zoo support: the shipped configs/ppo.yml is generated from the presets,
RL Zoo parses every key of it, and ``python -m rl_zoo3.train`` trains with it (zoo extra).

The file's checks need only PyYAML; the rest is skipped without rl_zoo3."""

from __future__ import annotations

import argparse
import inspect
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml

from bbgym import zoo
from bbgym.config import CONFIG_DIR, PRESET_FILES, LinearSchedule, load_preset, load_training
from bbgym.zoo import ZOO_FILE, zoo_hyperparams

ENV_IDS = [
    "BeachballSail-v0",
    "BeachballSail-v1",
    "BeachballThrow-v0",
    "BeachballCurve-v0",
    "BeachballCurve-v1",
    "BeachballTopple-v0",
    "BeachballTopple-v1",
]
ZOO_KEYS = {"n_envs", "n_timesteps", "env_kwargs"}
"""Keys of the shipped file that RL Zoo consumes itself (the rest go to ``PPO(...)``)."""


def _lists(value):
    if isinstance(value, (list, tuple)):
        return [_lists(v) for v in value]
    if isinstance(value, dict):
        return {k: _lists(v) for k, v in value.items()}
    return value


# -- (a) one source of truth ----------------------------------------------------------------
def test_shipped_file_is_generated_from_the_presets():
    assert ZOO_FILE == CONFIG_DIR / "ppo.yml" and ZOO_FILE.is_file()
    text = ZOO_FILE.read_text(encoding="utf-8")
    stale = "configs/ppo.yml is stale: regenerate it with `python -m bbgym.zoo`"
    assert yaml.safe_load(text) == zoo_hyperparams(), stale
    assert text == zoo.zoo_text(), stale  # the comments too
    assert text.startswith("# ") and "generated" in text.splitlines()[1].lower()
    assert "python -m bbgym.zoo" in text
    assert zoo.main(["--check"]) == 0
    assert list(zoo_hyperparams()) == ENV_IDS


def test_write_zoo_file(tmp_path):
    path = zoo.write_zoo_file(tmp_path / "ppo.yml")
    assert path.read_text(encoding="utf-8") == ZOO_FILE.read_text(encoding="utf-8")
    path.write_text("stale: true\n")
    assert zoo.main(["--check", "--out", str(path)]) == 1


def test_a_preset_change_makes_the_shipped_file_stale(tmp_path, monkeypatch):
    for name in set(PRESET_FILES.values()):
        shutil.copy(CONFIG_DIR / name, tmp_path / name)
    preset = tmp_path / "beachball_sail.yaml"
    preset.write_text(preset.read_text().replace("n_steps: 128", "n_steps: 64"))
    import bbgym.config

    monkeypatch.setattr(bbgym.config, "CONFIG_DIR", tmp_path)
    changed = zoo_hyperparams()
    assert changed["BeachballSail-v0"]["n_steps"] == 64
    assert changed != yaml.safe_load(ZOO_FILE.read_text(encoding="utf-8"))


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_mapping_of_the_preset(env_id):
    import gymnasium as gym

    path = CONFIG_DIR / PRESET_FILES[env_id]
    params = zoo_hyperparams()[env_id]
    ppo, train = load_training(path)
    assert params["n_envs"] == train["n_envs"]
    assert params["n_timesteps"] == train["total_timesteps"]
    assert params["policy"] == ppo.pop("policy")
    # RL Zoo evaluates policy_kwargs as Python (its globals hold nothing we rely on).
    assert eval(params["policy_kwargs"], {}) == ppo.pop("policy_kwargs")
    # A schedule (lin_<x>, which RL Zoo reads as its own linear schedule) stays text.
    ppo = {k: repr(v) if isinstance(v, LinearSchedule) else v for k, v in ppo.items()}
    assert {k: params[k] for k in ppo} == ppo
    # Reward normalization (Sail-v1) is RL Zoo's normalize key, rewards only.
    normalized = {"normalize"} if train["normalize_reward"] else set()
    assert set(params) == {*ppo, "policy", "policy_kwargs", *ZOO_KEYS, *normalized}
    if normalized:
        assert eval(params["normalize"], {"dict": dict}) == {"norm_obs": False, "norm_reward": True}
    _, env_kwargs = load_preset(path)
    env_kwargs.update(gym.spec(env_id).kwargs)  # BeachballCurve-v0: the screen, far targets
    assert params["env_kwargs"] == _lists(env_kwargs)
    # Full mini-batches: the rollout (n_envs x n_steps) is a multiple of batch_size.
    assert params["n_envs"] * params["n_steps"] % params["batch_size"] == 0
    flags = zoo.zoo_train_flags(env_id)
    assert flags[flags.index("--eval-freq") + 1] == str(train["eval_every_timesteps"])
    assert flags[flags.index("--save-freq") + 1] == str(train["checkpoint_every_timesteps"])


def test_curve_env_kwargs():
    params = zoo_hyperparams()
    curve, throw = params["BeachballCurve-v0"], params["BeachballThrow-v0"]
    assert curve["env_kwargs"]["screen"] is True
    assert curve["env_kwargs"]["target_distance_range"] == [7.0, 10.0]
    assert throw["env_kwargs"]["screen"] is False
    assert {k: v for k, v in curve.items() if k != "env_kwargs"} == {
        k: v for k, v in throw.items() if k != "env_kwargs"
    }


def test_policy_kwargs_string():
    text = zoo.policy_kwargs_string({"net_arch": (64, 64), "squash_output": True})
    assert text == "dict(net_arch=[64, 64], squash_output=True)"
    with pytest.raises(ValueError, match="identifier"):
        zoo.policy_kwargs_string({"not a name": 1})


# -- (b) RL Zoo parses every key ------------------------------------------------------------
def _experiment(env_id: str, log_folder: Path, config: str = str(ZOO_FILE)):
    from rl_zoo3.exp_manager import ExperimentManager

    return ExperimentManager(
        argparse.Namespace(), "ppo", env_id, str(log_folder), eval_freq=-1, verbose=0,
        device="cpu", config=config,
    )  # fmt: skip


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_rl_zoo_parses_every_key(env_id, tmp_path):
    pytest.importorskip("rl_zoo3")
    from stable_baselines3 import PPO

    import bbgym  # noqa: F401  (registers the envs, as --gym-packages bbgym does)

    em = _experiment(env_id, tmp_path)
    raw, _ = em.read_hyperparameters()
    expected = zoo_hyperparams()[env_id]
    assert raw == expected
    # RL Zoo's own pre-processing: it takes its keys out and returns PPO's arguments.
    hyperparams, env_wrapper, callbacks, vec_env_wrapper = em._preprocess_hyperparams(dict(raw))
    assert env_wrapper is None and vec_env_wrapper is None and callbacks == []
    assert em.frame_stack is None
    if "normalize" in expected:  # VecNormalize on the rewards alone, at PPO's discount
        assert em.normalize
        assert em.normalize_kwargs == {"norm_obs": False, "norm_reward": True,
                                       "gamma": expected["gamma"]}  # fmt: skip
    else:
        assert not em.normalize
    assert em.n_envs == expected["n_envs"] and em.n_timesteps == expected["n_timesteps"]
    assert em.env_kwargs == expected["env_kwargs"]
    ppo_args = set(inspect.signature(PPO.__init__).parameters) - {"self", "env"}
    assert set(hyperparams) <= ppo_args, sorted(set(hyperparams) - ppo_args)
    assert set(hyperparams) == set(expected) - ZOO_KEYS - {"normalize"}
    # The envs RL Zoo builds from env_kwargs (one here) and PPO built from the arguments.
    env = em.create_envs(1, no_log=True)
    # rl_zoo3 2.9 gives its eval env the file's env_kwargs only with --env-kwargs (else
    # the registered defaults): the same env as long as the presets equal the defaults.
    eval_env = em.create_envs(1, eval_env=True)
    try:
        np.testing.assert_array_equal(env.reset(), eval_env.reset())
        for _ in range(3):
            action = np.full((1, *env.action_space.shape), 0.5, np.float32)
            step, eval_step = env.step(action), eval_env.step(action)
            if "normalize" in expected:  # the training env scales its rewards
                step = (step[0], env.get_original_reward(), step[2])
            for a, b in zip(step[:3], eval_step[:3], strict=True):
                np.testing.assert_array_equal(a, b)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # one env: a truncated mini-batch
            model = PPO(env=env, seed=0, verbose=0, device="cpu", **hyperparams)
        policy_kwargs = eval(expected["policy_kwargs"], {})
        assert model.policy_kwargs["net_arch"] == policy_kwargs["net_arch"]
        assert model.use_sde == expected.get("use_sde", False)
        assert model.n_steps == expected["n_steps"] and model.batch_size == expected["batch_size"]
    finally:
        env.close()
        eval_env.close()


def test_rl_zoo_reads_the_module_form(tmp_path):
    pytest.importorskip("rl_zoo3")
    import bbgym  # noqa: F401

    em = _experiment("BeachballSail-v0", tmp_path, config="bbgym.zoo")
    raw, _ = em.read_hyperparameters()
    assert raw == zoo_hyperparams()["BeachballSail-v0"]


# -- (c) python -m rl_zoo3.train ------------------------------------------------------------
def _zoo_train(log_folder: Path, *extra: str) -> subprocess.CompletedProcess:
    command = [
        sys.executable, "-m", "rl_zoo3.train", "--algo", "ppo", "--env", "BeachballSail-v0",
        "--conf-file", str(ZOO_FILE), "-n", "2048", "--seed", "0",
        "--log-folder", str(log_folder), "--eval-freq", "-1", "--num-threads", "1",
        "--device", "cpu", *extra,
    ]  # fmt: skip
    return subprocess.run(
        command, capture_output=True, text=True, timeout=300, cwd=log_folder.parent
    )


def test_rl_zoo_train_needs_gym_packages(tmp_path):
    pytest.importorskip("rl_zoo3")
    done = _zoo_train(tmp_path / "logs")  # no --gym-packages bbgym: nothing registers the env
    assert done.returncode != 0
    assert "BeachballSail-v0 not found in gym registry" in done.stderr


def test_rl_zoo_train_saves_a_model(tmp_path):
    pytest.importorskip("rl_zoo3")
    import gymnasium as gym
    from stable_baselines3 import PPO

    logs = tmp_path / "logs"
    done = _zoo_train(logs, "--gym-packages", "bbgym")
    assert done.returncode == 0, (done.stdout[-2000:], done.stderr[-3000:])
    run = logs / "ppo" / "BeachballSail-v0_1"
    saved = yaml.unsafe_load((run / "BeachballSail-v0" / "config.yml").read_text())
    assert dict(saved) == zoo_hyperparams()["BeachballSail-v0"]  # what RL Zoo trained with
    assert len(list(run.glob("*.monitor.csv"))) == zoo_hyperparams()["BeachballSail-v0"]["n_envs"]
    model = PPO.load(run / "BeachballSail-v0.zip", device="cpu")
    # A rollout is n_envs x n_steps = 4096 steps: RL Zoo runs whole rollouts past -n 2048.
    assert model.num_timesteps >= 2048
    env = gym.make("BeachballSail-v0")
    obs, _ = env.reset(seed=0)
    action, _ = model.predict(obs, deterministic=True)
    assert env.action_space.contains(action)
    env.close()
