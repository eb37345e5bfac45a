"""One race as frames for ``bbgym record`` (the race spec's ``record``): every boat by the
scripted racer, at random, or the learning boats of a self-play model against scripted
racers."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from bbgym.envs.race.match import BeachballRaceMatchEnv
from bbgym.envs.race.view import RaceRenderer, places_text, race_scene
from bbgym.spec import AgentsEpisode


def race_model_settings(model: Path) -> dict[str, Any]:
    """How a self-play model races (``learners``, ``residual``): the JSON file
    ``scripts/race_selfplay.py`` writes beside it.

    Args:
        model: The saved model (``.zip``).

    Returns:
        ``{"learners": int, "residual": bool}``, the match env's keywords.

    Raises:
        ValueError: If the file is missing or does not say both.
    """
    settings = model.with_suffix(".json")
    try:
        found = json.loads(settings.read_text())
        return {"learners": int(found["learners"]), "residual": bool(found["residual"])}
    except (OSError, KeyError, TypeError, ValueError) as err:
        raise ValueError(
            f"--model {model}: {settings.name} beside it should say how it races "
            f"(learners, residual; scripts/race_selfplay.py writes it): {err}"
        ) from None


def race_outcome(place: np.ndarray, learned: np.ndarray) -> str:
    """The last caption of a race: the places in words (:func:`places_text`: ``"1st
    boat_1, 2nd boat_2, 3rd boat_3; boat_0 did not finish"``), learned boats marked ``*``
    where only some boats learn.

    Args:
        place: Each boat's place (0: did not finish).
        learned: Whether each boat is the model's.

    Returns:
        The caption.
    """
    return places_text(np.asarray(place).tolist(), np.asarray(learned, bool).tolist())


def recorded_race(
    policy_name: str,
    *,
    seed: int = 0,
    max_steps: int | None = None,
    model: Path | None = None,
    load_policy: Callable[[Any, Path], Callable[[Any], Any]] | None = None,
) -> AgentsEpisode:
    """One race (``reset(seed=seed)``), a frame per 0.25 s step and the first, each with
    the race clock as its caption; returns its statistics (``steps``, ``outcome``: the
    places in words, ``capped``, ``place``).

    Args:
        policy_name: ``"scripted"`` (every boat the racer), ``"random"`` or ``"ppo"``
            (the learning boats of ``model``, as it was trained, against scripted racers).
        seed: The race's seed (and the random actions').
        max_steps: Stop after this many steps (``None``: when the race ends).
        model: A model of ``scripts/race_selfplay.py`` (``"ppo"`` only).
        load_policy: ``load_policy(env, model) -> policy`` (``"ppo"`` only).

    Returns:
        A generator of ``(frame, caption)`` pairs that returns the statistics.

    Raises:
        ValueError: If ``"ppo"`` has no model or loader, or the model's settings are
            missing.
    """
    boats = BeachballRaceMatchEnv(1).num_boats
    learnt = None
    if policy_name == "ppo":
        if model is None or load_policy is None:
            raise ValueError("--policy ppo needs --model (a model of scripts/race_selfplay.py)")
        env = BeachballRaceMatchEnv(1, **race_model_settings(model))
        learnt = load_policy(env, model)
    else:  # every boat: the racer (a zero correction of its own action) or random
        env = BeachballRaceMatchEnv(1, learners=boats, residual=policy_name == "scripted")
        env.action_space.seed(seed)
    return _frames(env, learnt, policy_name == "scripted", seed, max_steps)


def _frames(
    env: BeachballRaceMatchEnv,
    learnt: Callable[[Any], Any] | None,
    scripted: bool,
    seed: int,
    max_steps: int | None,
) -> AgentsEpisode:
    renderer = RaceRenderer("rgb_array", 640, 480, 4.0)
    try:
        obs, _ = env.reset(seed=seed)

        def frame() -> tuple[np.ndarray, str]:
            clock = f"race clock {float(env.fleet.state.clock_s[0]):+.0f} s"
            return renderer.render(race_scene(env.task, env.fleet.state)), clock

        yield frame()
        steps = 0
        while not env.fleet.races_ended[0] and (max_steps is None or steps < max_steps):
            if learnt is not None:
                action = learnt(obs)
            elif scripted:
                action = np.zeros(env.action_space.shape, np.float32)
            else:
                action = env.action_space.sample()
            obs, *_ = env.step(action)
            steps += 1
            yield frame()
        place = env.fleet.state.place[0]
        return {
            "steps": steps,
            "outcome": race_outcome(place, env.mask[0]),
            "capped": not bool(env.fleet.races_ended[0]),
            "place": np.asarray(place).tolist(),
        }
    finally:
        renderer.close()
        env.close()
