"""The Race page's first example runs as printed and says what it prints: every boat's
place, not only the last finisher's."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

PAGE = Path(__file__).resolve().parents[2] / "docs" / "pages" / "envs" / "race.md"


def first_python_block(text: str) -> str:
    """The first fenced ``python`` code block of a Markdown ``text``."""
    found = re.search(r"^```python\n(.*?)^```$", text, re.MULTILINE | re.DOTALL)
    assert found is not None, f"{PAGE} has no python code block"
    return found.group(1)


def test_the_first_example_prints_every_boats_place() -> None:
    code = first_python_block(PAGE.read_text(encoding="utf-8"))
    args = [sys.executable, "-c", code]
    done = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    places = ast.literal_eval(done.stdout.strip())
    assert places == {"boat_0": 4, "boat_1": 1, "boat_2": 2, "boat_3": 3}
    # The comment on the print line says what it prints.
    printed = re.search(r"^print\(places\)  # (\{.*\})$", code, re.MULTILINE)
    assert printed is not None and ast.literal_eval(printed.group(1)) == places


def test_the_page_says_what_place_0_means() -> None:
    text = " ".join(PAGE.read_text(encoding="utf-8").split())
    assert (
        "A `place` of 0 means the boat did not finish: it capsized, or it was still racing" in text
    )
