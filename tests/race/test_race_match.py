"""Learning boats against scripted racers (bbgym.envs.race.match): which boats learn, that
the others sail exactly as the racer, residual actions, the SB3 adapter, and the
pairings count that scores the self-play baseline."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from bbgym.agents import RaceRacer  # noqa: E402

from bbgym.envs.race import BeachballRaceFleetEnv  # noqa: E402
from bbgym.envs.race.match import (  # noqa: E402
    BeachballRaceMatchEnv,
    learner_mask,
    play_matches,
    score_matches,
)


def test_learners_alternate_ends_of_the_line() -> None:
    """Even races: the first boats learn; odd races: the last (boats start in slots along
    the line by number, so each end gets learners equally often)."""
    mask = learner_mask(4, 4, 2)
    assert mask.tolist() == [[True, True, False, False], [False, False, True, True]] * 2
    env = BeachballRaceMatchEnv(3, learners=1, num_boats=3)
    assert env.num_envs == 3 and env.rows.tolist() == [0, 5, 6]


@pytest.mark.parametrize("relative", [False, True])
def test_scripted_boats_sail_as_the_racer_and_learners_as_told(relative: bool) -> None:
    """A match is the fleet with the racer's actions in the scripted rows and the policy's
    in the learning rows: the same observations and rewards, step by step, through a race
    restart (a 10 s race); ``relative=True`` takes the scripted boat's reward off each
    learning boat's of its race and changes nothing else."""
    kwargs = {"num_boats": 3, "countdown_s": 2.0, "max_race_time_s": 10.0}
    match = BeachballRaceMatchEnv(2, learners=2, relative=relative, **kwargs)
    fleet = BeachballRaceFleetEnv(2, **kwargs)
    racer = RaceRacer.for_env(fleet)
    obs, _ = match.reset(seed=7)
    fleet_obs, _ = fleet.reset(seed=7)
    rng = np.random.default_rng(0)
    restarted = moving = False
    for _ in range(60):
        np.testing.assert_array_equal(obs, fleet_obs[match.rows])
        actions = rng.uniform(-1, 1, (4, 3)).astype(np.float32)
        every = racer(fleet_obs)
        if fleet.races_ended.any():  # the match's racer forgets a restarted race's tacks
            restarted = True
            racer.pilot.reset(np.flatnonzero(np.repeat(fleet.races_ended, 3)))
        every[match.rows] = actions
        obs, rewards, terminated, truncated, _ = match.step(actions)
        fleet_obs, fleet_rewards, fleet_terminated, fleet_truncated, _ = fleet.step(every)
        expected = fleet_rewards[match.rows]
        if relative:  # race 0's scripted boat is boat 2 (row 2), race 1's boat 0 (row 3)
            expected = expected - np.repeat(fleet_rewards[[2, 3]], 2)
            moving |= np.abs(fleet_rewards[[2, 3]]).max() > 0.0
        np.testing.assert_allclose(rewards, expected, rtol=0.0, atol=1e-12)
        np.testing.assert_array_equal(truncated, fleet_truncated[match.rows])
    assert restarted
    assert moving or not relative  # the scripted boats' rewards were not all zero


def test_a_zero_residual_sails_as_the_racer() -> None:
    """``residual=True``: a zero action is the racer's own, so the scored races equal the
    racer in the learners' places, pairing for pairing; and with the racer on both sides,
    learned and scripted boats finish ahead about equally often."""
    kwargs = {"num_races": 6, "seed": 3, "num_boats": 3, "learners": 1}
    racer = RaceRacer.for_env(BeachballRaceMatchEnv(1, num_boats=3).fleet)
    as_racer = play_matches(racer, **kwargs)
    zero = play_matches(lambda obs: np.zeros((len(obs), 3), np.float32), residual=True, **kwargs)
    assert zero == as_racer
    assert as_racer.pairings == 6 * 1 * 2 and as_racer.ahead + as_racer.behind <= 12
    assert as_racer.learned_finished == 1.0 and as_racer.scripted_finished == 1.0
    # a residual pushing the rudder hard over sails in circles: it never finishes
    circling = play_matches(
        lambda obs: np.tile([2.0, 0.0, 0.0], (len(obs), 1)),
        residual=True,
        max_race_time_s=60.0,
        **kwargs,
    )
    assert circling.learned_finished == 0.0 and circling.ahead == 0


def test_a_racer_playing_the_shifts_sails_otherwise() -> None:
    """``tack_cone_deg`` reaches the racer's autopilot: in the gusty races' shifts it tacks
    on its own schedule, so its boats sail other races than the standard racer's."""
    fleet = BeachballRaceMatchEnv(1, num_boats=3).fleet
    kwargs = {"num_races": 4, "seed": 3, "num_boats": 3, "learners": 1}
    shifty = RaceRacer.for_env(fleet, tack_cone_deg=20.0)
    assert shifty.pilot.tack_cone == pytest.approx(np.radians(20.0))
    assert RaceRacer.for_env(fleet).pilot.tack_cone is None
    played = play_matches(shifty, **kwargs)
    assert played.learned_return != play_matches(RaceRacer.for_env(fleet), **kwargs).learned_return
    assert played.pairings == 4 * 2


def test_pairings_are_counted_by_place() -> None:
    """Each learned boat against each scripted one of its race: ahead when it finished
    earlier or the other never finished; two that never finish count for neither."""
    place = np.array([[1, 2, 3, 0], [0, 1, 0, 2]])
    finished = place > 0
    fouls = np.array([[1, 0, 2, 0], [3, 0, 1, 0]])
    learned = np.array([[True, False, True, False], [True, True, False, False]])
    result = score_matches(place, finished, fouls, learned)
    # race 0: 1 beats 2 and unplaced 4; 3 loses to 2, beats 4. race 1: 0 (unfinished) loses
    # to 4 (2nd) and ties 3 (unfinished); 2 (1st) beats both
    assert (result.pairings, result.ahead, result.behind) == (8, 5, 2)
    assert result.ahead_share == 5 / 8
    assert result.learned_fouls == 1.5 and result.scripted_fouls == 0.25
    assert result.learned_place == pytest.approx(5 / 3) and result.learned_finished == 0.75


def test_bad_arguments_name_themselves() -> None:
    with pytest.raises(ValueError, match="learners"):
        BeachballRaceMatchEnv(2, learners=5, num_boats=4)
    with pytest.raises(TypeError, match="learners"):
        BeachballRaceMatchEnv(2, learners=1.5)
    with pytest.raises(TypeError, match="residual"):
        BeachballRaceMatchEnv(2, residual="yes")
    with pytest.raises(TypeError, match="relative"):
        BeachballRaceMatchEnv(2, relative=1)
    with pytest.raises(ValueError, match="relative.*learners"):
        BeachballRaceMatchEnv(2, relative=True, learners=2, num_boats=2)
    env = BeachballRaceMatchEnv(2)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="actions"):
        env.step(np.full((4, 3), np.nan))


def test_bbgym_record_draws_a_race(tmp_path, capsys) -> None:
    """``bbgym record --env bbgym/BeachballRace-v0``: a frame per step and the first; a
    self-play model sails its learning boats as it was trained (the JSON beside it), and
    one without that JSON, or another race id, or a policy a race has not, is refused."""
    pytest.importorskip("pygame")
    pytest.importorskip("stable_baselines3")
    from PIL import Image
    from stable_baselines3 import PPO

    from bbgym import cli
    from bbgym.sb3 import NativeVecEnvAdapter

    out = tmp_path / "race.gif"
    argv = ["record", "--env", "bbgym/BeachballRace-v0", "--seed", "3", "--max-steps", "6"]
    assert cli.main([*argv, "--policy", "scripted", "--out", str(out)]) == 0
    with Image.open(out) as gif:
        assert gif.n_frames == 7
    assert "6 steps (cut at --max-steps 6)" in capsys.readouterr().out
    model = tmp_path / "seed_0.zip"
    PPO(
        "MlpPolicy",
        NativeVecEnvAdapter(BeachballRaceMatchEnv(1, residual=True)),
        n_steps=8,
        batch_size=8,
        seed=0,
    ).learn(8).save(model)
    with pytest.raises(SystemExit):
        cli.main([*argv, "--policy", "ppo", "--model", str(model)])
    assert "seed_0.json beside it" in capsys.readouterr().err
    model.with_suffix(".json").write_text('{"learners": 2, "residual": true}')
    assert cli.main([*argv, "--policy", "ppo", "--model", str(model), "--out", str(out)]) == 0
    # 6 steps: nobody finished; boats 0 and 1 are the model's (marked *)
    assert "boat_0*, boat_1*, boat_2, boat_3 did not finish" in capsys.readouterr().out
    for bad, message in (
        (["--env", "bbgym/BeachballRace-v9", "--policy", "random"], "v9"),
        (["--env", "bbgym/BeachballRace-v0", "--policy", "planner"], "--policy planner"),
    ):
        with pytest.raises(SystemExit):
            cli.main(["record", *bad])
        assert message in capsys.readouterr().err


def test_race_outcome_gives_the_places_in_words() -> None:
    """The last caption of a recorded race: the places in order, learned boats marked ``*``
    only where some (not all) learn."""
    from bbgym.envs.race.recording import race_outcome

    place, learned = np.array([0, 1, 2, 3]), np.array([True, False, False, False])
    assert (
        race_outcome(place, learned) == "1st boat_1, 2nd boat_2, 3rd boat_3; boat_0* did not finish"
    )
    assert race_outcome(np.array([2, 1, 4, 3]), np.ones(4, bool)) == (
        "1st boat_1, 2nd boat_0, 3rd boat_3, 4th boat_2"
    )
    assert race_outcome(np.zeros(2, int), np.zeros(2, bool)) == "boat_0, boat_1 did not finish"
