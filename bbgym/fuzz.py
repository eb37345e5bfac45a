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
  errors.

Step sizes and time limits are drawn from the slow end of their intervals only (a sim_dt
of 1e-4 s is accepted, but a fuzz run of a million steps at it would take days): the
:data:`COST_CAPS` say where.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Mapping
from dataclasses import fields
from typing import Any

import gymnasium as gym
import numpy as np

import bbgym  # noqa: F401  (registers the ids)
from bbgym.physics.dinghy import DinghyParams
from bbgym.physics.validation import Interval, interval
from bbgym.physics.wall import WallParams
from bbgym.spec import base_ids, spec_of

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


def sample_params(draw: Draw, cls: type, prefix: str) -> dict[str, Any]:
    """Every field of a parameter dataclass over its accepted interval. Cross-field
    constraints are met by construction where the class has them."""
    values: dict[str, Any] = {}
    for f in fields(cls):
        if isinstance(f.default, bool):
            values[f.name] = draw_flag(draw, f"{prefix}.{f.name}")
            continue
        accepted = f.metadata.get("interval")
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
    family's sampler, :attr:`bbgym.spec.FuzzSpec.sample_kwargs`)."""
    return _fuzzed(env_id).sample_kwargs(spec_of(env_id).version(env_id), draw)


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


def check_episode(
    env_id: str,
    kwargs: Mapping[str, Any],
    options: Mapping[str, Any] | None,
    steps: int,
    seed: int,
    num_envs: int = 0,
) -> int:
    """Step ``steps`` random actions (the action space's full box, beyond [-1, 1] too,
    which the env clips) through a single env (``num_envs == 0``, resetting with
    ``options`` when an episode ends) or a native vector env (autoreset), checking every
    output. Returns the number of env steps taken."""
    rng = np.random.default_rng(seed)
    if num_envs:
        env: Any = gym.make_vec(env_id, num_envs=num_envs, **kwargs)
        space = env.observation_space
        shape: tuple[int, ...] = (num_envs, *env.single_action_space.shape)
    else:
        env = gym.make(env_id, **kwargs)
        space = env.observation_space
        shape = env.action_space.shape
    try:
        obs, info = env.reset(seed=seed, options=options)
        check_step(space, obs, 0.0, info, f"{env_id} reset")
        for t in range(steps):
            action = rng.uniform(-1.5, 1.5, shape).astype(np.float32)
            obs, reward, terminated, truncated, info = env.step(action)
            check_step(space, obs, reward, info, f"{env_id} step {t}")
            if not num_envs and (terminated or truncated):
                obs, info = env.reset(options=options)
                check_step(space, obs, 0.0, info, f"{env_id} reset after step {t}")
    finally:
        env.close()
    return steps * max(num_envs, 1)


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


def _kwargs_with(path: str, value: Any) -> dict[str, Any]:
    if "." in path:
        group, key = path.split(".", 1)
        return {group: {key: value}}
    return {path: value}


def check_rejections(env_id: str) -> int:
    """Every number argument (and parameter field) refuses every value of
    :data:`BAD_NUMBERS` with the right error naming it, at construction. Returns how many
    errors were checked."""
    checked = 0
    for path in numeric_arguments(env_id):
        integer = path in spec_of(env_id).integer_arguments
        for value, error in BAD_NUMBERS:
            # An int argument refuses every float by its type, NaN and inf included.
            error = TypeError if integer else error
            try:
                gym.make(env_id, **_kwargs_with(path, value))
            except error as raised:
                if path not in str(raised):
                    raise AssertionError(
                        f"{env_id}: {path}={value!r} raised {raised!r}, which does not name {path}"
                    ) from None
            except Exception as raised:  # noqa: BLE001 - reported as the wrong error
                raise AssertionError(
                    f"{env_id}: {path}={value!r} raised {type(raised).__name__} ({raised}), "
                    f"expected {error.__name__}"
                ) from None
            else:
                raise AssertionError(f"{env_id}: {path}={value!r} was accepted")
            checked += 1
    return checked


# -- the long run ------------------------------------------------------------------------------


def run(total_steps: int, seed: int, num_envs: int = 32, minutes: float = math.inf) -> dict:
    """Fuzz every env for about ``total_steps`` env steps (half through single envs, half
    through native vector envs of ``num_envs``), a fresh random configuration and reset
    options for each episode check, and check every invalid number once per env. Returns
    the figures: steps, configurations, failures (with what reproduces each), errors
    checked, seconds. Stops early after ``minutes``."""
    import time

    rng = np.random.default_rng(seed)
    draw = numpy_draw(rng)
    start = time.perf_counter()
    report: dict[str, Any] = {"seed": seed, "num_envs": num_envs, "envs": {}, "failures": []}
    env_ids = base_ids()
    for env_id in env_ids:
        figures = {"steps": 0, "configurations": 0, "failures": 0}
        figures["errors_checked"] = check_rejections(env_id)
        report["envs"][env_id] = figures
    shares = {env_id: _fuzzed(env_id).step_share for env_id in env_ids}
    total_share = sum(shares.values())
    budget = {env_id: total_steps * share / total_share for env_id, share in shares.items()}
    kinds = [0, num_envs]
    turn = 0
    while any(report["envs"][e]["steps"] < budget[e] for e in env_ids):
        if time.perf_counter() - start > 60.0 * minutes:
            report["stopped_early"] = True
            break
        env_id = env_ids[turn % len(env_ids)]
        n = kinds[(turn // len(env_ids)) % 2]
        turn += 1
        figures = report["envs"][env_id]
        if figures["steps"] >= budget[env_id]:
            continue
        kwargs = sample_kwargs(env_id, draw)
        case_seed = int(rng.integers(2**31))
        try:
            probe = gym.make(env_id, **kwargs)
            options = sample_options(env_id, probe, draw)
            probe.close()
            steps = _fuzzed(env_id).episode_steps
            figures["steps"] += check_episode(env_id, kwargs, options, steps, case_seed, n)
        except Exception as error:  # noqa: BLE001 - every failure is reported, with its input
            figures["failures"] += 1
            report["failures"].append(
                {
                    "env_id": env_id,
                    "num_envs": n,
                    "kwargs": repr(kwargs),
                    "options": repr(locals().get("options")),
                    "seed": case_seed,
                    "error": f"{type(error).__name__}: {error}"[:2000],
                }
            )
        figures["configurations"] += 1
    report["seconds"] = time.perf_counter() - start
    report["steps"] = sum(f["steps"] for f in report["envs"].values())
    return report


def format_report(report: Mapping[str, Any]) -> str:
    """The figures of :func:`run` as a markdown table."""
    lines = [
        "| env | env steps | configurations | failures | invalid inputs checked |",
        "|---|---:|---:|---:|---:|",
    ]
    for env_id, f in report["envs"].items():
        lines.append(
            f"| {env_id} | {f['steps']:,} | {f['configurations']:,} | {f['failures']} "
            f"| {f['errors_checked']} |"
        )
    lines.append(
        f"\n{report['steps']:,} env steps in {report['seconds']:.0f} s (seed {report['seed']}, "
        f"vector envs of {report['num_envs']}); {len(report['failures'])} failures."
    )
    for failure in report["failures"][:20]:
        lines.append(
            f"- {failure['env_id']} num_envs={failure['num_envs']} seed={failure['seed']}: "
            f"{failure['error'][:300]}\n  kwargs={failure['kwargs']}"
            f"\n  options={failure['options']}"
        )
    return "\n".join(lines)
