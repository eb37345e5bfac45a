"""Optional extras: every command checks the extras it will need before it starts any work,
and every install hint is worded for how bbgym was installed (bbgym is on no public index)."""

from __future__ import annotations

import importlib.util
import json
import re
from importlib import metadata
from pathlib import Path

import pytest

from bbgym import _extras, cli

ROOT = Path(__file__).resolve().parents[1]


def hide(monkeypatch: pytest.MonkeyPatch, *modules: str) -> None:
    """Make ``modules`` look uninstalled to ``importlib.util.find_spec``."""
    find_spec = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name in modules else find_spec(name, *a),
    )


def test_baseline_fails_at_once_without_pygame(monkeypatch, capsys, tmp_path):
    """The documented baseline install (train, plots) once trained for the whole budget and
    failed at the recording step: now it stops before training, naming the render extra."""
    from bbgym.cli import train

    def must_not_train(*args, **kwargs):
        raise AssertionError("baseline started training without the extras it needs")

    monkeypatch.setattr(train, "train_sb3", must_not_train)
    hide(monkeypatch, "pygame")
    argv = ["baseline", "--env", "BeachballSail-v1", "--seeds", "1", "--out", str(tmp_path)]
    assert cli.main(argv) == 3
    err = capsys.readouterr().err
    assert "'pygame' (the 'render' extra)" in err
    assert _extras.install_hint("render") in err
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("argv", "extras"),
    [
        (["train", "--env", "BeachballSail-v1"], {"train"}),
        (["train", "--env", "BeachballSail-v0", "--engine", "rllib"], {"rllib"}),
        (["evaluate", "--env", "BeachballSail-v1"], set()),
        (
            ["evaluate", "--env", "BeachballSail-v1", "--policies", "sac", "--model", "m.zip"],
            {"train"},
        ),
        (["baseline", "--env", "BeachballSail-v1"], {"train", "plots", "render"}),
        (["record", "--env", "BeachballSail-v1", "--policy", "scripted"], {"render", "plots"}),
        (
            ["record", "--env", "BeachballSail-v1", "--policy", "ppo", "--model", "m.zip"],
            {"render", "plots", "train"},
        ),
        (
            ["record", "--env", "bbgym/BeachballRace-v0", "--policy", "scripted"],
            {"race", "render", "plots"},
        ),
        (["play", "--env", "BeachballSail-v1"], {"render"}),
        (["polar"], {"plots"}),
        (["demo"], {"render", "plots"}),
        (["bench"], set()),
        (["bench", "--backends"], {"torch"}),
        (["fuzz"], set()),
    ],
)
def test_each_command_names_the_extras_it_needs(argv, extras):
    args = cli.build_parser().parse_args(argv)
    needs = args._needs(args) if args._needs is not None else []
    assert {extra for _, extra in needs} == extras


def test_a_missing_extra_lists_every_one_with_one_install_command(monkeypatch, capsys):
    hide(monkeypatch, "pygame", "stable_baselines3", "tensorboard")
    assert (
        cli.main(["record", "--env", "BeachballSail-v1", "--policy", "sac", "--model", "m.zip"])
        == 3
    )
    err = capsys.readouterr().err
    assert "'pygame' (the 'render' extra)" in err
    assert "'stable_baselines3', 'tensorboard' (the 'train' extra)" in err
    assert err.rstrip().endswith(_extras.install_hint("render", "train"))


class FakeDistribution:
    def __init__(self, direct_url: dict | None) -> None:
        self.direct_url = direct_url

    def read_text(self, name: str) -> str | None:
        assert name == "direct_url.json"
        return None if self.direct_url is None else json.dumps(self.direct_url)


@pytest.mark.parametrize(
    ("direct_url", "hint"),
    [
        (
            {"url": "file:///src/bb%20gym", "dir_info": {"editable": True}},
            'pip install -e "/src/bb gym[train,render]"',
        ),
        ({"url": "file:///src/bbgym", "dir_info": {}}, 'pip install "/src/bbgym[train,render]"'),
        (
            {"url": "file:///tmp/dist/bbgym-0.8.0-py3-none-any.whl", "archive_info": {}},
            'pip install "/tmp/dist/bbgym-0.8.0-py3-none-any.whl[train,render]"',
        ),
        (None, 'pip install "bbgym[train,render]"'),
    ],
)
def test_the_install_hint_follows_how_bbgym_was_installed(monkeypatch, direct_url, hint):
    monkeypatch.setattr(metadata, "distribution", lambda name: FakeDistribution(direct_url))
    assert _extras.install_hint("train", "render") == hint


def test_the_install_hint_from_a_checkout_that_is_not_installed(monkeypatch):
    def not_installed(name):
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(metadata, "distribution", not_installed)
    assert _extras.install_hint("plots") == f'pip install -e "{ROOT}[plots]"'


def test_every_install_hint_in_the_package_comes_from_one_function():
    """No module but bbgym/_extras.py spells a pip command (a literal one was wrong for
    every user: bbgym is on no public index)."""
    spelled = [
        str(path.relative_to(ROOT))
        for path in (ROOT / "bbgym").rglob("*.py")
        if path.name != "_extras.py" and re.search(r"pip install", path.read_text())
    ]
    assert spelled == []


def test_the_readme_installs_what_the_baselines_need():
    """The README's install line for the baselines names every extra ``bbgym baseline``
    checks for."""
    args = cli.build_parser().parse_args(["baseline"])
    needed = {extra for _, extra in args._needs(args)}
    readme = (ROOT / "README.md").read_text()
    lines = [line for line in readme.splitlines() if "pip install" in line and "train" in line]
    assert lines, "no install line for the baselines in the README"
    listed = set(re.search(r"\[([a-z,]+)\]", lines[0]).group(1).split(","))
    assert needed <= listed, lines[0]
