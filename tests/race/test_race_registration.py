"""The race's ids register at ``import bbgym``: Gymnasium's one-boat id by module path,
PettingZoo's ids where PettingZoo (the ``race`` extra) is installed, and a missing PettingZoo
named with its install command at ``gym.make``. Each case runs in a fresh interpreter: what
is imported is the point."""

from __future__ import annotations

import subprocess
import sys
import textwrap

from bbgym import envs


def run(code: str) -> subprocess.CompletedProcess:
    """``code`` in a fresh Python (this one's), its output captured."""
    args = [sys.executable, "-c", textwrap.dedent(code)]
    return subprocess.run(args, capture_output=True, text=True, timeout=120)


def test_the_ids_are_the_race_specs_ids() -> None:
    from bbgym.envs.race import ENV_ID, SOLO_ENV_ID, SPEC
    from bbgym.spec import env_ids, multi_agent_spec_of, multi_agent_specs

    assert SPEC in envs.SPECS and list(multi_agent_specs()) == [SPEC]
    assert SPEC.ids == (ENV_ID, SOLO_ENV_ID)
    assert ENV_ID == "bbgym/BeachballRace-v0" and SOLO_ENV_ID == "bbgym/BeachballRaceSolo-v0"
    assert multi_agent_spec_of(ENV_ID) is SPEC and multi_agent_spec_of(SOLO_ENV_ID) is SPEC
    assert multi_agent_spec_of("BeachballSail-v2") is None
    assert not set(SPEC.ids) & set(env_ids())  # env_ids: the single-agent families' ids


def test_import_bbgym_registers_the_race_ids_in_gymnasium_and_pettingzoo() -> None:
    done = run("""
        import sys
        import bbgym
        import gymnasium as gym
        print("bbgym.envs.race.parallel" in sys.modules)  # loaded by make, not by import bbgym
        print("bbgym/BeachballRaceSolo-v0" in gym.registry)
        print("BeachballRaceSolo-v0" in gym.pprint_registry(disable_print=True))
        env = gym.make("bbgym/BeachballRaceSolo-v0", num_boats=2)
        observation, info = env.reset(seed=0)
        print(type(env.unwrapped).__name__, observation.shape, info["place"])
        import pettingzoo
        race = pettingzoo.make("parallel", "bbgym/BeachballRace-v0", num_boats=3)
        print(type(race).__name__, race.possible_agents)
        print(type(pettingzoo.make("aec", "bbgym/BeachballRace-v0")).__name__)
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "False",
        "True",
        "True",
        "BeachballRaceSoloEnv (43,) 0",  # 23 + 12 + 8 columns: one neighbour
        "BeachballRaceEnv ['boat_0', 'boat_1', 'boat_2']",
        "OrderEnforcingWrapper",
    ]


def test_pettingzoo_imported_first_gets_the_race_ids() -> None:
    done = run("""
        import pettingzoo
        import bbgym
        print("bbgym/BeachballRace-v0" in pettingzoo.parallel_registry,
              "bbgym/BeachballRace-v0" in pettingzoo.aec_registry)
        print(pettingzoo.make("parallel", "bbgym/BeachballRace-v0").possible_agents)
    """)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["True True", "['boat_0', 'boat_1', 'boat_2', 'boat_3']"]


def test_without_pettingzoo_gym_make_names_the_race_extra() -> None:
    done = run("""
        import sys
        sys.modules["pettingzoo"] = None  # as if PettingZoo were not installed
        import bbgym
        import gymnasium as gym
        from bbgym._extras import install_hint
        print(install_hint("race"))  # how this bbgym installs the extra (pip install ...)
        try:
            gym.make("bbgym/BeachballRaceSolo-v0")
        except ImportError as error:
            print(type(error).__name__, error)
    """)
    assert done.returncode == 0, done.stderr
    hint, message = done.stdout.splitlines()
    assert hint.startswith("pip install ") and hint.endswith('[race]"')
    assert message == f"ImportError BeachballRace needs PettingZoo (the 'race' extra): {hint}"
