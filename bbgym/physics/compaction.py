"""Working sets of a NumPy batch: the elements still busy taken out, and put back.

A host loop over a batch (:func:`bbgym.physics.flight.fly`) can drop the elements that are done
from its working set between chunks, so a batch costs what its busy elements do rather than
its longest one times its size, and put them back at the end: the results are those of the
masked loop over the whole batch, bit for bit. NumPy only (a compiled step cannot change
shapes). A tree is a NamedTuple (nested or not) of arrays, or one array.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def take(tree: Any, index: np.ndarray, size: int | None = None) -> Any:
    """The elements ``index`` of a tree of NumPy arrays; leaves that are not per element
    (Python numbers, arrays not of ``size`` elements) stay as they are."""
    if isinstance(tree, tuple):
        return type(tree)(*(take(leaf, index, size) for leaf in tree))
    per_element = isinstance(tree, np.ndarray) and tree.ndim >= 1
    if per_element and (size is None or tree.shape[0] == size):
        return tree[index]
    return tree


def scatter(full: Any, working: np.ndarray | None, flown: Any) -> Any:
    """``full`` with the elements ``working`` replaced by those of ``flown`` (all of it, for
    ``None``), leaf by leaf; ``full`` is not written."""
    if working is None:
        return flown
    if isinstance(full, tuple):
        return type(full)(*(scatter(a, working, b) for a, b in zip(full, flown, strict=True)))
    out = full.copy()
    out[working] = flown
    return out
