"""Writing a run folder's files whole or not at all.

A training can be killed at any instant (``kill -9``, a machine taken back); a file it was
writing must not be left half written for ``--resume``, ``bbgym evaluate`` or a reader of
the results to trip over. Each file is written under a temporary name beside its place
and renamed over it when complete: ``os.replace`` is atomic on POSIX and Windows within
one file system, so a reader sees the old file or the new one, never a part. (A crash of
the machine itself can still lose the last write: nothing here syncs to disk.)
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

PARTIAL = ".partial"
"""The infix of a file being written (``.model.partial.zip``); such a file is never read,
and a later write of the same file replaces it."""


def partial_path(path: Path) -> Path:
    """Where ``path`` is written before it is renamed into place: hidden, beside it, with
    its suffix kept (SB3 and NumPy add ``.zip`` or ``.npz`` to a path without one)."""
    path = Path(path)
    return path.with_name(f".{path.stem}{PARTIAL}{path.suffix}")


@contextmanager
def atomic_path(path: Path) -> Iterator[Path]:
    """A temporary path to write ``path`` through: renamed over ``path`` when the block
    ends, deleted if it raises."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = partial_path(path)
    try:
        yield temporary
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)


def write_atomic(path: Path, write: Callable[[Path], Any]) -> Path:
    """``write(temporary)``, then the temporary file renamed over ``path``; return ``path``."""
    with atomic_path(path) as temporary:
        write(temporary)
    return Path(path)


def write_text_atomic(path: Path, text: str) -> Path:
    """``path.write_text(text)`` (UTF-8), whole or not at all."""
    return write_atomic(path, lambda p: p.write_text(text, encoding="utf-8"))


def copy_atomic(source: Path, path: Path) -> Path:
    """``shutil.copy(source, path)``, whole or not at all."""
    return write_atomic(path, lambda p: shutil.copyfile(source, p))


def link_or_copy(source: Path, path: Path) -> Path:
    """``path`` as a hard link to ``source`` (no copy: files written through
    :func:`atomic_path` are replaced, never changed in place, so the link keeps the old
    content), or a copy where the file system has no hard links."""
    path = Path(path)
    try:
        with atomic_path(path) as temporary:
            temporary.unlink(missing_ok=True)
            os.link(source, temporary)
    except OSError:
        copy_atomic(source, path)
    return path
