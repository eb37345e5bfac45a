"""Helpers shared by the envs: argument validation and batch/element conversion."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import fields, replace
from typing import Any


def check_range(name: str, value: Any, low: float = 0.0, strict: bool = True) -> tuple:
    """Validate a ``(min, max)`` pair of finite numbers above ``low``."""
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a (min, max) pair of numbers, got {value!r}") from None
    ok = math.isfinite(lo) and math.isfinite(hi) and lo <= hi
    ok = ok and (lo > low if strict else lo >= low)
    if not ok:
        bound = ">" if strict else ">="
        raise ValueError(f"{name} must be finite with {bound} {low} and min <= max, got {value!r}")
    return lo, hi


def check_positive(name: str, value: Any) -> float:
    """Validate a finite number > 0."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return v


def make_params(cls: type, name: str, value: Any, **extra: Any) -> Any:
    """Build a params dataclass from ``None``, an instance or a mapping of field names."""
    if value is None:
        value = {}
    if isinstance(value, cls):
        return value if not extra else replace(value, **extra)
    if not isinstance(value, Mapping):
        raise ValueError(f"{name} must be a mapping of {cls.__name__} fields, got {value!r}")
    known = {f.name for f in fields(cls)}
    unknown = sorted(set(value) - known)
    if unknown:
        raise ValueError(f"{name} has unknown keys {unknown}; known: {sorted(known)}")
    return cls(**{**value, **extra})


def element(obj: Any, i: int) -> Any:
    """Element ``i`` of a batch dataclass, as Python scalars."""
    return type(obj)(**{f.name: getattr(obj, f.name)[i].item() for f in fields(obj)})
