"""The sailing family's spec: versions, arguments, fuzzing and agents (see :mod:`bbgym.spec`)."""

from __future__ import annotations

from typing import Any

from bbgym.envs.sail.task import ARGUMENT_TABLE
from bbgym.physics.calibration import CALIBRATED_SLOOP
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.water import WaterParams
from bbgym.physics.wind import GustParams
from bbgym.spec import EnvSpec, FuzzSpec, Showcase, Version

SHOWCASE = Showcase(seed=16, frame_skip=1, fps=10.0)
"""Seed 16 puts the mark upwind, so the episode is a beat with tacks, what the env is
about (a reach shows little); a frame every 0.25 s step at 10 fps plays 2.5x real time,
slow enough to follow the tacks. ``bbgym baseline`` records it, ``bbgym demo`` sails it."""

MAX_EPISODE_STEPS = 1200
"""300 s at 0.25 s a step: enough to beat 100 m upwind in light air."""

SMALL_WAVES = {
    "wave_amplitude_m": 0.1,
    "wavelength_m": 10.0,
    "wave_components": 3,
    "wave_spread_rad": 0.5,
}
"""v2's sea: 0.2 m from trough to crest, 10 m long, three components over +-29 deg: the
short chop 10 to 15 knots raise over a few kilometres of open water."""

V2_KWARGS = {
    "sail_model": "cambered",
    # The sail model once, as ``sail_model``: a user's ``sail_model=`` then changes the
    # sloop's (the race's ``boat={"sail_model": ...}`` too) without disagreeing with it.
    "dinghy": {k: v for k, v in CALIBRATED_SLOOP.items() if k != "sail_model"},
    "water": SMALL_WAVES,
    "current_speed_range": (0.0, 0.3),
    "initial_sheet": 1.0,
    "time_penalty": 0.1,
    "capsize_penalty": 30.0,
}
"""BeachballSail-v2: the sloop calibrated to a Laser, a light current (up to 0.3 m/s, 0.6
knots) and small waves, the boat starting with its sheets eased (sheeted in on a reach in
a gust, it would capsize before any policy could act), v1's reward."""


def _scripted(env: Any) -> Any:
    from bbgym.agents import VMGAutopilot

    return VMGAutopilot.for_env(env)


def _simple(env: Any) -> Any:
    from bbgym.agents import SimpleSailController

    return SimpleSailController(dinghy=env.unwrapped.task.params)


def _outcome(env: Any, info: dict[str, Any], terminated: bool, truncated: bool) -> tuple:
    if bool(info.get("is_success", False)):
        return "success: reached the mark", True
    if terminated:
        return ("capsized", False) if bool(info.get("capsized", False)) else ("failed", False)
    return "timed out", False


def _keyboard(env: Any, seed: int | None) -> Any:
    from bbgym.envs.sail.keys import SailKeys

    return SailKeys(env, seed)


def _demo(seed: int | None, frame_skip: int) -> tuple:
    from bbgym.envs.sail.demo import demo

    return demo(SHOWCASE.seed if seed is None else seed, frame_skip)


def _sample_kwargs(version: Version, draw: Any) -> dict[str, Any]:
    """Every argument over its accepted interval, the step sizes and mark distances over
    their cheap ends (:data:`bbgym.fuzz.COST_CAPS`)."""
    from bbgym.envs.sail import task
    from bbgym.fuzz.draws import COST_CAPS, draw_flag, draw_int, draw_pair, sample_params
    from bbgym.physics.dinghy import RIGS, SAIL_MODELS
    from bbgym.physics.validation import interval
    from bbgym.physics.water import WaterParams, max_wave_amplitude

    sim_dt = draw("sim_dt", COST_CAPS["sail_sim_dt"], True)
    substeps = draw_int(draw, "substeps", 1, int(COST_CAPS["sail_substeps"].high))
    mark_radius = draw("mark_radius", task.MARK_RADIUS_M, True)
    far = interval(mark_radius, mark_radius + COST_CAPS["mark_distance"].high, low_open=True)
    dinghy = sample_params(draw, DinghyParams, "dinghy")
    dinghy["rig"] = RIGS[draw_int(draw, "dinghy.rig", 0, len(RIGS) - 1)]
    water = sample_params(draw, WaterParams, "water")
    # Waves as steep as accepted at most: the amplitude as a share of that.
    most = max_wave_amplitude(water["wavelength_m"], water["wave_components"])
    water["wave_amplitude_m"] = draw("water.wave_amplitude_m", interval(0.0, most), False)
    kwargs = {
        "sail_model": SAIL_MODELS[draw_int(draw, "sail_model", 0, len(SAIL_MODELS) - 1)],
        "dinghy": dinghy,
        "water": water,
        "current_speed_range": draw_pair(draw, "current_speed_range", task.CURRENT_SPEED_MPS),
        "gust_params": sample_params(draw, GustParams, "gust_params"),
        "wind_speed_range": draw_pair(draw, "wind_speed_range", task.WIND_SPEED_MPS),
        "gusts": draw_flag(draw, "gusts"),
        "mark_radius": mark_radius,
        "mark_distance_range": draw_pair(draw, "mark_distance_range", far),
        "initial_speed_range": draw_pair(draw, "initial_speed_range", task.INITIAL_SPEED_MPS),
        "sim_dt": sim_dt,
        "ctrl_dt": sim_dt * substeps,
    }
    for name in ("progress_weight", "arrival_bonus", "capsize_penalty", "time_penalty"):
        kwargs[name] = draw(name, task.REWARD_WEIGHT, False)
    return kwargs


def _sample_options(sail_task: Any, draw: Any) -> dict[str, Any] | None:
    from bbgym.envs.sail import task
    from bbgym.fuzz.draws import COST_CAPS, draw_flag, draw_vector
    from bbgym.physics.validation import interval

    options: dict[str, Any] = {}

    def maybe(key: str) -> bool:
        return draw_flag(draw, f"options.has_{key}")

    if maybe("gusts"):
        options["gusts"] = draw_flag(draw, "options['gusts']")
    for key, accepted in (("wind_speed", task.WIND_SPEED_MPS), ("speed", task.INITIAL_SPEED_MPS)):
        if maybe(key):
            options[key] = draw(f"options[{key!r}]", accepted, False)
    angles = ["wind_from", "heading"]
    if sail_task.moving_water:
        if maybe("current_speed"):
            speed = draw("options['current_speed']", task.CURRENT_SPEED_MPS, False)
            options["current_speed"] = speed
        angles.append("current_set")
    if sail_task.water.components:
        angles += ["wave_direction", "wave_phase"]
    for key in angles:
        if maybe(key):
            options[key] = draw(f"options[{key!r}]", interval(-10.0, 10.0), False)
    if maybe("mark"):
        lo = sail_task.mark_distance.low
        near = interval(lo, lo + COST_CAPS["mark_distance"].high, low_open=True)
        options["mark"] = draw_vector(draw, "mark", near)
    return options or None


SPEC = EnvSpec(
    family="sail",
    env_class="BeachballSailEnv",
    vector_env_class="BeachballSailVectorEnv",
    max_episode_steps=MAX_EPISODE_STEPS,
    summary="sail a dinghy to a mark anywhere on the water (beat, tack, jibe) upright",
    actions="rudder, main sheet",
    versions=(
        Version(
            "BeachballSail-v0",
            "the first version: progress, +10 at the mark, -10 a capsize, -0.01 a step",
            preset="beachball_sail",
            base=True,
        ),
        # Time costs enough to race: 0.1 a step, against 0.01, and a capsize 30, more than
        # the discounted cost of the time left in any episode.
        Version(
            "BeachballSail-v1",
            "v0's physics; time costs 0.1 a step, a capsize 30",
            kwargs={"time_penalty": 0.1, "capsize_penalty": 30.0},
            preset="beachball_sail_v1",
        ),
        Version(
            "BeachballSail-v2",
            "a sloop calibrated to a Laser (cambered sails, a jib sheet as a third action), "
            "a light current and small waves; v1's reward",
            kwargs=V2_KWARGS,
            preset="beachball_sail_v2",
            actions="rudder, main sheet, jib sheets",
        ),
    ),
    jax_params=("dinghy.mass_kg", "dinghy.sail_area_m2"),
    param_groups={"dinghy": DinghyParams, "gust_params": GustParams, "water": WaterParams},
    shorthands={"sail_model": "dinghy.sail_model"},
    integer_arguments=("water.wave_components",),
    policies={"scripted": _scripted, "simple": _simple},
    timed_by_oracle=True,
    outcome=_outcome,
    argument_table=ARGUMENT_TABLE,
    fuzz=FuzzSpec(_sample_kwargs, _sample_options, step_share=0.4, episode_steps=300),
    keyboard=_keyboard,
    demo=_demo,
    showcase=SHOWCASE,
)
