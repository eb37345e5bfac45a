"""Argument validation shared by every parameter dataclass, env constructor and reset option.

One rule for every number a user can pass: a finite real number (a Python or NumPy int or
float; ``bool``, strings, complex numbers and arrays of more than one element are refused)
inside its documented interval. Errors name the full path of the argument
(``dinghy.mass_kg``, ``gust_params.speed_std``, ``options['speed']``): a wrong type raises
``TypeError``, a wrong value ``ValueError``.

Parameter dataclasses declare each field's accepted interval with :func:`param`; their
``__post_init__`` calls :func:`check_fields` (that of their base :class:`CheckedFields`,
where it is their only check), which validates every field and stores it as a Python
``float`` (or ``int`` / ``bool``), so the physics never sees a NumPy scalar or a string.
:func:`build_params` builds a dataclass from a user mapping and rewrites the error paths
from the class name to the argument name.

This module has no gymnasium import: the physics layer uses it too.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Mapping
from dataclasses import dataclass, fields
from dataclasses import field as dataclass_field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Interval:
    """The accepted values of a number: ``low .. high`` with open or closed ends."""

    low: float = -math.inf
    """The lower bound (``-inf``: none)."""
    high: float = math.inf
    """The upper bound (``inf``: none)."""
    low_open: bool = False
    """Whether ``low`` itself is refused."""
    high_open: bool = False
    """Whether ``high`` itself is refused."""

    def contains(self, value: float) -> bool:
        """Whether ``value`` lies inside the interval.

        Args:
            value: A real number (not checked for type or finiteness here).

        Returns:
            True where ``value`` is above ``low`` (or equal, for a closed end) and below
            ``high`` (or equal, for a closed end).
        """
        above = value > self.low if self.low_open else value >= self.low
        below = value < self.high if self.high_open else value <= self.high
        return above and below

    def __str__(self) -> str:
        left = "(" if self.low_open or self.low == -math.inf else "["
        right = ")" if self.high_open or self.high == math.inf else "]"
        return f"{left}{_fmt(self.low)}, {_fmt(self.high)}{right}"


def _fmt(value: float) -> str:
    return format_bound(value)


PI_DENOMINATORS = range(1, 181)
"""Denominators :func:`format_bound` tries for a multiple of pi: up to 180, a degree."""


def format_bound(value: float) -> str:
    """A bound as text that reads back as exactly ``value``: ``pi/3`` where ``value`` is
    ``k*pi/n`` to the last bit (``n`` up to 180), else the shortest decimal that does
    (``1e+05``, ``0.05235987755982989``). A bound rounded for show could fall outside its
    own interval, so a value copied from a table or an error would be refused.

    Args:
        value: A bound: a float, ``inf`` or ``-inf``.

    Returns:
        Text that :func:`parse_bound` reads back as exactly ``value``.
    """
    if value == math.inf:
        return "inf"
    if value == -math.inf:
        return "-inf"
    multiple = pi_multiple(value)
    if multiple is not None:
        k, n = multiple
        head = {1: "pi", -1: "-pi"}.get(k, f"{k}*pi")
        return head if n == 1 else f"{head}/{n}"
    short = f"{value:g}"
    if float(short) == value:
        return short
    if float(value).is_integer() and abs(value) < 2**53:
        return str(int(value))
    return repr(float(value))


def pi_multiple(value: float) -> tuple[int, int] | None:
    """``(k, n)`` in lowest terms with ``k * math.pi / n == value`` exactly (``n`` in
    :data:`PI_DENOMINATORS`, ``k`` nonzero), or ``None``.

    Args:
        value: A float (radians, where it is an angle).

    Returns:
        ``(k, n)``, or ``None`` for zero, for ``|value| >= 1000`` and where no ``n`` up to
        180 gives ``value`` to the last bit.
    """
    if value == 0.0 or not abs(value) < 1e3:  # beyond, no bound is meant as pi's multiple
        return None
    for n in PI_DENOMINATORS:
        k = round(value * n / math.pi)
        if k and math.gcd(k, n) == 1 and k * math.pi / n == value:
            return k, n
    return None


def parse_bound(text: str) -> float:
    """The number :func:`format_bound` wrote (``pi/3``, ``-2*pi``, ``0.5``, ``inf``).

    Args:
        text: ``[-][k*]pi[/n]`` or anything ``float()`` reads.

    Returns:
        The number as a float.

    Raises:
        ValueError: If ``text`` is neither a multiple of pi nor a number.
    """
    match = re.fullmatch(r"(-?)(?:(\d+)\*)?pi(?:/(\d+))?", text.strip())
    if match is None:
        return float(text)
    sign, k, n = match.groups()
    return (-1 if sign else 1) * int(k or 1) * math.pi / int(n or 1)


ANY = Interval()
POSITIVE = Interval(0.0, math.inf, low_open=True)
NON_NEGATIVE = Interval(0.0, math.inf)
UNIT = Interval(0.0, 1.0)
ANGLE_RAD = Interval(-1e4, 1e4)
"""Any direction, given as an angle of at most 10^4 rad (beyond, float64 angles lose
the precision that their sine and cosine need)."""


def interval(
    low: float, high: float, *, low_open: bool = False, high_open: bool = False
) -> Interval:
    """Shorthand for :class:`Interval`.

    Args:
        low: The lower bound (``-math.inf``: none).
        high: The upper bound (``math.inf``: none).
        low_open: Whether ``low`` itself is refused.
        high_open: Whether ``high`` itself is refused.

    Returns:
        ``Interval(float(low), float(high), low_open, high_open)``.
    """
    return Interval(float(low), float(high), low_open, high_open)


def param(default: Any, accepted: Interval | None = None, *, integer: bool = False) -> Any:
    """A dataclass field with its accepted interval (read by :func:`check_fields` and by the
    docs and fuzz tests through :func:`accepted_interval`).

    Args:
        default: The field's default value.
        accepted: Its accepted values; ``None``: any finite number.
        integer: Whether the field is an int (checked by :func:`check_integer`).

    Returns:
        A ``dataclasses.field`` whose metadata holds ``interval`` and ``integer``.
    """
    return dataclass_field(default=default, metadata={"interval": accepted, "integer": integer})


def accepted_interval(cls: type, name: str) -> Interval | None:
    """The interval declared for field ``name`` of dataclass ``cls`` (``None`` if none).

    Args:
        cls: A parameter dataclass (``DinghyParams``).
        name: One of its field names (``"mass_kg"``).

    Returns:
        The field's :class:`Interval`, or ``None`` where it declares none.

    Raises:
        KeyError: If ``cls`` has no field ``name``.
    """
    for f in fields(cls):
        if f.name == name:
            return f.metadata.get("interval")
    raise KeyError(name)


def is_real_number(value: Any) -> bool:
    """Python or NumPy int or float (0-d arrays included), never ``bool``.

    Args:
        value: Anything.

    Returns:
        Whether ``value`` is a real number bbgym accepts (finite or not).
    """
    if isinstance(value, (bool, np.bool_)):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and value.dtype.kind in "iuf"
    return isinstance(value, numbers.Real)


def is_traced(value: Any) -> bool:
    """Whether ``value`` is a JAX tracer: an argument that varies inside a jitted program
    (:mod:`bbgym.jax_env`'s params), which has no value to check while the program is
    traced. The checks pass it through; :meth:`bbgym.jax_env.JaxEnv.check_params` checks
    the concrete values before they go in.

    Args:
        value: Anything.

    Returns:
        True for a JAX tracer (found without importing JAX).
    """
    return type(value).__module__.startswith("jax") and "Tracer" in type(value).__name__


def check_number(path: str, value: Any, accepted: Interval | None = None, why: str = "") -> float:
    """``value`` as a Python float: a finite real number inside ``accepted`` (``why``, if
    given, says in the error where the interval comes from).

    Args:
        path: The argument's full name in errors (``"dinghy.mass_kg"``,
            ``"options['speed']"``).
        value: What the user passed.
        accepted: Its accepted values; ``None``: any finite number.
        why: Where the interval comes from, added to the error in brackets (``""``:
            nothing).

    Returns:
        ``float(value)``.

    Raises:
        TypeError: If ``value`` is not a real number (:func:`is_real_number`).
        ValueError: If ``value`` is not finite or lies outside ``accepted``.
    """
    if is_traced(value):
        return value
    if not is_real_number(value):
        raise TypeError(f"{path} must be a real number, got {value!r} ({type(value).__name__})")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{path} must be finite, got {value!r}")
    if accepted is not None and not accepted.contains(v):
        reason = f" ({why})" if why else ""
        raise ValueError(f"{path} must be in {accepted}{reason}, got {value!r}")
    return v


def check_integer(path: str, value: Any, accepted: Interval | None = None) -> int:
    """``value`` as a Python int: a Python or NumPy integer inside ``accepted``.

    Args:
        path: The argument's full name in errors.
        value: What the user passed.
        accepted: Its accepted values; ``None``: any int.

    Returns:
        ``int(value)``.

    Raises:
        TypeError: If ``value`` is not an int (a bool or a float is refused).
        ValueError: If ``value`` lies outside ``accepted``.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{path} must be an int, got {value!r} ({type(value).__name__})")
    v = int(value)
    if accepted is not None and not accepted.contains(v):
        raise ValueError(f"{path} must be in {accepted}, got {value!r}")
    return v


def check_bool(path: str, value: Any) -> bool:
    """``value`` as a Python bool: ``True``/``False`` or a NumPy bool.

    Args:
        path: The argument's full name in errors.
        value: What the user passed.

    Returns:
        ``bool(value)``.

    Raises:
        TypeError: If ``value`` is not a bool (``0`` and ``1`` are refused).
    """
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{path} must be a bool, got {value!r} ({type(value).__name__})")
    return bool(value)


def check_choice(path: str, value: Any, choices: tuple) -> Any:
    """``value`` if it is one of ``choices``.

    Args:
        path: The argument's full name in errors.
        value: What the user passed.
        choices: The accepted strings.

    Returns:
        ``value`` unchanged.

    Raises:
        ValueError: If ``value`` is not a string in ``choices``.
    """
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{path} must be one of {choices}, got {value!r}")
    return value


def choices_text(choices: tuple[str, ...]) -> str:
    """``choices`` for a table: `` `"a"`, `"b"` or `"c"` ``.

    Args:
        choices: The accepted strings, in the order shown.

    Returns:
        The choices in Markdown, each quoted as code, the last joined by "or".
    """
    quoted = [f'`"{c}"`' for c in choices]
    return " or ".join([", ".join(quoted[:-1]), quoted[-1]] if len(quoted) > 1 else quoted)


def check_range(
    path: str, value: Any, accepted: Interval | None = None, why: str = ""
) -> tuple[float, float]:
    """A ``(low, high)`` pair of numbers inside ``accepted`` with ``low <= high``.

    Args:
        path: The argument's full name in errors (``[0]`` and ``[1]`` name its entries).
        value: What the user passed: a sequence of two numbers.
        accepted: The accepted values of each end; ``None``: any finite number.
        why: Where the interval comes from, added to the error in brackets.

    Returns:
        ``(low, high)`` as Python floats.

    Raises:
        TypeError: If ``value`` is not a sequence, or an entry not a real number.
        ValueError: If ``value`` has not two entries, an entry is not finite or lies
            outside ``accepted``, or ``low > high``.
    """
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__"):
        raise TypeError(f"{path} must be a (low, high) pair of numbers, got {value!r}")
    if len(value) != 2:
        raise ValueError(f"{path} must be a (low, high) pair of numbers, got {value!r}")
    lo = check_number(f"{path}[0]", value[0], accepted, why)
    hi = check_number(f"{path}[1]", value[1], accepted, why)
    if not (is_traced(lo) or is_traced(hi)) and lo > hi:
        raise ValueError(f"{path} must have low <= high, got {value!r}")
    return lo, hi


def check_pair(path: str, value: Any, accepted: Interval | None = None) -> tuple[float, float]:
    """An ``(x, y)`` pair of numbers, each inside ``accepted``.

    Args:
        path: The argument's full name in errors (``[0]`` and ``[1]`` name its entries).
        value: What the user passed: a sequence of two numbers.
        accepted: The accepted values of each entry; ``None``: any finite number.

    Returns:
        ``(x, y)`` as Python floats.

    Raises:
        TypeError: If ``value`` is not a sequence, or an entry not a real number.
        ValueError: If ``value`` has not two entries, or an entry is not finite or lies
            outside ``accepted``.
    """
    if isinstance(value, (str, bytes, Mapping)) or not hasattr(value, "__len__"):
        raise TypeError(f"{path} must be an (x, y) pair of numbers, got {value!r}")
    if len(value) != 2:
        raise ValueError(f"{path} must be an (x, y) pair of numbers, got {value!r}")
    return (
        check_number(f"{path}[0]", value[0], accepted),
        check_number(f"{path}[1]", value[1], accepted),
    )


def check_norm(
    path: str, pair: tuple[float, float], accepted: Interval, why: str = ""
) -> tuple[float, float]:
    """A checked ``(x, y)`` pair whose length lies in ``accepted``.

    Args:
        path: The argument's full name in errors.
        pair: The pair, already checked by :func:`check_pair`.
        accepted: The accepted values of its length ``hypot(x, y)``.
        why: Where the interval comes from, added to the error in brackets.

    Returns:
        ``pair`` unchanged.

    Raises:
        ValueError: If the pair's length lies outside ``accepted``.
    """
    length = math.hypot(*pair)
    if not accepted.contains(length):
        reason = f" ({why})" if why else ""
        raise ValueError(
            f"{path} must have a length in {accepted}{reason}, got {pair!r} (length {length:g})"
        )
    return pair


def check_fields(obj: Any) -> None:
    """Validate every field of a (frozen) dataclass that declares an interval with
    :func:`param`, and store it as a Python number. Errors name ``ClassName.field``.

    Args:
        obj: A dataclass instance (its ``__post_init__`` calls this); frozen ones too.

    Raises:
        TypeError: If a field's value has the wrong type.
        ValueError: If a field's value is not finite or lies outside its interval.
    """
    owner = type(obj).__name__
    for f in fields(obj):
        if "interval" not in f.metadata:
            continue
        path = f"{owner}.{f.name}"
        value = getattr(obj, f.name)
        if f.metadata.get("integer"):
            checked: Any = check_integer(path, value, f.metadata["interval"])
        elif isinstance(f.default, bool):
            checked = check_bool(path, value)
        else:
            checked = check_number(path, value, f.metadata["interval"])
        object.__setattr__(obj, f.name, checked)


def check_at_least(obj: Any, name: str, least: str, why: str = "") -> None:
    """Check that a parameter dataclass's field ``name`` is not below its field ``least``
    (a wall's foot at least as deep as the wall is thick, a greatest speed at least the
    least): the bound between two fields, which no one field's interval can say.

    Args:
        obj: The dataclass instance (its ``__post_init__`` calls this after
            :func:`check_fields`).
        name: The field that must be the larger.
        least: The field it may not be below.
        why: Said at the end of the error (``": the balls start above the floor"``).

    Raises:
        ValueError: ``"<Class>.<name> must be >= <least> (<its value>), got <value><why>"``.
    """
    value, floor = getattr(obj, name), getattr(obj, least)
    if not (is_traced(value) or is_traced(floor)) and value < floor:
        raise ValueError(
            f"{type(obj).__name__}.{name} must be >= {least} ({floor!r}), got {value!r}{why}"
        )


class CheckedFields:
    """The base of a parameter dataclass whose only check is its fields' intervals: its
    ``__post_init__`` is :func:`check_fields`, so the dataclass need not write one. A class
    with checks of its own writes its ``__post_init__``, :func:`check_fields` first."""

    __slots__ = ()

    def __post_init__(self) -> None:
        check_fields(self)


def build_params(cls: type, path: str, value: Any, **extra: Any) -> Any:
    """A ``cls`` dataclass from ``None`` (defaults), an instance, or a mapping of its field
    names; ``extra`` overrides fields. Errors name ``path.field``: an unknown key raises
    ``TypeError`` (as an unknown keyword does), a bad value ``TypeError``/``ValueError``.

    Args:
        cls: The parameter dataclass (``DinghyParams``).
        path: The argument's name in errors (``"dinghy"``).
        value: ``None``, a ``cls`` instance, or a mapping of some of its field names to
            values.
        **extra: Field values that override ``value``'s.

    Returns:
        A ``cls`` instance (``value`` itself, if it is one and ``extra`` is empty).

    Raises:
        TypeError: If ``value`` is of another kind, has an unknown key, or a field's value
            has the wrong type.
        ValueError: If a field's value is not accepted.
    """
    if value is None:
        value = {}
    if isinstance(value, cls):
        if not extra:
            return value
        value = {f.name: getattr(value, f.name) for f in fields(cls)}
    if not isinstance(value, Mapping):
        raise TypeError(
            f"{path} must be a mapping of {cls.__name__} fields or a {cls.__name__}, got {value!r}"
        )
    known = [f.name for f in fields(cls)]
    for key in value:
        if key not in known:
            raise TypeError(f"{path} got an unexpected key {key!r}; known keys: {known}")
    try:
        return cls(**{**value, **extra})
    except (TypeError, ValueError) as error:
        message = str(error).replace(f"{cls.__name__}.", f"{path}.")
        raise type(error)(message) from None


def interval_rows(cls: type, group: str) -> list[str]:
    """Markdown table rows ``| `group.field` | default | accepted |`` for every field of a
    parameter dataclass that declares an interval (the README's tables are these rows, and
    a test keeps them equal).

    Args:
        cls: The parameter dataclass.
        group: The constructor argument that takes it (``"dinghy"``).

    Returns:
        One row per field that declares an interval, in field order.
    """
    rows = []
    for f in fields(cls):
        accepted = f.metadata.get("interval")
        if accepted is None:
            continue
        default = f.default
        shown = f"{default:.6g}" if isinstance(default, float) else repr(default)
        rows.append(f"| `{group}.{f.name}` | {shown} | {accepted} |")
    return rows
