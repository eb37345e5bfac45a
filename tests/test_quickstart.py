"""Every code block of the README and the quickstart page works as written, warning-free.

Python blocks run for real, a document's blocks in order in one fresh interpreter with
warnings as errors (a newcomer's first lines must not warn). Shell blocks: each `bbgym`
line is parsed by the real command line (an option renamed breaks it here), and the quick
ones (evaluate, record, scene) run for real; training, `make` and `pip install` lines are
checked against the Makefile and pyproject.toml (the wheel's install is tests/test_wheel.py,
training tests/test_train_smoke.py).
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = (ROOT / "README.md", ROOT / "docs" / "pages" / "quickstart.md")
FENCE = re.compile(r"^```(\w*)\n(.*?)^```$", re.MULTILINE | re.DOTALL)
RUN_FOR_REAL = ("evaluate", "record", "scene")
"""The `bbgym` commands quick enough to run here as the documents write them."""


def code_blocks(path: Path) -> list[tuple[str, str]]:
    """``(language, code)`` of every fenced block of a Markdown file, in order."""
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(path.read_text(encoding="utf-8"))]


def shell_lines(path: Path) -> list[str]:
    """The commands of a document's shell blocks (no language, bash or console), comments
    and continuation-free: one command a line."""
    lines = []
    for language, code in code_blocks(path):
        if language in ("", "bash", "console", "sh"):
            for line in code.splitlines():
                line = line.split("  #", 1)[0].strip()
                if line and not line.startswith("#"):
                    lines.extend(part.strip() for part in line.split("&&"))
    return lines


def run(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, SDL_VIDEODRIVER="dummy", PYTHONWARNINGS="error")
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: p.name)
def test_the_python_blocks_run_in_order_without_a_warning(path: Path, tmp_path: Path) -> None:
    blocks = [code for language, code in code_blocks(path) if language == "python"]
    assert len(blocks) >= 2, path
    script = tmp_path / "blocks.py"
    script.write_text("\n".join(blocks), encoding="utf-8")
    done = run([sys.executable, "-W", "error", str(script)], tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "warn" not in done.stderr.lower(), done.stderr
    if path.name == "quickstart.md":  # what its comments promise
        assert "(23,) (3,)" in done.stdout and "(64, 23) True" in done.stdout
        assert re.search(r"autopilot: \d+ s to the mark, success True", done.stdout)
    else:
        assert re.search(r"\(23,\) \(480, 640, 3\) \d+\.\d\d m/s", done.stdout), done.stdout


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: p.name)
def test_every_bbgym_line_parses_with_the_real_command_line(path: Path) -> None:
    from bbgym.cli import build_parser

    commands = [line for line in shell_lines(path) if line.startswith("bbgym ")]
    assert commands or path.name == "README.md", path  # the README's are `make` lines
    for line in commands:
        build_parser().parse_args(shlex.split(line)[1:])  # exits (SystemExit) if it changed


def test_the_quickstart_commands_run_and_write_what_they_say(tmp_path: Path) -> None:
    page = DOCUMENTS[1]
    commands = [
        line
        for line in shell_lines(page)
        if line.startswith("bbgym ")
        and shlex.split(line)[1] in RUN_FOR_REAL
        and "--model" not in line  # evaluates the model trained in section 5
    ]
    assert [shlex.split(c)[1] for c in commands] == list(RUN_FOR_REAL)
    bbgym = Path(sys.executable).with_name("bbgym")
    for line in commands:
        done = run([str(bbgym), *shlex.split(line)[1:]], tmp_path)
        assert done.returncode == 0, (line, done.stderr[-3000:])
        assert "warn" not in done.stderr.lower(), (line, done.stderr)
    quick = tmp_path / "runs" / "quickstart"
    table = (quick / "eval" / "BeachballSail-v2.md").read_text(encoding="utf-8")
    assert "| BeachballSail-v2 | scripted | 10 | 100% " in table
    for gif in ("episode.gif", "magnus.gif"):
        assert (quick / gif).read_bytes()[:6] == b"GIF89a", gif


def test_install_and_make_lines_match_the_makefile_and_the_extras() -> None:
    import tomllib

    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    pin = re.search(r"^TORCH \?= (\S+)$", makefile, re.MULTILINE).group(1)
    extras = set(
        tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    )
    targets = set(re.findall(r"^([a-z]+):", makefile, re.MULTILINE))
    seen_torch = 0
    for path in DOCUMENTS:
        for line in shell_lines(path):
            words = shlex.split(line)
            if words[:2] == ["pip", "install"] and "torch" in line:
                seen_torch += 1
                assert pin in words, line  # the pin the Makefile installs
                assert "https://download.pytorch.org/whl/cpu" in words, line  # the CPU build
            for spec in re.findall(r'"\S*\[([a-z,]+)\]"', line):
                assert set(spec.split(",")) <= extras, line
            if words[0] == "make":
                assert words[1] in targets, line
    assert seen_torch == 2
