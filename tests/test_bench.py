"""The benchmark script runs end to end (in its --quick mode), so it cannot rot."""

from __future__ import annotations

import argparse
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pytest


def test_bench_quick_writes_the_table(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "bbgym", "bench", "--quick", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    table = (tmp_path / "bench.md").read_text()
    result = json.loads((tmp_path / "bench.json").read_text())
    # By default the newest version of each task, so that bench makes no env Gymnasium
    # calls out of date (it printed four deprecation warnings of its own making).
    newest = ["BeachballSail-v2", "BeachballThrow-v1", "BeachballCurve-v2", "BeachballTopple-v2"]
    for env_id in ("CartPole-v1", *newest):
        assert env_id in table
    assert "-v0" not in table and "warn" not in done.stderr.lower(), done.stderr
    kinds = {row["kind"] for row in result["rows"]}
    assert {"single", "vector N=1", "vector N=8"} <= kinds
    assert all(row["rate"] > 0 for row in result["rows"])
    assert set(result["memory_mb"]) == set(newest)


def test_bench_quick_backend_rows(tmp_path):
    """--backends adds torch float64/float32 rows beside CartPole at the same N, with
    --step-graph more than one way (as each env compiles by default, and as one graph)."""
    import pytest

    pytest.importorskip("torch")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "bbgym",
            "bench",
            "--quick",
            "--backends",
            "--envs",
            "BeachballSail-v0",
            "--step-graph",
            "auto",
            "one",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    result = json.loads((tmp_path / "bench.json").read_text())
    kinds = {(row["env"], row["kind"]) for row in result["backend_rows"]}
    assert ("BeachballSail-v0", "N=8 torch float32") in kinds
    assert ("BeachballSail-v0", "N=8 torch float64") in kinds
    assert ("BeachballSail-v0", "N=8 torch float32, one graph") in kinds
    assert all(row["rate"] > 0 for row in result["backend_rows"])
    assert "torch float32" in (tmp_path / "bench.md").read_text()


def test_bench_quick_training_and_multi_agent_rows(tmp_path):
    """--training adds TorchRL PPO's training throughput beside SB3's PPO on CartPole;
    --race (``--multi-agent``'s other spelling) the race spec's rows: the PettingZoo race
    beside CartPole's single env, the fleet vector env beside CartPole's vector env at the
    same N, in boat-steps. One run for both: each run starts the interpreter and times
    CartPole and PPO again."""
    import pytest

    pytest.importorskip("torchrl")
    pytest.importorskip("stable_baselines3")
    pytest.importorskip("pettingzoo")
    done = run_bench(tmp_path, "--training", "--race")
    assert done.returncode == 0, done.stderr
    result = json.loads((tmp_path / "bench.json").read_text())
    rows = {(row["env"], row["kind"]): row for row in result["rows"]}
    training = rows["BeachballSail-v0", "TorchRL PPO N=8"]
    assert training["rate"] > 0
    assert training["ratio"] == training["rate"] / rows["CartPole-v1", "PPO 8 envs"]["rate"]
    assert 0.0 < training["update_share"] < 1.0 and training["first_batch_s"] > 0
    table = (tmp_path / "bench.md").read_text()
    assert "| BeachballSail-v0 | TorchRL PPO N=8 |" in table
    race = [r for r in result["rows"] if r["env"] == "bbgym/BeachballRace-v0"]
    assert [r["kind"] for r in race] == [
        "PettingZoo, 4 boats",
        "fleet N=4 (1 race)",
        "fleet N=8 (2 races)",
    ]
    assert all(r["rate"] > 0 and r["ratio"] > 0 for r in race)
    assert "boat-steps/s" in table


def run_bench(tmp_path, *argv: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "bbgym",
            "bench",
            "--quick",
            "--envs",
            "BeachballSail-v0",
            "--out",
            str(tmp_path),
            *argv,
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_bench_dtypes_picks_the_torch_rows(tmp_path):
    """--dtypes float32 times float32 alone (a GPU check's time goes where it matters)."""
    import pytest

    pytest.importorskip("torch")
    done = run_bench(tmp_path, "--backends", "--dtypes", "float32")
    assert done.returncode == 0, done.stderr
    result = json.loads((tmp_path / "bench.json").read_text())
    kinds = {row["kind"] for row in result["backend_rows"] if row["env"] != "CartPole-v1"}
    assert kinds == {"N=8 torch float32"}


def test_bench_device_is_checked(tmp_path):
    """--device names a device torch has here, or the error names --device and says why."""
    import pytest

    torch = pytest.importorskip("torch")
    done = run_bench(tmp_path, "--device", "nonsense")
    assert done.returncode != 0 and "--device 'nonsense': not a torch device" in done.stderr
    if not torch.cuda.is_available():
        done = run_bench(tmp_path, "--device", "cuda")
        assert done.returncode != 0 and "--device cuda: torch" in done.stderr
        assert "sees no CUDA device" in done.stderr
    assert not (tmp_path / "bench.json").exists()


def test_bench_device_cuda_runs_the_torch_rows_alone(tmp_path):
    """The GPU check: torch rows and TorchRL PPO's training on the GPU beside CartPole, and
    nothing else."""
    import pytest

    torch = pytest.importorskip("torch")
    if not torch.cuda.is_available():
        pytest.skip("no CUDA device")
    done = run_bench(tmp_path, "--device", "cuda")
    assert done.returncode == 0, done.stderr
    result = json.loads((tmp_path / "bench.json").read_text())
    assert result["memory_mb"] == {}
    training = [row for row in result["rows"] if row["env"] != "CartPole-v1"]
    assert [row["kind"] for row in training] == ["TorchRL PPO N=8"] and training[0]["rate"] > 0
    kinds = {row["kind"] for row in result["backend_rows"] if row["env"] != "CartPole-v1"}
    # both ways of compiling the step, no NumPy row (it lives on the CPU)
    assert kinds == {
        f"N=8 torch {dtype} cuda, {graph}"
        for dtype in ("float64", "float32")
        for graph in ("parts", "one graph")
    }
    assert all(row["rate"] > 0 for row in result["backend_rows"])
    assert result["machine"]["gpu"]


def test_bench_times_tensors_in_and_out():
    """The timed loop of an on-device run (tensors in and out), here on the CPU."""
    import pytest

    pytest.importorskip("torch")
    from bbgym.cli.bench import time_backend

    row = time_backend(
        "BeachballSail-v0",
        8,
        4,
        1.0,
        0,
        backend="torch",
        dtype="float32",
        compile=False,
        output="torch",
    )
    assert row["rate"] > 0 and row["state_mb"] > 0


def test_race_backend_rows_time_the_fleet_on_torch():
    """``--multi-agent --backends``: the race fleet on torch for each dtype beside CartPole's vector
    env at the same N, with the first step's time."""
    pytest.importorskip("pettingzoo")
    pytest.importorskip("torch")
    from bbgym.cli.bench import agents_backend_rows
    from bbgym.envs.race import SPEC

    args = argparse.Namespace(
        device="cpu",
        backend_envs=(8,),
        steps=6,
        seconds=0.2,
        seed=0,
        dtypes=["float64", "float32"],
        compile=False,
        repeats=1,
    )
    rows = agents_backend_rows(SPEC, args)
    assert [r["kind"] for r in rows] == [
        "fleet N=8 (2 races) torch float64",
        "fleet N=8 (2 races) torch float32",
    ]
    assert all(r["rate"] > 0 and r["ratio"] > 0 and r["warmup_s"] > 0 for r in rows)


def test_bench_scenes_times_the_spring_and_sph_scenes_alone(tmp_path):
    """--scenes: the spring scene on NumPy and torch at each grid size, beside CartPole's
    native vector env stepping as many envs as the scene steps particles, and the SPH dam
    break's steps/s by the grid and by every pair; nothing else."""
    pytest.importorskip("torch")
    from bbgym.cli import main

    assert main(["bench", "--quick", "--scenes", "--out", str(tmp_path)]) == 0
    result = json.loads((tmp_path / "bench.json").read_text())
    assert result["rows"] == [] and result["memory_mb"] == {}
    rows = result["backend_rows"]
    kinds = [(row["env"], row["kind"]) for row in rows]
    assert kinds == [
        ("CartPole-v1", "N=48"),
        ("scene sproing", "16 particles x 3, numpy"),
        ("scene sproing", "16 particles x 3, torch float64"),
        ("CartPole-v1", "N=192"),
        ("scene sproing", "64 particles x 3, numpy"),
        ("scene sproing", "64 particles x 3, torch float64"),
    ]
    reference = None
    for row in rows:
        assert row["rate"] > 0
        if row["env"] == "CartPole-v1":
            reference = row["rate"]
            continue
        # each scene row against the CartPole row timed just before it, at its N
        assert row["ratio"] == pytest.approx(row["rate"] / reference)
        assert row["state_mb"] > 0
    assert "particle-steps/s" in (tmp_path / "bench.md").read_text()
    # the SPH dam break: the grid on NumPy and torch, every pair on NumPy, at each size;
    # each row's cost of a step against its kind's at the smallest size
    sph = result["sph_rows"]
    assert [row["kind"] for row in sph] == [
        f"{n} particles, {kind}"
        for n in (64, 256)
        for kind in ("grid, numpy", "grid, torch float64", "all, numpy")
    ]
    for row in sph:
        assert row["steps_per_s"] > 0 and row["rate"] == row["steps_per_s"] * row["particles"]
    assert [row["cost"] for row in sph[:3]] == [1.0, 1.0, 1.0]
    assert "cost of a step" in (tmp_path / "bench.md").read_text()


def test_bench_jax_adds_float64_and_float32_rows(tmp_path):
    """--jax: the JAX step's rows in each dtype beside CartPole at the same N, timed (the
    test's settings are --quick's, the smallest the command takes)."""
    pytest.importorskip("jax")
    from bbgym.cli import main

    argv = ["bench", "--quick", "--jax", "--envs", "BeachballSail-v0", "--out", str(tmp_path)]
    assert main(argv) == 0
    result = json.loads((tmp_path / "bench.json").read_text())
    rows = {row["kind"]: row for row in result["backend_rows"] if row["env"] != "CartPole-v1"}
    assert set(rows) == {"N=8 jax float64", "N=8 jax float32"}
    assert all(row["rate"] > 0 and row["ratio"] > 0 for row in rows.values())
    assert "| BeachballSail-v0 | N=8 jax float32 |" in (tmp_path / "bench.md").read_text()
    assert result["machine"]["jax"]


def load_compile_times():
    """scripts/compile_times.py as a module (scripts/ is no package)."""
    path = Path(__file__).resolve().parents[1] / "scripts" / "compile_times.py"
    spec = importlib.util.spec_from_file_location("bbgym_compile_times", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_compile_times_takes_each_backends_defaults_and_refuses_torch_threads_on_jax(capsys):
    """scripts/compile_times.py: torch as before (float64, compile.json); --backend jax in
    float32 into compile-jax.json; a torch thread option with jax fails naming it."""
    script = load_compile_times()
    torch_args = script.parse_args([])
    assert (torch_args.backend, torch_args.dtype, torch_args.torch_threads) == (
        "torch",
        "float64",
        "default",
    )
    assert torch_args.out.name == "compile.json"
    jax_args = script.parse_args(["--backend", "jax", "--num-envs", "8"])
    assert (jax_args.dtype, jax_args.num_envs, jax_args.out.name) == (
        "float32",
        8,
        "compile-jax.json",
    )
    for flag in ("--other-threads", "--torch-threads"):
        with pytest.raises(SystemExit):
            script.parse_args(["--backend", "jax", flag, "1"])
        assert f"{flag}: torch's thread count" in capsys.readouterr().err
