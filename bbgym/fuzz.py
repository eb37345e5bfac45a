"""Fuzzing the envs through their public API: random valid arguments, options and actions.

Every accepted input must run finite, stay inside the observation space and raise nothing;
every rejected one must raise ``TypeError`` or ``ValueError`` naming the argument. One
sampler serves both the property-based tests (``tests/test_fuzz.py``, where hypothesis
draws each number, so a failure shrinks to a small example) and the long run of
``bbgym fuzz`` (a NumPy generator draws them):

* :func:`sample_kwargs` draws constructor arguments: every field of the physics parameter
  dataclasses over its whole accepted interval (log-uniform where the interval is
  positive, ends included), and the task's arguments within their intervals;
* :func:`sample_options` draws ``reset`` options within the same intervals;
* :func:`check_episode` steps a single env or a native vector env with random actions and
  checks every output; :func:`check_rejections` passes invalid values and checks the
  errors;
* :func:`sample_race_kwargs` and :func:`check_race_episode` do the same for the PettingZoo
  race (``bbgym.envs.race``, its parallel and AEC forms), :func:`check_race_rejections`
  for its invalid numbers;
* :func:`sample_scene_params` and :func:`check_scene` for the course's scenes
  (``bbgym.scenes``), on NumPy and torch.

Step sizes and time limits are drawn from the slow end of their intervals only (a sim_dt
of 1e-4 s is accepted, but a fuzz run of a million steps at it would take days): the
:data:`COST_CAPS` say where; :data:`SCENE_MOST_BODIES` caps the scenes' counts alike.
:func:`run` is the long run, :func:`format_report` its tables.
"""

from __future__ import annotations

import importlib
import math
import re
import sys
from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the ids)
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.validation import Interval, interval
from bbgym.physics.wall import WallParams
from bbgym.spec import spec_of

Draw = Callable[[str, Interval, bool], float]
"""``draw(name, interval, log) -> float``: a number inside ``interval`` (log-uniform if
``log``); ``name`` identifies the draw (hypothesis labels it)."""

COST_CAPS = {
    "sail_sim_dt": interval(0.02, 0.25),
    "sail_substeps": interval(1, 10),
    "ball_sim_dt": interval(0.005, 0.05),
    "max_flight_time": interval(0.5, 12.0),
    "topple_interval": interval(0.5, 4.0),
    "mark_distance": interval(0.0, 500.0),
    "race_countdown_s": interval(0.0, 30.0),
}
"""Where the fuzzer draws from less than the accepted interval, to bound the cost of a
step (each is the cheap end of an interval the validation accepts)."""


def numpy_draw(rng: np.random.Generator) -> Draw:
    """A :data:`Draw` from a NumPy generator: ends of closed intervals one time in ten
    each, else uniform (log-uniform for ``log``)."""

    def draw(name: str, accepted: Interval, log: bool) -> float:
        lo, hi = accepted.low, accepted.high
        u = rng.random()
        if u < 0.1 and not accepted.low_open:
            return lo
        if u < 0.2 and not accepted.high_open:
            return hi
        if log and hi > 0.0:
            low = log_floor(accepted)
            value = math.exp(rng.uniform(math.log(low), math.log(hi)))
        else:
            value = rng.uniform(lo, hi)
        return float(min(max(value, lo), hi)) if accepted.contains(value) else (lo + hi) / 2

    return draw


def log_floor(accepted: Interval) -> float:
    """Where a log-uniform draw starts: the low end, or six decades below the high end
    for an interval open at 0."""
    return accepted.low if accepted.low > 0.0 else accepted.high * 1e-6


def draw_pair(draw: Draw, name: str, accepted: Interval, log: bool = False) -> tuple:
    """A ``(low, high)`` range inside ``accepted``."""
    a, b = draw(f"{name}[0]", accepted, log), draw(f"{name}[1]", accepted, log)
    return (min(a, b), max(a, b))


def draw_flag(draw: Draw, name: str) -> bool:
    return draw(name, interval(0.0, 1.0), False) < 0.5


def draw_int(draw: Draw, name: str, low: int, high: int) -> int:
    return int(min(high, math.floor(draw(name, interval(low, high + 1, high_open=True), False))))


def sample_params(
    draw: Draw, cls: type, prefix: str, caps: Mapping[str, Interval] | None = None
) -> dict[str, Any]:
    """Every field of a parameter dataclass over its accepted interval (or over its
    ``caps`` entry, a part of it that bounds the cost). Cross-field constraints are met by
    construction where the class has them.

    Args:
        draw: draws each number.
        cls: the dataclass.
        prefix: the draws' labels begin with it (``dinghy``: ``dinghy.mass_kg``).
        caps: intervals to draw some fields from instead, by field name.

    Returns:
        The drawn fields by name (those without a finite interval left out).
    """
    values: dict[str, Any] = {}
    for f in fields(cls):
        if isinstance(f.default, bool):
            values[f.name] = draw_flag(draw, f"{prefix}.{f.name}")
            continue
        accepted = (caps or {}).get(f.name, f.metadata.get("interval"))
        if accepted is None:
            continue
        lo, hi = accepted.low, accepted.high
        if math.isinf(lo) or math.isinf(hi):
            continue
        if f.metadata.get("integer"):
            values[f.name] = draw_int(draw, f"{prefix}.{f.name}", int(lo), int(hi))
            continue
        values[f.name] = draw(f"{prefix}.{f.name}", accepted, lo > 0.0 or accepted.low_open)
    order = {
        DinghyParams: (
            ("sheet_min_rad", "sheet_max_rad"),
            ("jib_sheet_min_rad", "jib_sheet_max_rad"),
        ),
        WallParams: (("thickness_m", "base_depth_m"),),
    }
    for small, large in order.get(cls, ()):
        if not (small in values and large in values):
            continue
        lo, hi = sorted((values[small], values[large]))
        if lo == hi:  # strict order needed: fall back to the defaults' pair
            defaults = cls()
            lo, hi = getattr(defaults, small), getattr(defaults, large)
        values[small], values[large] = lo, hi
    return values


def draw_vector(draw: Draw, key: str, lengths: Interval) -> tuple[float, float]:
    """An ``options[key]`` vector ``(x, y)`` of a length inside ``lengths``, any direction."""
    length = draw(f"options[{key!r}].length", lengths, False)
    angle = draw(f"options[{key!r}].angle", interval(-math.pi, math.pi), False)
    # Rounding may take the length just out of an open interval: pull it in.
    x, y = length * math.cos(angle), length * math.sin(angle)
    if not lengths.contains(math.hypot(x, y)):
        x, y = x * (1 - 1e-9), y * (1 - 1e-9)
        if not lengths.contains(math.hypot(x, y)):
            x, y = x * (1 + 2e-9), y * (1 + 2e-9)
    return (x, y)


def _fuzzed(env_id: str) -> Any:
    spec = spec_of(env_id)
    if spec.fuzz is None:
        raise ValueError(f"{env_id}: its family ({spec.family}) declares no fuzz sampler")
    return spec.fuzz


def sample_kwargs(env_id: str, draw: Draw) -> dict[str, Any]:
    """Constructor arguments of ``env_id`` drawn over their accepted intervals (by its
    family's sampler, :attr:`bbgym.spec.FuzzSpec.sample_kwargs`). A version that is no
    base task keeps what it pins (:func:`pin_version`), so Topple-v2 is fuzzed in its RK4
    steps and Sail-v2 as a sloop; the family's :attr:`~bbgym.spec.FuzzSpec.fit` then
    meets the constraints between arguments."""
    version = spec_of(env_id).version(env_id)
    fuzz = _fuzzed(env_id)
    kwargs = fuzz.sample_kwargs(version, draw)
    if not version.base:
        kwargs = pin_version(version.kwargs, kwargs)
    return fuzz.fit(kwargs) if fuzz.fit is not None else kwargs


def pin_version(pinned: Mapping[str, Any], drawn: dict[str, Any]) -> dict[str, Any]:
    """Drawn arguments with a version's registered ones in their place. A parameter group
    the version sets (Sail-v2's ``dinghy``) keeps the version's choices (strings: the rig,
    the sail model) and takes the drawn numbers over the version's: the version's boat
    with random constants, as a user changing one constant gets it."""
    kwargs = {**drawn, **pinned}
    for key, value in pinned.items():
        if isinstance(value, Mapping) and isinstance(drawn.get(key), Mapping):
            numbers = {k: v for k, v in drawn[key].items() if not isinstance(v, str)}
            kwargs[key] = {**value, **numbers}
    return kwargs


def sample_options(env_id: str, env: Any, draw: Draw) -> dict[str, Any] | None:
    """``reset`` options for an env made with some kwargs (``env.unwrapped.task``), each
    key present or not, within the same intervals as the constructor's ranges."""
    return _fuzzed(env_id).sample_options(getattr(env, "unwrapped", env).task, draw)


def _finite_floats(value: Any, path: str) -> None:
    """Raise AssertionError naming the first non-finite float inside ``value``."""
    if isinstance(value, Mapping):
        for key, item in value.items():
            _finite_floats(item, f"{path}[{key!r}]")
    elif isinstance(value, np.ndarray) and value.dtype == object:
        for i, item in enumerate(value):
            _finite_floats(item, f"{path}[{i}]")
    elif isinstance(value, (float, int, np.floating, np.integer, np.ndarray)) and not isinstance(
        value, (bool, np.bool_)
    ):
        array = np.asarray(value)
        if array.dtype.kind in "fc" and not np.isfinite(array).all():
            raise AssertionError(f"non-finite value in {path}: {value!r}")


def check_step(space: gym.Space, obs: Any, reward: Any, info: Mapping, where: str) -> None:
    """Obs inside the space, reward finite, every float in info finite."""
    if not space.contains(obs):
        raise AssertionError(f"{where}: observation outside its space: {obs!r}")
    _finite_floats(reward, f"{where}: reward")
    _finite_floats(info, f"{where}: info")


BACKENDS = ("numpy", "torch", "torchrl")
"""The paths :func:`check_episode` steps a vector env through: the NumPy reference, the
torch backend (eager: a compile per configuration would cost minutes) with tensors in and
out, and the TorchRL env over it."""

BAD_ACTIONS: tuple[tuple[str, float | complex, type], ...] = (
    ("nan", math.nan, ValueError),
    ("inf", math.inf, ValueError),
    ("-inf", -math.inf, ValueError),
    ("complex", 1j, TypeError),
)
"""Action entries every path refuses, and the error each raises."""

BAD_ACTION_RATE = 0.1
"""The share of steps :func:`check_episode` first tries with one bad entry."""


class _Stepper:
    """One env of a kind behind one interface: ``reset``, ``step`` with a NumPy action,
    ``bad(action)`` (the same action as the path's own type, for the refusal), the
    observation space, and NumPy outputs."""

    def __init__(
        self, env_id: str, kwargs: Mapping[str, Any], num_envs: int, backend: str, seed: int
    ) -> None:
        self.num_envs, self.backend = num_envs, backend
        self.torch: Any = None
        if backend == "torchrl":
            import torch

            from bbgym.torchrl import BbgymTorchRLEnv

            self.torch = torch
            self.env: Any = BbgymTorchRLEnv(
                env_id, num_envs, compile_step=False, seed=seed, **kwargs
            )
            core = self.env.core
            self.space = core.observation_space
            self.shape = (num_envs, *core.single_action_space.shape)
            self.autoreset = False  # TorchRL resets the finished envs between steps
        elif num_envs:
            extra = {}
            if backend == "torch":
                import torch

                self.torch = torch
                extra = {"backend": "torch", "output": "torch", "compile": False}
            self.env = gym.make_vec(env_id, num_envs=num_envs, **kwargs, **extra)
            self.space = self.env.observation_space
            self.shape = (num_envs, *self.env.single_action_space.shape)
            self.autoreset = True
        else:
            self.env = gym.make(env_id, **kwargs)
            self.space = self.env.observation_space
            self.shape = self.env.action_space.shape
            self.autoreset = False

    def _tensor(self, action: Any) -> Any:
        if self.torch is None:
            return action
        dtype = self.torch.complex128 if np.iscomplexobj(action) else self.torch.float32
        return self.torch.as_tensor(action, dtype=dtype)

    def reset(self, seed: int | None, options: Any) -> tuple[Any, dict]:
        if self.backend == "torchrl":  # seeded on construction; takes no options
            self._td = self.env.reset()
            return _numpy(self._td["observation"]), {}
        obs, info = self.env.reset(seed=seed, options=options)
        return _numpy(obs), info

    def step(self, action: np.ndarray) -> tuple[Any, Any, Any, Any, Mapping]:
        if self.backend == "torchrl":
            self._td["action"] = self._tensor(action)
            td, self._td = self.env.step_and_maybe_reset(self._td)
            nxt = td["next"]
            info = {"is_success": _numpy(nxt["is_success"])}
            return (
                _numpy(nxt["observation"]),
                _numpy(nxt["reward"]),
                _numpy(nxt["terminated"]),
                _numpy(nxt["truncated"]),
                info,
            )
        obs, reward, terminated, truncated, info = self.env.step(self._tensor(action))
        return _numpy(obs), _numpy(reward), terminated, truncated, _numpy_tree(info)

    def close(self) -> None:
        self.env.close()


def _numpy(x: Any) -> Any:
    return x.detach().cpu().numpy() if hasattr(x, "detach") else x


def _numpy_tree(info: Any) -> Any:
    if isinstance(info, Mapping):
        return {k: _numpy_tree(v) for k, v in info.items()}
    return _numpy(info)


def check_episode(
    env_id: str,
    kwargs: Mapping[str, Any],
    options: Mapping[str, Any] | None,
    steps: int,
    seed: int,
    num_envs: int = 0,
    backend: str = "numpy",
) -> int:
    """Step ``steps`` random actions (the action space's full box, beyond [-1, 1] too,
    which the env clips) through a single env (``num_envs == 0``, resetting with
    ``options`` when an episode ends) or a vector env of ``num_envs`` on ``backend`` (one
    of :data:`BACKENDS`; autoreset), checking every output. Before one step in ten
    (:data:`BAD_ACTION_RATE`) the same action with one entry NaN, inf or complex
    (:data:`BAD_ACTIONS`) must raise the right error and change nothing (the valid step
    that follows is checked as usual). Returns the number of env steps taken.

    Args:
        env_id: a registered bbgym id.
        kwargs: its constructor arguments.
        options: ``reset`` options, or ``None``.
        steps: steps to take.
        seed: seeds the env and the actions.
        num_envs: 0 for a single env, else the vector env's size.
        backend: the vector env's path (single envs run on NumPy).

    Returns:
        ``steps * max(num_envs, 1)``.
    """
    if backend not in BACKENDS or (backend != "numpy" and not num_envs):
        raise ValueError(f"backend must be one of {BACKENDS} (a vector env), got {backend!r}")
    rng = np.random.default_rng(seed)
    env = _Stepper(env_id, kwargs, num_envs, backend, seed)
    where = f"{env_id} ({backend}, num_envs={num_envs})"
    try:
        obs, info = env.reset(seed, options)
        check_step(env.space, obs, 0.0, info, f"{where} reset")
        for t in range(steps):
            action = rng.uniform(-1.5, 1.5, env.shape).astype(np.float32)
            if rng.random() < BAD_ACTION_RATE:
                _check_refused(env, action, rng, f"{where} step {t}")
            obs, reward, terminated, truncated, info = env.step(action)
            check_step(env.space, obs, reward, info, f"{where} step {t}")
            if not env.autoreset and not num_envs and (terminated or truncated):
                obs, info = env.reset(None, options)
                check_step(env.space, obs, 0.0, info, f"{where} reset after step {t}")
    finally:
        env.close()
    return steps * max(num_envs, 1)


def _bad_action(action: np.ndarray, rng: np.random.Generator) -> tuple[str, np.ndarray, type]:
    """A copy of ``action`` with one entry of :data:`BAD_ACTIONS` (drawn, as its place):
    the bad value's name, the action and the error it must raise."""
    name, value, error = BAD_ACTIONS[int(rng.integers(len(BAD_ACTIONS)))]
    bad = action.astype(np.complex128 if isinstance(value, complex) else np.float64)
    bad[np.unravel_index(int(rng.integers(bad.size)), bad.shape)] = value
    return name, bad, error


def _check_refused(env: _Stepper, action: np.ndarray, rng: np.random.Generator, where: str):
    """``action`` with one bad entry raises the right error on ``env``'s path."""
    name, bad, error = _bad_action(action, rng)
    try:
        env.step(bad)
    except error:
        return
    except Exception as raised:  # noqa: BLE001 - reported as the wrong error
        raise AssertionError(
            f"{where}: a {name} action raised {type(raised).__name__} ({raised}), "
            f"expected {error.__name__}"
        ) from None
    raise AssertionError(f"{where}: a {name} action was accepted")


# -- invalid input ---------------------------------------------------------------------------

BAD_NUMBERS: tuple[tuple[Any, type], ...] = (
    ("x", TypeError),
    (True, TypeError),
    (None, TypeError),
    (1 + 2j, TypeError),
    (float("nan"), ValueError),
    (float("inf"), ValueError),
    (-float("inf"), ValueError),
    (np.array([1.0, 2.0]), TypeError),
)
"""Values no number argument accepts, and the error each raises."""


def numeric_arguments(env_id: str) -> list[str]:
    """The env's constructor arguments that take one number (for :func:`check_rejections`),
    and each field of its parameter groups as ``group.field``."""
    import inspect

    spec = spec_of(env_id)
    env_class = getattr(importlib.import_module(spec.module), spec.env_class)
    names = []
    for name, parameter in inspect.signature(env_class.task_class.__init__).parameters.items():
        default = parameter.default
        if name in spec.param_groups:
            names += [
                f"{name}.{f.name}"
                for f in fields(spec.param_groups[name])
                if "interval" in f.metadata and not isinstance(f.default, bool)
            ]
        elif isinstance(default, (int, float)) and not isinstance(default, bool):
            names.append(name)
    return names


def check_refusals(
    make: Callable[..., Any], paths: list[str], integers: set[str], where: str
) -> int:
    """``make(**kwargs)`` with each number argument (or parameter field, ``group.field``)
    of ``paths`` set to each value of :data:`BAD_NUMBERS` raises the right error naming the
    path; an int argument (in ``integers``) refuses every float by its type, NaN and inf
    included. Returns how many errors were checked."""
    checked = 0
    for path in paths:
        for value, error in BAD_NUMBERS:
            error = TypeError if path in integers else error
            case = f"{where}: {path}={value!r}"
            try:
                make(**_nested(path, value))
            except error as raised:
                if path not in str(raised):
                    message = f"{case} raised {raised!r}, which does not name {path}"
                    raise AssertionError(message) from None
            except Exception as raised:  # noqa: BLE001 - reported as the wrong error
                raise AssertionError(
                    f"{case} raised {type(raised).__name__} ({raised}), expected {error.__name__}"
                ) from None
            else:
                raise AssertionError(f"{case} was accepted")
            checked += 1
    return checked


def _nested(path: str, value: Any) -> dict[str, Any]:
    """``{"a": {"b": value}}`` for the path ``a.b``."""
    head, _, rest = path.partition(".")
    return {head: _nested(rest, value) if rest else value}


def check_rejections(env_id: str) -> int:
    """Every number argument (and parameter field) of ``env_id`` refuses every value of
    :data:`BAD_NUMBERS` with the right error naming it, at construction
    (:func:`check_refusals`). Returns how many errors were checked."""
    integers = set(spec_of(env_id).integer_arguments)

    def make(**kwargs: Any) -> None:
        gym.make(env_id, **kwargs).close()

    return check_refusals(make, numeric_arguments(env_id), integers, env_id)


# -- the race (PettingZoo) ---------------------------------------------------------------------

RACE_FORMS = ("parallel", "aec")
"""The race's two PettingZoo forms :func:`check_race_episode` steps: every boat acting at
once (``bbgym.envs.race.parallel_env``), and boats acting in turn (``bbgym.envs.race.env``)."""

RACE_EPISODE_STEPS = 160
"""Race steps (of 0.25 s) per check of the long run: 40 s, past the gun of a countdown of
at most :data:`COST_CAPS`'s ``race_countdown_s``."""

PROGRESS_EVERY_S = 30.0
"""How often a :func:`run` says on stderr how far it is."""

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
    for name in (
        "progress_weight",
        "waypoint_bonus",
        "finish_bonus",
        "ocs_penalty",
        "capsize_penalty",
        "time_penalty",
        "foul_penalty",
    ):
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
    _finite_floats(shown, where)


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
            name, bad, error = _bad_action(actions[agent], rng)
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
                name, bad, error = _bad_action(action, rng)
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


# -- the course's scenes --------------------------------------------------------------------------

SCENE_BACKENDS = ("numpy", "torch")
"""The array namespaces :func:`check_scene` runs a scene on (``bbgym.scenes.simulate``'s)."""

SCENE_MOST_BODIES = {"numpy": 256, "torch": 64}
"""The most bodies a scene check draws, by backend: a count field (particles, balls,
points, blocks; a grid's side counts its ``side ** dims`` cells) is drawn up to this or
four times its low end, whichever is larger. The intervals reach 65,536 SPH particles or a
128 x 128 spring grid (the bench's sizes), seconds a step; 256 keep a check of
:data:`SCENE_STEPS` steps on NumPy under about a second, 64 on torch, whose eager step on a
CPU is some hundred small kernels (a dam-break step of 256 particles takes 0.1 s)."""

SCENE_NOT_COUNTS = ("seed",)
"""Integer fields of the scenes' parameters that count nothing the step loops over."""

SCENE_GRID_SIDES = ("size",)
"""Integer fields that are a grid's side: its cells are ``side ** params.shape_dims``."""

SCENE_ORDERED = (
    ("speed_min_mps", "speed_max_mps"),
    ("angle_min_deg", "angle_max_deg"),
    ("mu_kinetic", "mu_static"),
    ("thickness_m", "base_depth_m"),
    ("water_width_m", "box_width_m"),
    ("water_height_m", "box_height_m"),
    ("radius_m", "drop_height_m"),
)
"""Pairs of fields a scene's rule orders (``low <= high``, or ``<``: the water inside the
dam-break's box, a ball dropped from above its radius): drawn, then sorted where the
sorted pair still lies in both intervals, that most draws are run rather than refused
(each rule alone would refuse half)."""

SCENE_SHARES = {"jitter_under_half_spacing": ("jitter_m", "spacing_m", 0.5)}
"""Fields a scene's rule bounds by a share of another (a spring grid's jitter under half
its spacing): half the draws are redrawn under that bound, the other half keep the whole
interval (and are refused where they break the rule). A rule that most draws break would
leave its scene hardly run otherwise (the grids' jitter, in [0, 1] m, against spacings
from 5 cm)."""

SCENE_STEPS = 40
"""Steps of a scene check in the long run."""


def scene_count_caps(params_class: type, most_bodies: int) -> dict[str, Interval]:
    """The intervals :func:`sample_scene_params` draws a scene's counts from: each integer
    field but :data:`SCENE_NOT_COUNTS` up to ``max(most_bodies, 4 * low)`` bodies (a grid
    side of :data:`SCENE_GRID_SIDES` up to the side of that many cells).

    Args:
        params_class: a scene's parameter dataclass.
        most_bodies: the bodies allowed (:data:`SCENE_MOST_BODIES`).

    Returns:
        The capped intervals, by field name (only those the cap narrows).
    """
    caps = {}
    for f in fields(params_class):
        accepted = f.metadata.get("interval")
        if accepted is None or not f.metadata.get("integer") or f.name in SCENE_NOT_COUNTS:
            continue
        dims = getattr(params_class, "shape_dims", 1) if f.name in SCENE_GRID_SIDES else 1
        low = int(accepted.low)
        most = max(most_bodies, 4 * low**dims)
        side = int(math.floor(most ** (1.0 / dims) + 1e-9))
        if side < accepted.high:
            caps[f.name] = interval(low, max(low, side))
    return caps


def _scene_choices(params_class: type) -> dict[str, tuple[int, ...]]:
    """Integer fields whose accepted values are a set inside their interval, as their
    docstrings say: a spring grid's ``neighbours`` (4, 6 or 8 in 2D: no grid has 5 or 7)."""
    if "neighbours" not in {f.name for f in fields(params_class)}:
        return {}
    from bbgym.scenes.springs import neighbour_counts

    accepted = next(f for f in fields(params_class) if f.name == "neighbours").metadata["interval"]
    counts = neighbour_counts(params_class.shape_dims)
    return {"neighbours": tuple(n for n in counts if accepted.contains(n))}


def sample_scene_params(
    scene: Any, draw: Draw, most_bodies: int = SCENE_MOST_BODIES["numpy"]
) -> dict[str, Any]:
    """A scene's parameters: every field over its accepted interval (log-uniform where it
    is positive, ends included), its counts capped (:func:`scene_count_caps`), ordered
    pairs sorted (:data:`SCENE_ORDERED`), a field taking a set of values drawn from it.

    Args:
        scene: a :class:`bbgym.scenes.Scene`.
        draw: draws each number.
        most_bodies: the bodies a count may reach (:data:`SCENE_MOST_BODIES`).

    Returns:
        The parameters by field name, for ``simulate(scene, params)``.
    """
    cls = scene.params
    values = sample_params(draw, cls, scene.name, scene_count_caps(cls, most_bodies))
    for name, choices in _scene_choices(cls).items():
        values[name] = choices[draw_int(draw, f"{scene.name}.{name}", 0, len(choices) - 1)]
    for small, large in SCENE_ORDERED:
        if small in values and large in values:
            lo, hi = sorted((values[small], values[large]))
            if _field_accepts(cls, small, lo) and _field_accepts(cls, large, hi):
                values[small], values[large] = lo, hi
    for share, (small, large, most) in SCENE_SHARES.items():
        if small in values and large in values and draw_flag(draw, f"{scene.name}.{share}"):
            accepted = next(f for f in fields(cls) if f.name == small).metadata["interval"]
            below = interval(accepted.low, min(accepted.high, most * values[large]), high_open=True)
            if below.low < below.high:
                values[small] = draw(f"{scene.name}.{small}", below, False)
    return values


def _field_accepts(cls: type, name: str, value: float) -> bool:
    accepted = next(f for f in fields(cls) if f.name == name).metadata["interval"]
    return accepted.contains(value)


def _refusal_names_another_field(scene: Any, message: str, fields_drawn: list[str]) -> bool:
    """Whether a scene's ``ValueError`` is a documented refusal of a combination: it
    begins with ``<scene>.`` and names a field besides the one it begins with."""
    if not message.startswith(f"{scene.name}."):
        return False
    head = message[len(scene.name) + 1 :]
    first = next(
        (n for n in sorted(fields_drawn, key=len, reverse=True) if head.startswith(n)), None
    )
    others = [n for n in fields_drawn if n != first]
    return any(re.search(rf"\b{re.escape(n)}\b", message) for n in others)


def check_scene(
    name: str, params: Mapping[str, Any], steps: int, backend: str = "numpy"
) -> int | None:
    """Run scene ``name`` with ``params`` (inside their intervals) for ``steps`` steps on
    ``backend`` and check it: every measure finite, one column per body, every float of
    its last state finite. A ``ValueError`` building the parameters that begins with
    ``<scene>.`` and names another field is a documented refusal of a combination
    (``arrow.target_distance_m: out of range at this speed_mps``); any other raises
    ``AssertionError`` (the interval promised a value the scene does not take).

    Args:
        name: a key of ``bbgym.scenes.SCENES``.
        params: the scene's parameters (:func:`sample_scene_params`).
        steps: steps to run.
        backend: one of :data:`SCENE_BACKENDS`.

    Returns:
        ``steps``, or ``None`` where the scene refused the combination.
    """
    from bbgym.scenes import SCENES, simulate

    scene = SCENES[name]
    where = f"scene {name} ({backend})"
    try:
        built = scene.make_params(params)
    except ValueError as error:
        if _refusal_names_another_field(scene, str(error), [f.name for f in fields(scene.params)]):
            return None
        raise AssertionError(
            f"{where}: refused values inside their intervals with {error!r}, "
            f"which names no other field"
        ) from None
    run = simulate(scene, built, steps, backend)
    bodies = len(scene.names(built))
    for measure, values in run.measures.items():
        if values.shape != (steps + 1, bodies):
            raise AssertionError(
                f"{where}: measure {measure} has shape {values.shape}, "
                f"expected {(steps + 1, bodies)}"
            )
        if not np.isfinite(values).all():
            step = int(np.argwhere(~np.isfinite(values))[0][0])
            raise AssertionError(
                f"{where}: non-finite {measure} at step {step}: {values[step].tolist()}"
            )
    for field_name, value in zip(type(run.state)._fields, run.state, strict=True):
        array = np.asarray(_numpy(value))
        if array.dtype.kind in "fc" and not np.isfinite(array).all():
            raise AssertionError(f"{where}: non-finite value in the last state's {field_name}")
    return steps


def installed_scene_backends(backends: tuple[str, ...] | None = None) -> tuple[str, ...]:
    """The :data:`SCENE_BACKENDS` installed here (torch's with the ``torch`` extra).

    Args:
        backends: keep only these (``run``'s vector paths), if given.

    Returns:
        The backends, NumPy first.
    """
    import importlib.util

    have = importlib.util.find_spec("torch") is not None
    return tuple(
        b for b in SCENE_BACKENDS if (b == "numpy" or have) and (backends is None or b in backends)
    )


# -- the long run ------------------------------------------------------------------------------


RACE_SHARE = 0.1
"""The share of a long run's steps given to the race (its boat steps), by default."""
SCENE_SHARE = 0.1
"""The share given to the course's scenes (their steps), by default."""


def run(
    total_steps: int,
    seed: int,
    num_envs: int = 32,
    minutes: float = math.inf,
    env_ids: list[str] | None = None,
    backends: tuple[str, ...] | None = None,
    race_share: float = RACE_SHARE,
    scene_share: float = SCENE_SHARE,
) -> dict:
    """Fuzz every registered id (or ``env_ids``), the race and the course's scenes for
    about ``total_steps`` steps. The ids share ``1 - race_share - scene_share`` of them:
    turn by turn a single env and a vector env of ``num_envs`` on each backend of
    :data:`BACKENDS` that is installed (or ``backends``), a fresh random configuration and
    reset options for each episode check, bad actions among the valid ones; and every
    invalid number is checked once per id. The race (with the ``race`` extra) takes
    ``race_share`` in boat steps, its parallel and AEC forms in turn
    (:func:`check_race_episode`); the scenes ``scene_share`` in their steps, one scene
    after another, on NumPy and torch in turn (:data:`SCENE_BACKENDS` installed and among
    ``backends``; :func:`check_scene`).

    Args:
        total_steps: env steps, race boat steps and scene steps in all.
        seed: seeds every configuration.
        num_envs: the vector envs' size.
        minutes: stop after this.
        env_ids: the ids to fuzz (default: every registered one).
        backends: the vector paths (default: those installed).
        race_share: the race's share of ``total_steps`` (0: no race).
        scene_share: the scenes' share (0: no scenes).

    Returns:
        The figures: steps (by id and path, by race form, by scene and backend),
        configurations, refusals, failures (with what reproduces each), errors checked,
        seconds.
    """
    import time

    from bbgym.spec import env_ids as registered

    if not (0.0 <= race_share and 0.0 <= scene_share and race_share + scene_share < 1.0):
        raise ValueError(
            f"race_share and scene_share must be >= 0 with a sum under 1, got "
            f"{race_share} and {scene_share}"
        )
    rng = np.random.default_rng(seed)
    draw = numpy_draw(rng)
    start = time.perf_counter()
    ids = env_ids or registered()
    paths = [("numpy", 0)] + [(b, num_envs) for b in (backends or installed_backends())]
    report: dict[str, Any] = {
        "seed": seed,
        "num_envs": num_envs,
        "paths": [f"{b}:{n}" for b, n in paths],
        "envs": {},
        "failures": [],
    }
    for env_id in ids:
        figures = {"steps": 0, "configurations": 0, "failures": 0}
        figures["errors_checked"] = check_rejections(env_id)
        figures["by_path"] = {f"{b}:{n}": 0 for b, n in paths}
        report["envs"][env_id] = figures
    # A family's share is split between its ids.
    family_ids: dict[str, int] = {}
    for env_id in ids:
        family_ids[spec_of(env_id).family] = family_ids.get(spec_of(env_id).family, 0) + 1
    shares = {e: _fuzzed(e).step_share / family_ids[spec_of(e).family] for e in ids}
    total_share = sum(shares.values())
    env_steps = total_steps * (1.0 - race_share - scene_share)
    budget = {env_id: env_steps * share / total_share for env_id, share in shares.items()}
    targets: list[str] = list(ids)
    race = _race_figures(report, race_share)
    if race is not None:
        budget["race"] = total_steps * race_share
        targets.append("race")
    scene_backends = installed_scene_backends(backends)
    scene_names = _scene_figures(report, scene_share, scene_backends)
    if scene_names:
        budget["scenes"] = total_steps * scene_share
        targets.append("scenes")
    done = {target: 0 for target in targets}
    race_turn = scene_turn = turn = 0
    visits: dict[str, int] = {}
    last_said = time.perf_counter()
    while any(done[t] < budget[t] for t in targets):
        now = time.perf_counter()
        if now - start > 60.0 * minutes:
            report["stopped_early"] = True
            break
        if now - last_said > PROGRESS_EVERY_S:  # a long run says where it is
            last_said = now
            print(
                f"bbgym fuzz: {sum(done.values()):,.0f} of {total_steps:,} steps, "
                f"{len(report['failures'])} failures, {(now - start) / 60:.1f} min",
                file=sys.stderr,
                flush=True,
            )
        target = targets[turn % len(targets)]
        # Each id takes the paths in turn (a global rotation let an id whose budget ends
        # after few configurations, Sail's long episodes, miss a path).
        backend, n = paths[visits.get(target, 0) % len(paths)]
        turn += 1
        if done[target] >= budget[target]:
            continue
        if target == "race":
            form = RACE_FORMS[race_turn % len(RACE_FORMS)]
            race_turn += 1
            done[target] += _race_turn(report, form, draw, int(rng.integers(2**31)))
            continue
        if target == "scenes":
            name = scene_names[scene_turn % len(scene_names)]
            backend = scene_backends[(scene_turn // len(scene_names)) % len(scene_backends)]
            scene_turn += 1
            done[target] += _scene_turn(report, name, backend, draw)
            continue
        env_id = target
        visits[env_id] = visits.get(env_id, 0) + 1
        figures = report["envs"][env_id]
        kwargs = sample_kwargs(env_id, draw)
        case_seed = int(rng.integers(2**31))
        options = None
        try:
            probe = gym.make(env_id, **kwargs)
            options = sample_options(env_id, probe, draw)
            probe.close()
            steps = _fuzzed(env_id).episode_steps
            taken = check_episode(env_id, kwargs, options, steps, case_seed, n, backend)
            figures["steps"] += taken
            figures["by_path"][f"{backend}:{n}"] += taken
            done[env_id] += taken
        except Exception as error:  # noqa: BLE001 - every failure is reported, with its input
            figures["failures"] += 1
            report["failures"].append(
                {
                    "env_id": env_id,
                    "backend": backend,
                    "num_envs": n,
                    "kwargs": repr(kwargs),
                    "options": repr(options),
                    "seed": case_seed,
                    "error": _error_text(error),
                }
            )
        figures["configurations"] += 1
    report["seconds"] = time.perf_counter() - start
    report["steps"] = sum(f["steps"] for f in report["envs"].values())
    if race is not None:
        report["race_steps"] = sum(f["steps"] for f in race["forms"].values())
    if scene_names:
        report["scene_steps"] = sum(f["steps"] for f in report["scenes"].values())
    return report


def _error_text(error: BaseException) -> str:
    return f"{type(error).__name__}: {error}"[:2000]


def _race_figures(report: dict[str, Any], race_share: float) -> dict[str, Any] | None:
    """The race's figures in ``report`` (and its invalid numbers checked), or ``None``
    without its share or its extra (PettingZoo)."""
    import importlib.util

    if race_share <= 0.0 or importlib.util.find_spec("pettingzoo") is None:
        return None
    forms = {form: {"steps": 0, "configurations": 0, "failures": 0} for form in RACE_FORMS}
    race = {"forms": forms, "errors_checked": 0}
    report["race"] = race
    try:
        race["errors_checked"] = check_race_rejections()
    except Exception as error:  # noqa: BLE001 - reported as a failure
        report["failures"].append({"race": "constructor", "error": _error_text(error)})
    return race


def _scene_figures(
    report: dict[str, Any], scene_share: float, scene_backends: tuple[str, ...]
) -> list[str]:
    """The scenes' figures in ``report``; returns their names (none without a share)."""
    if scene_share <= 0.0:
        return []
    from bbgym.scenes import SCENES

    report["scene_backends"] = list(scene_backends)
    report["scenes"] = {
        name: {
            "steps": 0,
            "by_backend": {b: 0 for b in scene_backends},
            "configurations": 0,
            "refused": 0,
            "failures": 0,
        }
        for name in SCENES
    }
    return list(SCENES)


def _race_turn(report: dict[str, Any], form: str, draw: Draw, case_seed: int) -> int:
    """One race check in ``form`` with fresh arguments and options; returns its boat steps
    (a failure counts :data:`RACE_EPISODE_STEPS`, that a failing race still ends)."""
    figures = report["race"]["forms"][form]
    kwargs = sample_race_kwargs(draw)
    options = sample_race_options(draw)
    figures["configurations"] += 1
    try:
        taken = check_race_episode(kwargs, RACE_EPISODE_STEPS, case_seed, form, options)
    except Exception as error:  # noqa: BLE001 - every failure is reported, with its input
        figures["failures"] += 1
        report["failures"].append(
            {
                "race": form,
                "kwargs": repr(kwargs),
                "options": repr(options),
                "seed": case_seed,
                "error": _error_text(error),
            }
        )
        return RACE_EPISODE_STEPS
    figures["steps"] += taken
    return taken


def _scene_turn(report: dict[str, Any], name: str, backend: str, draw: Draw) -> int:
    """One check of scene ``name`` on ``backend`` with fresh parameters; returns its steps
    (:data:`SCENE_STEPS` for a refusal or a failure too, that the share is spent)."""
    from bbgym.scenes import SCENES

    figures = report["scenes"][name]
    params = sample_scene_params(SCENES[name], draw, SCENE_MOST_BODIES[backend])
    figures["configurations"] += 1
    try:
        taken = check_scene(name, params, SCENE_STEPS, backend)
    except Exception as error:  # noqa: BLE001 - every failure is reported, with its input
        figures["failures"] += 1
        report["failures"].append(
            {
                "scene": name,
                "backend": backend,
                "params": repr(params),
                "steps": SCENE_STEPS,
                "error": _error_text(error),
            }
        )
        return SCENE_STEPS
    if taken is None:
        figures["refused"] += 1
        return SCENE_STEPS
    figures["steps"] += taken
    figures["by_backend"][backend] += taken
    return taken


def installed_backends() -> tuple[str, ...]:
    """The vector paths of :data:`BACKENDS` whose extras are installed."""
    import importlib.util

    have = {name: importlib.util.find_spec(name) is not None for name in ("torch", "torchrl")}
    return tuple(b for b in BACKENDS if b == "numpy" or have.get(b, False))


def format_report(report: Mapping[str, Any]) -> str:
    """The figures of :func:`run` as markdown: a table of steps by id and by path (single
    NumPy env, then each vector backend); a table of the race's boat steps by form and the
    scenes' steps by backend, with the combinations each scene refused; and the failures
    with what reproduces them.

    Args:
        report: what :func:`run` returned (or its JSON; a report from before the race and
            the scenes were fuzzed has no second table).

    Returns:
        The text.
    """
    paths = report["paths"]
    lines = [
        "| env | env steps | " + " | ".join(paths) + " | configurations | failures "
        "| invalid inputs checked |",
        "|---|---:|" + "---:|" * len(paths) + "---:|---:|---:|",
    ]
    for env_id, f in report["envs"].items():
        by_path = " | ".join(f"{f['by_path'][p]:,}" for p in paths)
        lines.append(
            f"| {env_id} | {f['steps']:,} | {by_path} | {f['configurations']:,} "
            f"| {f['failures']} | {f['errors_checked']} |"
        )
    lines += _race_scene_table(report)
    non_finite = sum(
        "non-finite" in f["error"] or "outside" in f["error"] for f in report["failures"]
    )
    done = [f"{report['steps']:,} env steps"]
    if "race_steps" in report:
        done.append(f"{report['race_steps']:,} race boat steps")
    if "scene_steps" in report:
        done.append(f"{report['scene_steps']:,} scene steps")
    lines.append(
        f"\n{', '.join(done)} in {report['seconds']:.0f} s (seed {report['seed']}, "
        f"vector envs of {report['num_envs']}); {len(report['failures'])} failures, "
        f"{non_finite} of them a non-finite value or an observation outside its space."
    )
    for failure in report["failures"][:20]:
        lines.append(_failure_line(failure))
    return "\n".join(lines)


def _race_scene_table(report: Mapping[str, Any]) -> list[str]:
    """The second table of :func:`format_report` (none in a report without either)."""
    race, scenes = report.get("race"), report.get("scenes")
    if race is None and scenes is None:
        return []
    backends = list(report.get("scene_backends", ("numpy",)))
    lines = [
        "",
        "| race / scene | steps | " + " | ".join(backends) + " | configurations | refused "
        "| failures |",
        "|---|---:|" + "---:|" * len(backends) + "---:|---:|---:|",
    ]
    for form, f in (race or {}).get("forms", {}).items():
        # The race runs on NumPy alone.
        by_backend = " | ".join(f"{f['steps']:,}" if b == "numpy" else "-" for b in backends)
        lines.append(
            f"| race ({form}) | {f['steps']:,} | {by_backend} "
            f"| {f['configurations']:,} | - | {f['failures']} |"
        )
    for name, f in (scenes or {}).items():
        by_backend = " | ".join(f"{f['by_backend'].get(b, 0):,}" for b in backends)
        lines.append(
            f"| scene {name} | {f['steps']:,} | {by_backend} "
            f"| {f['configurations']:,} | {f['refused']} | {f['failures']} |"
        )
    notes = []
    if race is not None:
        notes.append(
            f"Race steps are boat steps (each racing boat's action; a turn in the AEC form); "
            f"{race['errors_checked']} invalid race arguments checked."
        )
    if scenes is not None:
        notes.append(
            "Scene steps are `simulate`'s; refused: combinations a scene refuses by a rule "
            "that names another field."
        )
    lines.append("\n" + " ".join(notes))
    return lines


def _failure_line(failure: Mapping[str, Any]) -> str:
    """One failure and what reproduces it, by its kind (env, race or scene)."""
    error = failure["error"][:300]
    if "scene" in failure:
        return (
            f"- scene {failure['scene']} {failure['backend']} steps={failure['steps']}: "
            f"{error}\n  params={failure['params']}"
        )
    if "race" in failure:
        if "kwargs" not in failure:
            return f"- race {failure['race']}: {error}"
        return (
            f"- race ({failure['race']}) seed={failure['seed']}: {error}"
            f"\n  kwargs={failure['kwargs']}\n  options={failure['options']}"
        )
    return (
        f"- {failure['env_id']} {failure['backend']} num_envs={failure['num_envs']} "
        f"seed={failure['seed']}: {error}\n  kwargs={failure['kwargs']}"
        f"\n  options={failure['options']}"
    )
