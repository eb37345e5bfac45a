"""The site's generated tables, and the MkDocs hook that puts them into the pages.

A page asks for a table with a marker on a line of its own, and ``python docs/tables.py
write`` writes the table into the page after it, up to an end line (``<!-- /table -->``):
the pages read the same in the repository, an editor and the site, and no page holds a
figure typed by hand. The site's build (:func:`on_page_markdown`) and the test suite fail
on a page whose written table differs from what its results and code give now:

    <!-- table: baselines [ENV_PREFIX] -->   docs/results/baselines/*.json (bbgym baseline)
    <!-- table: baselines-summary [PREFIX] --> the same, a row per task, algorithm and engine
    <!-- table: baselines-files NAME ... -->  the same columns, a row per named results file
    <!-- table: speed -->                    docs/results/speed/bench.json (bbgym bench)
    <!-- table: speed-summary -->            the same, as ratios to CartPole-v1 in one grid
    <!-- table: speed-gpu -->                docs/results/speed/cuda-*.log (bench --device cuda)
    <!-- table: backends -->                 docs/results/speed/bench-backends-0.3.1.json
    <!-- table: polar -->                    docs/results/polar/polar.csv (bbgym polar)
    <!-- table: polar-compare -->            docs/results/polar/compare.csv (bbgym polar --compare)
    <!-- table: race-selfplay -->            docs/results/race/*.json (scripts/race_selfplay.py)
    <!-- table: fuzz -->                     docs/results/fuzz/fuzz.json (bbgym fuzz)
    <!-- table: compile -->                  docs/results/speed/compile.json
                                             (scripts/compile_times.py)
    <!-- table: backends-jax -->             docs/results/speed/bench-jax.json
                                             (bbgym bench --jax)
    <!-- table: compile-jax -->              docs/results/speed/compile-jax.json
                                             (scripts/compile_times.py --backend jax)
    <!-- table: arguments FAMILY -->         ARGUMENT_TABLE of bbgym.envs.FAMILY (the code)
    <!-- table: params GROUP -->             the intervals of a physics parameter dataclass
    <!-- include: CHANGELOG.md -->           a file of docs/, as it is (a .py file as a
                                             code block)

Every results table names the command that wrote its results file, and says where a file
was transcribed rather than written by that command (its ``source`` field). A missing or
malformed results file raises :class:`ResultsError` naming it, which fails the build.

    python docs/tables.py write            # write every page's tables (after new results)
    python docs/tables.py check            # list the pages whose tables are stale
    python docs/tables.py baselines        # print a table (any marker's words)
    python docs/tables.py record-baseline RUN [--command C] [--note N] [--name NAME]
                                           # a bbgym baseline run folder -> its results file
                                           # (<env>-<algo>.json, or NAME.json)
"""

from __future__ import annotations

import csv
import json
import re
import sys
from pathlib import Path
from typing import Any

DOCS = Path(__file__).resolve().parent
RESULTS = DOCS / "results"

BASELINE_FILES = (
    "BeachballSail-v2-sac.json",
    "BeachballSail-v1-sac.json",
    "BeachballSail-v1-sac-quick.json",
    "BeachballSail-v1-ppo.json",
    "BeachballSail-v1-torchrl-ppo.json",
    "BeachballSail-v1-rejax-sac.json",
    "BeachballSail-v0-ppo.json",
    "BeachballThrow-v1-ppo.json",
    "BeachballThrow-v1-rejax-ppo.json",
    "BeachballThrow-v0-ppo.json",
    "BeachballThrow-v0-torchrl-ppo.json",
    "BeachballCurve-v2-ppo.json",
    "BeachballCurve-v1-ppo.json",
    "BeachballCurve-v1-sac.json",
    "BeachballCurve-v1-torchrl-ppo.json",
    "BeachballTopple-v2-ppo.json",
    "BeachballTopple-v1-ppo.json",
    "BeachballTopple-v1-torchrl-ppo.json",
    "BeachballTopple-v2-torchrl-ppo.json",
    "main.json",
)
"""The baselines' results files, in the order of the table's rows."""
SPEED_FILE = "speed/bench.json"
BACKENDS_FILE = "speed/bench-backends-0.3.1.json"
BACKENDS_JAX_FILE = "speed/bench-jax.json"
SCENES_SPEED_FILE = "speed/bench-scenes.json"
POLAR_FILE = "polar/polar.json"
FUZZ_FILE = "fuzz/fuzz.json"
COMPILE_FILE = "speed/compile.json"
COMPILE_JAX_FILE = "speed/compile-jax.json"
RACE_SELFPLAY_FILES = ("race/selfplay.json", "race/selfplay_absolute.json")
"""The race's self-play results (``scripts/race_selfplay.py --results``), one row each."""

THROW_ENVS = ("BeachballThrow", "BeachballCurve", "BeachballTopple")

MARKER = re.compile(r"^<!-- (table|include): *([^>]*?) *-->$", re.MULTILINE)
BLOCK = re.compile(
    r"^<!-- (table|include): *([^>]*?) *-->\n"  # the marker
    # what was written after it, up to its end line: lazily, and never across another marker
    r"(?:(?:(?!<!-- (?:table|include):).*\n)*?<!-- /\1 -->\n)?",
    re.MULTILINE,
)
"""A marker and, where :func:`expand` has written it, its table and end line."""
PAGES = DOCS / "pages"


class ResultsError(ValueError):
    """A results file is missing or malformed (the message names the file)."""


def _name(path: Path) -> str:
    try:
        return str(path.relative_to(DOCS.parent))
    except ValueError:
        return str(path)


def read_json(path: Path) -> Any:
    """A results file's JSON, or :class:`ResultsError` naming the file."""
    if not path.is_file():
        raise ResultsError(f"{_name(path)}: results file missing")
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as err:
        raise ResultsError(f"{_name(path)}: not valid JSON ({err})") from None


def field(data: Any, key: str, path: Path, kind: type | tuple[type, ...] = object) -> Any:
    """``data[key]``, of type ``kind``, or :class:`ResultsError` naming the file and key."""
    if not isinstance(data, dict) or key not in data:
        raise ResultsError(f"{_name(path)}: no {key!r} field")
    value = data[key]
    if not isinstance(value, kind):
        raise ResultsError(f"{_name(path)}: {key!r} is {type(value).__name__}, not as expected")
    return value


def pct(rate: float) -> str:
    return f"{100 * rate:.0f}%"


def rate_cell(row: dict, unit: str = "") -> str:
    """``98% (93-99%), 1.1 throws`` or ``100% (96-100%), 37.3 s to the mark``."""
    text = pct(row["success_rate"])
    if row.get("success_ci95"):
        low, high = row["success_ci95"]
        text += f" ({100 * low:.0f}-{100 * high:.0f}%)"
    if row.get("mean_time_to_mark_s"):
        text += f", {row['mean_time_to_mark_s']:.1f} s to the mark"
    elif unit and row.get("mean_length") is not None:
        text += f", {row['mean_length']:.1f} {unit}"
    return text


def failures(outcomes: dict | None) -> str:
    failed = {k: v for k, v in (outcomes or {}).items() if k != "success"}
    return ", ".join(f"{kind} {count}" for kind, count in failed.items()) or "none"


def budget(steps: int, unit: str) -> str:
    if steps >= 1_000_000:
        return f"{steps / 1e6:g}M {unit}"
    return f"{steps / 1e3:g}k {unit}"


def baseline_row(path: Path) -> tuple[str, str]:
    """One row of the baselines table from a results file, and its source note."""
    data = read_json(path)
    source = field(data, "source", path, str)
    command = field(data, "command", path, str)
    summary = field(data, "summary", path, dict)
    rows = field(data, "results", path, list)
    env = field(summary, "env", path, str)
    algo = field(summary, "algo", path, str)
    engine = summary.get("engine", "sb3")
    by_policy = {r.get("policy"): r for r in rows if isinstance(r, dict)}
    learnt = [r for r in rows if isinstance(r, dict) and r.get("algo") == algo]
    for name in ("random", "scripted"):
        if name not in by_policy:
            raise ResultsError(f"{_name(path)}: no {name!r} row in 'results'")
    if not learnt:
        raise ResultsError(f"{_name(path)}: no row of the learnt policy ({algo}) in 'results'")
    try:
        ball = env.startswith(THROW_ENVS)
        unit = "steps" if env.startswith("BeachballTopple") else "throws" if ball else ""
        planner = data.get("planner")
        r = learnt[0]
        low, high = r["success_ci95"]
        seeds = r["success_by_seed"]
        if len(seeds) > 1:
            mean = (
                f"{100 * r['success_rate']:.1f}% ({100 * low:.0f}-{100 * high:.0f}%), "
                f"worst {pct(r['worst_seed_success_rate'])} (seed {r['worst_seed']}); "
                f"seeds {', '.join(f'{100 * s:.0f}' for s in seeds)}%"
            )
        else:
            mean = f"{rate_cell(r)} (seed {r['training_seeds'][0]})"
        ratio = r.get("time_vs_oracle")
        if ratio is not None and len(seeds) > 1:
            ratio = f"{ratio:.2f} (worst seed {r['worst_time_vs_oracle']:.2f})"
        elif ratio is not None:
            ratio = f"{ratio:.2f}"
        cells = [
            f"{env}, {algo.upper()}"
            + (f" ({engine})" if engine != "sb3" else "")
            + _named_preset(env, summary.get("config"))
            + (" (`make run`)" if path.stem == "main" else ""),
            rate_cell(by_policy["random"], unit),
            rate_cell(by_policy["scripted"], unit),
            rate_cell(planner, unit) if planner else "-",
            mean,
            ratio or "-",
            failures(r.get("outcomes")),
            f"{budget(summary['timesteps'], unit or 'steps')}, {summary['n_envs']} envs",
            data.get("wall_time", "-"),
            summary.get("bbgym", "-"),
            f"`{command}`",
        ]
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    return "| " + " | ".join(cells) + " |", f"`{_name(path)}`: {source}"


def _named_preset(env: str, config: Any) -> str:
    """`` (`beachball_sail_v1_quick`)`` for a row trained from a shipped preset other than
    the env id's own, so that two rows of one env and algorithm say which is which (a file
    of the user's, not shipped, is not named)."""
    from bbgym.config import CONFIG_DIR, env_preset

    if not config or config == env_preset(env)[0].stem:
        return ""
    return f" (`{config}`)" if (CONFIG_DIR / f"{config}.yaml").is_file() else ""


def baselines_table(env_prefix: str = "", results: Path = RESULTS) -> str:
    """The baselines table: a row per results file (those of envs starting with
    ``env_prefix``), and under it where each file came from."""
    lines = [
        "| env, algorithm | random | scripted | planner (winnable, at least) | learnt: mean "
        "(95% interval over seeds), worst seed | time / oracle | failures of the learnt policy "
        "| budget | training time | bbgym | command |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    notes = []
    for name in BASELINE_FILES:
        if not name.startswith(env_prefix):
            continue
        row, note = baseline_row(results / "baselines" / name)
        lines.append(row)
        notes.append(note)
        data = read_json(results / "baselines" / name)
        if data.get("note"):
            notes[-1] += f" {data['note']}"
        if data.get("planner_command"):
            notes[-1] += f" Planner column: `{data['planner_command']}`."
    if not notes:
        raise ResultsError(f"no baselines results file for envs {env_prefix!r}")
    lines += ["", '??? note "Where each results file came from (each row\'s command made it)"', ""]
    lines += [f"    - {note}" for note in notes]
    return "\n".join(lines)


def current_ids() -> list[str]:
    """The newest registered version of each task (``BeachballCurve-v2``), in the
    families' order: what ``gym.make`` users should pick."""
    newest: dict[str, str] = {}
    for spec in families().values():
        for version in spec.versions:
            task, _, number = version.env_id.rpartition("-v")
            known = newest.get(task)
            if known is None or int(number) > int(known.rpartition("-v")[2]):
                newest[task] = version.env_id
    return list(newest.values())


def _version(env_id: str) -> tuple[str, int]:
    task, _, number = env_id.rpartition("-v")
    return task, int(number)


def _train_minutes(data: dict, summary: dict) -> str:
    """``17.5-19.4 min (2 at once, 1 thread each)``: a seed's training time, from the
    per-seed seconds where the file has them, else from its ``wall_time`` text."""
    seconds = summary.get("train_wall_time_s_per_seed")
    if seconds:
        low, high = min(seconds.values()) / 60, max(seconds.values()) / 60
        text = f"{low:.1f} min" if low == high else f"{low:.1f}-{high:.1f} min"
    else:
        found = re.match(r"[\d.]+(?:-[\d.]+)? min", str(data.get("wall_time", "")))
        text = found.group(0) if found else "-"
    if summary.get("engine") == "rejax":  # one program trains every seed: its share
        return f"{text} ({len(seconds or [1])} seeds in one JAX program, its time / seeds)"
    jobs, threads = summary.get("jobs", 1), summary.get("torch_threads", 1)
    how = f"{jobs} at once" if jobs > 1 else "one at a time"
    return f"{text} ({how}, {threads} thread{'s' if threads > 1 else ''} each)"


def _summary_cells(path: Path) -> tuple[str, str, list[str], str]:
    """``(env, engine, cells, command)`` of the summary row of a results file."""
    data = read_json(path)
    summary = field(data, "summary", path, dict)
    rows = field(data, "results", path, list)
    command = field(data, "command", path, str)
    try:
        env, algo = summary["env"], summary["algo"]
        engine = summary.get("engine", "sb3")
        by_policy = {r.get("policy"): r for r in rows if isinstance(r, dict)}
        scripted = by_policy["scripted"]
        learnt = next(r for r in rows if isinstance(r, dict) and r.get("algo") == algo)
        worst = learnt["worst_seed_success_rate"]
        seeds = len(learnt["success_by_seed"])
        success = f"{100 * learnt['success_rate']:.1f}% (worst {pct(worst)}, {seeds} seeds)"
        unit = "steps" if env.startswith("BeachballTopple") else "throws"
        if learnt.get("time_vs_oracle") is not None:
            ratio = (
                f"time {learnt['time_vs_oracle']:.2f}x "
                f"(worst seed {learnt['worst_time_vs_oracle']:.2f}x)"
            )
        elif learnt.get("mean_length") and scripted.get("mean_length"):
            ratio = f"{unit} {learnt['mean_length'] / scripted['mean_length']:.2f}x"
        else:
            ratio = f"{unit}: not recorded"
        name = algo.upper() + {"torchrl": " (TorchRL)", "rejax": " (rejax)"}.get(engine, "")
        preset = summary.get("config") or "-"
        cells = [
            f"{name}, `{preset}`",
            success,
            f"{pct(scripted['success_rate'])}; {ratio}",
            _train_minutes(data, summary),
        ]
    except (KeyError, TypeError, ValueError, StopIteration) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    return env, engine, cells, command


def baselines_summary_table(
    env_prefix: str = "", results: Path = RESULTS, current: list[str] | None = None
) -> str:
    """The answer first: per task, the newest env version trained with each algorithm and
    engine, one row each (success over the seeds with the worst seed, the scripted oracle's
    success and the learnt policy's time or throws over the oracle's, training time a seed),
    and a row "not trained yet" for each current id that has no stable-baselines3 run; the
    command of each row in a collapsed note under it. Only the envs whose id starts with
    ``env_prefix`` or one of its comma-separated prefixes (an env page's:
    ``"BeachballThrow,BeachballCurve"``)."""
    from bbgym.config import env_preset, load_training

    prefixes = tuple(env_prefix.split(","))
    current = current_ids() if current is None else current
    current = [env for env in current if env.startswith(prefixes)]
    chosen: dict[tuple, tuple] = {}  # (task, algo, engine) -> the newest version's row
    trained_sb3 = set()
    for name in BASELINE_FILES:
        if name == "main.json":  # `make run`: a single seed of the quick preset's row
            continue
        env, engine, cells, command = _summary_cells(results / "baselines" / name)
        if not env.startswith(prefixes):
            continue
        if engine == "sb3":
            trained_sb3.add(env)
        task, number = _version(env)
        key = (task, cells[0].split(",")[0], engine)
        if key not in chosen or number > _version(chosen[key][0])[1]:
            chosen[key] = (env, engine, cells, command)
    for env in current:
        if env not in trained_sb3:
            algo = str(load_training(env)[1]["algo"]).upper()
            cells = [f"{algo}, `{env_preset(env)[0].stem}`", "**not trained yet**", "-", "-"]
            chosen[(*_version(env), "gap")] = (env, "sb3", cells, f"bbgym baseline --env {env}")
    tasks = [_version(env)[0] for env in current]

    def order(row: tuple) -> tuple:
        task, number = _version(row[0])
        return (tasks.index(task) if task in tasks else len(tasks), -number, row[1] != "sb3")

    return _summary_rows(sorted(chosen.values(), key=order), current)


def baselines_files_table(names: str, results: Path = RESULTS) -> str:
    """The summary rows (:func:`baselines_summary_table`'s columns) of the named results
    files, in the order named: ``names`` is space-separated file names without ``.json``,
    e.g. two engines' runs of one env side by side."""
    rows = []
    for name in names.split():
        if f"{name}.json" not in BASELINE_FILES:
            raise ResultsError(f"baselines-files: {name}.json is not in BASELINE_FILES")
        rows.append(_summary_cells(results / "baselines" / f"{name}.json"))
    return _summary_rows(rows, current_ids())


def _summary_rows(rows: list[tuple], current: list[str]) -> str:
    """The summary table of ``rows`` (``(env, engine, cells, command)``), its legend and
    the collapsed note of each row's command."""
    lines = [
        "| env | algorithm, preset | success (worst seed) | scripted oracle: success; learnt "
        "/ oracle | training a seed (2 cores) |",
        "|---|---|---|---|---|",
    ]
    commands = ["| env, algorithm | command |", "|---|---|"]
    for env, _, cells, command in rows:
        shown = f"**{env}**" if env in current else env
        lines.append(f"| {shown} | " + " | ".join(cells) + " |")
        what = "not run yet: " if "not trained yet" in cells[1] else ""
        commands.append(f"| {env}, {cells[0].split(',')[0]} | {what}`{command}` |")
    legend = (
        "**Bold**: the current version of each task (the newest id registered); the others "
        "are the newest version trained with that algorithm. Success: the learnt policy's "
        "mean over its training seeds on evaluation episodes 0-99, and its worst seed. "
        "Learnt / oracle: its time to the mark (sailing) or its throws or steps an episode "
        "(the ball envs) over the scripted agent's. Training: minutes a seed on the "
        "project's 2-core CPU machine, as the run was made. Every run of every results "
        "file, with its random and scripted play, failures and budget: Baselines, every run."
    )
    note = ['??? note "The command of each row"', ""]
    note += [f"    {line}" for line in commands]
    return "\n".join([*lines, "", legend, "", *note])


def _bench(path: Path) -> tuple[dict, str]:
    data = read_json(path)
    command = field(data, "command", path, str)
    source = field(data, "source", path, str)
    settings = f" Settings: {data['settings']}." if data.get("settings") else ""
    return data, f"Generated from `{_name(path)}`, written by `{command}`: {source}.{settings}"


def _machine(data: dict) -> str:
    m = data.get("machine") or {}
    return (
        f"Machine: {m.get('platform', '?')}, {m.get('cpu_count', '?')} CPUs, Python "
        f"{m.get('python', '?')}, NumPy {m.get('numpy', '?')}, Gymnasium "
        f"{m.get('gymnasium', '?')}, torch {m.get('torch', '-')} on "
        f"{m.get('torch_threads', '-')} threads."
    )


def _unit(row: dict, ppo_is_steps: bool = True) -> str:
    if row["env"].startswith("scene "):
        return " particle-steps/s"
    if row["env"].startswith(THROW_ENVS) and not (ppo_is_steps and row["kind"].startswith("PPO")):
        return " throws/s"
    return ""


def speed_table(path: Path | None = None) -> str:
    """``bbgym bench``'s rows and memory table (its ``bench.md``, from ``bench.json``)."""
    path = path or RESULTS / SPEED_FILE
    data, note = _bench(path)
    rows = field(data, "rows", path, list)
    memory = field(data, "memory_mb", path, dict)
    try:
        lines = [
            "| env | kind | steps/s | ratio to CartPole-v1 (same kind) |",
            "|---|---|---:|---:|",
        ]
        lines += [
            f"| {r['env']} | {r['kind']} | {r['rate']:,.0f}{_unit(r)} | {r['ratio']:.4f} |"
            for r in rows
        ]
        lines += ["", "| env | peak memory of the vector env, N=4096 |", "|---|---:|"]
        lines += [f"| {env} | {mb:.1f} MB |" for env, mb in memory.items()]
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    return "\n".join([*lines, "", note, _machine(data)])


def _fraction(ratio: float) -> str:
    """A rate over CartPole's as ``1/191`` (CartPole made 191 times as many), or ``2.5x``."""
    if ratio >= 1:
        return f"{ratio:.2g}x" if ratio < 10 else f"{ratio:,.0f}x"
    times = 1 / ratio
    return f"1/{times:.1f}" if times < 10 else f"1/{times:,.0f}"


def speed_summary_table(path: Path | None = None) -> str:
    """The answer first: ``bbgym bench``'s rows as one grid, an env a row and a kind of
    stepping a column, each cell the env's rate as a fraction of CartPole-v1's in the same
    kind and run (CartPole's row: its own rate)."""
    path = path or RESULTS / SPEED_FILE
    data, note = _bench(path)
    rows = field(data, "rows", path, list)
    try:
        kinds = list(dict.fromkeys(r["kind"] for r in rows))
        envs = list(dict.fromkeys(r["env"] for r in rows))
        cell = {(r["env"], r["kind"]): r for r in rows}
        reference = [env for env in envs if env.startswith("CartPole")]
        if not reference:
            raise ResultsError(f"{_name(path)}: no CartPole row to compare with")
        lines = ["| env | " + " | ".join(kinds) + " |", "|---|" + "---:|" * len(kinds)]
        for env in reference + [env for env in envs if env not in reference]:
            cells = []
            for kind in kinds:
                r = cell.get((env, kind))
                if r is None:
                    cells.append("-")
                elif env in reference:
                    cells.append(f"{r['rate']:,.0f}/s")
                else:
                    cells.append(_fraction(r["ratio"]))
            lines.append(f"| {env} | " + " | ".join(cells) + " |")
    except (KeyError, TypeError, ValueError, ZeroDivisionError) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    legend = (
        f"{reference[0]}'s row: its steps per second. The others: the env's rate over "
        f"{reference[0]}'s in the same column and run (1/191: CartPole made 191 times as "
        "many steps; the ball envs' env rows count throws, their PPO rows steps, one step "
        "a throw). The NumPy backend on the CPU."
    )
    return "\n".join([*lines, "", legend, "", note, _machine(data)])


GPU_LOG = "speed/cuda-h200-2026-12-04.log"
"""The output of ``bbgym bench --device cuda`` runs on a lent GPU, as printed."""
_GPU_ROW = re.compile(
    r"^(?P<env>\S+) N=(?P<n>\d+) (?P<backend>torch|numpy) (?P<dtype>float\d+)"
    r"(?P<cuda> cuda)?(?:, (?P<graph>[a-z ]+))?: (?P<rate>[\d,]+)/s"
    r"(?:, warm-up (?P<warmup>[\d.]+) s)?$"
)
_CARTPOLE_ROW = re.compile(r"^(?P<env>CartPole-v1) N=(?P<n>\d+): (?P<rate>[\d,]+)/s$")


def gpu_speed_table(path: Path | None = None, smallest: int = 4096) -> str:
    """The GPU rows (N >= ``smallest``) of a ``bbgym bench --device cuda`` log: each with
    its ratio to CartPole's NumPy vector env on the CPU and to the env's own NumPy backend
    at the same N, where the same lease (a ``## lease`` section) measured them."""
    path = path or RESULTS / GPU_LOG
    if not path.is_file():
        raise ResultsError(f"{_name(path)}: results file missing")
    text = path.read_text(encoding="utf-8").splitlines()
    leases: list[list[re.Match]] = [[]]
    for line in text:
        if line.startswith("## lease"):
            leases.append([])
        match = _GPU_ROW.match(line) or _CARTPOLE_ROW.match(line)
        if match:
            leases[-1].append(match)
    lines = [
        "| env | N, dtype, step | steps/s on the GPU | over CartPole (CPU) | over NumPy (CPU) "
        "| first step (compile) |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for lease in leases:
        rate = {}
        for m in lease:
            key = "numpy" if m.groupdict().get("backend") == "numpy" else m["env"]
            rate[(key if key in ("numpy", "CartPole-v1") else "gpu", m["env"], m["n"])] = m
        for m in lease:
            if m.groupdict().get("cuda") is None or int(m["n"]) < smallest:
                continue
            gpu = int(m["rate"].replace(",", ""))
            cartpole = rate.get(("CartPole-v1", "CartPole-v1", m["n"]))
            numpy = rate.get(("numpy", m["env"], m["n"]))

            def over(ref: re.Match | None, gpu: int = gpu) -> str:
                return _fraction(gpu / int(ref["rate"].replace(",", ""))) if ref else "-"

            unit = " throws" if m["env"].startswith(THROW_ENVS) else ""
            lines.append(
                f"| {m['env']} | {int(m['n']):,}, {m['dtype']}, {m['graph']} | "
                f"{gpu:,}{unit} | {over(cartpole)} | {over(numpy)} | {m['warmup']} s |"
            )
    if len(lines) == 2:
        raise ResultsError(f"{_name(path)}: no GPU row of N >= {smallest}")
    header = text[0].lstrip("# ").rstrip(",") if text else ""
    note = (
        f"Read from `{_name(path)}`: {header}. The rows at N >= {smallest:,}; a ratio only "
        "where the same lease measured the reference at the same N ('-': not measured)."
    )
    return "\n".join([*lines, "", note])


def backends_table(path: Path | None = None) -> str:
    """The backend rows of a ``bbgym bench --backends`` (torch) or ``--jax`` run."""
    path = path or RESULTS / BACKENDS_FILE
    data, note = _bench(path)
    rows = field(data, "backend_rows", path, list)
    lines = [
        "| env | N, backend | steps/s | ratio to CartPole-v1 (same N) | first step (compile) "
        "| state |",
        "|---|---|---:|---:|---:|---:|",
    ]
    try:
        for r in rows:
            extra = f"{r['warmup_s']:.1f} s | {r['state_mb']:.1f} MB" if "warmup_s" in r else " | "
            lines.append(
                f"| {r['env']} | {r['kind']} | {r['rate']:,.0f}{_unit(r)} | "
                f"{r['ratio']:.4f} | {extra} |"
            )
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    return "\n".join([*lines, "", note, _machine(data)])


def sph_speed_table(path: Path | None = None) -> str:
    """The SPH dam break's rows of ``bbgym bench --scenes``: steps/s by the uniform grid and
    by every pair, and each step's cost over its kind's at the smallest size beside the
    particles' ratio (the grid's cost grows like it, every pair's like its square)."""
    path = path or RESULTS / SCENES_SPEED_FILE
    data, note = _bench(path)
    rows = field(data, "sph_rows", path, list)
    lines = [
        "| particles | neighbours, backend | steps/s | particle-steps/s | cost of a step "
        "(x the smallest size's) | particles (x the smallest size's) | first step (compile) |",
        "|---:|---|---:|---:|---:|---:|---:|",
    ]
    try:
        smallest = min(r["particles"] for r in rows)
        for r in rows:
            lines.append(
                f"| {r['particles']:,} | {r['neighbours']} | {r['steps_per_s']:,.2f} | "
                f"{r['rate']:,.0f} | {r['cost']:.1f} | "
                f"{r['particles'] / smallest:g} | {r['warmup_s']:.1f} s |"
            )
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    return "\n".join([*lines, "", note, _machine(data)])


def polar_table(path: Path | None = None) -> str:
    """The polar's figures (best upwind VMG, straight upwind, fastest, leeway) from the
    CSV of ``bbgym polar``, beside a Laser's and the bands ``tests/sail/test_polar.py`` asserts."""
    path = path or RESULTS / POLAR_FILE
    meta = read_json(path)
    command = field(meta, "command", path, str)
    source = field(meta, "source", path, str)
    wind = field(meta, "wind_speed_mps", path, (int, float))
    csv_path = path.parent / field(meta, "csv", path, str)
    if not csv_path.is_file():
        raise ResultsError(f"{_name(csv_path)}: results file missing")
    try:
        with csv_path.open(newline="") as f:
            rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
        upwind = [r for r in rows if r["true_wind_angle_deg"] < 90]
        best = max(upwind, key=lambda r: r["vmg_mps"])
        head = min(rows, key=lambda r: abs(r["true_wind_angle_deg"]))
        fast = max(rows, key=lambda r: r["boat_speed_mps"])
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(csv_path)}: malformed polar CSV ({err!r})") from None
    if not rows:
        raise ResultsError(f"{_name(csv_path)}: no rows")
    lines = [
        "| figure | bbgym | real dinghy (Laser) | band asserted by `tests/sail/test_polar.py` |",
        "|---|---|---|---|",
        f"| best upwind VMG | {best['true_wind_angle_deg']:.0f} deg, {best['vmg_mps']:.2f} m/s "
        "| about 40 deg | 38-48 deg |",
        f"| straight upwind | VMG {head['vmg_mps']:.2f} m/s | no progress | <= 0 |",
        f"| fastest point of sail | {fast['true_wind_angle_deg']:.0f} deg, "
        f"{fast['boat_speed_mps']:.2f} m/s = {fast['boat_speed_mps'] / wind:.2f} x wind "
        "| about 120 deg, 0.67 x wind | 90-135 deg, 0.55-0.85 |",
        f"| leeway at best upwind VMG | {best['leeway_deg']:.1f} deg (heel "
        f"{best['heel_deg']:.0f} deg) | a few degrees | 2-8 deg |",
    ]
    return "\n".join(
        [
            *lines,
            "",
            f"True wind {wind:g} m/s. Generated from `{_name(csv_path)}`, written by "
            f"`{command}`: {source}.",
        ]
    )


COMPARE_FILE = "polar/compare.csv"


def polar_compare_table(path: Path | None = None) -> str:
    """The calibrated sloop against a Laser's reference polar, from the CSV of
    ``bbgym polar --compare``."""
    path = path or RESULTS / COMPARE_FILE
    if not path.is_file():
        raise ResultsError(f"{_name(path)}: results file missing")
    try:
        with path.open(newline="") as f:
            rows = list(csv.DictReader(f))
        lines = [
            "| source | wind (kn) | figure | TWA | reference | bbgym | error | within |",
            "|---|---:|---|---:|---:|---:|---:|---|",
        ]
        for r in rows:
            ref, ours, err = float(r["reference"]), float(r["bbgym"]), float(r["error"])
            if r["quantity"] == "best TWA":
                cells = f"best TWA | | {ref:.1f} deg | {ours:.0f} deg | {err:+.1f} deg"
            else:
                cells = (
                    f"{r['quantity']} | {float(r['true_wind_angle_deg']):g} deg | {ref:.2f} kn "
                    f"| {ours:.2f} kn | {100 * err:+.1f}%"
                )
            within = "yes" if int(r["within"]) else "**no**"
            lines.append(f"| {r['source']} | {float(r['wind_kn']):g} | {cells} | {within} |")
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(path)}: malformed comparison CSV ({err!r})") from None
    if len(lines) == 2:
        raise ResultsError(f"{_name(path)}: no rows")
    return "\n".join(
        [
            *lines,
            "",
            f"Generated from `{_name(path)}`, written by "
            "`bbgym polar --compare --out docs/results/polar`.",
        ]
    )


def families() -> dict[str, Any]:
    """The registered Gymnasium env families' specs by name (:mod:`bbgym.spec`)."""
    import bbgym  # noqa: F401  (registers the families)
    from bbgym.spec import specs

    return {spec.family: spec for spec in specs()}


def every_family() -> dict[str, Any]:
    """:func:`families` and the families of many agents (the race's spec) by name: what
    the argument tables cover."""
    from bbgym.spec import multi_agent_specs

    return families() | {spec.family: spec for spec in multi_agent_specs()}


def param_groups() -> dict[str, type]:
    """The physics parameter dataclasses that envs take as mappings, by their argument
    name, from the families' specs."""
    specs = every_family().values()
    return {name: cls for spec in specs for name, cls in spec.param_groups.items()}


def argument_rows(family: str) -> list[tuple[str, str]]:
    """``(names, accepted)`` rows of an env family's arguments and reset options: its
    spec's ``argument_table`` (the intervals the validation uses, formatted by it)."""
    known = every_family()
    if family not in known:
        raise LookupError(f"unknown env family {family!r}; known: {', '.join(known)}")
    return [(str(names), str(accepted)) for names, accepted in known[family].argument_rows()]


def arguments_table(family: str) -> str:
    lines = ["| argument or option | accepted |", "|---|---|"]
    lines += [f"| {names} | {accepted} |" for names, accepted in argument_rows(family)]
    return "\n".join(lines)


def _space(space: Any) -> str:
    """A Box as ``Box(low, high, shape)`` with its bounds written as scalars when uniform."""
    import numpy as np

    low, high = np.unique(space.low), np.unique(space.high)
    if len(low) == 1 and len(high) == 1:
        return f"`Box({low[0]:g}, {high[0]:g}, {space.shape})`"
    return f"`{space}`"


def versions_table(family: str) -> str:
    """``| id | actions | observation | what it is |`` for every version of a family, newest
    first: the spaces from the env itself (``gym.make``), the rest from its spec."""
    import importlib

    known = families()
    if family not in known:
        raise LookupError(f"unknown env family {family!r}; known: {', '.join(known)}")
    spec = known[family]
    lines = ["| id | actions | observation | what it is |", "|---|---|---|---|"]
    for version in reversed(spec.versions):
        # The class itself with the registered kwargs: gym.make would warn that an old
        # version is out of date, and only the spaces are wanted.
        env_class = getattr(importlib.import_module(spec.module), spec.env_class)
        env = env_class(**version.kwargs)
        actions = f"{_space(env.action_space)}: {version.actions_of(spec)}"
        lines.append(
            f"| `{version.env_id}` | {actions} | {_space(env.observation_space)} "
            f"| {version.changes} |"
        )
        env.close()
    return "\n".join(lines)


def params_table(group: str) -> str:
    """``| `group.field` | default | accepted |`` for every field of the group's dataclass
    that declares an interval (``bbgym.physics.validation.interval_rows``)."""
    from bbgym.physics.validation import interval_rows

    groups = param_groups()
    if group not in groups:
        raise LookupError(f"unknown parameter group {group!r}; known: {', '.join(groups)}")
    cls = groups[group]
    lines = ["| field | default | accepted |", "|---|---:|---|"]
    return "\n".join([*lines, *interval_rows(cls, group)])


def race_selfplay_table(results: Path = RESULTS) -> str:
    """Learned boats against scripted racers: per results file a row of the learned boats
    (mean, worst seed and interval over training seeds) and the reference row (the racer
    in the learners' places, the same races; once where files share it)."""
    lines = [
        "| boats in the learners' places | training | pairings ahead of a scripted boat "
        "(mean, worst seed, 95% interval over seeds) | fouls a boat, learned / scripted "
        "| finished, learned / scripted | return of a learning boat |",
        "|---|---|---|---|---|---:|",
    ]

    def cells(row: dict) -> str:
        return (
            f"{row['learned_fouls']:.2f} / {row['scripted_fouls']:.2f} | "
            f"{pct(row['learned_finished'])} / {pct(row['scripted_finished'])} | "
            f"{row['learned_return']:.1f} |"
        )

    notes = []
    for name in RACE_SELFPLAY_FILES:
        path = results / name
        data = read_json(path)
        try:
            seeds, ref = data["seeds"], data["reference"]
            spread = data["ahead_share_interval"]  # null for one seed
            span = f"{pct(spread[0])}-{pct(spread[1])}" if spread else "no interval: one seed"
            mean = {
                key: sum(s[key] for s in seeds) / len(seeds)
                for key in (
                    "learned_fouls",
                    "scripted_fouls",
                    "learned_finished",
                    "scripted_finished",
                    "learned_return",
                )
            }
            training = (
                f"{len(seeds)} seeds x {budget(data['timesteps'], 'steps')}, "
                f"{data['races_trained_at_once']} races at once"
            )
            reward = "relative reward" if data["relative_reward"] else "the race's reward"
            training = f"{training}, {reward}"
            lines.append(
                f"| {data['policy']} | {training} | {pct(data['ahead_share_mean'])} "
                f"({pct(data['ahead_share_worst'])}, {span}) | "
                f"{cells(mean)}"
            )
            reference = (
                f"| the scripted racer (reference) | - | {pct(ref['ahead_share'])} | {cells(ref)}"
            )
            if reference not in lines:  # the same races scored: one row serves both
                lines.append(reference)
            source = f", {data['source']}" if "source" in data else ""
            notes.append(
                f"`{_name(path)}`, written by `{data['command']} --results` "
                f"({data['eval_races']} races seeded from {data['eval_seed']}, "
                f"torch on {data['torch_threads']} threads{source})"
            )
        except (KeyError, TypeError, ValueError, ZeroDivisionError) as err:
            raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    return "\n".join([*lines, "", "Generated from " + "; ".join(notes) + "."])


def scenes_table() -> str:
    """The course's scenes (:mod:`bbgym.scenes`): each one's section, what the text
    claims and the test that checks it, from the registry."""
    from bbgym.scenes import SCENES

    root = Path(__file__).resolve().parents[1]
    lines = [
        "| scene | section | what the text shows, as the test checks it | test |",
        "|---|---|---|---|",
    ]
    for scene in SCENES.values():
        file = next(
            path.relative_to(root).as_posix()
            for path in sorted((root / "tests").rglob("test_scenes*.py"))
            if f"\ndef {scene.test}(" in path.read_text()
        )
        lines.append(
            f"| `{scene.name}`: {scene.title} | {scene.section} | {scene.claim} | "
            f"`{file}::{scene.test}` |"
        )
    return "\n".join(lines)


def scene_table(name: str) -> str:
    """A scene's measures at the start and the end of its default run, least and greatest,
    computed when the site is built (what ``bbgym scene NAME`` prints)."""
    from bbgym.scenes import get_scene, simulate
    from bbgym.scenes.scene import summary_rows

    scene = get_scene(name)
    run = simulate(scene)
    steps = len(run.times_s) - 1
    lines = ["| measure | body | start | end | least | greatest |", "|---|---|---:|---:|---:|---:|"]
    for measure, body, *numbers in summary_rows(run, scene.names(run.params)):
        lines.append(f"| {measure} | {body} | " + " | ".join(f"{v:.4g}" for v in numbers) + " |")
    note = (
        f"Generated by `bbgym scene {name}` ({steps} steps of {run.params.dt_s:.4g} s, "
        "the scene's defaults)."
    )
    return "\n".join([*lines, "", note])


def fuzz_table(path: Path | None = None) -> str:
    """The last long fuzz run (``bbgym fuzz --out docs/results/fuzz``): steps by id and
    path, failures, and the command that ran it."""
    from bbgym.fuzz import format_report

    path = path or RESULTS / FUZZ_FILE
    data = read_json(path)
    command = field(data, "command", path, str)
    return f"{format_report(data)}\n\nWritten by `{command}`. {_machine(data)}"


def _compile_cell(run: dict | None, cache: str = "inductor_cache", digits: int = 0) -> str:
    """A first step's seconds and what the compile cache did (``78 s (miss)``).

    Args:
        run: a run of ``scripts/compile_times.py`` (None: not run).
        cache: the run's key of cache counters named ``..._cache_hit`` and the like
            (``inductor_cache`` on torch, ``jax_cache`` on JAX).
        digits: the decimals of the seconds.

    Returns:
        The table cell.
    """
    if not run:
        return "-"
    if "error" in run:
        return f"failed: {run['error']}"
    counters = run.get(cache) or {}
    did = [k.split("_cache_")[-1] for k, v in sorted(counters.items()) if v and "_cache_" in k]
    return f"{run['first_step_s']:.{digits}f} s ({', '.join(did) or 'no cache'})"


def _later_cell(warm: dict, digits: int = 0) -> str:
    """The warm run's second step in milliseconds (``2 ms``), or ``-``."""
    return f"{warm['second_step_s'] * 1000:.{digits}f} ms" if "second_step_s" in warm else "-"


def _compile_note(data: dict, path: Path, package: str) -> str:
    """The footer of a compile table: the command that wrote ``path`` and the machine, with
    ``package``'s version (``"torch"``, ``"jax"``)."""
    command = field(data, "command", path, str)
    source = f" {data['source']}" if data.get("source") else ""
    m = data.get("machine") or {}
    return (
        f"Written by `{command}`, each run a fresh process (cold: an empty cache folder)."
        + f"{source} "
        + f"Machine: {m.get('platform', '?')}, {m.get('cpu_count', '?')} CPUs, {package} "
        + f"{m.get(package, '?')}."
    )


def compile_table(path: Path | None = None) -> str:
    """The torch backend's first step per env, with a cold and a warm compile cache and
    warm under another thread count, from ``scripts/compile_times.py``'s JSON file."""
    path = path or RESULTS / COMPILE_FILE
    data = read_json(path)
    rows = field(data, "rows", path, list)
    threads = {r.get("warm_other_threads", {}).get("torch_threads") for r in rows} - {None}
    other = (
        f"warm, {'/'.join(map(str, sorted(threads)))} thread(s)"
        if threads
        else "warm, other threads"
    )
    lines = [
        f"| env | batch, dtype | cold cache | warm cache | {other} | later steps |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for row in rows:
        warm = row.get("warm") or {}
        lines.append(
            f"| {row['env_id']} | {row['num_envs']}, {row['dtype']} "
            f"| {_compile_cell(row.get('cold'))} | {_compile_cell(warm)} "
            f"| {_compile_cell(row.get('warm_other_threads'))} | {_later_cell(warm)} |"
        )
    return "\n".join(lines) + "\n\n" + _compile_note(data, path, "torch")


def compile_jax_table(path: Path | None = None) -> str:
    """The JAX backend's first step per env (the ``jax.jit`` compile), with a cold and a
    warm persistent compile cache, from ``scripts/compile_times.py --backend jax``'s JSON
    file: seconds to a tenth, later steps to a hundredth of a millisecond."""
    path = path or RESULTS / COMPILE_JAX_FILE
    data = read_json(path)
    rows = field(data, "rows", path, list)
    lines = [
        "| env | batch, dtype | cold cache | warm cache | later steps |",
        "|---|---|---:|---:|---:|",
    ]
    try:
        for row in rows:
            warm = row.get("warm") or {}
            cold, warm_cell = (_compile_cell(r, "jax_cache", 1) for r in (row.get("cold"), warm))
            lines.append(
                f"| {row['env_id']} | {row['num_envs']}, {row['dtype']} | {cold} | {warm_cell} "
                f"| {_later_cell(warm, 2)} |"
            )
        made = [
            run["make_and_reset_s"]
            for row in rows
            for run in (row.get("cold"), row.get("warm"))
            if run and "make_and_reset_s" in run
        ]
    except (KeyError, TypeError, ValueError) as err:
        raise ResultsError(f"{_name(path)}: malformed results ({err!r})") from None
    # The reset is a program of its own, compiled in every process (too quick for JAX to
    # cache it): a cost the first-step columns leave out.
    span = sorted({f"{min(made):.1f}", f"{max(made):.1f}"}, key=float) if made else []
    reset = (
        f" Making and resetting the env, before the first step: {'-'.join(span)} s a run, "
        "cold or warm."
        if span
        else ""
    )
    return "\n".join(lines) + "\n\n" + _compile_note(data, path, "jax") + reset


def table(spec: str) -> str:
    """The table a marker's words ask for (``"baselines BeachballSail"``)."""
    kind, _, arg = spec.partition(" ")
    arg = arg.strip()
    if kind == "baselines-files":
        return baselines_files_table(arg)
    if kind == "baselines-summary":
        return baselines_summary_table(arg)
    if kind == "speed-summary" and not arg:
        return speed_summary_table()
    if kind == "speed-gpu" and not arg:
        return gpu_speed_table()
    if kind == "baselines":
        return baselines_table(arg)
    if kind == "speed" and not arg:
        return speed_table()
    if kind == "backends" and not arg:
        return backends_table()
    if kind == "backends-jax" and not arg:
        return backends_table(RESULTS / BACKENDS_JAX_FILE)
    if kind == "polar" and not arg:
        return polar_table()
    if kind == "polar-compare" and not arg:
        return polar_compare_table()
    if kind == "race-selfplay" and not arg:
        return race_selfplay_table()
    if kind == "compile" and not arg:
        return compile_table()
    if kind == "compile-jax" and not arg:
        return compile_jax_table()
    if kind == "fuzz" and not arg:
        return fuzz_table()
    if kind == "arguments":
        return arguments_table(arg)
    if kind == "params":
        return params_table(arg)
    if kind == "versions":
        return versions_table(arg)
    if kind == "scenes" and not arg:
        return scenes_table()
    if kind == "scenes-speed" and not arg:
        return backends_table(RESULTS / SCENES_SPEED_FILE)
    if kind == "sph-speed" and not arg:
        return sph_speed_table()
    if kind == "scene":
        return scene_table(arg)
    raise LookupError(f"unknown table marker {spec!r}")


def include(name: str) -> str:
    path = (DOCS / name).resolve()
    if DOCS not in path.parents or not path.is_file():
        raise LookupError(f"include: no file {name!r} in docs/")
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".py":  # a runnable example, shown whole as code
        return f"```python\n{text.rstrip()}\n```"
    return re.sub(r"\A# .*\n", "", text)  # the page keeps its own title


def expand(markdown: str) -> str:
    """The page's markdown with each marker followed by its table or file as they are now
    (written or rewritten up to the marker's end line; idempotent).

    Blank lines around the table keep Markdown from reading it as part of the comments.
    """

    def replace(match: re.Match) -> str:
        kind, spec = match.group(1), match.group(2)
        body = include(spec) if kind == "include" else table(spec)
        return f"<!-- {kind}: {spec} -->\n\n{body.strip()}\n\n<!-- /{kind} -->\n"

    if not markdown.endswith("\n"):
        markdown += "\n"
    return BLOCK.sub(replace, markdown)


def markdown_pages() -> list[Path]:
    """Every page of the site (docs/pages/**/*.md), in a stable order."""
    return sorted(PAGES.rglob("*.md"))


def stale_pages(pages: list[Path] | None = None) -> list[Path]:
    """The pages whose written tables differ from what the results and code give now."""
    pages = markdown_pages() if pages is None else pages
    return [
        p for p in pages if expand(p.read_text(encoding="utf-8")) != p.read_text(encoding="utf-8")
    ]


def write_pages(pages: list[Path] | None = None) -> list[Path]:
    """Write every marker's table into its page; returns the pages that changed."""
    changed = []
    for page in markdown_pages() if pages is None else pages:
        text = page.read_text(encoding="utf-8")
        new = expand(text)
        if new != text:
            page.write_text(new, encoding="utf-8")
            changed.append(page)
    return changed


SPHINX_ROLE = re.compile(r":(?:func|meth|class|data|attr|mod|obj):<code>~?([^<]*)</code>")
"""A reST cross-reference role in a docstring, as Markdown renders it (``:func:`x```)."""


def on_page_content(html: str, page: Any, config: Any, files: Any) -> str:
    """MkDocs hook: the docstrings' reST roles (``:func:`~a.b```) shown as plain code."""
    return SPHINX_ROLE.sub(r"<code>\1</code>", html)


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    """MkDocs hook (``hooks:`` in docs/mkdocs.yml)."""
    from mkdocs.exceptions import PluginError

    try:
        fresh = expand(markdown)
    except (ResultsError, LookupError) as err:
        raise PluginError(f"docs/tables.py, page {page.file.src_path}: {err}") from None
    if fresh.rstrip() != markdown.rstrip():  # MkDocs may drop the file's last newline
        raise PluginError(
            f"docs/tables.py: page {page.file.src_path} has a stale or unwritten table: "
            "run `python docs/tables.py write` and commit the pages"
        )
    return markdown


SUMMARY_KEYS = (
    "env",
    "config",
    "algo",
    "engine",
    "evaluated_model",
    "training_seeds",
    "jobs",
    "torch_threads",
    "timesteps",
    "n_envs",
    "eval_episodes",
    "eval_seeds",
    "versions",
    "machine",
    "train_wall_time_s_per_seed",
)
"""What a baselines results file keeps of a run folder's ``summary.json``."""


def _rounded(value: Any) -> Any:
    """Floats to 4 significant digits, per-episode lists dropped: a results file is read
    by people and diffs, and the run folder keeps everything."""
    if isinstance(value, float):
        return float(f"{value:.4g}")
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items() if not k.startswith("episode_")}
    if isinstance(value, list):
        return [_rounded(v) for v in value]
    return value


def baseline_results(run: Path, command: str | None = None, note: str = "") -> dict:
    """The baselines results file of a ``bbgym baseline`` run folder (its ``results.json``
    and ``summary.json``): the rows :func:`baseline_row` reads, the summary's settings and
    versions, each seed's training time, and ``command`` (default: the one the summary
    records) that remakes it."""
    summary = read_json(run / "summary.json")
    rows = read_json(run / "results.json")
    if not isinstance(summary, dict) or not isinstance(rows, list):
        raise ResultsError(f"{_name(run)}: not a bbgym baseline run folder")
    for key in ("env", "algo", "command", "versions", "train_wall_time_s_per_seed"):
        field(summary, key, run / "summary.json")
    kept = {key: summary[key] for key in SUMMARY_KEYS if key in summary}
    kept["config"] = Path(str(kept.get("config", ""))).stem
    kept["bbgym"] = summary["versions"].get("bbgym", "-")
    seconds = list(summary["train_wall_time_s_per_seed"].values())
    threads = summary.get("torch_threads", "?")
    wall = f"{min(seconds) / 60:.1f}-{max(seconds) / 60:.1f} min a seed"
    if len(set(seconds)) == 1:  # one seed, or one program's time shared by its seeds
        wall = f"{seconds[0] / 60:.1f} min" + (" a seed" if len(seconds) > 1 else "")
    if summary.get("engine") == "rejax":
        wall += f" ({len(seconds)} seeds in one JAX program, its wall time / seeds)"
    else:
        wall += f" (up to {summary.get('jobs', 1)} at once, {threads} torch thread(s) each)"
    if summary.get("eval_wall_time_s") is not None:
        wall += f"; evaluation {summary['eval_wall_time_s']:.0f} s"
    data = {
        "source": f"written by `python docs/tables.py record-baseline` from the run folder's "
        f"results.json and summary.json (bbgym {kept['bbgym']}).",
        "command": command or " ".join(str(a) for a in summary["command"]),
        **({"note": note} if note else {}),
        "summary": _rounded(kept),
        "wall_time": wall,
        "results": _rounded(rows),
    }
    return data


def record_baseline(
    run: Path,
    command: str | None = None,
    note: str = "",
    results: Path = RESULTS,
    name: str | None = None,
) -> Path:
    """Write :func:`baseline_results` to ``results/baselines/<env>-<algo>.json`` (a run of
    ``--engine torchrl``: ``<env>-torchrl-<algo>.json``; ``name``, where given, is the
    file's name without ``.json``: a second preset's row beside the env's own, or
    ``main``), checked by building its table row; return the path."""
    data = baseline_results(run, command, note)
    env, algo = data["summary"]["env"], data["summary"]["algo"]
    engine = data["summary"].get("engine", "sb3")
    algo = algo if engine == "sb3" else f"{engine}-{algo}"  # beside SB3's, not over it
    path = results / "baselines" / f"{name or f'{env}-{algo}'}.json"
    path.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    baseline_row(path)
    return path


def main(argv: list[str]) -> None:
    if argv[:1] in (["write"], ["check"]):
        pages = [Path(a).resolve() for a in argv[1:]] or None
        if argv[0] == "write":
            for page in write_pages(pages):
                print(f"wrote {_name(page)}")
            return
        stale = stale_pages(pages)
        for page in stale:
            print(f"stale: {_name(page)} (python docs/tables.py write)")
        sys.exit(1 if stale else 0)
    if argv[:1] != ["record-baseline"]:
        print(table(" ".join(argv)))
        return
    import argparse

    parser = argparse.ArgumentParser(prog="docs/tables.py record-baseline")
    parser.add_argument("run", type=Path, help="a bbgym baseline run folder")
    parser.add_argument("--command", help="the command that remakes it (default: the run's)")
    parser.add_argument("--note", default="", help="how it was run, where that differs")
    parser.add_argument("--name", help="the file's name without .json (default <env>-<algo>)")
    args = parser.parse_args(argv[1:])
    print(record_baseline(args.run, args.command, args.note, name=args.name))


if __name__ == "__main__":
    main(sys.argv[1:])
