"""Arguments as the user passes them: a partial parameter group on top of a version's own,
``sail_model`` against ``dinghy.sail_model``, the documentation's tables showing bounds
the validation accepts and every accepted choice, and a scene's declared interval."""

from __future__ import annotations

import importlib
import importlib.util
import math
import re
from dataclasses import fields
from pathlib import Path

import gymnasium as gym
import pytest

import bbgym  # noqa: F401  (registers the ids)
from bbgym.physics.calibration import calibrated_sloop
from bbgym.physics.dinghy import RIGS, SAIL_MODELS, DinghyParams
from bbgym.physics.validation import (
    Interval,
    accepted_interval,
    check_number,
    format_bound,
    parse_bound,
)
from bbgym.physics.water import WaterParams

DOCS = Path(__file__).resolve().parents[1] / "docs"


def load_tables():
    spec = importlib.util.spec_from_file_location("bbgym_docs_tables", DOCS / "tables.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def task_of(env: gym.Env):
    return env.unwrapped.task


# -- 1. a partial group on top of the version's -------------------------------------------


def test_a_partial_dinghy_changes_only_its_fields_of_v2s_sloop() -> None:
    env = gym.make("BeachballSail-v2", dinghy={"mass_kg": 150})
    assert env.action_space.shape == (3,)
    assert task_of(env).params == calibrated_sloop().replace(mass_kg=150.0)
    assert task_of(env).water == task_of(gym.make("BeachballSail-v2")).water
    venv = gym.make_vec(
        "BeachballSail-v2",
        num_envs=2,
        vectorization_mode="vector_entry_point",
        dinghy={"mass_kg": 150},
    )
    assert venv.single_action_space.shape == (3,)
    assert venv.unwrapped.task.params == calibrated_sloop().replace(mass_kg=150.0)
    venv.close()
    sync = gym.make_vec(
        "BeachballSail-v2", num_envs=1, vectorization_mode="sync", dinghy={"mass_kg": 150}
    )
    assert sync.single_action_space.shape == (3,)
    sync.close()


def test_the_first_versions_keep_their_boat_with_the_field_changed() -> None:
    for env_id in ("BeachballSail-v0", "BeachballSail-v1"):
        env = gym.make(env_id, dinghy={"mass_kg": 150})
        assert task_of(env).params == DinghyParams(mass_kg=150.0)
        assert env.action_space.shape == (2,)


def test_a_partial_water_keeps_v2s_sea_and_none_or_a_dataclass_are_whole() -> None:
    v2 = task_of(gym.make("BeachballSail-v2"))
    longer = task_of(gym.make("BeachballSail-v2", water={"wavelength_m": 20.0}))
    assert longer.water.wavelength_m == 20.0
    assert (longer.water.wave_amplitude_m, longer.water.wave_components) == (0.1, 3)
    assert task_of(gym.make("BeachballSail-v2", dinghy=None)).params == v2.params
    assert task_of(gym.make("BeachballSail-v2", water=None)).water == v2.water
    cat = task_of(gym.make("BeachballSail-v2", dinghy=DinghyParams(mass_kg=150.0)))
    assert cat.params == DinghyParams(mass_kg=150.0)
    assert task_of(gym.make("BeachballSail-v2", water=WaterParams())).water == WaterParams()


def test_no_kwargs_and_a_remade_spec_give_the_same_env() -> None:
    env = gym.make("BeachballSail-v2", dinghy={"mass_kg": 150})
    assert task_of(gym.make(env.spec)).params == task_of(env).params
    assert gym.spec("BeachballSail-v2").kwargs["dinghy"]["rig"] == "sloop"
    assert task_of(gym.make("BeachballSail-v2")).params == calibrated_sloop()


# -- 1. sail_model and dinghy.sail_model ---------------------------------------------------


@pytest.mark.parametrize("env_id", ["BeachballSail-v0", "BeachballSail-v2"])
def test_a_bad_sail_model_names_the_spelling_the_user_passed(env_id: str) -> None:
    with pytest.raises(ValueError, match=r"^sail_model must be one of"):
        gym.make(env_id, sail_model="bogus")
    with pytest.raises(ValueError, match=r"^dinghy\.sail_model must be one of"):
        gym.make(env_id, dinghy={"sail_model": "bogus"})


@pytest.mark.parametrize("env_id", ["BeachballSail-v0", "BeachballSail-v2"])
def test_either_spelling_sets_the_sail_model_and_both_must_agree(env_id: str) -> None:
    rig = task_of(gym.make(env_id)).params.rig
    for kwargs in (
        {"sail_model": "seed"},
        {"dinghy": {"sail_model": "seed"}},
        {"sail_model": "seed", "dinghy": {"sail_model": "seed"}},
    ):
        params = task_of(gym.make(env_id, **kwargs)).params
        assert (params.sail_model, params.rig) == ("seed", rig), kwargs
    with pytest.raises(ValueError, match=r"sail_model='lift' and dinghy\.sail_model='seed'"):
        gym.make(env_id, sail_model="lift", dinghy={"sail_model": "seed"})
    with pytest.raises(ValueError, match=r"sail_model='lift' and dinghy\.sail_model='seed'"):
        gym.make(env_id, sail_model="lift", dinghy=DinghyParams(sail_model="seed"))


# -- 2. and 3. the documentation's tables -----------------------------------------------------

INTERVAL = re.compile(r"([\[(])([^,\[\]()]+), ([^,\[\]()]+)([\])])")


def shown_bounds(text: str) -> list[tuple[str, float | None, float | None, bool, bool]]:
    """``(interval text, low, high, low closed, high closed)`` of each interval written
    in ``text``; a bound that is not a number (``mark_radius``) is ``None``."""

    def number(bound: str) -> float | None:
        try:
            return parse_bound(bound)
        except ValueError:
            return None

    return [
        (m.group(0), number(m.group(2)), number(m.group(3)), m.group(1) == "[", m.group(4) == "]")
        for m in INTERVAL.finditer(text)
    ]


def test_every_bound_of_every_params_table_reads_back_as_an_accepted_value() -> None:
    tables = load_tables()
    for group, cls in tables.param_groups().items():
        rows = tables.params_table(group).splitlines()[2:]
        for f in fields(cls):
            accepted = accepted_interval(cls, f.name)
            if accepted is None:
                continue
            row = next(r for r in rows if r.startswith(f"| `{group}.{f.name}` |"))
            ((text, low, high, low_closed, high_closed),) = shown_bounds(row.split(" | ")[-1])
            assert (low, high) == (accepted.low, accepted.high), row
            for bound, closed in ((low, low_closed), (high, high_closed)):
                if closed and math.isfinite(bound):
                    check_number(f"{group}.{f.name}", bound, accepted)


def test_every_numeric_interval_of_every_arguments_table_is_the_validations() -> None:
    tables = load_tables()
    modules = {
        "race": "bbgym.envs.race.task",
        **{family: f"{spec.module}.task" for family, spec in tables.families().items()},
    }
    for family, name in modules.items():
        known = {
            str(v): v
            for v in vars(importlib.import_module(name)).values()
            if isinstance(v, Interval)
        }
        for names, accepted_text in tables.argument_rows(family):
            for text, low, high, low_closed, high_closed in shown_bounds(accepted_text):
                if low is None or high is None:
                    continue  # a bound that is another argument (mark_radius)
                if text not in known:  # typed beside its check: the env must take its ends
                    argument = re.fullmatch(r"`(\w+)`", names)
                    assert argument and family != "race", (family, names, accepted_text)
                    env_id = tables.families()[family].versions[0].env_id
                    for bound, closed in ((low, low_closed), (high, high_closed)):
                        if closed:
                            gym.make(env_id, **{argument.group(1): bound}).close()
                    continue
                accepted = known[text]
                assert (low, high) == (accepted.low, accepted.high), text
                for bound, closed in ((low, low_closed), (high, high_closed)):
                    if closed and math.isfinite(bound):
                        assert accepted.contains(bound), text


def test_rudder_max_rad_copied_from_the_table_is_accepted() -> None:
    row = next(
        r
        for r in load_tables().params_table("dinghy").splitlines()
        if r.startswith("| `dinghy.rudder_max_rad` |")
    )
    assert row.endswith("| [pi/180, pi/3] |"), row
    assert DinghyParams(rudder_max_rad=parse_bound("pi/3")).rudder_max_rad == math.pi / 3
    gym.make("BeachballSail-v0", dinghy={"rudder_max_rad": parse_bound("pi/180")})


def test_bounds_are_written_exactly() -> None:
    for value in (
        math.pi / 3,
        -math.pi,
        2 * math.pi,
        math.radians(3.0),
        2**31 - 1.0,
        1e5,
        1e-4,
        1.0 / 60.0,
        0.1,
    ):
        assert parse_bound(format_bound(value)) == value, value
    assert format_bound(math.pi / 3) == "pi/3" and format_bound(-2 * math.pi) == "-2*pi"
    assert format_bound(math.radians(3.0)) == repr(math.radians(3.0))  # not quite pi/60


def test_the_sail_table_lists_every_accepted_sail_model_and_rig() -> None:
    rows = dict(load_tables().argument_rows("sail"))
    for names, choices in (
        ("`sail_model`, `dinghy.sail_model`", SAIL_MODELS),
        ("`dinghy.rig`", RIGS),
    ):
        assert re.findall(r'`"(\w+)"`', rows[names]) == list(choices), rows[names]
    for model in SAIL_MODELS:
        gym.make("BeachballSail-v0", sail_model=model)
    for rig in RIGS:
        gym.make("BeachballSail-v0", dinghy={"rig": rig})


# -- 4. a scene's declared interval ---------------------------------------------------------


def test_sproings_declared_neighbours_are_accepted_and_a_refusal_names_the_scene() -> None:
    from bbgym.scenes import get_scene

    for name in ("sproing", "sproing-cloth", "sproing-3d"):
        scene = get_scene(name)
        accepted = accepted_interval(scene.params, "neighbours")
        for value in (int(accepted.low), int(accepted.high)):
            assert scene.make_params({"neighbours": value}).neighbours == value
    with pytest.raises(ValueError, match=r"^sproing\.neighbours must be in \[4, 8\], got 26"):
        get_scene("sproing").make_params({"neighbours": 26})
    with pytest.raises(ValueError, match=r"^sproing-cloth\.neighbours must be one of 4, 6, 8"):
        get_scene("sproing-cloth").make_params({"neighbours": 5})
