"""What the race does with the inputs users hand it: a bad action in the AEC form refused
at its own turn, constructor errors naming the ``boat`` path passed, ``step`` wanting a
dict, PettingZoo's stock API and seed tests passing on the race as the docs make it, and
the rule for reset options the race does not know."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

import pettingzoo  # noqa: E402
from pettingzoo.test import (  # noqa: E402
    api_test,
    parallel_api_test,
    parallel_seed_test,
    seed_test,
)

from bbgym.envs.race import (  # noqa: E402
    ENV_ID,
    BeachballRaceFleetEnv,
    BeachballRaceSoloEnv,
    parallel_env,
)

ZERO = np.zeros(3, dtype=np.float32)
BAD_ACTIONS = [
    pytest.param([np.nan, 0.0, 0.0], id="nan"),
    pytest.param([0.0, np.inf, 0.0], id="inf"),
    pytest.param([0.0, 0.0], id="short"),
    pytest.param(np.zeros((1, 3)), id="2d"),
    pytest.param("fast", id="text"),
]


def aec(num_boats: int) -> Any:
    """The AEC form as the docs make it."""
    return pettingzoo.make("aec", ENV_ID, num_boats=num_boats)


@pytest.mark.parametrize("turn", [0, 1, 2])
@pytest.mark.parametrize("bad", BAD_ACTIONS)
def test_the_aec_form_refuses_a_bad_action_at_its_turn_and_races_on(bad: Any, turn: int) -> None:
    """The boat whose turn it is gets the error (naming it), keeps its turn, and once it
    passes a valid action the race is the one that never saw the bad action."""
    env, clean = aec(3), aec(3)
    env.reset(seed=5)
    clean.reset(seed=5)
    for _ in range(turn):
        env.step(ZERO)
        clean.step(ZERO)
    agent = f"boat_{turn}"
    assert env.agent_selection == agent
    with pytest.raises(ValueError, match=rf"action.*'{agent}'|'{agent}'.*action") as error:
        env.step(bad)
    assert agent in str(error.value)
    assert env.agent_selection == agent  # still its turn
    for _ in range(3 * 4 - turn):  # the rest of this cycle, then three more
        assert env.agent_selection == clean.agent_selection
        env.step(ZERO)
        clean.step(ZERO)
    for agent in env.possible_agents:
        np.testing.assert_array_equal(env.observe(agent), clean.observe(agent))
    assert env.unwrapped.state_.clock_s[0] == clean.unwrapped.state_.clock_s[0]
    assert env.unwrapped.state_.clock_s[0] > -env.unwrapped.task.countdown_s


BOAT_ERRORS = [
    ({"dinghy": {"mass_kg": -1}}, ValueError, "boat.dinghy.mass_kg"),
    ({"dinghy": {"hull": 1}}, TypeError, "boat.dinghy got an unexpected key 'hull'"),
    ({"dinghy": 5}, TypeError, "boat.dinghy must be a mapping"),
    ({"sail_model": "x"}, ValueError, "boat.sail_model"),
    ({"initial_sheet": float("nan")}, ValueError, "boat.initial_sheet"),
    ({"initial_sheet": "full"}, TypeError, "boat.initial_sheet"),
    ({"initial_speed_range": (3.0, 1.0)}, ValueError, "boat.initial_speed_range"),
    ({"initial_speed_range": (1.0, 99.0)}, ValueError, "boat.initial_speed_range[1]"),
    ({"hull": 1}, TypeError, "boat got an unexpected key 'hull'"),
    (5, TypeError, "boat must be a mapping"),
    ("sloop", TypeError, "boat must be a mapping"),
    ([], TypeError, "boat must be a mapping"),
]


@pytest.mark.parametrize(("boat", "error", "path"), BOAT_ERRORS)
def test_boat_errors_name_the_path_passed(boat: Any, error: type, path: str) -> None:
    """In every race env that takes ``boat``: the error's type is the one an argument of
    that kind raises, and its message begins with the path the user wrote."""
    makers = [
        lambda: parallel_env(num_boats=2, boat=boat),
        lambda: BeachballRaceFleetEnv(1, num_boats=2, boat=boat),
        lambda: BeachballRaceSoloEnv(num_boats=2, boat=boat),
    ]
    for make in makers:
        with pytest.raises(error, match="^" + re.escape(path)):
            make()


def test_a_good_boat_still_builds() -> None:
    env = parallel_env(num_boats=2, boat={"sail_model": "lift", "initial_sheet": 0.5})
    assert env.task.sail.params.sail_model == "lift" and env.task.sail.initial_sheet == 0.5
    assert env.task.sail.params.rig == "sloop"  # the newest boat's dinghy kept


@pytest.mark.parametrize(
    "actions",
    [
        pytest.param([ZERO, ZERO], id="list"),
        pytest.param((ZERO, ZERO), id="tuple"),
        pytest.param(None, id="none"),
        pytest.param(np.zeros((2, 3)), id="array"),
        pytest.param("boat_0", id="text"),
    ],
)
def test_the_parallel_step_wants_a_dict(actions: Any) -> None:
    env = parallel_env(num_boats=2)
    env.reset(seed=0)
    with pytest.raises(TypeError, match="actions must be a dict keyed by agent names"):
        env.step(actions)
    env.step({"boat_0": ZERO, "boat_1": ZERO})  # the race goes on


@pytest.mark.parametrize(
    ("actions", "named"),
    [
        ({"boat_0": ZERO}, "boat_1"),
        ({"boat_0": ZERO, "boat_1": ZERO, "boat_7": ZERO}, "boat_7"),
        ({"boat_0": ZERO, "boat_1": [0.0, np.nan, 0.0]}, "boat_1"),
        ({"boat_0": [np.inf, 0.0, 0.0], "boat_1": ZERO}, "boat_0"),
        ({"boat_0": ZERO, "boat_1": [0.0, 0.0]}, "boat_1"),
    ],
)
def test_a_bad_dict_of_actions_names_the_agent(actions: dict, named: str) -> None:
    env = parallel_env(num_boats=2)
    env.reset(seed=0)
    clock = env.state_.clock_s.copy()
    with pytest.raises(ValueError, match=re.escape(f"actions[{named!r}]")):
        env.step(actions)
    np.testing.assert_array_equal(env.state_.clock_s, clock)  # nothing stepped
    env.step({"boat_0": ZERO, "boat_1": ZERO})


def test_pettingzoos_parallel_api_test_passes_as_the_docs_make_the_race() -> None:
    parallel_api_test(pettingzoo.make("parallel", ENV_ID, num_boats=2), num_cycles=20)


def test_pettingzoos_aec_api_test_passes_as_the_docs_make_the_race() -> None:
    api_test(aec(2), num_cycles=10)


def test_pettingzoos_seed_tests_pass() -> None:
    seed_test(lambda: aec(2), num_cycles=10)
    parallel_seed_test(lambda: pettingzoo.make("parallel", ENV_ID, num_boats=2), num_cycles=10)


def test_reset_ignores_an_unknown_option_but_refuses_a_near_miss_of_a_known_one() -> None:
    """PettingZoo's and Gymnasium's envs ignore reset options they do not take (PettingZoo's
    API test passes ``{"options": 1}``), and so does the race; but a key that is a typo of
    one the race takes, or one of the sail env's, would leave what the user meant to pin
    drawn at random, so it raises."""
    env = parallel_env(num_boats=2)
    fleet = BeachballRaceFleetEnv(1, num_boats=2)
    plain, _ = env.reset(seed=3)
    probed, _ = env.reset(seed=3, options={"options": 1, "tide": 1.0, 7: "x"})
    for agent in plain:
        np.testing.assert_array_equal(plain[agent], probed[agent])
    np.testing.assert_array_equal(
        fleet.reset(seed=3)[0], fleet.reset(seed=3, options={"tide": 1.0})[0]
    )
    # a known key alongside an unknown one still pins
    env.reset(seed=3, options={"tide": 1.0, "wind_speed": 4.0})
    assert env.state_.wind_speed_mps[0] == 4.0
    for typo, meant in [
        ("wind_sped", "wind_speed"),
        ("windspeed", "wind_speed"),
        ("Wind_Speed", "wind_speed"),
        ("wind_form", "wind_from"),
        ("gust", "gusts"),
    ]:
        for target in (env, fleet):
            with pytest.raises(TypeError, match=rf"options\['{typo}'\].*did you mean '{meant}'"):
                target.reset(options={typo: 4.0})
    # the sail env's options, which the race's boats might seem to take, are refused by name
    for key in ("heading", "mark", "speed", "current_speed"):
        with pytest.raises(TypeError, match=rf"options\['{key}'\].*the sail env's option"):
            env.reset(options={key: 0.0})
    with pytest.raises(TypeError, match="options must be a dict"):
        env.reset(options=[("wind_speed", 4.0)])
    with pytest.raises(ValueError, match=r"options\['wind_speed'\]"):
        env.reset(options={"wind_speed": float("nan"), "tide": 1.0})


def test_a_partial_dinghy_changes_only_its_fields_on_the_newest_boat() -> None:
    """``boat={"dinghy": {"mass_kg": 150}}`` is the newest sail version's sloop at 150 kg
    (it was the default cat rig with two actions), as ``gym.make`` merges Sail-v2's."""
    import dataclasses

    from bbgym.envs.race.parallel import parallel_env

    heavy = parallel_env(boat={"dinghy": {"mass_kg": 150.0}})
    default = parallel_env()
    assert heavy.task.sail.params == dataclasses.replace(default.task.sail.params, mass_kg=150.0)
    assert heavy.task.action_space.shape == default.task.action_space.shape == (3,)
