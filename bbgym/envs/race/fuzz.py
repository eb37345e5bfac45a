"""Fuzzing the PettingZoo race: its arguments, its parallel and AEC forms stepped with bad
actions among the valid ones, and its invalid numbers. ``bbgym fuzz`` finds it through the
race's spec (:data:`FUZZ`); the tools it uses are :mod:`bbgym.fuzz`'s."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

import numpy as np

from bbgym.fuzz.draws import (
    COST_CAPS,
    Draw,
    draw_flag,
    draw_int,
    draw_pair,
    sample_params,
)
from bbgym.fuzz.envs import (
    BAD_ACTION_RATE,
    bad_action,
    check_refusals,
    check_step,
    finite_floats,
)
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.validation import Interval
from bbgym.spec import MultiAgentFuzz

RACE_FORMS = ("parallel", "aec")
"""The race's two PettingZoo forms :func:`check_race_episode` steps: every boat acting at
once (``bbgym.envs.race.parallel_env``), and boats acting in turn (``bbgym.envs.race.env``)."""

RACE_EPISODE_STEPS = 160
"""Race steps (of 0.25 s) per check of the long run: 40 s, past the gun of a countdown of
at most :data:`COST_CAPS`'s ``race_countdown_s``."""

RACE_INFINITE_UNTIL_SET = ("finish_time",)
"""Race infos that are ``inf`` until they happen (a boat's finish time before it
finishes): ``+inf`` is their value then, ``-inf`` or NaN still a failure."""


def _log(accepted: Interval) -> bool:
    """Whether :func:`sample_params` draws inside ``accepted`` log-uniform (positive)."""
    return accepted.low > 0.0 or accepted.low_open


def sample_race_kwargs(draw: Draw) -> dict[str, Any]:
    """The race's constructor arguments (:class:`bbgym.envs.race.task.RaceTask`) over
    their accepted intervals: its counts, its course, its wind and gusts, its shadows, its
    rules and reward weights, and a ``boat`` with any of its keys (each present or not: an
    absent key keeps the newest sail env's): a dinghy with every constant drawn, either
    rig. A race step is 0.25 s in five substeps whatever the arguments, and one of eight
    boats costs about what one of one does, so only the countdown is capped
    (:data:`COST_CAPS`), that a check of :data:`RACE_EPISODE_STEPS` sees the gun.

    Args:
        draw: draws each number.

    Returns:
        Keyword arguments for ``bbgym.envs.race.parallel_env`` (and ``env``).
    """
    from bbgym.envs.race import task as race
    from bbgym.envs.sail import task as sail
    from bbgym.physics.dinghy import RIGS, SAIL_MODELS
    from bbgym.physics.shadow import ShadowParams
    from bbgym.physics.wind import GustParams

    def number(name: str, accepted: Interval) -> float:
        return draw(name, accepted, _log(accepted))

    def count(name: str, accepted: Interval) -> int:
        return draw_int(draw, name, int(accepted.low), int(accepted.high))

    kwargs: dict[str, Any] = {
        "num_boats": count("num_boats", race.BOATS),
        "neighbours": count("neighbours", race.NEIGHBOURS),
        "laps": count("laps", race.LAPS),
        "line_length_m": number("line_length_m", race.LINE_LENGTH_M),
        "leg_length_m": number("leg_length_m", race.LEG_LENGTH_M),
        "gate_depth_m": number("gate_depth_m", race.GATE_DEPTH_M),
        "gate_width_m": number("gate_width_m", race.GATE_WIDTH_M),
        "countdown_s": number("countdown_s", COST_CAPS["race_countdown_s"]),
        "start_depth_range": draw_pair(draw, "start_depth_range", race.START_DEPTH_M),
        "max_race_time_s": number("max_race_time_s", race.RACE_TIME_S),
        "wind_speed_range": draw_pair(draw, "wind_speed_range", sail.WIND_SPEED_MPS),
        "gusts": draw_flag(draw, "gusts"),
        "gust_params": sample_params(draw, GustParams, "gust_params"),
        "shadow": draw_flag(draw, "shadow"),
        "shadow_params": sample_params(draw, ShadowParams, "shadow_params"),
        "collisions": draw_flag(draw, "collisions"),
        "restitution": number("restitution", race.RESTITUTION),
        "keep_clear_m": number("keep_clear_m", race.KEEP_CLEAR_M),
        "penalty": race.PENALTIES[draw_int(draw, "penalty", 0, len(race.PENALTIES) - 1)],
        "penalty_time_s": number("penalty_time_s", race.PENALTY_TIME_S),
    }
    for name in race.REWARD_WEIGHTS:
        kwargs[name] = draw(name, race.REWARD_WEIGHT, False)
    boat: dict[str, Any] = {}
    if draw_flag(draw, "boat.has_sail_model"):
        boat["sail_model"] = SAIL_MODELS[draw_int(draw, "boat.sail_model", 0, len(SAIL_MODELS) - 1)]
    if draw_flag(draw, "boat.has_dinghy"):
        dinghy = sample_params(draw, DinghyParams, "boat.dinghy")
        dinghy["rig"] = RIGS[draw_int(draw, "boat.dinghy.rig", 0, len(RIGS) - 1)]
        boat["dinghy"] = dinghy
    if draw_flag(draw, "boat.has_initial_sheet"):
        boat["initial_sheet"] = draw("boat.initial_sheet", sail.UNIT_INTERVAL, False)
    if draw_flag(draw, "boat.has_initial_speed_range"):
        boat["initial_speed_range"] = draw_pair(
            draw, "boat.initial_speed_range", sail.INITIAL_SPEED_MPS
        )
    if boat:
        kwargs["boat"] = boat
    return kwargs


def sample_race_options(draw: Draw) -> dict[str, Any] | None:
    """The race's ``reset`` options (its mean wind's speed and direction, its gusts on or
    off), each present or not, over their accepted intervals.

    Args:
        draw: draws each number.

    Returns:
        The options, or ``None`` for none.
    """
    from bbgym.envs.sail import task as sail
    from bbgym.physics.validation import ANGLE_RAD

    options: dict[str, Any] = {}
    if draw_flag(draw, "options.has_wind_speed"):
        options["wind_speed"] = draw("options['wind_speed']", sail.WIND_SPEED_MPS, False)
    if draw_flag(draw, "options.has_wind_from"):
        options["wind_from"] = draw("options['wind_from']", ANGLE_RAD, False)
    if draw_flag(draw, "options.has_gusts"):
        options["gusts"] = draw_flag(draw, "options['gusts']")
    return options or None


def _check_race_info(info: Mapping, where: str) -> None:
    """Every float of one boat's info finite, but :data:`RACE_INFINITE_UNTIL_SET`'s, which
    may also be ``+inf``."""
    shown = dict(info)
    for key in RACE_INFINITE_UNTIL_SET:
        if key in shown:
            value = np.asarray(shown[key], dtype=np.float64)
            shown[key] = np.where(value == math.inf, 0.0, value)
    finite_floats(shown, where)


def _check_race_outputs(
    env: Any, agents: list[str], obs: Mapping, rewards: Mapping, infos: Mapping, where: str
) -> None:
    """A parallel reset's or step's dicts: one entry per boat of ``agents`` in each, every
    observation inside its boat's space, every reward and info float finite."""
    for name, outputs in (("observations", obs), ("infos", infos)):
        if set(outputs) != set(agents):
            raise AssertionError(f"{where}: {name} for {sorted(outputs)}, racing {agents}")
    for agent in agents:
        check_step(
            env.observation_space(agent),
            obs[agent],
            rewards.get(agent, 0.0),
            {},
            f"{where} {agent}",
        )
        _check_race_info(infos[agent], f"{where} {agent}: info")


def _race_action(env: Any, agent: str, rng: np.random.Generator) -> np.ndarray:
    """A random action over the box and beyond it (the race clips to [-1, 1])."""
    return rng.uniform(-1.5, 1.5, env.action_space(agent).shape).astype(np.float32)


def _race_snapshot(race: Any) -> tuple:
    """What a refused action must leave as it was: the race's state (immutable, replaced
    by each step), its boats racing and its random generator."""
    return race.state_, list(race.agents), race._np_random.bit_generator.state


def _check_race_refusal(
    race: Any,
    step: Callable[[Any], Any],
    bad: Any,
    agent: str,
    name: str,
    error: type,
    where: str,
) -> None:
    """``step(bad)`` (``bad`` holding a bad action of ``agent``) raises ``error`` naming the
    boat and leaves the race as it was."""
    before = _race_snapshot(race)
    try:
        step(bad)
    except error as raised:
        if repr(agent) not in str(raised):
            raise AssertionError(
                f"{where}: a {name} action of {agent} raised {raised!r}, which does not name it"
            ) from None
    except Exception as raised:  # noqa: BLE001 - reported as the wrong error
        raise AssertionError(
            f"{where}: a {name} action of {agent} raised {type(raised).__name__} ({raised}), "
            f"expected {error.__name__}"
        ) from None
    else:
        raise AssertionError(f"{where}: a {name} action of {agent} was accepted")
    after = _race_snapshot(race)
    if after[0] is not before[0] or after[1] != before[1] or after[2] != before[2]:
        raise AssertionError(f"{where}: a refused {name} action of {agent} changed the race")


def check_race_episode(
    kwargs: Mapping[str, Any],
    steps: int,
    seed: int,
    form: str,
    options: Mapping[str, Any] | None = None,
) -> int:
    """Race ``steps`` steps of random actions (each boat's box, beyond [-1, 1] too) in one
    of :data:`RACE_FORMS`, resetting (with ``options``) when every boat's race has ended,
    and check every output: the dicts name the boats racing, each observation lies inside
    its boat's space, every reward and info float is finite. Before one step in ten
    (:data:`BAD_ACTION_RATE`; in the AEC form, one turn in ten) a boat's action with one
    entry NaN, inf or complex (:data:`BAD_ACTIONS`) must raise the right error naming the
    boat and change nothing; the valid action then goes through.

    Args:
        kwargs: the race's constructor arguments (:func:`sample_race_kwargs`).
        steps: race steps to take; the AEC form takes ``num_boats`` turns a step.
        seed: seeds the race and the actions.
        form: ``"parallel"`` or ``"aec"``.
        options: ``reset`` options, or ``None``.

    Returns:
        The boat steps taken: each racing boat's action in a parallel step, each turn in
        the AEC form (a finished boat's last turn included).
    """
    if form not in RACE_FORMS:
        raise ValueError(f"form must be one of {RACE_FORMS}, got {form!r}")
    from bbgym.envs.race import env as aec_env
    from bbgym.envs.race import parallel_env

    rng = np.random.default_rng(seed)
    where = f"race ({form})"
    if form == "parallel":
        race = parallel_env(**kwargs)
        try:
            return _race_parallel(race, steps, seed, options, rng, where)
        finally:
            race.close()
    env = aec_env(**kwargs)
    try:
        return _race_aec(env, steps, seed, options, rng, where)
    finally:
        env.close()


def _race_parallel(
    race: Any, steps: int, seed: int, options: Any, rng: np.random.Generator, where: str
) -> int:
    obs, infos = race.reset(seed=seed, options=options)
    _check_race_outputs(race, list(race.agents), obs, {}, infos, f"{where} reset")
    taken = 0
    for t in range(steps):
        if not race.agents:
            obs, infos = race.reset(options=options)
            _check_race_outputs(race, list(race.agents), obs, {}, infos, f"{where} reset")
        racing = list(race.agents)
        actions = {agent: _race_action(race, agent, rng) for agent in racing}
        if rng.random() < BAD_ACTION_RATE:
            agent = racing[int(rng.integers(len(racing)))]
            name, bad, error = bad_action(actions[agent], rng)
            _check_race_refusal(
                race,
                race.step,
                {**actions, agent: bad},
                agent,
                name,
                error,
                f"{where} step {t}",
            )
        obs, rewards, terminations, truncations, infos = race.step(actions)
        _check_race_outputs(race, racing, obs, rewards, infos, f"{where} step {t}")
        for name, flags in (("terminations", terminations), ("truncations", truncations)):
            if set(flags) != set(racing):
                raise AssertionError(f"{where} step {t}: {name} for {sorted(flags)}")
        taken += len(racing)
    return taken


def _race_aec(
    env: Any, steps: int, seed: int, options: Any, rng: np.random.Generator, where: str
) -> int:
    race = env.unwrapped
    env.reset(seed=seed, options=options)
    turns = steps * len(race.possible_agents)
    for t in range(turns):
        if not env.agents:
            env.reset(options=options)
        agent = env.agent_selection
        obs, reward, terminated, truncated, info = env.last()
        check_step(env.observation_space(agent), obs, reward, {}, f"{where} turn {t} {agent}")
        _check_race_info(info, f"{where} turn {t} {agent}: info")
        action = None
        if not (terminated or truncated):
            action = _race_action(env, agent, rng)
            if rng.random() < BAD_ACTION_RATE:
                name, bad, error = bad_action(action, rng)
                _check_race_refusal(race, env.step, bad, agent, name, error, f"{where} turn {t}")
                if env.agent_selection != agent:
                    raise AssertionError(
                        f"{where} turn {t}: {agent} lost its turn to a refused action"
                    )
        env.step(action)
    return turns


def race_numeric_arguments() -> list[str]:
    """The race's constructor arguments that take one number, each field of its parameter
    groups as ``group.field`` and the boat's as ``boat.dinghy.field`` (for
    :func:`check_race_rejections`).

    Returns:
        The paths, as the errors name them.
    """
    import inspect

    from bbgym.envs.race.task import RaceTask
    from bbgym.physics.shadow import ShadowParams
    from bbgym.physics.wind import GustParams

    names = []
    for name, parameter in inspect.signature(RaceTask.__init__).parameters.items():
        default = parameter.default
        if isinstance(default, (int, float)) and not isinstance(default, bool):
            names.append(name)
    names.append("boat.initial_sheet")
    for group, cls in (
        ("boat.dinghy", DinghyParams),
        ("gust_params", GustParams),
        ("shadow_params", ShadowParams),
    ):
        names += [
            f"{group}.{f.name}"
            for f in fields(cls)
            if "interval" in f.metadata and not isinstance(f.default, bool)
        ]
    return names


def check_race_rejections() -> int:
    """Every number argument of the race (:func:`race_numeric_arguments`) refuses every
    value of :data:`BAD_NUMBERS` at construction with the right error naming its path
    (``boat.dinghy.mass_kg``; :func:`check_refusals`): an int argument (``num_boats``)
    refuses every float with ``TypeError``.

    Returns:
        How many errors were checked.
    """
    import inspect

    from bbgym.envs.race import parallel_env
    from bbgym.envs.race.task import RaceTask

    signature = inspect.signature(RaceTask.__init__).parameters
    paths = race_numeric_arguments()
    integers = {
        path
        for path in paths
        if path in signature
        and isinstance(signature[path].default, int)
        and not isinstance(signature[path].default, bool)
    }
    return check_refusals(parallel_env, paths, integers, "race")


FUZZ = MultiAgentFuzz(
    forms=RACE_FORMS,
    episode_steps=RACE_EPISODE_STEPS,
    sample_kwargs=sample_race_kwargs,
    sample_options=sample_race_options,
    check_episode=check_race_episode,
    check_rejections=check_race_rejections,
)
"""The race's fuzzing, as ``bbgym fuzz`` takes it (:attr:`bbgym.spec.MultiAgentSpec.fuzz`)."""
