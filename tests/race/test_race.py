"""BeachballRace as users meet it: PettingZoo's API tests, determinism, a boat alone
sailing exactly as the sail env's, the shadow slowing a boat, the start, the finish and
the penalties, and errors that name the argument."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

pytest.importorskip("pettingzoo")

from bbgym.agents import RaceRacer  # noqa: E402
from pettingzoo.test import api_test, parallel_api_test  # noqa: E402
from pettingzoo.utils import parallel_to_aec  # noqa: E402

from bbgym.envs.race import ENV_ID, BeachballRaceEnv, parallel_env  # noqa: E402
from bbgym.envs.race.parallel import newest_boat  # noqa: E402
from bbgym.physics.namespace import replaced  # noqa: E402


def test_parallel_api() -> None:
    parallel_api_test(BeachballRaceEnv(num_boats=3), num_cycles=300)


def test_aec_api() -> None:
    api_test(parallel_to_aec(BeachballRaceEnv(num_boats=2)), num_cycles=100)


def test_made_through_pettingzoos_registry() -> None:
    import pettingzoo

    parallel = pettingzoo.make("parallel", ENV_ID, num_boats=2)
    assert isinstance(parallel, BeachballRaceEnv) and parallel.possible_agents == [
        "boat_0",
        "boat_1",
    ]
    aec = pettingzoo.make("aec", ENV_ID)
    aec.reset(seed=0)
    assert aec.agent_selection == "boat_0"


def play(env, seed: int, steps: int, policy=None) -> list:
    """Observations and rewards of ``steps`` steps of random (seeded) or given play."""
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    trace = []
    for _ in range(steps):
        if not env.agents:
            break
        if policy is None:
            actions = {a: rng.uniform(-1, 1, 3) for a in env.agents}
        else:
            actions = policy(env, obs)
        obs, rewards, _, _, _ = env.step(actions)
        trace.append((obs, rewards))
    return trace


def test_deterministic_under_a_seed() -> None:
    a = play(parallel_env(), 7, 200)
    b = play(parallel_env(), 7, 200)
    c = play(parallel_env(), 8, 200)
    for (oa, ra), (ob, rb) in zip(a, b, strict=True):
        assert ra == rb
        for agent in oa:
            np.testing.assert_array_equal(oa[agent], ob[agent])
    assert any(not np.array_equal(a[-1][0][k], c[-1][0][k]) for k in a[-1][0])


def test_random_play_stays_finite_and_in_bounds() -> None:
    env = parallel_env(num_boats=8, laps=2)
    for seed in range(2):
        for obs, rewards in play(env, seed, 400):
            for agent, o in obs.items():
                assert o.dtype == np.float32 and env.observation_space(agent).contains(o)
            assert all(math.isfinite(r) for r in rewards.values())


def test_a_boat_alone_sails_exactly_as_the_sail_env() -> None:
    """One boat, the sail family's newest boat in still water, the same wind, heading,
    speed and actions: the same boat state, bit for bit, as the sail family's NumPy
    vector env's, started where the race started it."""
    race = parallel_env(num_boats=1, gusts=False)
    race.reset(seed=3, options={"wind_speed": 5.0, "wind_from": 1.0})
    start = race.state_.boats.boat
    sail = gym.make_vec(
        "BeachballSail-v2",
        num_envs=1,
        vectorization_mode="vector_entry_point",
        water={"wave_amplitude_m": 0.0},
        current_speed_range=(0.0, 0.0),
        gusts=False,
    )
    sail.reset(seed=0, options={"wind_speed": 5.0, "wind_from": 1.0})
    # the race's boat where the race put it, heading and moving as it drew
    state = sail.unwrapped.state
    sail.unwrapped.state = replaced(state, boat=start)
    rng = np.random.default_rng(0)
    for _ in range(300):
        action = rng.uniform(-1, 1, 3).astype(np.float32)
        race.step({"boat_0": action})
        sail.step(action[None])
    ours, theirs = race.state_.boats.boat, sail.unwrapped.state.boat
    for field, ours_value in zip(ours._fields, ours, strict=True):
        np.testing.assert_array_equal(ours_value, getattr(theirs, field), err_msg=field)
    assert math.hypot(ours.x_m[0] - start.x_m[0], ours.y_m[0] - start.y_m[0]) > 5.0  # it moved


def place(env, **fields) -> None:
    """Set fields of every boat's state (arrays of one value per boat) between steps."""
    state = env.state_
    boat = replaced(state.boats.boat, **{k: np.asarray(v, dtype=float) for k, v in fields.items()})
    env.state_ = replaced(state, boats=replaced(state.boats, boat=boat))


def _two_boats_in_line(shadow: bool, gap_m: float):
    """Two boats on a beam reach (heading east, the wind from the north), boat 1 ``gap_m``
    behind boat 0 along boat 0's apparent wind (where its sail sends the air)."""
    env = parallel_env(num_boats=2, gusts=False, shadow=shadow, countdown_s=0.0)
    env.reset(seed=0, options={"wind_speed": 5.0, "wind_from": math.pi / 2})
    flow = np.array([-2.5, -5.0]) / math.hypot(2.5, 5.0)  # the wind (0, -5) less (2.5, 0)
    place(
        env,
        x_m=[0.0, gap_m * flow[0]],
        y_m=[-30.0, -30.0 + gap_m * flow[1]],
        heading_rad=[0.0, 0.0],
        vx_mps=[2.5, 2.5],
        vy_mps=[0.0, 0.0],
        yaw_rate_rps=[0.0, 0.0],
    )
    return env


def test_a_boat_in_anothers_shadow_is_slower() -> None:
    """Boat 1 sails 6 m behind boat 0 along its apparent wind, both on the same beam reach
    with the same controls: with shadows boat 1 feels some 5% less wind and after 10 s is
    measurably slower than without them; boat 0, upwind, sails exactly as without."""
    speeds = {}
    for shadow in (False, True):
        env = _two_boats_in_line(shadow, 6.0)
        factors = []
        for _ in range(40):
            _, _, _, _, infos = env.step({"boat_0": [0.0, 0.2, 0.2], "boat_1": [0.0, 0.2, 0.2]})
            factors.append(infos["boat_1"]["wind_factor"])
        speeds[shadow] = [infos[a]["boat_speed"] for a in ("boat_0", "boat_1")]
        if shadow:
            assert np.mean(factors) < 0.97
            assert infos["boat_0"]["wind_factor"] == 1.0
        else:
            assert set(factors) == {1.0}
    assert speeds[True][1] < 0.99 * speeds[False][1]
    assert speeds[True][0] == speeds[False][0]


def test_boats_on_collision_course_bounce_and_never_overlap() -> None:
    """Two boats sailing at each other bow to bow: they touch, the step reports it, and
    their hulls never overlap by more than a centimetre."""
    from bbgym.physics.collision import hull_contacts

    env = parallel_env(num_boats=2, gusts=False, countdown_s=0.0, shadow=False)
    env.reset(seed=0, options={"wind_speed": 5.0, "wind_from": math.pi / 2})
    place(
        env,
        x_m=[-6.0, 6.0],
        y_m=[-30.0, -30.0],
        heading_rad=[0.0, math.pi],
        vx_mps=[3.0, -3.0],
        vy_mps=[0.0, 0.0],
        yaw_rate_rps=[0.0, 0.0],
    )
    touched = False
    for _ in range(12):
        _, _, _, _, infos = env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
        touched |= infos["boat_0"]["touched"]
        boat = env.state_.boats.boat
        gap = hull_contacts(
            env.task.hulls, boat.x_m[None], boat.y_m[None], boat.heading_rad[None], np
        ).gap_m[0, 0, 1]
        assert gap > -0.01
    assert touched
    assert env.state_.boats.boat.vx_mps[0] < 1.0  # stopped or sent back


def test_over_the_line_at_the_gun_must_return() -> None:
    """A boat on the course side at the gun is OCS, costs the OCS penalty, cannot start
    until it has been back below the line, and then starts."""
    env = parallel_env(num_boats=1, gusts=False, countdown_s=1.0)
    env.reset(seed=0, options={"wind_speed": 5.0, "wind_from": math.pi / 2})
    place(env, x_m=[0.0], y_m=[3.0])
    for _ in range(4):  # the gun fires at the fourth step's end
        obs, r, _, _, infos = env.step({"boat_0": [0.0, 1.0, 1.0]})
    assert infos["boat_0"]["ocs"] and infos["boat_0"]["reward_terms"]["ocs"] == -5.0
    assert obs["boat_0"][26] == 1.0 and obs["boat_0"][25] == 0.0  # the docstring's columns
    _, r, _, _, infos = env.step({"boat_0": [0.0, 1.0, 1.0]})
    assert infos["boat_0"]["ocs"] and infos["boat_0"]["reward_terms"]["ocs"] == 0.0
    assert infos["boat_0"]["leg"] == 0
    # carried back behind the line: clear; then sailing up across it: started
    place(env, y_m=[-2.0])
    _, _, _, _, infos = env.step({"boat_0": [0.0, 1.0, 1.0]})
    assert not infos["boat_0"]["ocs"] and infos["boat_0"]["leg"] == 0
    place(env, y_m=[-0.5], heading_rad=[math.pi / 2], vx_mps=[0.0], vy_mps=[4.0])
    _, r, _, _, infos = env.step({"boat_0": [0.0, 1.0, 1.0]})
    assert infos["boat_0"]["leg"] == 1 and infos["boat_0"]["reward_terms"]["waypoint"] == 5.0


class AutopilotAlone(RaceRacer):
    """The sail env's VMG autopilot on each boat's first 23 columns (the sail env's
    observation, its mark the point steered for), nothing else."""

    def __call__(self, obs):
        return self.pilot(np.asarray(obs)[..., : self.sail_size])


def autopilots(env, obs) -> dict:
    if not hasattr(env, "_pilot"):
        env._pilot = AutopilotAlone.for_env(env)
    return env._pilot.actions(obs, env.agents)


def test_autopilots_finish_the_course_in_order() -> None:
    """Boats far apart (no shadows, collisions or fouls between them) steered by the
    sail env's autopilot to the points the race names: every boat passes the start, the
    windward mark and the finish, places are 1..K in the order they finished, and the
    winner takes the largest finish reward."""
    env = parallel_env(num_boats=3, line_length_m=300.0, shadow=False, collisions=False)
    obs, _ = env.reset(seed=1)
    finish = {}
    for _ in range(3000):
        if not env.agents:
            break
        obs, _, terms, truncs, infos = env.step(autopilots(env, obs))
        for agent, info in infos.items():
            assert not truncs[agent]
            if terms[agent]:
                assert info["finished"] and info["leg"] == 3
                finish[agent] = (info["finish_time"], info["place"], info["reward_terms"]["finish"])
    assert sorted(p for _, p, _ in finish.values()) == [1, 2, 3]
    by_time = sorted(finish.values())
    assert [p for _, p, _ in by_time] == [1, 2, 3]
    assert by_time[0][2] > by_time[1][2] > by_time[2][2] > 0.0


def _port_starboard_crossing(**kwargs):
    """Boat 0 on port tack (heading north-east, the wind from the north) and boat 1 on
    starboard tack (north-west), their bows touching."""
    env = parallel_env(num_boats=2, gusts=False, countdown_s=0.0, shadow=False, **kwargs)
    env.reset(seed=0, options={"wind_speed": 5.0, "wind_from": math.pi / 2})
    place(
        env,
        x_m=[0.0, 2.5],
        y_m=[-40.0, -40.0],
        heading_rad=[math.radians(45.0), math.radians(135.0)],
        vx_mps=[0.0, 0.0],
        vy_mps=[0.0, 0.0],
        yaw_rate_rps=[0.0, 0.0],
    )
    return env


def test_a_foul_costs_a_penalty_turn_before_the_next_waypoint() -> None:
    """The port-tack boat fouls the starboard-tack one: one foul, a turn owed, the foul's
    reward; the encounter going on is no new foul; a full circle pays the turn."""
    env = _port_starboard_crossing()
    obs, r, _, _, infos = env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
    assert infos["boat_0"]["fouls"] == 1 and infos["boat_1"]["fouls"] == 0
    assert infos["boat_0"]["turns_owed"] == 1
    # the docstring's columns: a turn owed, and each sees who keeps clear of whom
    assert obs["boat_0"][28] == 0.5 and obs["boat_1"][28] == 0.0
    assert obs["boat_0"][35] == 1.0 and obs["boat_0"][42] == -1.0 and obs["boat_1"][42] == 1.0
    assert (
        infos["boat_0"]["reward_terms"]["foul"]
        == -2.0
        == r["boat_0"] - sum(v for k, v in infos["boat_0"]["reward_terms"].items() if k != "foul")
    )
    _, _, _, _, infos = env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
    assert infos["boat_0"]["fouls"] == 1
    # boat 0 spun round (a yaw rate set before each step), far from boat 1
    for step in range(24):  # noqa: B007 (read after the loop)
        boat = env.state_.boats.boat
        place(env, x_m=boat.x_m - [30.0, 0.0], yaw_rate_rps=[4.0, 0.0])
        _, _, _, _, infos = env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
        if infos["boat_0"]["turns_owed"] == 0:
            break
    # about half a radian a step: 2 pi takes 13 steps or more
    assert infos["boat_0"]["turns_owed"] == 0 and step >= 11


def test_time_penalty_delays_the_finish() -> None:
    """With ``penalty="time"`` the foul owes 20 s: two boats crossing the finish together,
    the one that fouled finishes 80 steps (20 s) after the other and second."""
    env = _port_starboard_crossing(penalty="time", penalty_time_s=20.0)
    _, _, _, _, infos = env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
    assert infos["boat_0"]["penalty_owed"] == 20.0 and infos["boat_0"]["turns_owed"] == 0
    env.state_ = replaced(env.state_, leg=np.array([[2, 2]]))  # on the way to the finish
    place(
        env,
        x_m=[-10.0, 10.0],
        y_m=[0.5, 0.5],
        heading_rad=[-math.pi / 2] * 2,
        vx_mps=[0.0, 0.0],
        vy_mps=[-4.0, -4.0],
        yaw_rate_rps=[0.0, 0.0],
    )
    finished = {}
    for step in range(200):
        _, _, terms, _, infos = env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
        finished |= {a: (step, infos[a]["place"]) for a in terms if terms[a]}
        if not env.agents:
            break
    assert finished["boat_1"] == (0, 1) and finished["boat_0"][1] == 2
    assert 79 <= finished["boat_0"][0] - finished["boat_1"][0] <= 81


@pytest.mark.parametrize(
    ("kwargs", "error", "names"),
    [
        ({"num_boats": 0}, ValueError, "num_boats"),
        ({"num_boats": 2.0}, TypeError, "num_boats"),
        ({"laps": 9}, ValueError, "laps"),
        ({"shadow_params": {"length_m": -1.0}}, ValueError, "shadow_params.length_m"),
        ({"boat": {"dinghy": {"mass_kg": -3.0}}}, ValueError, "boat.dinghy.mass_kg"),
        ({"boat": {"hull": 1}}, TypeError, "hull"),
        ({"penalty": "dsq"}, ValueError, "penalty"),
        ({"restitution": 1.5}, ValueError, "restitution"),
        ({"render_mode": "ansi"}, ValueError, "render_mode"),
    ],
)
def test_bad_arguments_name_themselves(kwargs, error, names) -> None:
    with pytest.raises(error, match=names.replace(".", r"\.")):
        parallel_env(**kwargs)


def test_bad_options_and_actions_name_themselves() -> None:
    env = parallel_env(num_boats=2)
    with pytest.raises(ValueError, match=r"options\['wind_speed'\]"):
        env.reset(options={"wind_speed": -1.0})
    # a typo of a known key (other unknown keys are ignored: tests/race/test_race_inputs.py)
    with pytest.raises(TypeError, match=r"options\['wind_sped'\]"):
        env.reset(options={"wind_sped": 1.0})
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"actions\['boat_1'\]"):
        env.step({"boat_0": [0, 0, 0], "boat_1": [np.nan, 0, 0]})
    with pytest.raises(ValueError, match="boat_1"):
        env.step({"boat_0": [0, 0, 0]})
    with pytest.raises(ValueError, match="boat_7"):
        env.step({"boat_0": [0, 0, 0], "boat_1": [0, 0, 0], "boat_7": [0, 0, 0]})


def test_the_default_boat_is_the_sail_familys_newest() -> None:
    from bbgym.envs.sail.spec import SPEC

    env = parallel_env()
    assert newest_boat()["dinghy"] == SPEC.versions[-1].kwargs["dinghy"]
    assert env.task.sail.params.rig == "sloop"
    assert env.action_space("boat_0").shape == (3,)


def test_the_scripted_racer_finishes_and_fouls_less_than_the_autopilot() -> None:
    """Two seeded four-boat races: every RaceRacer boat finishes, none over early at the
    gun is left unreturned, and the fleet commits fewer fouls than the autopilot alone
    (which neither avoids nor takes its penalty turns)."""
    fouls = {}
    for name in ("racer", "autopilot"):
        env = parallel_env(num_boats=4)
        racer = (RaceRacer if name == "racer" else AutopilotAlone).for_env(env)
        total, finished = 0, 0
        for seed in (0, 1):
            obs, _ = env.reset(seed=seed)
            racer.reset()
            last = {}
            while env.agents:
                obs, _, _, _, infos = env.step(racer.actions(obs, env.agents))
                last |= infos
            total += sum(info["fouls"] for info in last.values())
            finished += sum(info["finished"] for info in last.values())
        fouls[name] = total
        if name == "racer":
            assert finished == 8
    assert fouls["racer"] < fouls["autopilot"]


def test_render_draws_the_course_the_boats_and_their_shadows() -> None:
    """``rgb_array`` frames of a race: the course's white line and orange marks, each boat
    in its own colour, and the shaded cones (darker water) downwind of the boats; no
    frame without a render mode."""
    pytest.importorskip("pygame")
    from bbgym.envs.race.view import BOAT_COLORS, MARK_COLOR, WATER_COLOR

    env = parallel_env(num_boats=3, render_mode="rgb_array")
    env.reset(seed=0)
    for _ in range(8):
        env.step({a: [0.0, 0.0, 0.0] for a in env.agents})
    frame = env.render()
    env.close()
    assert frame.shape == (480, 640, 3) and frame.dtype == np.uint8
    pixels = frame.reshape(-1, 3)
    colours = {tuple(p) for p in np.unique(pixels, axis=0)}
    assert tuple(WATER_COLOR) in colours and tuple(MARK_COLOR) in colours
    for colour in BOAT_COLORS[:3]:
        assert tuple(colour) in colours, colour
    shaded = np.all(pixels < np.array(WATER_COLOR), axis=1).sum()
    assert shaded > 2000  # three cones of about 140 m^2, at some 2.3 px a metre
    assert parallel_env(num_boats=2).render() is None


def test_the_solo_view_is_a_gymnasium_env() -> None:
    """One boat against scripted racers: Gymnasium's env checker passes, a seed gives the
    same episode, its Gymnasium id makes it, and Gymnasium's vector env runs it."""
    from gymnasium.utils.env_checker import check_env

    from bbgym.envs.race import BeachballRaceSoloEnv

    env = BeachballRaceSoloEnv(num_boats=3)
    check_env(env, skip_render_check=True)
    runs = []
    for _ in range(2):
        obs, _ = env.reset(seed=4)
        trace = [obs]
        for t in range(60):
            obs, reward, terminated, truncated, info = env.step(
                env.action_space.sample() if t < 0 else [0.0, 0.3, 0.3]
            )
            trace.append(obs)
        runs.append(np.stack(trace))
    np.testing.assert_array_equal(runs[0], runs[1])
    assert set(info) >= {"is_success", "won", "place", "fouls"}
    # its Gymnasium id makes the same env, keyword arguments passed on, no time limit added
    made = gym.make("bbgym/BeachballRaceSolo-v0", num_boats=3)
    assert isinstance(made.unwrapped, BeachballRaceSoloEnv) and made.spec.max_episode_steps is None
    obs, _ = made.reset(seed=4)
    for _ in range(60):
        obs, *_ = made.step([0.0, 0.3, 0.3])  # the list the runs above took
    np.testing.assert_array_equal(obs, runs[0][-1])
    made.close()
    vec = gym.vector.SyncVectorEnv([lambda: BeachballRaceSoloEnv(num_boats=2)] * 2)
    obs, _ = vec.reset(seed=0)
    obs, rewards, *_ = vec.step(np.zeros((2, 3), dtype=np.float32))
    # two boats: one neighbour observed (where three boats observe two)
    assert obs.shape == (2, 23 + 12 + 8) and np.isfinite(rewards).all()
    vec.close()


def test_the_fleet_vector_env_races_as_the_pettingzoo_env() -> None:
    """Race ``r`` of the fleet env reset with ``seed=s`` is the PettingZoo env reset with
    ``seed=s + r``: the same observations and rewards under the same actions."""
    from bbgym.envs.race import BeachballRaceFleetEnv

    fleet = BeachballRaceFleetEnv(num_races=3, num_boats=2)
    obs, info = fleet.reset(seed=10)
    assert obs.shape == (6, 43) and obs.dtype == np.float32 and info["place"].shape == (6,)
    race = parallel_env(num_boats=2)
    race_obs, _ = race.reset(seed=12)
    rng = np.random.default_rng(0)
    for _ in range(120):
        np.testing.assert_array_equal(obs[4:6], np.stack([race_obs["boat_0"], race_obs["boat_1"]]))
        actions = rng.uniform(-1, 1, (6, 3)).astype(np.float32)
        obs, rewards, _, _, _ = fleet.step(actions)
        race_obs, race_rewards, _, _, _ = race.step({"boat_0": actions[4], "boat_1": actions[5]})
        assert list(rewards[4:6]) == [race_rewards["boat_0"], race_rewards["boat_1"]]
    with pytest.raises(ValueError, match="actions"):
        fleet.step(np.full((6, 3), np.nan))


def test_a_boat_that_finished_sits_out_until_its_race_restarts() -> None:
    """One race of two boats: boat 0 carried across the finish terminates (its real last
    observation), then sits out (zeros, reward 0) while boat 1 races on; at the time limit
    both stop (truncated), and the next step starts a new race (reward 0, the clock back)."""
    from bbgym.envs.race import BeachballRaceFleetEnv

    fleet = BeachballRaceFleetEnv(
        num_races=1, num_boats=2, countdown_s=0.0, max_race_time_s=20.0, gusts=False
    )
    fleet.reset(seed=0)
    state = fleet.state
    fleet.state = replaced(state, leg=np.array([[2, 0]]))  # boat 0 on its way to the finish
    # the finish line is the start line crossed downwind: boat 0 sits on top of it
    wind = fleet.state.wind_from_rad[0]
    course_up = np.array([math.cos(wind), math.sin(wind)])
    across = np.array([-course_up[1], course_up[0]])
    positions = np.stack([0.5 * course_up, 100.0 * across])
    heading0 = math.atan2(-course_up[1], -course_up[0])
    boat = replaced(
        fleet.state.boats.boat,
        x_m=positions[:, 0],
        y_m=positions[:, 1],
        heading_rad=np.array([heading0, 0.0]),
        vx_mps=np.array([-4.0 * course_up[0], 0.0]),
        vy_mps=np.array([-4.0 * course_up[1], 0.0]),
    )
    fleet.state = replaced(fleet.state, boats=replaced(fleet.state.boats, boat=boat))
    obs, rewards, terminated, truncated, info = fleet.step(np.zeros((2, 3), np.float32))
    assert list(terminated) == [True, False] and info["place"][0] == 1
    assert np.any(obs[0] != 0.0)
    for _ in range(200):
        obs, rewards, terminated, truncated, info = fleet.step(np.zeros((2, 3), np.float32))
        if truncated.any():
            break
        assert np.all(obs[0] == 0.0) and rewards[0] == 0.0 and not terminated[0]
    assert list(truncated) == [True, True] and not terminated.any()
    obs, rewards, terminated, truncated, info = fleet.step(np.zeros((2, 3), np.float32))
    assert list(rewards) == [0.0, 0.0] and not (terminated.any() or truncated.any())
    assert np.all(info["race_clock"] == 0.0) and np.any(obs != 0.0, axis=1).all()


def _draw_arguments(rng: np.random.Generator) -> dict:
    """Every race argument drawn over its accepted interval (the reward weights too), with
    a short race so that a draw costs little."""
    from bbgym.envs.race import task as rt
    from bbgym.envs.sail.task import WIND_SPEED_MPS
    from bbgym.physics.shadow import ShadowParams
    from bbgym.physics.validation import accepted_interval

    def within(interval, top=None):
        high = interval.high if top is None else min(interval.high, top)
        return float(rng.uniform(interval.low, high))

    def pair(interval, top=None):
        return tuple(sorted((within(interval, top), within(interval, top))))

    shadow = {
        f: within(accepted_interval(ShadowParams, f))
        for f in ("length_m", "base_width_m", "end_width_m", "acting_time_s", "air_height_m")
    }
    kwargs = {
        "num_boats": int(rng.integers(1, 9)),
        "laps": int(rng.integers(1, 4)),
        "neighbours": int(rng.integers(0, 8)),
        "line_length_m": within(rt.LINE_LENGTH_M),
        "leg_length_m": within(rt.LEG_LENGTH_M, 300.0),
        "gate_depth_m": within(rt.GATE_DEPTH_M),
        "gate_width_m": within(rt.GATE_WIDTH_M),
        "countdown_s": within(rt.COUNTDOWN_S, 20.0),
        "start_depth_range": pair(rt.START_DEPTH_M),
        "max_race_time_s": within(rt.RACE_TIME_S, 40.0),
        "wind_speed_range": pair(WIND_SPEED_MPS),
        "gusts": bool(rng.integers(2)),
        "shadow": bool(rng.integers(2)),
        "shadow_params": shadow,
        "collisions": bool(rng.integers(2)),
        "restitution": within(rt.RESTITUTION),
        "keep_clear_m": within(rt.KEEP_CLEAR_M),
        "penalty": str(rng.choice(rt.PENALTIES)),
        "penalty_time_s": within(rt.PENALTY_TIME_S),
        "boat": {"sail_model": str(rng.choice(["lift", "seed", "cambered"]))},
    }
    for name in (
        "progress_weight",
        "waypoint_bonus",
        "finish_bonus",
        "ocs_penalty",
        "capsize_penalty",
        "time_penalty",
        "foul_penalty",
    ):
        kwargs[name] = within(rt.REWARD_WEIGHT)
    return kwargs


def test_random_valid_arguments_run_finite() -> None:
    """Races of arguments drawn over their accepted intervals (a crowded 5 m line of eight
    boats, gales, no shadows or collisions, time penalties, ...) under random actions: every
    observation finite and inside its space, every reward finite, in the PettingZoo env
    and in a fleet of two races."""
    from bbgym.envs.race import BeachballRaceFleetEnv

    rng = np.random.default_rng(2026)
    for draw in range(24):
        kwargs = _draw_arguments(rng)
        env = parallel_env(**kwargs)
        obs, _ = env.reset(seed=draw)
        for _ in range(200):
            if not env.agents:
                break
            actions = {a: rng.uniform(-1, 1, env.action_space(a).shape) for a in env.agents}
            obs, rewards, _, _, infos = env.step(actions)
            for agent, o in obs.items():
                assert env.observation_space(agent).contains(o), (draw, kwargs)
            assert all(math.isfinite(r) for r in rewards.values()), (draw, kwargs)
        fleet = BeachballRaceFleetEnv(2, **kwargs)
        fleet.reset(seed=draw)
        for _ in range(60):
            obs, rewards, *_ = fleet.step(rng.uniform(-1, 1, fleet.action_space.shape))
            assert np.isfinite(obs).all() and np.isfinite(rewards).all(), (draw, kwargs)


@pytest.mark.parametrize("kind", ["fleet", "match"])
def test_stable_baselines3_trains_one_shared_policy_on_the_fleet(kind: str) -> None:
    """The fleet (every boat learns) and a match (two of four boats learn, correcting the
    racer) through bbgym's SB3 adapter: a boat that ends hands SB3 its last observation
    (``terminal_observation``) and begins its wait at once; a race that ends starts anew on
    that same step (its clock back at the countdown); and SB3's PPO learns a few updates
    from it."""
    pytest.importorskip("stable_baselines3")
    from stable_baselines3 import PPO

    from bbgym.envs.race import BeachballRaceFleetEnv, BeachballRaceMatchEnv
    from bbgym.sb3 import NativeVecEnvAdapter

    short = {"max_race_time_s": 10.0, "countdown_s": 5.0}
    if kind == "fleet":
        env = fleet = BeachballRaceFleetEnv(num_races=2, num_boats=2, **short)
    else:
        env = BeachballRaceMatchEnv(2, residual=True, **short)
        fleet = env.fleet
    venv = NativeVecEnvAdapter(env)
    venv.seed(0)
    venv.reset()
    for step in range(80):  # noqa: B007 (read after the loop)
        obs, rewards, dones, infos = venv.step(np.zeros((4, 3), np.float32))
        if dones.any():
            break
    assert dones.all() and step == 59  # 15 s: every boat truncated at the time limit
    assert all("terminal_observation" in info and info["TimeLimit.truncated"] for info in infos)
    assert np.all(fleet.state.clock_s == -5.0) and np.any(obs != 0.0, axis=1).all()
    model = PPO("MlpPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, seed=0)
    model.learn(128)
