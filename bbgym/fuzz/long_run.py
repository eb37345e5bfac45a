"""The long run of ``bbgym fuzz``: every id, the families of many agents (the race) and the
scenes for a number of steps, and the report's tables."""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping
from typing import Any

import gymnasium as gym
import numpy as np

from bbgym.fuzz.draws import (
    Draw,
    numpy_draw,
)
from bbgym.fuzz.envs import (
    BACKENDS,
    _fuzzed,
    check_episode,
    check_rejections,
    sample_kwargs,
    sample_options,
)
from bbgym.fuzz.scenes import (
    SCENE_MOST_BODIES,
    SCENE_STEPS,
    check_scene,
    installed_scene_backends,
    sample_scene_params,
)
from bbgym.spec import MultiAgentFuzz, MultiAgentSpec, multi_agent_specs, spec_of

# -- the long run ------------------------------------------------------------------------------


PROGRESS_EVERY_S = 30.0
"""How often a :func:`run` says on stderr how far it is."""
MULTI_AGENT_SHARE = 0.1
"""The share of a long run's steps given to the families of many agents (their agent
steps: the race's boat steps), by default."""
SCENE_SHARE = 0.1
"""The share given to the course's scenes (their steps), by default."""


def run(
    total_steps: int,
    seed: int,
    num_envs: int = 32,
    minutes: float = math.inf,
    env_ids: list[str] | None = None,
    backends: tuple[str, ...] | None = None,
    multi_agent_share: float = MULTI_AGENT_SHARE,
    scene_share: float = SCENE_SHARE,
) -> dict:
    """Fuzz every registered id (or ``env_ids``), the families of many agents and the
    course's scenes for about ``total_steps`` steps. The ids share ``1 - multi_agent_share
    - scene_share`` of them:
    turn by turn a single env and a vector env of ``num_envs`` on each backend of
    :data:`BACKENDS` that is installed (or ``backends``), a fresh random configuration and
    reset options for each episode check, bad actions among the valid ones; and every
    invalid number is checked once per id. The families of many agents (their spec's
    :class:`~bbgym.spec.MultiAgentFuzz`, where their extra is installed: the race's
    PettingZoo) split ``multi_agent_share`` in agent steps, each stepping its forms in turn
    (the race: parallel and AEC); the scenes ``scene_share`` in their steps, one scene
    after another, on NumPy and torch in turn (:data:`SCENE_BACKENDS` installed and among
    ``backends``; :func:`check_scene`).

    Args:
        total_steps: env steps, agent steps and scene steps in all.
        seed: seeds every configuration.
        num_envs: the vector envs' size.
        minutes: stop after this.
        env_ids: the ids to fuzz (default: every registered one).
        backends: the vector paths (default: those installed).
        multi_agent_share: the families of many agents' share of ``total_steps`` (0:
            none).
        scene_share: the scenes' share (0: no scenes).

    Returns:
        The figures: steps (by id and path, by family of many agents and form, by scene
        and backend),
        configurations, refusals, failures (with what reproduces each), errors checked,
        seconds.
    """
    import time

    from bbgym.spec import env_ids as registered

    shares = (multi_agent_share, scene_share)
    if not (min(shares) >= 0.0 and sum(shares) < 1.0):
        raise ValueError(
            f"multi_agent_share and scene_share must be >= 0 with a sum under 1, got "
            f"{multi_agent_share} and {scene_share}"
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
    env_steps = total_steps * (1.0 - multi_agent_share - scene_share)
    budget = {env_id: env_steps * share / total_share for env_id, share in shares.items()}
    targets: list[str] = list(ids)
    fuzzed = _multi_agent_figures(report, multi_agent_share)
    for family in fuzzed:
        budget[family] = total_steps * multi_agent_share / len(fuzzed)
        targets.append(family)
    scene_backends = installed_scene_backends(backends)
    scene_names = _scene_figures(report, scene_share, scene_backends)
    if scene_names:
        budget["scenes"] = total_steps * scene_share
        targets.append("scenes")
    done = {target: 0 for target in targets}
    scene_turn = turn = 0
    form_turns = {family: 0 for family in fuzzed}
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
        if target in fuzzed:
            spec, fuzz = fuzzed[target]
            form = fuzz.forms[form_turns[target] % len(fuzz.forms)]
            form_turns[target] += 1
            done[target] += _agents_turn(report, spec, fuzz, form, draw, int(rng.integers(2**31)))
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
    for family in fuzzed:
        report[f"{family}_steps"] = sum(f["steps"] for f in report[family]["forms"].values())
    if scene_names:
        report["scene_steps"] = sum(f["steps"] for f in report["scenes"].values())
    return report


def _error_text(error: BaseException) -> str:
    return f"{type(error).__name__}: {error}"[:2000]


def _multi_agent_figures(
    report: dict[str, Any], share: float
) -> dict[str, tuple[MultiAgentSpec, MultiAgentFuzz]]:
    """The figures of each fuzzed family of many agents in ``report`` (under its name,
    ``report["multi_agent"]`` listing them; its invalid numbers checked): those whose spec
    has a :class:`~bbgym.spec.MultiAgentFuzz` and whose extra is installed, none without a
    share."""
    from bbgym._extras import extra_needs, missing_modules

    fuzzed: dict[str, tuple[MultiAgentSpec, MultiAgentFuzz]] = {}
    for spec in multi_agent_specs():
        if share <= 0.0 or spec.fuzz is None or missing_modules(extra_needs(spec.extra)):
            continue
        fuzz = spec.load(spec.fuzz)
        forms = {form: {"steps": 0, "configurations": 0, "failures": 0} for form in fuzz.forms}
        figures = {"forms": forms, "errors_checked": 0}
        report[spec.family] = figures
        try:
            figures["errors_checked"] = fuzz.check_rejections()
        except Exception as error:  # noqa: BLE001 - reported as a failure
            failure = {"family": spec.family, "form": "constructor", "error": _error_text(error)}
            report["failures"].append(failure)
        fuzzed[spec.family] = (spec, fuzz)
    if fuzzed:
        report["multi_agent"] = list(fuzzed)
    return fuzzed


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


def _agents_turn(
    report: dict[str, Any],
    spec: MultiAgentSpec,
    fuzz: MultiAgentFuzz,
    form: str,
    draw: Draw,
    case_seed: int,
) -> int:
    """One check of a family of many agents in ``form`` with fresh arguments and options;
    returns its agent steps (a failure counts the check's steps: a failing episode still
    ends)."""
    figures = report[spec.family]["forms"][form]
    kwargs = fuzz.sample_kwargs(draw)
    options = fuzz.sample_options(draw)
    figures["configurations"] += 1
    try:
        taken = fuzz.check_episode(kwargs, fuzz.episode_steps, case_seed, form, options)
    except Exception as error:  # noqa: BLE001 - every failure is reported, with its input
        figures["failures"] += 1
        report["failures"].append(
            {
                "family": spec.family,
                "form": form,
                "kwargs": repr(kwargs),
                "options": repr(options),
                "seed": case_seed,
                "error": _error_text(error),
            }
        )
        return fuzz.episode_steps
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
    NumPy env, then each vector backend); a table of the agent steps of each family of
    many agents by form (the race's boat steps) and the scenes' steps by backend, with the
    combinations each scene refused; and the failures with what reproduces them.

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
    lines += _agents_scene_table(report)
    non_finite = sum(
        "non-finite" in f["error"] or "outside" in f["error"] for f in report["failures"]
    )
    done = [f"{report['steps']:,} env steps"]
    for family in _multi_agent_families(report):
        done.append(f"{report[f'{family}_steps']:,} {family} {_agent_name(family)} steps")
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


def _multi_agent_families(report: Mapping[str, Any]) -> list[str]:
    """The families of many agents a report has figures of (a report written before
    ``multi_agent`` listed them has the race's alone, under ``race``)."""
    return list(report.get("multi_agent", ["race"] if "race" in report else []))


def _agent_name(family: str) -> str:
    """What an agent of ``family`` is called (its spec's ``agent_name``: ``"boat"``)."""
    spec = next((s for s in multi_agent_specs() if s.family == family), None)
    return spec.agent_name if spec is not None else "agent"


def _agents_scene_table(report: Mapping[str, Any]) -> list[str]:
    """The second table of :func:`format_report` (none in a report without either)."""
    families, scenes = _multi_agent_families(report), report.get("scenes")
    if not families and scenes is None:
        return []
    backends = list(report.get("scene_backends", ("numpy",)))
    lines = [
        "",
        f"| {' / '.join([*families, 'scene'])} | steps | "
        + " | ".join(backends)
        + " | configurations | refused | failures |",
        "|---|---:|" + "---:|" * len(backends) + "---:|---:|---:|",
    ]
    notes = []
    for family in families:
        for form, f in report[family].get("forms", {}).items():
            # The PettingZoo forms run on NumPy alone.
            by_backend = " | ".join(f"{f['steps']:,}" if b == "numpy" else "-" for b in backends)
            lines.append(
                f"| {family} ({form}) | {f['steps']:,} | {by_backend} "
                f"| {f['configurations']:,} | - | {f['failures']} |"
            )
        agent = _agent_name(family)
        notes.append(
            f"{family.capitalize()} steps are {agent} steps (each {agent}'s action in a "
            f"parallel step; a turn in the AEC form); {report[family]['errors_checked']} "
            f"invalid {family} arguments checked."
        )
    for name, f in (scenes or {}).items():
        by_backend = " | ".join(f"{f['by_backend'].get(b, 0):,}" for b in backends)
        lines.append(
            f"| scene {name} | {f['steps']:,} | {by_backend} "
            f"| {f['configurations']:,} | {f['refused']} | {f['failures']} |"
        )
    if scenes is not None:
        notes.append(
            "Scene steps are `simulate`'s; refused: combinations a scene refuses by a rule "
            "that names another field."
        )
    lines.append("\n" + " ".join(notes))
    return lines


def _failure_line(failure: Mapping[str, Any]) -> str:
    """One failure and what reproduces it, by its kind (env, family of many agents or
    scene)."""
    error = failure["error"][:300]
    if "scene" in failure:
        return (
            f"- scene {failure['scene']} {failure['backend']} steps={failure['steps']}: "
            f"{error}\n  params={failure['params']}"
        )
    if "family" in failure or "race" in failure:  # a family of many agents ("race": older)
        family, form = failure.get("family", "race"), failure.get("form", failure.get("race"))
        if "kwargs" not in failure:
            return f"- {family} {form}: {error}"
        return (
            f"- {family} ({form}) seed={failure['seed']}: {error}"
            f"\n  kwargs={failure['kwargs']}\n  options={failure['options']}"
        )
    return (
        f"- {failure['env_id']} {failure['backend']} num_envs={failure['num_envs']} "
        f"seed={failure['seed']}: {error}\n  kwargs={failure['kwargs']}"
        f"\n  options={failure['options']}"
    )
