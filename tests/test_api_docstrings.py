"""The public API documents itself in Google style, as the site's API reference renders it
(``docstring_style: google`` in docs/mkdocs.yml).

For each module of :data:`MODULES`, every public function and every public method a public
class defines there (not inherited; ``_private`` and dunder names are skipped) has:

- an ``Args:`` section naming each of its parameters (``self``/``cls`` aside; a bare
  ``*args`` / ``**kwargs`` may go unnamed, any other ``*name`` / ``**name`` is named with
  its stars, as griffe expects), and no entry for a parameter it does not take;
- a ``Returns:`` (or ``Yields:``) section where its return annotation is not ``None``.

A class with its own ``__init__`` documents the constructor's arguments the same way, in
the class docstring or ``__init__``'s; a dataclass documents each field with a docstring
under it (what mkdocstrings renders as the class's attributes) or in an ``Attributes:``
section; a property has a docstring.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import re
import textwrap
from collections.abc import Iterator
from types import ModuleType
from typing import Any

import pytest

MODULES = [
    "bbgym.spec",
    "bbgym.envs.common",
    "bbgym.physics.validation",
    "bbgym.backends",
    "bbgym.envs.functional",
    "bbgym.testing",
    "bbgym.envs.core",
    "bbgym.jax_env",
    "bbgym.mlp_policy",
    "bbgym.rejax",
]
"""The modules whose public API this test holds to the rule (extend it as modules are
documented)."""

ARGS_TITLES = ("Args", "Arguments", "Parameters")
RETURNS_TITLES = ("Returns", "Return", "Yields", "Yield")
ATTRIBUTES_TITLES = ("Attributes",)
UNNAMED_VARIADIC = {"*args", "**kwargs"}
"""Variadic parameters that may go undocumented: only under these generic names."""

SECTION = re.compile(r"^(\w[\w ]*):\s*$")
ENTRY = re.compile(r"^(\*{0,2}\w+)\s*(?:\([^)]*\))?\s*:")
NAMED_VALUE = re.compile(r"^(\w+)?\s*(?:\((.+)\))?:")
"""How griffe reads a Returns: paragraph's start as ``name (type):``: ``Nothing: ...`` or
``The :class:`X` ...`` would render ``Nothing`` / ``The`` as the returned value's name."""


def sections(doc: str | None) -> dict[str, list[str]]:
    """A Google-style docstring's sections: title -> the names of its entries (the text
    before the colon of each line indented one level under the title)."""
    found: dict[str, list[str]] = {}
    current: list[str] | None = None
    entry_indent: int | None = None
    for line in inspect.cleandoc(doc or "").splitlines():
        if not line.strip():
            continue
        indent = len(line) - len(line.lstrip())
        title = SECTION.match(line) if indent == 0 else None
        if title is not None:
            current = found.setdefault(title.group(1), [])
            entry_indent = None
            continue
        if indent == 0:
            current = None  # prose after a section ends it
            continue
        if current is None:
            continue
        if entry_indent is None:
            entry_indent = indent
        if indent == entry_indent:
            entry = ENTRY.match(line.strip())
            if entry is not None:
                current.append(entry.group(1))
    return found


def named(found: dict[str, list[str]], titles: tuple[str, ...]) -> list[str] | None:
    """The entries of the first of ``titles`` present, or ``None`` if none is."""
    for title in titles:
        if title in found:
            return found[title]
    return None


def parameter_names(fn: Any, bound: bool) -> list[str]:
    """``fn``'s parameters as a docstring names them (``*args``, ``**kwargs``), without the
    ``self``/``cls`` of a method (``bound``)."""
    names = []
    parameters = list(inspect.signature(fn).parameters.values())
    if bound and parameters and parameters[0].name in ("self", "cls"):
        parameters = parameters[1:]
    for p in parameters:
        star = {p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "")
        names.append(star + p.name)
    return names


def args_problems(where: str, fn: Any, doc: str | None, bound: bool) -> list[str]:
    """What is wrong with the ``Args:`` of ``fn``'s docstring ``doc``."""
    wanted = parameter_names(fn, bound)
    entries = named(sections(doc), ARGS_TITLES)
    problems = []
    needed = [name for name in wanted if name not in UNNAMED_VARIADIC]
    if not wanted:
        return []
    if entries is None:
        if needed:
            problems.append(f"{where}: no Args: section (parameters: {', '.join(needed)})")
        return problems
    missing = [name for name in needed if name not in entries]
    if missing:
        problems.append(f"{where}: Args: does not name {', '.join(missing)}")
    unknown = [name for name in entries if name not in wanted]
    if unknown:
        problems.append(f"{where}: Args: names {', '.join(unknown)}, not parameters")
    return problems


def returns_problems(where: str, fn: Any, doc: str | None) -> list[str]:
    """What is wrong with the ``Returns:`` of ``fn``'s docstring ``doc``."""
    annotation = inspect.signature(fn).return_annotation
    if annotation is inspect.Signature.empty:
        return [f"{where}: no return annotation (annotate it, None if it returns nothing)"]
    text = annotation if isinstance(annotation, str) else getattr(annotation, "__name__", "")
    if text in ("None", "NoReturn") or annotation is None:
        return []
    if named(sections(doc), RETURNS_TITLES) is None:
        return [f"{where}: returns {text} but has no Returns: (or Yields:) section"]
    first = first_line(doc, RETURNS_TITLES)
    reads_named = NAMED_VALUE.match(first)
    if reads_named is not None and any(reads_named.groups()):
        return [f"{where}: Returns: starts {first!r}, which renders as a value named so"]
    return []


def first_line(doc: str | None, titles: tuple[str, ...]) -> str:
    """The first line of text under the first of ``titles`` (stripped)."""
    lines = inspect.cleandoc(doc or "").splitlines()
    for title in titles:
        if f"{title}:" in lines:
            after = lines[lines.index(f"{title}:") + 1 :]
            return next((line.strip() for line in after if line.strip()), "")
    return ""


def field_docstrings(cls: type) -> set[str]:
    """The names of ``cls``'s class-level assignments followed by a docstring (in its
    source; griffe reads them the same way)."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
    body = tree.body[0].body  # type: ignore[attr-defined]
    documented = set()
    for statement, following in zip(body, body[1:], strict=False):
        is_doc = (
            isinstance(following, ast.Expr)
            and isinstance(following.value, ast.Constant)
            and isinstance(following.value.value, str)
        )
        if is_doc and isinstance(statement, ast.AnnAssign | ast.Assign):
            targets = [statement.target] if isinstance(statement, ast.AnnAssign) else []
            if isinstance(statement, ast.Assign):
                targets = statement.targets
            documented |= {t.id for t in targets if isinstance(t, ast.Name)}
    return documented


def public_classes(module: ModuleType) -> Iterator[tuple[str, type]]:
    for name, obj in vars(module).items():
        if not name.startswith("_") and inspect.isclass(obj):
            if obj.__module__ == module.__name__:
                yield name, obj


def problems_of(module_name: str) -> list[str]:
    """Every rule this module's public API breaks, one line each."""
    module = importlib.import_module(module_name)
    problems: list[str] = []
    for name, obj in vars(module).items():
        if name.startswith("_") or not inspect.isfunction(obj):
            continue
        if obj.__module__ != module.__name__:
            continue  # imported from elsewhere
        where = f"{module_name}.{name}"
        problems += args_problems(where, obj, obj.__doc__, bound=False)
        problems += returns_problems(where, obj, obj.__doc__)
    for class_name, cls in public_classes(module):
        for attr, member in vars(cls).items():
            where = f"{module_name}.{class_name}.{attr}"
            if attr.startswith("_"):
                continue
            if isinstance(member, property):
                if not (member.__doc__ or "").strip():
                    problems.append(f"{where}: a property without a docstring")
                continue
            bound = not isinstance(member, staticmethod)
            if isinstance(member, staticmethod | classmethod):
                member = member.__func__
            if not inspect.isfunction(member):
                continue
            problems += args_problems(where, member, member.__doc__, bound=bound)
            problems += returns_problems(where, member, member.__doc__)
        init = vars(cls).get("__init__")
        generated = dataclasses.is_dataclass(cls)
        if inspect.isfunction(init) and not generated:
            own = named(sections(init.__doc__), ARGS_TITLES) is not None
            doc = init.__doc__ if own else cls.__doc__
            problems += args_problems(f"{module_name}.{class_name}()", init, doc, bound=True)
        if generated:
            documented = field_docstrings(cls)
            documented |= set(named(sections(cls.__doc__), ATTRIBUTES_TITLES) or [])
            for f in dataclasses.fields(cls):
                if not f.name.startswith("_") and f.name not in documented:
                    problems.append(
                        f"{module_name}.{class_name}.{f.name}: a field without a docstring "
                        "(or an Attributes: entry)"
                    )
    return problems


@pytest.mark.parametrize("module_name", MODULES)
def test_the_public_api_has_google_style_sections(module_name):
    problems = problems_of(module_name)
    assert problems == [], "\n".join(problems)


def test_the_checker_notices_a_missing_section_and_a_wrong_entry():
    def documented(speed: float, *args: Any, **extra: Any) -> float:
        """A speed.

        Args:
            speed: In m/s.
            **extra: Anything.

        Returns:
            The speed.
        """
        return speed

    def undocumented(speed: float, heading: float) -> float:
        """A speed, without sections."""
        return speed

    def wrong(speed: float) -> None:
        """Nothing.

        Args:
            sped: A typo.
        """

    def context() -> Iterator[None]:
        """A context.

        Yields:
            Nothing.
        """
        yield

    assert args_problems("f", documented, documented.__doc__, bound=False) == []
    assert returns_problems("f", documented, documented.__doc__) == []
    assert returns_problems("f", context, context.__doc__) == []
    assert args_problems("f", undocumented, undocumented.__doc__, bound=False) == [
        "f: no Args: section (parameters: speed, heading)"
    ]
    assert returns_problems("f", undocumented, undocumented.__doc__) == [
        "f: returns float but has no Returns: (or Yields:) section"
    ]
    assert args_problems("f", wrong, wrong.__doc__, bound=False) == [
        "f: Args: does not name speed",
        "f: Args: names sped, not parameters",
    ]
    assert returns_problems("f", wrong, wrong.__doc__) == []

    def named_by_mistake() -> float:
        """A speed.

        Returns:
            The :class:`float` speed.
        """
        return 0.0

    assert returns_problems("f", named_by_mistake, named_by_mistake.__doc__) == [
        "f: Returns: starts 'The :class:`float` speed.', which renders as a value named so"
    ]


SAMPLE = '''
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Params:
    """Parameters."""

    mass_kg: float = 1.0
    """The mass, kg."""
    drag: float = 0.5


class Stream:
    """A stream."""

    def __init__(self, batch: int) -> None:
        self.batch = batch

    @property
    def size(self) -> int:
        return self.batch


def fine(x: float) -> None:
    """Nothing.

    Args:
        x: A number.
    """
'''


def test_a_constructor_a_field_and_a_property_are_held_to_the_rule(tmp_path, monkeypatch):
    (tmp_path / "api_docstrings_sample.py").write_text(SAMPLE)
    monkeypatch.syspath_prepend(str(tmp_path))
    assert problems_of("api_docstrings_sample") == [
        "api_docstrings_sample.Params.drag: a field without a docstring (or an Attributes: entry)",
        "api_docstrings_sample.Stream.size: a property without a docstring",
        "api_docstrings_sample.Stream(): no Args: section (parameters: batch)",
    ]
