"""bbgym's optional extras (``pyproject.toml``'s ``[project.optional-dependencies]``): which
importable modules each one brings, which are missing, and the one command that installs
them, worded for how this bbgym was installed.

bbgym is on no public package index, so ``pip install "bbgym[render]"`` only works where
bbgym came from an index a user set up. :func:`install_hint` reads the installed
distribution's ``direct_url.json`` (PEP 610, written by pip for an install from a folder, a
file or a URL): an editable install from a checkout gets ``pip install -e "<checkout>[extra]"``,
an install from a checkout folder ``pip install "<checkout>[extra]"``, one from a wheel
``pip install "<wheel>[extra]"``; anything else ``pip install "bbgym[extra]"``. Every hint in
the package comes from it. Imports nothing heavy (the ``bbgym`` command's ``--help`` stays
light).
"""

from __future__ import annotations

import importlib.util
import json
from collections.abc import Iterable
from importlib import metadata
from pathlib import Path
from urllib.parse import unquote, urlparse

EXTRA_MODULES: dict[str, tuple[str, ...]] = {
    "render": ("pygame",),
    "plots": ("matplotlib", "PIL"),
    "train": ("stable_baselines3", "torch", "tensorboard"),
    "torch": ("torch", "array_api_compat"),
    "jax": ("jax",),
    "rejax": ("rejax", "jax", "flax", "gymnax"),
    "rllib": ("ray", "torch"),
    "zoo": ("rl_zoo3", "torch"),
    "torchrl": ("torchrl", "tensordict", "torch", "array_api_compat"),
    "race": ("pettingzoo",),
}
"""Extra -> the modules a command needs of it (imported by name; ``PIL`` is Pillow). The
``plots`` extra's imageio-ffmpeg is needed only for ``.mp4`` and MoviePy only for
Gymnasium's ``RecordVideo``: the commands that need them ask for them by module."""

DISTRIBUTION = "bbgym"


def missing_modules(needs: Iterable[tuple[str, str]]) -> dict[str, list[str]]:
    """Of ``needs``, pairs ``(module, extra)``, the modules that cannot be imported, by
    extra (in the order first needed; empty where nothing is missing)."""
    missing: dict[str, list[str]] = {}
    for module, extra in needs:
        if importlib.util.find_spec(module) is None:
            names = missing.setdefault(extra, [])
            if module not in names:
                names.append(module)
    return missing


def extra_needs(*extras: str) -> list[tuple[str, str]]:
    """``(module, extra)`` for every module of each of ``extras`` (:data:`EXTRA_MODULES`)."""
    unknown = [extra for extra in extras if extra not in EXTRA_MODULES]
    if unknown:
        raise ValueError(f"unknown extras {unknown}; bbgym's: {', '.join(EXTRA_MODULES)}")
    return [(module, extra) for extra in extras for module in EXTRA_MODULES[extra]]


def _direct_url() -> dict | None:
    """The installed bbgym's ``direct_url.json`` (None where it has none or is not
    installed, as when it runs from a checkout on ``PYTHONPATH``)."""
    try:
        text = metadata.distribution(DISTRIBUTION).read_text("direct_url.json")
    except metadata.PackageNotFoundError:
        return None
    if not text:
        return None
    try:
        data = json.loads(text)
    except ValueError:
        return None
    return data if isinstance(data, dict) else None


def _local_path(url: str) -> str | None:
    parsed = urlparse(url)
    if parsed.scheme != "file":
        return None
    return unquote(parsed.path)


def _source_checkout() -> Path | None:
    """The checkout this bbgym runs from where it is not installed (its parent folder holds
    ``pyproject.toml``), else None."""
    root = Path(__file__).resolve().parent.parent
    return root if (root / "pyproject.toml").is_file() else None


def install_hint(*extras: str) -> str:
    """The pip command that installs bbgym's ``extras`` the way this bbgym was installed
    (see the module's docstring), e.g. ``pip install -e "/src/bbgym[train,render]"``."""
    names = ",".join(dict.fromkeys(extras))
    direct = _direct_url()
    if direct is None:
        try:
            metadata.distribution(DISTRIBUTION)
        except metadata.PackageNotFoundError:
            checkout = _source_checkout()
            if checkout is not None:  # run from a checkout, not installed
                return f'pip install -e "{checkout}[{names}]"'
        return f'pip install "bbgym[{names}]"'
    path = _local_path(str(direct.get("url", "")))
    if path is None:  # a VCS or archive URL: install it again with the extras
        return f'pip install "bbgym[{names}] @ {direct.get("url", "")}"'
    if "dir_info" in direct:
        editable = bool(direct["dir_info"].get("editable"))
        return f'pip install {"-e " if editable else ""}"{path}[{names}]"'
    return f'pip install "{path}[{names}]"'  # a wheel or an sdist file


def missing_message(missing: dict[str, list[str]], what: str = "this command") -> str:
    """One message for the ``missing`` modules by extra (:func:`missing_modules`): what is
    missing, in which extra, and the one command that installs them all."""
    parts = [
        f"{', '.join(repr(m) for m in modules)} (the {extra!r} extra)"
        for extra, modules in missing.items()
    ]
    return f"{what} needs {'; '.join(parts)}, not installed: {install_hint(*missing)}"
