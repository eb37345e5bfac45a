"""CI's packaging check: build a wheel, install it into a fresh virtual environment outside
the checkout and run ``scripts/smoke_installed.py`` there (what ``pip install bbgym`` gives:
the presets, the ``bbgym`` command, no top-level ``agents``)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    # Built from a copy of what the wheel is made of, so no build/ folder is left in the
    # checkout, and none of an earlier build's files can slip into this one.
    source = tmp_path_factory.mktemp("source")
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, source / name)
    for name in ("bbgym", "agents", "configs"):
        shutil.copytree(ROOT / name, source / name, ignore=shutil.ignore_patterns("__pycache__"))
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            str(source),
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    (path,) = out.glob("bbgym-*.whl")
    return path


def test_the_wheel_holds_one_package_with_its_presets(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    roots = {name.split("/")[0] for name in names if not name.split("/")[0].endswith(".dist-info")}
    assert roots == {"bbgym"}
    for preset in (
        "beachball_sail.yaml",
        "beachball_throw.yaml",
        "beachball_topple.yaml",
        "ppo.yml",
    ):
        assert f"bbgym/configs/{preset}" in names
    assert "bbgym/agents/sail_autopilot.py" in names
    # Every package of the checkout is in the wheel (pyproject lists them by name).
    for init in (ROOT / "bbgym").rglob("__init__.py"):
        assert init.relative_to(ROOT).as_posix() in names
    entry_points = next(n for n in names if n.endswith(".dist-info/entry_points.txt"))
    assert "bbgym = bbgym.cli:main" in zipfile.ZipFile(wheel).read(entry_points).decode()


def test_the_installed_wheel_passes_the_smoke_script(wheel, tmp_path):
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    python = env_dir / "bin" / "python"
    environ = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    environ["PATH"] = f"{env_dir / 'bin'}{os.pathsep}{environ.get('PATH', '')}"
    done = subprocess.run(
        [str(python), "-m", "pip", "install", "-q", str(wheel)],
        capture_output=True,
        text=True,
        timeout=600,
        env=environ,
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    work = tmp_path / "work"
    done = subprocess.run(
        [str(python), str(ROOT / "scripts" / "smoke_installed.py"), "--out", str(work)],
        capture_output=True,
        text=True,
        timeout=600,
        env=environ,
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "smoke test passed" in done.stdout


def test_every_option_of_every_command_has_help_with_its_default():
    """``bbgym COMMAND --help`` shows each option's help and default (argparse shows the
    default only for options that have a help string)."""
    import argparse

    from bbgym.cli import COMMANDS, build_parser

    parser = build_parser()
    (commands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    assert sorted(commands.choices) == sorted(COMMANDS)
    for name, sub in commands.choices.items():
        for action in sub._actions:
            assert action.help, f"bbgym {name} {action.option_strings}: no help"
        assert "(default:" in sub.format_help(), name
