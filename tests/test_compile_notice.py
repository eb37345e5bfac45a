"""No silent minute: a torch env's first compiled step, a scripted agent's polar and
``bbgym evaluate`` say on stderr what they wait for (issue 52, item 4), and inductor's
cache serves the compiled steps across thread counts and the one graph's ``while_loop``."""

from __future__ import annotations

import logging
import re
import time

import gymnasium as gym
import numpy as np
import pytest

torch = pytest.importorskip("torch")

from bbgym import backends  # noqa: E402


@pytest.fixture(autouse=True)
def fresh_notices(monkeypatch):
    """Each test starts with no compile announced and bbgym not quiet."""
    monkeypatch.setattr(backends, "_ANNOUNCED", set())
    monkeypatch.delenv(backends.QUIET_VARIABLE, raising=False)


def lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith("bbgym: ")]


def test_a_first_compile_is_announced_on_stderr_with_progress(capfd) -> None:
    """What compiles, where, the expected wait, a line every interval, and the end."""
    backend = backends.Backend("torch", dtype="float32")
    with backends.compile_logged("the BeachballSail-v2 step", backend, 4, "parts", interval_s=0.1):
        time.sleep(0.45)
    err = lines(capfd.readouterr().err)
    assert err[0].startswith(
        "bbgym: compiling the BeachballSail-v2 step for torch (cpu, float32, batch 4) "
        "(the step's parts): a first step takes 45-140 s with a cold compile cache and 5-15 s "
        "with a warm one on a 2-core CPU"
    ), err
    assert f"reuse the compile cache ({backends.compile_cache_dir()})" in err[0]
    progress = [line for line in err if "still compiling" in line]
    assert len(progress) >= 2, err
    assert re.fullmatch(
        r"bbgym: still compiling the BeachballSail-v2 step: \d+ s so far", progress[0]
    )
    assert re.fullmatch(
        r"bbgym: compiled the BeachballSail-v2 step in 0\.\d s \(0 new graphs\)", err[-1]
    ), err


def test_once_per_process_per_graph_and_quiet_on_request(capfd, monkeypatch) -> None:
    """A second compile of the same graph in the process (quick: Dynamo's own cache) says
    nothing; another batch size is a new graph; ``BBGYM_QUIET=1`` silences all of it."""
    backend = backends.Backend("torch")
    for _ in range(2):
        with backends.compile_logged("tiny", backend, 3, graph="one", interval_s=5.0):
            pass
    err = lines(capfd.readouterr().err)
    assert len(err) == 2 and "the step as one graph" in err[0], err
    assert "a first step takes 45-140 s with a cold compile cache" in err[0]
    monkeypatch.setenv(backends.QUIET_VARIABLE, "1")
    with backends.compile_logged("tiny", backend, 5, interval_s=0.05):
        time.sleep(0.2)
    assert capfd.readouterr().err == ""


def test_a_logging_setup_that_shows_info_gets_the_lines_instead(capfd, caplog) -> None:
    """Where logging prints bbgym's INFO (the ``bbgym`` command, a basicConfig), the lines
    go there and not a second time on stderr; progress goes to ``bbgym.backends.progress``."""
    caplog.set_level(logging.INFO, logger="bbgym")
    with backends.compile_logged("tiny", backends.Backend("torch"), 3, interval_s=0.1):
        time.sleep(0.25)
    assert lines(capfd.readouterr().err) == []
    names = [r.name for r in caplog.records]
    assert names.count("bbgym.backends") == 2 and "bbgym.backends.progress" in names


def test_an_envs_first_torch_step_names_the_env_and_its_graph(capfd, monkeypatch) -> None:
    """The env's own first step (its compile stood in for by a slow eager call)."""

    def slow(fn, backend):
        def call(*args):
            time.sleep(0.1)
            return fn(*args)

        return call

    monkeypatch.setattr(backends, "compiled", slow)
    monkeypatch.setattr(backends, "PROGRESS_INTERVAL_S", 0.1)
    env = gym.make_vec(
        "BeachballSail-v0", num_envs=2, vectorization_mode="vector_entry_point", backend="torch"
    )
    env.reset(seed=0)
    capfd.readouterr()
    env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    err = lines(capfd.readouterr().err)
    assert err[0].startswith(
        "bbgym: compiling the BeachballSail-v0 step for torch (cpu, float64, batch 2) "
        "(the step's parts): a first step takes 45-140 s with a cold compile cache"
    ), err
    assert any("still compiling the BeachballSail-v0 step" in line for line in err), err
    assert err[-1].startswith("bbgym: compiled the BeachballSail-v0 step in ")
    env.step(np.zeros(env.action_space.shape, dtype=np.float32))
    assert capfd.readouterr().err == ""  # later steps say nothing


def test_announced_speaks_only_past_its_threshold(capfd, monkeypatch) -> None:
    monkeypatch.setattr(backends, "NOTICE_AFTER_S", 0.05)
    with backends.announced("quick"):
        pass
    with backends.announced("slow thing"):
        time.sleep(0.2)
    err = lines(capfd.readouterr().err)
    assert err[0] == "bbgym: slow thing..."
    assert re.fullmatch(r"bbgym: slow thing: done in 0\.\d s", err[1]) and len(err) == 2, err


def test_the_autopilots_polar_is_announced(capfd, monkeypatch) -> None:
    """``VMGAutopilot.for_env`` and ``RaceRacer.for_env`` say what they compute when it
    takes long (the polar: seconds per boat and process)."""
    from bbgym.agents import RaceRacer, VMGAutopilot, sail_autopilot

    from bbgym.envs.race.parallel import BeachballRaceEnv

    def slow_tables(*args):  # the polar stood in for: a pause, no tables
        time.sleep(0.2)

    monkeypatch.setattr(sail_autopilot, "sailing_tables", slow_tables)
    monkeypatch.setattr(backends, "NOTICE_AFTER_S", 0.05)
    VMGAutopilot.for_env(gym.make("BeachballSail-v0"))
    err = lines(capfd.readouterr().err)
    assert err[0] == "bbgym: VMGAutopilot: computing the boat's polar for BeachballSail-v0..."
    assert err[1].startswith("bbgym: VMGAutopilot: computing the boat's polar for ")
    assert " done in " in err[1]
    RaceRacer.for_env(BeachballRaceEnv())
    err = lines(capfd.readouterr().err)
    assert err[0] == "bbgym: RaceRacer: computing the boats' polar for their autopilot...", err


def test_evaluate_counts_making_the_policy_and_says_the_total(monkeypatch) -> None:
    """The wall time of a row includes making the env and policy (a sailing autopilot's
    polar took 6.5 s the old rows left out); the total line accounts for the rest."""
    from bbgym.cli import evaluate

    real = evaluate.make_policy

    def slow_policy(*args):
        time.sleep(0.5)
        return real(*args)

    monkeypatch.setattr(evaluate, "make_policy", slow_policy)
    row = evaluate.evaluate("BeachballThrow-v0", "random", 1, 0, None)
    assert row["wall_time_s"] >= 0.5
    line = evaluate.total_line([row], 20.0, [{"wall_time_s": 4.0}])
    assert line.startswith("total wall time 20 s: the table's policies 1 s")
    assert "the scripted policy for time / oracle 4 s" in line
    seconds = evaluate.process_seconds()
    assert seconds is None or 0.0 < seconds < 24 * 3600


def test_inductor_caches_across_thread_counts_and_the_while_loop(monkeypatch, tmp_path) -> None:
    """``CACHE_OPTIONS``: a graph holding a ``while_loop`` (the one-graph step's loop),
    compiled under one torch thread count, is read from inductor's on-disk cache by a later
    compile under another (Dynamo's in-memory caches emptied between, as in a new process).
    Inductor's defaults bypass the cache for such a graph and key it by the thread count."""
    import torch._dynamo
    from torch._dynamo.utils import counters
    from torch._higher_order_ops import while_loop

    monkeypatch.setenv("TORCHINDUCTOR_CACHE_DIR", str(tmp_path / "inductor"))

    def looped(x):
        def more(i, y):
            return i < 3

        def body(i, y):
            return i + 1, y * 2.0 + 1.0

        return while_loop(more, body, (torch.zeros((), dtype=torch.int64), x))[1].sin()

    threads = torch.get_num_threads()
    results = []
    try:
        for count in (1, 2):
            torch.set_num_threads(count)
            torch._dynamo.reset()
            counters.clear()
            step = backends.compiled(looped, backends.Backend("torch"))
            results.append(step(torch.arange(4.0, dtype=torch.float64)))
            hits = counters["inductor"]["fxgraph_cache_hit"]
            assert counters["inductor"]["fxgraph_cache_bypass"] == 0
        assert hits == 1, dict(counters["inductor"])
    finally:
        torch.set_num_threads(threads)
        torch._dynamo.reset()
    torch.testing.assert_close(results[0], results[1])
