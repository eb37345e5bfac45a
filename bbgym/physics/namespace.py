"""The array namespaces the physics runs on (the contract every law keeps), and the
Python-float namespace of the single envs. (The vector envs' backends, which pick a namespace,
a device and a dtype, are :mod:`bbgym.backends`.)

Every physics function takes ``xp``: the namespace whose functions it calls. The physics
uses only names of the Python array API standard (``xp.asin``, ``xp.atan2``, ``xp.where``,
``xp.astype``, ...), never branches in Python on array values and keeps shapes fixed, so
one source runs on:

- :data:`floats`: one env on plain Python floats, where an array library's per-call
  overhead (about a microsecond, for arrays of one element) would dominate;
- ``numpy`` (NumPy >= 2.1 has the standard's names in its main namespace): a batch;
- ``array_api_strict``: the standard and nothing more (the tests run the physics on it);
- torch through ``array_api_compat.torch``, eager or under ``torch.compile``, CPU or CUDA
  (:mod:`bbgym.backends`).

What the standard leaves to the caller, and the physics does accordingly: a bool is not a
number (``xp.where(mask, x, 0.0)`` instead of ``mask * x``; counts by
``xp.astype(mask, xp.int64)``), Python scalars mix with arrays only in operators and in
the functions that allow it (``where``, ``maximum``, ``minimum``, ``clip``), and a loop
that may stop early checks "all done" (``bool(xp.all(done))``, a device sync on a GPU) at
most every K substeps.

One exception keeps the host fast: where a mask is false for every env on the host (a
Python ``False`` on :data:`floats`, an all-false NumPy array), the masked update it guards
may be skipped (:func:`skippable`), with the same result as the masked update's. Every
other namespace (torch, compiled or not; ``array_api_strict``) takes the masked update.
"""

from __future__ import annotations

import dataclasses
import math
import operator
from types import SimpleNamespace
from typing import Any

import numpy as np

Array = Any
"""A batch of values (an array of any namespace) or one value (a Python float)."""


def skippable(mask: Any) -> bool:
    """Whether an update masked by ``mask`` can be left out because it changes nothing: a
    Python ``False`` (one env on :data:`floats`) or an all-false NumPy array (a host batch,
    where the check costs a microsecond and is never traced). Masks of any other namespace
    are never skippable: a compiled step has no branch on array values."""
    return mask is False or (type(mask) is np.ndarray and not mask.any())


def _where(condition: Any, if_true: Any, if_false: Any) -> Any:
    return if_true if condition else if_false


def _clip(x: float, low: float | None = None, high: float | None = None) -> float:
    if low is not None and x < low:
        return low
    if high is not None and x > high:
        return high
    return x


def _sign(x: float) -> float:
    return 1.0 if x > 0.0 else -1.0 if x < 0.0 else 0.0


def _astype(x: Any, dtype: type, /, *, copy: bool = True) -> Any:
    return dtype(x)


def _zeros_like(x: Any, dtype: Any = None) -> Any:
    return (dtype or float)(0)


def _full_like(x: Any, fill_value: Any, dtype: Any = None) -> Any:
    return (dtype or type(fill_value))(fill_value)


_MATH_NAMES = ("sin", "cos", "tan", "tanh", "exp", "log", "sqrt", "asin", "acos", "atan2", "hypot")
"""The standard's functions that :mod:`math` has under the same names."""

floats = SimpleNamespace(
    float64=float,
    float32=float,
    int64=int,
    bool=bool,  # Python's own types stand for the dtypes
    **{name: getattr(math, name) for name in _MATH_NAMES},
    abs=abs,
    sign=_sign,
    maximum=max,
    minimum=min,
    clip=_clip,
    where=_where,
    astype=_astype,
    remainder=operator.mod,  # Python's float % has the standard's remainder semantics
    logical_not=operator.not_,
    logical_and=operator.and_,
    logical_or=operator.or_,
    any=bool,
    all=bool,
    zeros_like=_zeros_like,
    full_like=_full_like,
)
"""Namespace of the standard's functions on Python floats (and bools, ints)."""

numpy = np
"""The batched reference namespace."""


def as_float(x: Any, like: Any, xp: Any) -> Any:
    """Counts or flags ``x`` as floats of ``like``'s dtype (a Python float on
    :data:`floats`): the standard mixes no int or bool array with a float one.

    Args:
        x: an int or bool array (a Python int or bool for one env).
        like: a float array of the dtype wanted (a float for one env).
        xp: the array namespace.

    Returns:
        ``x`` as floats.
    """
    return float(x) if xp is floats else xp.astype(x, like.dtype)


def iterate(body: Any, times: int, start: tuple, xp: Any) -> tuple:
    """``body`` applied ``times`` times to ``start`` (a tuple of arrays): a fixed-point
    iteration. A Python loop on every namespace but JAX's, where it is one
    ``jax.lax.fori_loop``: XLA's fusion recomputes a value in each of its uses, so an
    unrolled iteration whose result is used k times costs k^times (a sea of 3 waves, 20
    iterations: a Sail-v2 step went from milliseconds to minutes).

    Args:
        body: a function of the tuple, returning a tuple of the same arrays.
        times: how many times (a Python int).
        start: the first tuple.
        xp: the array namespace.

    Returns:
        The tuple after the last application.
    """
    if getattr(xp, "bbgym_backend", None) == "jax" and times > 1:
        import jax

        return jax.lax.fori_loop(0, times, lambda _, values: tuple(body(values)), tuple(start))
    values = tuple(start)
    for _ in range(times):
        values = tuple(body(values))
    return values


def replaced(record: Any, **changes: Any) -> Any:
    """``record`` (a NamedTuple) with the fields in ``changes`` replaced: ``_replace``
    spelled as a plain constructor call. Under ``torch.compile`` in torch 2.11, a record
    made by ``_replace`` came out of the compiled function as an empty tuple (Dynamo
    traced its ``_make`` wrongly); a constructor call traces the same on every version.
    The package makes records by their constructors alone (a test keeps it so)."""
    values = [changes.pop(name, value) for name, value in zip(record._fields, record, strict=True)]
    if changes:
        raise ValueError(f"{type(record).__name__} has no field {sorted(changes)}")
    return type(record)(*values)


def _values(record: Any) -> tuple:
    if isinstance(record, tuple):
        return tuple(record)
    return tuple(getattr(record, f.name) for f in dataclasses.fields(record))


def select(mask: Array, new: Any, old: Any, xp: Any) -> Any:
    """A record with ``new``'s values where ``mask`` (per env) and ``old``'s elsewhere
    (NamedTuple or dataclass of arrays, built by its constructor: see :func:`replaced`). A
    field ``new`` took over from ``old`` (the same object: states are never written, so
    sharing is safe) is kept without a ``where``."""
    if xp is floats:
        return xp.where(mask, new, old)  # one env: the whole record is one choice
    values = [
        b if a is b else xp.where(mask, a, b)
        for a, b in zip(_values(new), _values(old), strict=True)
    ]
    return type(old)(*values)


def namespace_of(x: Any) -> Any:
    """``numpy`` for NumPy arrays, :data:`floats` for Python numbers."""
    return np if isinstance(x, np.ndarray) else floats
