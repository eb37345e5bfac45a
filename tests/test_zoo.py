"""RL Baselines3 Zoo support: the shipped configs/ppo.yml and sac.yml are generated from the
presets, RL Zoo parses every key of them, and ``python -m rl_zoo3.train`` trains with them
(zoo extra).

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
from bbgym.config import CONFIG_DIR, LinearSchedule, load_preset, load_training, preset_files
from bbgym.spec import env_ids
from bbgym.zoo import ZOO_FILE, ZOO_FILES, zoo_hyperparams

ENV_IDS = list(env_ids())
"""Every registered id, in registration order (the order of the shipped files)."""
SAC_IDS = ("BeachballSail-v1", "BeachballSail-v2")
ALGO_OF = {env_id: "sac" if env_id in SAC_IDS else "ppo" for env_id in ENV_IDS}
"""The algorithm each env id's preset trains (RL Zoo's file it is in)."""
ZOO_KEYS = {"n_envs", "n_timesteps", "env_kwargs"}
"""Keys of the shipped files that RL Zoo consumes itself (the rest go to ``PPO(...)`` or
``SAC(...)``)."""


def _lists(value):
    if isinstance(value, (list, tuple)):
        return [_lists(v) for v in value]
    if isinstance(value, dict):
        return {k: _lists(v) for k, v in value.items()}
    return value


# -- (a) one source of truth ----------------------------------------------------------------
@pytest.mark.parametrize("algo", ["ppo", "sac"])
def test_shipped_file_is_generated_from_the_presets(algo):
    path = ZOO_FILES[algo]
    assert path == CONFIG_DIR / f"{algo}.yml" and path.is_file()
    text = path.read_text(encoding="utf-8")
    stale = f"configs/{algo}.yml is stale: regenerate it with `python -m bbgym.zoo`"
    assert yaml.safe_load(text) == zoo_hyperparams(algo), stale
    assert text == zoo.zoo_text(algo), stale  # the comments too
    assert text.startswith("# ") and "generated" in text.splitlines()[1].lower()
    assert f"--algo {algo}" in text and "python -m bbgym.zoo" in text
    assert list(zoo_hyperparams(algo)) == [e for e in ENV_IDS if ALGO_OF[e] == algo]
    assert zoo.main(["--check"]) == 0
    # The module form (``--conf-file bbgym.zoo``) holds every env id.
    assert list(zoo_hyperparams()) == ENV_IDS
    assert ZOO_FILE == ZOO_FILES["ppo"]


def test_write_zoo_file(tmp_path, capsys):
    for algo in ("ppo", "sac"):
        path = zoo.write_zoo_file(tmp_path / f"{algo}.yml", algo)
        assert path.read_text(encoding="utf-8") == ZOO_FILES[algo].read_text(encoding="utf-8")
        path.write_text("stale: true\n")
        assert zoo.main(["--check", "--algo", algo, "--out", str(path)]) == 1
    assert zoo.main(["--path", "--algo", "sac"]) == 0
    assert capsys.readouterr().out.strip() == str(ZOO_FILES["sac"])
    with pytest.raises(SystemExit):
        zoo.main(["--out", str(tmp_path / "x.yml")])  # one file needs its algorithm
    with pytest.raises(ValueError, match="algo must be one of"):
        zoo_hyperparams("dqn")


def test_a_preset_change_makes_the_shipped_file_stale(tmp_path, monkeypatch):
    for name in {path.name for path in preset_files().values()}:
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

    path = preset_files()[env_id]
    params = zoo_hyperparams(ALGO_OF[env_id])[env_id]
    section, train = load_training(path)
    assert train["algo"] == ALGO_OF[env_id]
    assert params["n_envs"] == train["n_envs"]
    assert params["n_timesteps"] == train["total_timesteps"]
    assert params["policy"] == section.pop("policy")
    # RL Zoo evaluates policy_kwargs as Python (its globals hold nothing we rely on).
    assert eval(params["policy_kwargs"], {}) == section.pop("policy_kwargs")
    # A schedule (lin_<x>, which RL Zoo reads as its own linear schedule) stays text.
    section = {k: repr(v) if isinstance(v, LinearSchedule) else v for k, v in section.items()}
    assert {k: params[k] for k in section} == section
    # Reward normalization (Sail-v1's PPO preset) is RL Zoo's normalize key, rewards only.
    normalized = {"normalize"} if train["normalize_reward"] else set()
    assert set(params) == {*section, "policy", "policy_kwargs", *ZOO_KEYS, *normalized}
    if normalized:
        assert eval(params["normalize"], {"dict": dict}) == {"norm_obs": False, "norm_reward": True}
    _, env_kwargs = load_preset(path)
    env_kwargs.update(gym.spec(env_id).kwargs)  # BeachballCurve-v0: the screen, far targets
    assert params["env_kwargs"] == _lists(env_kwargs)
    if train["algo"] == "ppo":  # full mini-batches: the rollout is a multiple of batch_size
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
def _experiment(env_id: str, log_folder: Path, config: str | None = None):
    from rl_zoo3.exp_manager import ExperimentManager

    algo = ALGO_OF[env_id]
    return ExperimentManager(
        argparse.Namespace(),
        algo,
        env_id,
        str(log_folder),
        eval_freq=-1,
        verbose=0,
        device="cpu",
        config=config or str(ZOO_FILES[algo]),
    )


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_rl_zoo_parses_every_key(env_id, tmp_path):
    pytest.importorskip("rl_zoo3")
    import bbgym  # noqa: F401  (registers the envs, as --gym-packages bbgym does)
    from bbgym.sb3 import algorithm_class

    algorithm = algorithm_class(ALGO_OF[env_id])
    em = _experiment(env_id, tmp_path)
    raw, _ = em.read_hyperparameters()
    expected = zoo_hyperparams()[env_id]
    assert raw == expected
    # RL Zoo's own pre-processing: it takes its keys out and returns PPO's (SAC's) arguments.
    hyperparams, env_wrapper, callbacks, vec_env_wrapper = em._preprocess_hyperparams(dict(raw))
    assert env_wrapper is None and vec_env_wrapper is None and callbacks == []
    assert em.frame_stack is None
    if "normalize" in expected:  # VecNormalize on the rewards alone, at PPO's discount
        assert em.normalize
        assert em.normalize_kwargs == {
            "norm_obs": False,
            "norm_reward": True,
            "gamma": expected["gamma"],
        }
    else:
        assert not em.normalize
    assert em.n_envs == expected["n_envs"] and em.n_timesteps == expected["n_timesteps"]
    assert em.env_kwargs == expected["env_kwargs"]
    known = set(inspect.signature(algorithm.__init__).parameters) - {"self", "env"}
    assert set(hyperparams) <= known, sorted(set(hyperparams) - known)
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
            model = algorithm(env=env, seed=0, verbose=0, device="cpu", **hyperparams)
        policy_kwargs = eval(expected["policy_kwargs"], {})
        assert model.policy_kwargs["net_arch"] == policy_kwargs["net_arch"]
        assert model.use_sde == expected.get("use_sde", False)
        assert model.batch_size == expected["batch_size"]
        if ALGO_OF[env_id] == "ppo":
            assert model.n_steps == expected["n_steps"]
        else:
            assert model.buffer_size == expected["buffer_size"]
            assert model.gradient_steps == expected["gradient_steps"]
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
def _zoo_train(
    log_folder: Path, *extra: str, env_id: str = "BeachballSail-v0", steps: int = 2048
) -> subprocess.CompletedProcess:
    algo = ALGO_OF[env_id]
    command = [
        sys.executable,
        "-m",
        "rl_zoo3.train",
        "--algo",
        algo,
        "--env",
        env_id,
        "--conf-file",
        str(ZOO_FILES[algo]),
        "-n",
        str(steps),
        "--seed",
        "0",
        "--log-folder",
        str(log_folder),
        "--eval-freq",
        "-1",
        "--num-threads",
        "1",
        "--device",
        "cpu",
        *extra,
    ]
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


def test_rl_zoo_trains_sac_from_its_file(tmp_path):
    pytest.importorskip("rl_zoo3")
    from bbgym.sb3 import load_model

    logs = tmp_path / "logs"
    # A short run: learning starts (and the buffer is sized) within it.
    done = _zoo_train(
        logs,
        "--gym-packages",
        "bbgym",
        "--hyperparams",
        "learning_starts:256",
        "buffer_size:2048",
        env_id="BeachballSail-v1",
        steps=1024,
    )
    assert done.returncode == 0, (done.stdout[-2000:], done.stderr[-3000:])
    run = logs / "sac" / "BeachballSail-v1_1"
    saved = dict(yaml.unsafe_load((run / "BeachballSail-v1" / "config.yml").read_text()))
    expected = zoo_hyperparams("sac")["BeachballSail-v1"]
    assert saved == {**expected, "learning_starts": 256, "buffer_size": 2048}
    model = load_model(run / "BeachballSail-v1.zip", "sac")  # (SB3 warns on a direct load)
    assert model.num_timesteps >= 1024
    # Updates ran: two gradient steps per step of the 8 envs once learning started.
    assert model._n_updates >= expected["gradient_steps"] * (1024 - 256) // expected["n_envs"] - 2
