"""The conformance kit (:mod:`bbgym.testing`) over every registered family, and over the
template family on every backend: the shared checks name no id, they read the specs."""

from __future__ import annotations

import pytest

from bbgym import testing
from bbgym.envs import puck
from bbgym.spec import env_ids, spec_of, specs

HOST = tuple(c for c in testing.CHECKS if c not in ("backends", "fuzz"))


@pytest.mark.parametrize("env_id", env_ids())
def test_every_version_conforms_on_the_host(env_id):
    """Python floats (the single env) and NumPy (the vector envs): every check but the
    kit's one fuzzed episode (tests/test_fuzz.py fuzzes every version with hypothesis,
    many episodes a run)."""
    report = testing.check_family(spec_of(env_id).family, ids=[env_id], checks=HOST, steps=10)
    assert len(report) == len(HOST)


@pytest.mark.parametrize("family", [s.family for s in specs()])
def test_the_newest_version_steps_alike_on_every_eager_backend(family):
    """``array_api_strict``, torch (eager, float64) and JAX (jitted: its compile takes
    seconds, its eager ops compile one by one) step as NumPy does through autoresets
    (torch compiled is checked per family in tests/**/test_backends*.py, where its compile
    time is paid once)."""
    newest = next(s for s in specs() if s.family == family).ids[-1]
    backends = ("array_api_strict", "torch", "jax-compiled")
    report = testing.check_family(
        family, ids=[newest], checks=["backends"], backends_=backends, steps=4
    )
    assert all(line.split(": ")[1].startswith("ok") for line in report), report


def test_the_template_conforms_on_every_backend():
    """The puck, the template of docs/new-env.md, unregistered: registered for the kit,
    which runs every check on Python floats, NumPy, array_api_strict, and torch and JAX
    eager and compiled, and removes it after."""
    pytest.importorskip("torch")
    report = testing.check_family(puck.SPEC)
    assert len(report) == len(testing.CHECKS) - 1 + len(testing.BACKENDS)
    assert all(": ok in" in line for line in report), report
    assert puck.ENV_ID not in env_ids()


def test_a_failed_check_names_the_id_the_check_and_the_backend(monkeypatch):
    """A task that breaks the contract (its torch step differs from NumPy's) fails the kit
    with a message that says where."""
    import dataclasses

    class Drifting(puck.PuckTask):
        def advance(self, state, action, noise, xp):
            moved = super().advance(state, action, noise, xp)
            drift = 1e-3 if xp is not __import__("numpy") else 0.0
            return moved._replace(x_m=moved.x_m + drift)

    monkeypatch.setattr(puck.PuckEnv, "task_class", Drifting)
    monkeypatch.setattr(puck.PuckVectorEnv, "task_class", Drifting)
    spec = dataclasses.replace(puck.SPEC)
    with pytest.raises(
        AssertionError, match=r"BeachballPuck-v0 backends \(array_api_strict\): obs"
    ):
        testing.check_family(spec, checks=["backends"], backends_=["array_api_strict"], steps=4)
    with pytest.raises(ValueError, match="unknown checks"):
        testing.check_family(spec, checks=["nothing"])


def code_lines(source: str) -> int:
    """Lines of code in ``source``: not blank, not comments, not docstrings."""
    import ast
    import io
    import tokenize

    tree = ast.parse(source)
    docstrings = set()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list):
            for stmt in body:
                is_doc = isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Constant)
                if is_doc and isinstance(stmt.value.value, str):
                    docstrings.update(range(stmt.lineno, stmt.end_lineno + 1))
    lines = set()
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT):
            if token.type not in (tokenize.DEDENT, tokenize.ENDMARKER):
                lines.update(range(token.start[0], token.end[0] + 1))
    return len(lines - docstrings)


def test_the_template_is_one_short_folder():
    """The template family is one folder of at most about 150 lines of code (docstrings
    aside), and the package lists it (a family's folder is its only place)."""
    from pathlib import Path

    tomllib = pytest.importorskip("tomllib")  # Python 3.11+

    folder = Path(puck.__file__).parent
    total = sum(code_lines(p.read_text()) for p in folder.glob("*.py"))
    assert total <= 150, total
    assert code_lines('"""doc"""\nx = 1  # one\n\n# two\ny = [\n    2,\n]\n') == 4
    root = folder.parents[2]
    listed = set(
        tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    )
    packages = {
        ".".join(p.parent.relative_to(root).parts)
        for p in (root / "bbgym").rglob("__init__.py")
        if "__pycache__" not in p.parts
    }
    assert packages <= listed, sorted(packages - listed)
