"""Property-based fuzzing of the PettingZoo race and the course's scenes (hypothesis), as
``tests/test_fuzz.py`` fuzzes the Gymnasium envs.

The race: random valid constructor arguments (its counts, course, wind, shadows, rules,
reward weights and a boat with every dinghy constant drawn) and reset options, random
actions in both of its forms, bad actions that must be refused at their call naming the
boat; every observation inside its space, every reward and info float finite; every
invalid number refused naming its path. The scenes: every parameter over its interval
(counts capped), on NumPy and torch; every measure finite, and a refusal only of a
combination, naming another field. And ``bbgym fuzz``'s run reports both.
"""

from __future__ import annotations

import importlib.util
import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_fuzz import hypothesis_draw

from bbgym.envs.race.fuzz import (
    RACE_FORMS,
    check_race_episode,
    check_race_rejections,
    race_numeric_arguments,
    sample_race_kwargs,
    sample_race_options,
)
from bbgym.fuzz import (
    BAD_NUMBERS,
    SCENE_MOST_BODIES,
    check_scene,
    format_report,
    run,
    sample_scene_params,
    scene_count_caps,
)
from bbgym.fuzz.scenes import _refusal_names_another_field
from bbgym.physics.validation import Interval
from bbgym.scenes import SCENES, get_scene, simulate
from bbgym.scenes.scene import to_numpy

HAVE_TORCH = importlib.util.find_spec("torch") is not None
needs_race = pytest.mark.skipif(
    importlib.util.find_spec("pettingzoo") is None, reason="the race needs the 'race' extra"
)


def fuzz_settings(examples: int) -> settings:
    """CI's settings of ``tests/test_fuzz.py`` with ``examples`` examples: the same every
    run (derandomize), no deadline (a first torch call imports torch)."""
    return settings(
        max_examples=examples,
        deadline=None,
        derandomize=True,
        suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    )


# -- the race --------------------------------------------------------------------------------


@needs_race
@pytest.mark.parametrize("form", RACE_FORMS)
@fuzz_settings(10)
@given(data=st.data(), seed=st.integers(0, 2**31 - 1))
def test_the_race_runs_finite_and_refuses_bad_actions(form, data, seed):
    draw = hypothesis_draw(data)
    kwargs = sample_race_kwargs(draw)
    options = sample_race_options(draw)
    taken = check_race_episode(kwargs, 20, seed, form, options)
    assert taken >= 20  # at least one boat acts each step (a turn each, in the AEC form)


@needs_race
def test_the_race_refuses_every_invalid_number_naming_its_path():
    names = race_numeric_arguments()
    for path in (
        "num_boats",
        "leg_length_m",
        "boat.initial_sheet",
        "boat.dinghy.mass_kg",
        "gust_params.speed_std",
        "shadow_params.length_m",
    ):
        assert path in names
    assert check_race_rejections() == len(names) * len(BAD_NUMBERS)


@needs_race
def test_a_race_check_fails_where_a_bad_action_is_let_through(monkeypatch):
    """The check is no formality: a race that let a NaN action through fails it."""
    from bbgym.envs.race.parallel import BeachballRaceEnv

    monkeypatch.setattr(
        BeachballRaceEnv,
        "check_action",
        lambda self, agent, action, path=None: np.clip(np.nan_to_num(np.real(action)), -1.0, 1.0),
    )
    with pytest.raises(AssertionError, match="action of boat_0 was accepted"):
        check_race_episode({"num_boats": 1}, 200, 0, "parallel")


# -- the scenes ------------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(SCENES))
@fuzz_settings(5)
@given(data=st.data())
def test_every_scene_runs_finite_on_numpy(name, data):
    params = sample_scene_params(SCENES[name], hypothesis_draw(data))
    assert check_scene(name, params, 20, "numpy") in (20, None)


@pytest.mark.skipif(not HAVE_TORCH, reason="the torch backend needs the 'torch' extra")
@pytest.mark.parametrize("name", list(SCENES))
@fuzz_settings(2)
@given(data=st.data())
def test_every_scene_runs_finite_on_torch(name, data):
    draw = hypothesis_draw(data)
    params = sample_scene_params(SCENES[name], draw, SCENE_MOST_BODIES["torch"])
    assert check_scene(name, params, 10, "torch") in (10, None)


def highest(name: str, accepted: Interval, log: bool) -> float:
    """A draw that takes the top of every interval (inside an open one)."""
    return math.nextafter(accepted.high, -math.inf) if accepted.high_open else accepted.high


def test_counts_are_capped_by_bodies_and_a_grid_by_its_cells():
    """Counts stop at 256 bodies on NumPy (64 on torch), a grid's side at that many cells;
    a seed keeps its whole interval; sproing's neighbours are a grid's (4, 6 or 8)."""
    assert sample_scene_params(get_scene("dam-break"), highest)["particles"] == 256
    assert sample_scene_params(get_scene("dam-break"), highest, 64)["particles"] == 64
    assert sample_scene_params(get_scene("gerstner"), highest)["points"] == 256
    assert sample_scene_params(get_scene("sproing"), highest)["size"] == 16
    assert sample_scene_params(get_scene("sproing-3d"), highest)["size"] == 6
    assert sample_scene_params(get_scene("sproing-3d"), highest, 64)["size"] == 4
    top = sample_scene_params(get_scene("sproing"), highest)
    assert top["seed"] == 2**31 - 1 and top["neighbours"] == 8
    assert sample_scene_params(get_scene("sproing-3d"), highest)["neighbours"] == 26
    # a small interval is not narrowed: rotation-box's 1..16 balls
    assert "balls" not in scene_count_caps(get_scene("rotation-box").params, 256)


def test_a_refusal_must_name_another_field():
    """A scene's refusal of values inside their intervals is a documented combination only
    where it names another field; else the interval promised a value the scene refuses."""
    arrow = get_scene("arrow")
    fields = ["speed_mps", "target_distance_m", "height_m", "dt_s"]
    assert check_scene("arrow", {"speed_mps": 10.0, "target_distance_m": 100.0}, 5) is None
    combination = "arrow.target_distance_m: out of range at this speed_mps"
    assert _refusal_names_another_field(arrow, combination, fields)
    alone = "arrow.target_distance_m must be a multiple of 3"
    assert not _refusal_names_another_field(arrow, alone, fields)
    assert not _refusal_names_another_field(arrow, "push.speed_mps: no", fields)


def test_the_dam_break_names_the_block_it_has_too_few_particles_for():
    """Found by the fuzz: too few particles for one row of a wide, flat block was refused
    naming ``particles`` alone, not the block's shape that makes the row so long."""
    params = {
        "particles": 16,
        "water_width_m": 7.0,
        "water_height_m": 0.01,
        "box_width_m": 11.0,
        "box_height_m": 200.0,
    }
    with pytest.raises(ValueError, match=r"^dam-break\.particles") as error:
        simulate(get_scene("dam-break"), params, steps=1)
    assert re.search(r"\bwater_width_m\b.*\bwater_height_m\b", str(error.value))
    assert check_scene("dam-break", params, 1) is None


@pytest.mark.parametrize(
    "backend",
    ["numpy", pytest.param("torch", marks=pytest.mark.skipif(not HAVE_TORCH, reason="no torch"))],
)
def test_a_wave_of_fewer_points_than_wavelengths_runs(backend):
    """Found by the fuzz: 8 points on 14 wavelengths (each inside its interval) left the
    first wavelength no point, and the first crest's measure raised from ``argmax``."""
    params = {"wavelengths": 14, "points": 8, "amplitude_m": 900.0, "dt_s": 1e-4}
    assert check_scene("gerstner", params, 3, backend) == 3
    wave = simulate(get_scene("gerstner"), params, steps=3, backend=backend)
    # the first wavelength's one point is the surface's first
    first_point = np.asarray(to_numpy(wave.state.x_m))[0, 0]
    assert wave.measures["first_crest_x_m"][-1, 0] == first_point


# -- the long run ----------------------------------------------------------------------------


@needs_race
def test_the_long_run_reports_the_race_and_the_scenes():
    """The race through its spec's fuzz (bbgym/envs/race/fuzz.py): its forms in turn, its
    invalid numbers, its steps beside the scenes'; an older report (the race's figures with
    no ``multi_agent`` list, failures keyed ``race``) reads as before."""
    report = run(3000, seed=0, num_envs=2, env_ids=["BeachballSail-v0"], backends=("numpy",))
    assert report["failures"] == []
    assert report["multi_agent"] == ["race"] and set(report["race"]["forms"]) == set(RACE_FORMS)
    assert report["race_steps"] > 0 and report["scene_steps"] > 0
    assert report["race"]["errors_checked"] == len(race_numeric_arguments()) * len(BAD_NUMBERS)
    assert report["scene_backends"] == ["numpy"]  # the backends asked for, torch not among
    assert sum(f["configurations"] for f in report["scenes"].values()) >= 5
    text = format_report(report)
    assert "| race (parallel) |" in text and "| scene push |" in text
    assert "race boat steps" in text and "scene steps" in text
    assert "invalid race arguments checked" in text
    older = {k: v for k, v in report.items() if k != "multi_agent"}
    older["failures"] = [
        {"race": "aec", "seed": 3, "kwargs": "{}", "options": "None", "error": "E"}
    ]
    older_text = format_report(older)
    assert older_text.startswith(text.split("\n\n")[0])  # the same first table
    assert "| race (parallel) |" in older_text and "race boat steps" in older_text
    assert "- race (aec) seed=3: E\n  kwargs={}\n  options=None" in older_text
