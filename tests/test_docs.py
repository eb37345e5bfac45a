"""The README is a short guide, and the documentation site's tables come from results files
(docs/results) and the code through docs/tables.py, the MkDocs hook; the site builds
strictly."""

from __future__ import annotations

import importlib.util
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def load_tables():
    spec = importlib.util.spec_from_file_location("bbgym_docs_tables", DOCS / "tables.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


tables = load_tables()


def test_the_readme_is_a_short_guide_that_names_the_two_commands():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(readme.splitlines()) <= 250
    for command in ("make run", "make test"):
        assert f"**`{command}`**" in readme, command
    for picture in ("sail", "throw", "curve", "topple"):
        path = f"docs/pages/img/{picture}.png"
        assert path in readme and (ROOT / path).stat().st_size < 100_000, path


def test_every_baselines_file_makes_a_row_naming_its_command_and_source():
    text = tables.baselines_table()
    rows = [line for line in text.splitlines() if line.startswith("| Beachball")]
    assert len(rows) == len(tables.BASELINE_FILES)
    for name in tables.BASELINE_FILES:
        data = json.loads((tables.RESULTS / "baselines" / name).read_text())
        assert f"`{data['command']}`" in text, name
        assert data["source"] in text, name
    assert "| BeachballSail-v1, SAC | 2% (1-7%) | 100% (96-100%), 37.3 s to the mark |" in text
    # Two rows of one env and algorithm: the second names its shipped preset.
    assert "| BeachballSail-v1, SAC (`beachball_sail_v1_quick`) | 2% (1-7%)" in text
    assert "91.8% (88-96%), worst 87% (seed 1); seeds 95, 87, 95, 90, 92%" in text
    sail_only = tables.baselines_table("BeachballSail")
    assert "BeachballSail-v1, SAC" in sail_only and "Curve" not in sail_only


def test_the_baselines_summary_has_a_row_for_every_current_id_and_filters_by_prefix():
    """Each current id has an SB3 row or a 'not trained yet' row (never silently absent); a
    file's row shows its mean, worst seed and seed count; a prefix keeps that task's rows."""
    text = tables.baselines_summary_table()
    rows = [line for line in text.splitlines() if line.startswith("| **Beachball")]
    for env in tables.current_ids():
        mine = [row for row in rows if row.startswith(f"| **{env}** |")]
        assert mine, env
    assert (
        "| **BeachballCurve-v2** | PPO, `beachball_curve_v2` | 92.8% (worst 90%, 5 seeds) |" in text
    )
    # Per task and algorithm the newest version only: Curve-v1 keeps its SAC row, not PPO's.
    assert "| BeachballCurve-v1 | SAC, `beachball_curve_sac` | 85.8% (worst 82%, 5 seeds) |" in text
    assert "| BeachballCurve-v1 | PPO, `beachball_curve` |" not in text
    # A current id with no SB3 results file (Topple-v0 has none) gets a row saying so.
    gap = tables.baselines_summary_table(current=["BeachballSail-v2", "BeachballTopple-v0"])
    assert "| **BeachballTopple-v0** | PPO, `beachball_topple` | **not trained yet** |" in gap
    sail = tables.baselines_summary_table("BeachballSail")
    assert "**BeachballSail-v2**" in sail and "Throw" not in sail and "Curve" not in sail
    topple = tables.baselines_summary_table("BeachballTopple")
    assert "Sail" not in topple.split("**Bold**")[0]


def test_the_compile_table_shows_every_id_and_the_cache_serving_warm_runs():
    """scripts/compile_times.py's results: every registered id, its cold run a cache miss
    and both warm runs (another thread count included) hits."""
    import gymnasium as gym

    import bbgym  # noqa: F401  (registers the ids: the test passes run alone too)

    text = tables.compile_table()
    rows = [line for line in text.splitlines() if line.startswith("| Beachball")]
    assert sorted(row.split(" | ")[0][2:] for row in rows) == sorted(
        k for k in gym.registry if k.startswith("Beachball")
    )
    for row in rows:
        cold, warm, other = row.split(" | ")[2:5]
        assert cold.endswith("(miss)") and warm.endswith("(hit)") and other.endswith("(hit)"), row
    assert "`python scripts/compile_times.py " in text


def test_the_jax_compile_table_shows_the_cache_serving_warm_runs(tmp_path):
    """scripts/compile_times.py --backend jax's results: each id's cold run compiled the
    step and wrote it to the cache (a miss), its warm run loaded it (a hit); a malformed
    row fails naming the file."""
    text = tables.compile_jax_table()
    rows = [line for line in text.splitlines() if line.startswith("| Beachball")]
    assert rows
    for row in rows:
        cold, warm = row.split(" | ")[2:4]
        assert cold.endswith("(miss)") and warm.endswith("(hit)"), row
    assert "`python scripts/compile_times.py --backend jax" in text and "CPUs, jax " in text
    data = json.loads((tables.RESULTS / tables.COMPILE_JAX_FILE).read_text())
    del data["rows"][0]["env_id"]
    path = tmp_path / "compile-jax.json"
    path.write_text(json.dumps(data))
    with pytest.raises(tables.ResultsError, match="compile-jax.json: malformed"):
        tables.compile_jax_table(path)


def test_speed_and_polar_tables_name_their_commands():
    speed = tables.speed_table()
    assert "`bbgym bench --repeats 3 --out runs/bench`" in speed
    assert "| CartPole-v1 | single |" in speed and "| BeachballTopple-v2 | vector N=4096 |" in speed
    backends = tables.backends_table()
    assert "`bbgym bench --backends`" in backends and "| N=65536 torch float32 |" in backends
    polar = tables.polar_table()
    assert "`bbgym polar --wind-speed 5 --out runs/polar`" in polar
    assert "| best upwind VMG | 45 deg, 1.51 m/s |" in polar  # the polar test's band: 38-48


def test_the_race_selfplay_table_gives_seeds_reference_and_command(tmp_path):
    """A row of the learned boats over their seeds (mean, worst, interval), the scripted
    reference on the same races, and the command; a field missing fails naming the file."""
    seed = {
        "ahead_share": 0.25,
        "learned_fouls": 1.0,
        "scripted_fouls": 2.0,
        "learned_finished": 1.0,
        "scripted_finished": 0.5,
        "learned_return": 100.0,
    }
    data = {
        "command": "python scripts/race_selfplay.py --seeds 2",
        "policy": "residual PPO",
        "timesteps": 5_000_000,
        "races_trained_at_once": 64,
        "eval_races": 100,
        "eval_seed": 7,
        "torch_threads": 2,
        "ahead_share_mean": 0.375,
        "ahead_share_worst": 0.25,
        "ahead_share_interval": [0.1, 0.65],
        "seeds": [seed, seed | {"ahead_share": 0.5, "learned_return": 110.0}],
        "reference": seed | {"ahead_share": 0.5, "learned_return": 90.0},
    }
    path = tmp_path / "race" / "selfplay.json"
    path.parent.mkdir()
    path.write_text(json.dumps(data | {"relative_reward": True}))
    absolute = data | {"relative_reward": False, "source": "renamed"}
    (tmp_path / "race" / "selfplay_absolute.json").write_text(json.dumps(absolute))
    table = tables.race_selfplay_table(tmp_path)
    assert (
        "| residual PPO | 2 seeds x 5M steps, 64 races at once, relative reward | 38% (25%, "
        "10%-65%) | 1.00 / 2.00 | 100% / 50% | 105.0 |"
    ) in table
    assert "| 2 seeds x 5M steps, 64 races at once, the race's reward | 38% (25%" in table
    reference = "| the scripted racer (reference) | - | 50% | 1.00 / 2.00 | 100% / 50% | 90.0 |"
    assert table.count(reference) == 1  # the same races: one reference row for both files
    assert "`python scripts/race_selfplay.py --seeds 2 --results` (100 races seeded from 7" in table
    assert "torch on 2 threads, renamed)" in table and table.count("torch on 2 threads)") == 1
    del data["reference"]["learned_return"]
    path.write_text(json.dumps(data | {"relative_reward": True}))
    with pytest.raises(tables.ResultsError, match="selfplay.json: malformed"):
        tables.race_selfplay_table(tmp_path)


def copy_results(tmp_path: Path) -> Path:
    results = tmp_path / "results"
    shutil.copytree(tables.RESULTS, results)
    return results


def test_a_missing_results_file_fails_naming_it(tmp_path):
    results = copy_results(tmp_path)
    (results / "baselines" / "BeachballThrow-v0-ppo.json").unlink()
    with pytest.raises(tables.ResultsError, match="BeachballThrow-v0-ppo.json: results file"):
        tables.baselines_table(results=results)
    (results / "polar" / "polar.csv").unlink()
    with pytest.raises(tables.ResultsError, match="polar.csv: results file missing"):
        tables.polar_table(results / "polar" / "polar.json")
    with pytest.raises(tables.ResultsError, match="bench.json: results file missing"):
        tables.speed_table(tmp_path / "speed" / "bench.json")


def test_a_malformed_results_file_fails_naming_it(tmp_path):
    results = copy_results(tmp_path)
    path = results / "baselines" / "BeachballSail-v1-sac.json"
    path.write_text("{ not json")
    with pytest.raises(tables.ResultsError, match="BeachballSail-v1-sac.json: not valid JSON"):
        tables.baselines_table(results=results)
    data = json.loads((tables.RESULTS / "baselines" / "BeachballSail-v1-sac.json").read_text())
    del data["source"]
    path.write_text(json.dumps(data))
    with pytest.raises(tables.ResultsError, match="BeachballSail-v1-sac.json: no 'source'"):
        tables.baselines_table(results=results)
    data = json.loads((tables.RESULTS / "baselines" / "BeachballSail-v1-sac.json").read_text())
    del data["results"][-1]["success_rate"], data["results"][2]["success_ci95"]
    path.write_text(json.dumps(data))
    with pytest.raises(tables.ResultsError, match="BeachballSail-v1-sac.json: malformed"):
        tables.baselines_table(results=results)
    bench = results / "speed" / "bench.json"
    data = json.loads(bench.read_text())
    data["rows"][0].pop("rate")
    bench.write_text(json.dumps(data))
    with pytest.raises(tables.ResultsError, match="bench.json: malformed"):
        tables.speed_table(bench)
    csv_path = results / "polar" / "polar.csv"
    csv_path.write_text("true_wind_angle_deg,boat_speed_mps\n0,fast\n")
    with pytest.raises(tables.ResultsError, match="polar.csv: malformed"):
        tables.polar_table(results / "polar" / "polar.json")
    compare_path = results / "polar" / "compare.csv"
    compare_path.write_text("source,wind_kn,quantity\nDay 2017,6,VMG\n")
    with pytest.raises(tables.ResultsError, match="compare.csv: malformed"):
        tables.polar_compare_table(compare_path)
    compare_path.unlink()
    with pytest.raises(tables.ResultsError, match="compare.csv: results file missing"):
        tables.polar_compare_table(compare_path)


def test_the_polar_comparison_table_marks_every_miss():
    table = tables.polar_compare_table()
    rows = [
        line
        for line in table.splitlines()
        if line.startswith("| Day") or line.startswith("| Binns")
    ]
    assert len(rows) == 20
    assert "`bbgym polar --compare --out docs/results/polar`" in table
    with (tables.RESULTS / "polar" / "compare.csv").open() as f:
        misses = sum(line.rstrip().endswith(",0") for line in f)
    assert sum(row.endswith("| **no** |") for row in rows) == misses


def test_every_page_holds_its_tables_as_they_are_now_and_an_unknown_marker_fails():
    """The tables are written into the pages (they read the same in the repository and the
    site), and none is stale: `python docs/tables.py write` after new results or code."""
    assert tables.stale_pages() == [], "run: python docs/tables.py write"
    for page in tables.markdown_pages():
        text = page.read_text(encoding="utf-8")
        for kind in ("table", "include"):
            assert text.count(f"<!-- {kind}:") == text.count(f"<!-- /{kind} -->"), page
    changelog = tables.expand("<!-- include: CHANGELOG.md -->")
    assert "## 0.1.0" in changelog and "## 0.8.0" in changelog
    assert changelog.endswith("<!-- /include -->\n")
    with pytest.raises(LookupError, match="unknown table marker"):
        tables.expand("<!-- table: nonsense -->")


def test_a_stale_or_unwritten_table_is_noticed_and_rewritten_in_place():
    page = "# Title\n\ntext\n\n<!-- table: versions sail -->\n\nafter\n"
    written = tables.expand(page)
    assert written != page and tables.expand(written) == written  # idempotent
    assert written.startswith("# Title\n\ntext\n\n<!-- table: versions sail -->\n\n| ")
    assert written.endswith("\n\n<!-- /table -->\n\nafter\n")
    row = next(line for line in written.splitlines() if line.startswith("| `BeachballSail-v2`"))
    stale = written.replace(row, row.replace("v2", "v9", 1))
    assert tables.expand(stale) == written  # the stale row is replaced, nothing else moves
    two = tables.expand(page + "<!-- table: versions throw -->\n")
    assert two.count("<!-- /table -->") == 2 and "BeachballThrow-v1" in two


def built_page(site: Path, name: str) -> Path:
    """A built page: ``name.html`` (``use_directory_urls: false``: the site works opened
    from a file)."""
    return site / f"{name}.html"


@pytest.mark.skipif(
    importlib.util.find_spec("mkdocs") is None or importlib.util.find_spec("mkdocstrings") is None,
    reason="the docs extra (mkdocs, mkdocstrings) is not installed",
)
def test_the_site_builds_strictly(tmp_path):
    site = tmp_path / "site"
    build = subprocess.run(
        [
            sys.executable,
            "-m",
            "mkdocs",
            "build",
            "--strict",
            "-f",
            str(DOCS / "mkdocs.yml"),
            "--site-dir",
            str(site),
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        env={"NO_MKDOCS_2_WARNING": "1", "PATH": "", "HOME": str(tmp_path)},
    )
    assert build.returncode == 0, build.stderr[-3000:]
    baselines = built_page(site, "baselines-all").read_text(encoding="utf-8")
    assert "bbgym baseline --env BeachballSail-v1 --seeds 5 --jobs 1 --torch-threads 2" in baselines
    validation = built_page(site, "validation").read_text(encoding="utf-8")
    # The table written under its marker is in the site (the marker and end line stay, as
    # HTML comments): a row of it, and every marker with its end line.
    assert "<td><code>dinghy.mass_kg</code></td>" in validation
    assert validation.count("<!-- table:") == validation.count("<!-- /table -->") > 0
    api = built_page(site, "api").read_text(encoding="utf-8")
    assert "BeachballSailEnv" in api and "Version History" in api
    changelog = built_page(site, "changelog").read_text(encoding="utf-8")
    assert "0.1.0" in changelog
    # Opened from a file: links go to page files (no folder's index.html to find), and the
    # search index is a script the page loads (the offline plugin), not a fetch of JSON.
    assert (site / "baselines.html").is_file() and not (site / "baselines").exists()
    assert 'href="quickstart.html"' in built_page(site, "index").read_text(encoding="utf-8")
    assert (site / "search" / "search_index.js").is_file()


def test_each_env_page_lists_its_family_versions_with_the_envs_own_spaces():
    import gymnasium as gym

    from bbgym.spec import specs

    for spec in specs():
        table = tables.versions_table(spec.family)
        rows = [line for line in table.splitlines()[2:]]
        assert [row.split("`")[1] for row in rows] == [v.env_id for v in reversed(spec.versions)]
        for row, version in zip(rows, reversed(spec.versions), strict=True):
            env = gym.spec(version.env_id).make()  # what a user gets, checked against the table
            assert f"{env.action_space.shape})`: {version.actions_of(spec)}" in row
            assert f"{env.observation_space.shape})`" in row
            assert version.changes in row
            env.close()
    with pytest.raises(LookupError, match="unknown env family"):
        tables.versions_table("nonsense")


def test_every_test_the_physics_page_cites_exists():
    """The Physics pages say which test checks each law: each name they cite is a test."""
    page = "".join(path.read_text() for path in sorted((DOCS / "pages").glob("physics*.md")))
    cited = set(re.findall(r"`(test_\w+)`", page))
    defined = set()
    for path in (ROOT / "tests").rglob("test_*.py"):
        defined |= set(re.findall(r"^def (test_\w+)", path.read_text(), re.MULTILINE))
    assert len(cited) > 40
    assert sorted(cited - defined) == []
