"""The array namespaces the physics runs on.

Every physics function takes ``xp``: the namespace whose functions it calls. ``numpy``
runs a batch (state arrays with a leading batch axis); :data:`scalar` runs one env on
plain Python floats, where NumPy's per-call overhead (about a microsecond, for arrays of
one element) would dominate. The physics uses only names that both provide, and that the
Python array API standard also has, so a GPU namespace (torch) can be added the same way.
"""

from __future__ import annotations

import math
import operator
from types import SimpleNamespace
from typing import Any

import numpy as np

Array = np.ndarray | float
"""A batch of values (NumPy) or one value (a Python float)."""


def _where(condition: Any, if_true: Any, if_false: Any) -> Any:
    return if_true if condition else if_false


def _clip(x: float, low: float, high: float) -> float:
    return low if x < low else high if x > high else x


def _sign(x: float) -> float:
    return 1.0 if x > 0.0 else -1.0 if x < 0.0 else 0.0


def _zeros_like(x: Any, dtype: Any = float) -> Any:
    return dtype(0)


scalar = SimpleNamespace(
    sin=math.sin,
    cos=math.cos,
    tanh=math.tanh,
    exp=math.exp,
    sqrt=math.sqrt,
    arcsin=math.asin,
    arctan2=math.atan2,
    hypot=math.hypot,
    abs=abs,
    sign=_sign,
    maximum=max,
    minimum=min,
    clip=_clip,
    where=_where,
    remainder=operator.mod,  # Python's float % has NumPy's remainder semantics
    logical_not=operator.not_,
    any=bool,
    all=bool,
    zeros_like=_zeros_like,
)
"""Namespace of functions on Python floats, with NumPy's names."""

numpy = np
"""The batched namespace."""


def namespace_of(x: Any) -> Any:
    """``numpy`` for arrays, :data:`scalar` for Python numbers."""
    return np if isinstance(x, np.ndarray) else scalar
