"""The benchmark script runs end to end (in its --quick mode), so it cannot rot."""

from __future__ import annotations

import json
import subprocess
import sys


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
    for env_id in ("CartPole-v1", "BeachballSail-v0", "BeachballThrow-v0", "BeachballTopple-v0"):
        assert env_id in table
    kinds = {row["kind"] for row in result["rows"]}
    assert {"single", "vector N=1", "vector N=8"} <= kinds
    assert all(row["rate"] > 0 for row in result["rows"])
    assert set(result["memory_mb"]) == {
        "BeachballSail-v0", "BeachballThrow-v0", "BeachballCurve-v0", "BeachballTopple-v0"
    }  # fmt: skip


def test_bench_quick_backend_rows(tmp_path):
    """--backends adds torch float64/float32 rows beside CartPole at the same N."""
    import pytest

    pytest.importorskip("torch")
    done = subprocess.run(
        [sys.executable, "-m", "bbgym", "bench", "--quick", "--backends", "--envs",
         "BeachballSail-v0", "--out", str(tmp_path)],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    result = json.loads((tmp_path / "bench.json").read_text())
    kinds = {(row["env"], row["kind"]) for row in result["backend_rows"]}
    assert ("BeachballSail-v0", "N=8 torch float32") in kinds
    assert ("BeachballSail-v0", "N=8 torch float64") in kinds
    assert all(row["rate"] > 0 for row in result["backend_rows"])
    assert "torch float32" in (tmp_path / "bench.md").read_text()
