"""The privileged throw planner: its hits are real (a copy of the env draws the very gusts
the env does), and it wins what the observation-only solver wins."""

from __future__ import annotations

import copy

import gymnasium as gym
import numpy as np
import pytest
from bbgym.agents.planner import (
    plan_throw,
    plan_throw_episode,
    plan_topple,
    plan_topple_episode,
    winnable_fraction,
)

import bbgym  # noqa: F401


@pytest.mark.parametrize("env_id", ["BeachballThrow-v0", "BeachballCurve-v0"])
def test_a_copy_of_the_env_flies_the_same_throw(env_id):
    """What the planner verifies on a copy is what the env then does: same gusts, same
    landing, to the bit."""
    env = gym.make(env_id)
    env.reset(seed=11)  # gusts on: the flight draws from the env's stream
    action = np.array([0.4, 0.1, 0.35, 0.2, 0.0, 0.1], np.float32)
    trial = copy.deepcopy(env)
    copied = trial.step(action)
    real = env.step(action)
    assert copied[1] == real[1] and copied[4]["miss_distance"] == real[4]["miss_distance"]
    np.testing.assert_array_equal(copied[4]["trajectory"], real[4]["trajectory"])
    env.close()


def test_a_planned_hit_hits():
    env = gym.make("BeachballCurve-v0")
    env.reset(seed=3)
    action, hits = plan_throw(env, refine=2, candidates=3)
    assert hits
    *_, info = env.step(action)
    assert info["is_success"] and info["miss_distance"] <= env.unwrapped.task.target_radius
    env.close()


def test_the_planner_wins_at_least_what_the_scripted_solver_wins():
    from bbgym.cli.evaluate import evaluate

    seeds = 4
    scripted = evaluate("BeachballCurve-v0", "scripted", seeds, 20, None)
    planned = winnable_fraction("BeachballCurve-v0", seeds, seed=20, refine=2, candidates=3)
    assert planned["winnable"] >= scripted["success_rate"]
    assert planned["seeds"] == [20, 23] and len(planned["lost_seeds"]) == round(
        seeds * (1 - planned["winnable"])
    )
    episode = plan_throw_episode(gym.make("BeachballThrow-v0"), 0, refine=2, candidates=3)
    assert episode.won and episode.throws == len(episode.misses_m) >= 1


def test_a_topple_plan_that_wins_on_the_core_wins_on_the_env():
    """The search steps the task core on NumPy batches with the noise the env's stream
    will give: its winning plan (here one that waits for its moment first) wins when the
    env plays it, and planning leaves the env as it was."""
    env = gym.make("BeachballTopple-v0")
    env.reset(seed=8)
    untouched = copy.deepcopy(env)
    plan = plan_topple(env)
    assert plan.wins and len(plan.actions) >= 2
    assert not np.any(plan.actions[0][:3])  # it waits first: a throw now would not do
    wait = np.zeros(6, np.float32)
    np.testing.assert_array_equal(env.step(wait)[0], untouched.step(wait)[0])
    env.reset(seed=8)
    info = {}
    for action in plan.actions:
        *_, info = env.step(action.astype(np.float32))
    assert info["is_success"] and info["wall_state"] in ("fallen_away", "loose")
    env.close()


def test_the_topple_planner_wins_at_least_what_the_scripted_agent_wins():
    from bbgym.cli.evaluate import evaluate

    seeds, first = 6, 0
    scripted = evaluate("BeachballTopple-v0", "scripted", seeds, first, None)
    planned = winnable_fraction("BeachballTopple-v0", seeds, seed=first)
    assert planned["winnable"] >= scripted["success_rate"]
    as_policy = evaluate("BeachballTopple-v0", "planner", seeds, first, None)
    assert as_policy["success_rate"] == planned["winnable"]
    episode = plan_topple_episode(gym.make("BeachballTopple-v0"), 3)
    assert episode.won and episode.throws == 1  # seed 3: one throw from the start does it
