"""Helpers shared by the envs: argument validation and batch/element conversion."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import fields, replace
from typing import Any

import numpy as np


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


def vector_seeds(seed: int | list[int | None] | None, num_envs: int) -> list[int | None]:
    """Per-sub-env seeds: ``seed + i`` for an int (Gymnasium's convention), a list as given,
    or fresh entropy for ``None``."""
    if seed is None:
        return [None] * num_envs
    if isinstance(seed, (int, np.integer)):
        return [int(seed) + i for i in range(num_envs)]
    seeds = list(seed)
    if len(seeds) != num_envs:
        raise ValueError(f"seed must have {num_envs} entries, got {len(seeds)}")
    return seeds


def vector_info(info: dict[str, Any], num_envs: int) -> dict[str, Any]:
    """Gymnasium's vector info layout: every key with a ``_key`` mask (all envs report)."""
    mask = np.ones(num_envs, dtype=bool)
    out: dict[str, Any] = {}
    for key, value in info.items():
        out[key] = vector_info(value, num_envs) if isinstance(value, dict) else value
        out[f"_{key}"] = mask
    return out
