"""Backends of the native vector envs: which array namespace runs the step, on which
device, in which float dtype, and the random numbers drawn there.

``numpy`` (float64, the reference) runs the task core op by op on NumPy with each env's
own ``numpy.random.Generator``, so sub-env ``i`` equals the single env seeded ``seed + i``.
``torch`` runs the same core through ``array_api_compat.torch`` as one ``torch.compile``d
function per step on ``device`` (``"cpu"`` or ``"cuda"``), in float64 or float32; ``jax``
runs it through ``jax.numpy`` as one ``jax.jit`` executable. Both draw from a
counter-based generator (:func:`uniforms`, :func:`normals`) evaluated inside that
function: a pure hash of (env key, step counter, stream, index) in 32-bit modular
arithmetic, done in int64 that never overflows (NumPy, torch) or in uint32 that wraps (JAX,
which then needs no ``jax_enable_x64``), so the uniform draws are the same bits on every
device and in every namespace (the normals agree to the rounding of ``log`` and ``cos``),
a run is deterministic under a seed, and the generator's state is one counter per env.
"""

from __future__ import annotations

import logging
import math
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np

BACKENDS = ("numpy", "torch", "jax")
DTYPES = ("float64", "float32")
OUTPUTS = ("numpy", "torch", "jax")
STEP_GRAPHS = ("auto", "parts", "one")
"""How the torch backend compiles a step: ``parts``, each part of ``VectorStep`` its own
graph, called one by one; ``one``, the whole step one graph (``VectorStep.fused``), a
flight's or interval's chunks in a loop inside it; ``auto`` (the default), ``one`` where a
transition runs more than one chunk (the ball envs) and ``parts`` where it runs one
(sailing). Measured on a 2-core CPU (``scripts/bench_fused.py``, N=4096, float32): one
graph stepped the sailing env at 0.51-0.57x the parts' rate and the ball envs at
1.2-1.45x; on a GPU ``bbgym bench --device cuda`` times both."""

_MASK32 = 0xFFFFFFFF

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Backend:
    """Where and how a vector env's step runs (see the module docstring)."""

    name: str = "numpy"
    """The array namespace that runs the step: ``"numpy"``, ``"torch"`` or ``"jax"``
    (:data:`BACKENDS`)."""
    device: str = "cpu"
    """Where torch or JAX runs it: ``"cpu"``, ``"cuda"`` or ``"cuda:N"`` (always ``"cpu"``
    for numpy)."""
    dtype: str = "float64"
    """The float dtype of the state: ``"float64"`` or ``"float32"`` (torch and JAX)."""
    output: str = "numpy"
    """What ``reset`` and ``step`` return: ``"numpy"`` arrays, or the backend's own arrays
    on :attr:`device` (``"torch"`` tensors, ``"jax"`` arrays)."""
    compile: bool = True
    """Whether torch runs the step under ``torch.compile``, JAX under ``jax.jit``
    (``False``: eagerly)."""
    step_graph: str = "auto"
    """How torch compiles a step: ``"auto"``, ``"parts"`` or ``"one"``
    (:data:`STEP_GRAPHS`); JAX always compiles it as one program."""

    @property
    def xp(self) -> Any:
        """The array namespace."""
        if self.name == "jax":
            return jax_namespace(self.dtype == "float64")
        return np if self.name == "numpy" else torch_namespace()

    def context(self) -> Any:
        """The context every call into this backend's arrays runs in: for JAX,
        ``jax.enable_x64`` on for float64 and off for float32, so the step has the 64-bit
        types it needs (or none it would not use) whatever the user's process sets;
        nothing for the others.

        Returns:
            A context manager.
        """
        if self.name != "jax":
            return _NO_CONTEXT
        return jax_x64(self.dtype == "float64")

    @property
    def jax_device(self) -> Any:
        """The ``jax.Device`` of :attr:`device` (JAX only)."""
        import jax

        platform, _, index = self.device.partition(":")
        return jax.devices("cpu" if platform == "cpu" else "gpu")[int(index or 0)]

    @property
    def float_dtype(self) -> Any:
        """The namespace's float dtype named by :attr:`dtype` (``np.float64``,
        ``torch.float32``, ...)."""
        return getattr(self.xp, self.dtype)


def resolve_backend(
    backend: str = "numpy",
    device: str | None = None,
    dtype: str = "float64",
    output: str = "numpy",
    compile: bool = True,
    step_graph: str = "auto",
) -> Backend:
    """Validate the backend keywords of a vector env; errors name the argument.

    Args:
        backend: ``"numpy"`` (the float64 reference), ``"torch"`` or ``"jax"``.
        device: ``"cpu"``, ``"cuda"`` or ``"cuda:N"`` (torch and JAX); ``None``:
            ``"cpu"``.
        dtype: ``"float64"``, or ``"float32"`` (torch and JAX).
        output: ``"numpy"``, or the backend's own arrays on ``device``: ``"torch"``
            (torch only) or ``"jax"`` (JAX only).
        compile: Whether torch or JAX compiles the step (``False``: runs it eagerly).
        step_graph: ``"auto"``, ``"parts"`` or ``"one"`` (torch; JAX compiles one
            program, ``"auto"`` or ``"one"``; :data:`STEP_GRAPHS`).

    Returns:
        The checked :class:`Backend`.

    Raises:
        ValueError: If a keyword is not one of its accepted values, is one that needs
            another backend than the one named, or names a CUDA device the backend
            does not find.
        TypeError: If ``compile`` is not a bool.
        ImportError: If ``backend="torch"`` and torch or array-api-compat is not
            installed, or ``backend="jax"`` and jax is not; the message says how to
            install them.
    """
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {list(BACKENDS)}, got {backend!r}")
    if dtype not in DTYPES:
        raise ValueError(f"dtype must be one of {list(DTYPES)}, got {dtype!r}")
    if output not in OUTPUTS:
        raise ValueError(f"output must be one of {list(OUTPUTS)}, got {output!r}")
    if not isinstance(compile, bool):
        raise TypeError(f"compile must be a bool, got {compile!r}")
    if step_graph not in STEP_GRAPHS:
        raise ValueError(f"step_graph must be one of {list(STEP_GRAPHS)}, got {step_graph!r}")
    if output != "numpy" and output != backend:
        raise ValueError(f"output={output!r} needs backend={output!r}, got backend={backend!r}")
    if backend == "numpy":
        if step_graph == "one":
            raise ValueError(f"step_graph={step_graph!r} needs backend='torch' or 'jax'")
        if device not in (None, "cpu"):
            raise ValueError(f"device must be 'cpu' for backend='numpy', got {device!r}")
        if dtype != "float64":
            raise ValueError("dtype must be 'float64' for backend='numpy' (the reference)")
        return Backend()
    if backend == "jax":
        return _resolve_jax(device, dtype, output, compile, step_graph)
    try:
        import array_api_compat  # noqa: F401
        import torch
    except ImportError as error:
        from bbgym._extras import install_hint

        raise ImportError(
            "backend='torch' needs torch and array-api-compat (the 'torch' extra): "
            f"{install_hint('torch')} ({error})"
        ) from None
    device = _check_device(device)
    if device.startswith("cuda") and not torch.cuda.is_available():
        raise ValueError(f"device={device!r}: torch finds no CUDA device on this machine")
    return Backend("torch", device, dtype, output, compile, step_graph)


def _check_device(device: Any) -> str:
    """``device`` checked as ``"cpu"``, ``"cuda"`` or ``"cuda:N"`` (None: ``"cpu"``)."""
    device = "cpu" if device is None else device
    if not isinstance(device, str) or device.split(":")[0] not in ("cpu", "cuda"):
        raise ValueError(f"device must be 'cpu' or 'cuda' (or 'cuda:N'), got {device!r}")
    return device


def _resolve_jax(device: Any, dtype: str, output: str, compile: bool, step_graph: str) -> Backend:
    """:func:`resolve_backend` for ``backend="jax"`` (its other keywords checked)."""
    if step_graph == "parts":
        raise ValueError(
            "step_graph='parts' needs backend='torch': backend='jax' compiles the whole "
            "step as one program (step_graph='auto' or 'one')"
        )
    try:
        import jax
    except ImportError as error:
        from bbgym._extras import install_hint

        raise ImportError(
            f"backend='jax' needs jax (the 'jax' extra): {install_hint('jax')} ({error})"
        ) from None
    device = _check_device(device)
    platform, _, index = device.partition(":")
    try:
        found = jax.devices("cpu" if platform == "cpu" else "gpu")
    except RuntimeError:
        found = []
    if int(index or 0) >= len(found):
        raise ValueError(f"device={device!r}: jax finds no such device on this machine")
    return Backend("jax", device, dtype, output, compile, "one")


class _NoContext:
    """A context manager that does nothing (reusable, unlike ``nullcontext`` in 3.10)."""

    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: Any) -> None:
        return None


_NO_CONTEXT = _NoContext()

_JAX_NAMESPACES: dict[bool, Any] = {}


def jax_namespace(x64: bool = False) -> Any:
    """``jax.numpy`` (the array API standard's names since jax 0.4.32) as the namespace of
    a step in float64 (``x64``, run under ``jax.enable_x64(True)``) or in float32. In
    float32 the step runs without JAX's 64-bit types, and ``int64`` names ``int32`` (the
    counts a task keeps, substeps and hits, fit in 31 bits), so a task's
    ``xp.astype(mask, xp.int64)`` neither warns nor asks for a type JAX lacks there.

    Args:
        x64: Whether the step runs with JAX's 64-bit types (float64 state).

    Returns:
        A namespace object (made once per process and mode) with the array API's names.
    """
    if x64 in _JAX_NAMESPACES:
        return _JAX_NAMESPACES[x64]
    import jax.numpy as jnp

    names = {k: getattr(jnp, k) for k in dir(jnp) if not k.startswith("_")}
    if not x64:
        names["int64"] = jnp.int32
    names["bbgym_backend"] = "jax"
    _JAX_NAMESPACES[x64] = SimpleNamespace(**names)
    return _JAX_NAMESPACES[x64]


def jax_x64(on: bool) -> Any:
    """``jax.enable_x64(on)``, the context that turns JAX's 64-bit types on or off for the
    block only (``jax.experimental.enable_x64`` before jax 0.7).

    Args:
        on: Whether the block has JAX's 64-bit types.

    Returns:
        A context manager.
    """
    import jax

    switch = getattr(jax, "enable_x64", None)
    if switch is None:  # jax < 0.7 (Python 3.10 installs 0.6)
        from jax.experimental import enable_x64 as switch
    return switch(on)


def is_jax(xp: Any) -> bool:
    """Whether ``xp`` is a namespace of :func:`jax_namespace`.

    Args:
        xp: An array namespace.

    Returns:
        True for the JAX namespaces.
    """
    return getattr(xp, "bbgym_backend", None) == "jax"


_TORCH_NAMESPACE: Any = None


def torch_namespace() -> Any:
    """``array_api_compat.torch`` with four functions traced better by ``torch.compile``.

    array-api-compat turns a Python scalar argument of ``maximum``, ``minimum`` and ``clip``
    into a tensor through ``torch.result_type``, which Dynamo cannot put in a graph: every
    such call breaks the compiled step in two (measured: a sailing step fell from a fused
    kernel to 0.3 s of graph fragments). Here a scalar bound goes to ``torch.clamp_min`` or
    ``torch.clamp_max``, which take it natively with the same result (the standard's
    promotion: the tensor's dtype wins over a Python scalar), and ``where`` to
    ``torch.where``, which does the same (two Python scalars, which torch would turn into
    float32, raise as the standard says).
    Everything else is array-api-compat's.

    Returns:
        A namespace object (made once per process) with the array API's functions.
    """
    global _TORCH_NAMESPACE
    if _TORCH_NAMESPACE is not None:
        return _TORCH_NAMESPACE
    import torch
    from array_api_compat import torch as compat

    number = (int, float)

    def scalar_bound(clamp: Any, compat_fn: Any) -> Any:
        """``compat_fn`` (maximum or minimum), with a Python-number operand sent to
        ``clamp`` (``torch.clamp_min`` or ``torch.clamp_max``) as the bound."""

        def bounded(x1: Any, x2: Any, /) -> Any:
            if isinstance(x2, number):
                return clamp(x1, x2)
            if isinstance(x1, number):
                return clamp(x2, x1)
            return compat_fn(x1, x2)

        return bounded

    maximum = scalar_bound(torch.clamp_min, compat.maximum)
    minimum = scalar_bound(torch.clamp_max, compat.minimum)

    def clip(x: Any, /, min: Any = None, max: Any = None) -> Any:  # noqa: A002 (the standard's names)
        if min is not None:
            x = maximum(x, min)
        return x if max is None else minimum(x, max)

    def where(condition: Any, x1: Any, x2: Any, /) -> Any:
        if isinstance(x1, number) and isinstance(x2, number):
            # torch would make torch's default dtype (float32) of two Python floats
            raise TypeError(
                "where() needs an array in x1 or x2 (the standard's rule): "
                "xp.where(mask, 1.0, xp.full_like(x, -0.01))"
            )
        return torch.where(condition, x1, x2)

    names = {k: getattr(compat, k) for k in dir(compat) if not k.startswith("_")}
    names.update(maximum=maximum, minimum=minimum, clip=clip, where=where)
    _TORCH_NAMESPACE = SimpleNamespace(**names)
    return _TORCH_NAMESPACE


INDUCTOR_OPTIONS: dict[str, Any] = {}
"""Inductor's settings for bbgym's compiled steps (``torch.compile(options=...)``, these
graphs only); empty: inductor's defaults. Measured and left so: a lower
``realize_opcount_threshold`` (inductor stores a pointwise result costing more ops than
this, else recomputes it in every kernel that reads it; default 30) halves the cold
compile of the ball envs' steps (22 or less: 34-44 s instead of 68-81 s on the 2-core
machine) but slows their steps by 17-61%, so it is a trade for each user, not a default
(docs/pages/speed-torch.md, "What was tried to compile faster"; ``python
scripts/bench_inductor.py``)."""

CACHE_OPTIONS: dict[str, Any] = {
    "cpp.dynamic_threads": True,
    "unsafe_marked_cacheable_functions": {"torch.ops.higher_order.while_loop": "bbgym"},
}
"""Inductor's settings that let its on-disk cache (FX graph and AOTAutograd caches, under
:func:`compile_cache_dir`) serve bbgym's compiled steps across processes, in force while
a compiled function's first call compiles it (as a config patch, not ``torch.compile``'s
``options``, which a backend other than inductor would be handed; a later recompile, rare
at a fixed batch size, uses inductor's defaults). ``cpp.dynamic_threads``: the C++ kernels
ask OpenMP for the thread count at run time instead of holding ``torch.get_num_threads()``
as a constant, which put the thread count in the cache key (a run with another
``torch.set_num_threads`` compiled from cold). ``unsafe_marked_cacheable_functions``:
inductor and AOTAutograd refuse to cache a graph holding a higher-order op unless it is
marked cacheable, and ``while_loop`` (the one graph's loop over chunks) is not, so the
ball envs' one-graph step compiled from cold at every start; the cache key holds the
loop's condition and body graphs (the graph module pickles its submodules' code), so
marking it is safe for these graphs. Measured in docs/pages/speed-torch.md, "The compile
cache"."""


def compiled(fn: Any, backend: Backend) -> Any:
    """``fn`` under ``torch.compile`` (a static graph per input shape), or ``fn`` itself
    unless the backend is torch with ``compile=True``.

    Compiling happens at the first call (and again for a new input shape). If it fails (no
    working C++ compiler, an op the compiler cannot take), the call raises a
    ``RuntimeError`` naming what failed; nothing falls back silently: ``compile=False``
    runs the torch backend eagerly (slower).

    Args:
        fn: A function of arrays (a step or a part of one), called positionally.
        backend: The vector env's backend.

    Returns:
        A callable taking ``fn``'s positional arguments: ``fn`` compiled, or ``fn``.
    """
    if backend.name == "numpy" or not backend.compile:
        return fn
    if backend.name == "jax":
        import jax

        return jax.jit(fn)
    import torch
    import torch._dynamo
    from torch._dynamo.exc import TorchDynamoException

    # Dynamo keeps compiled graphs per code object: every task, dtype and batch size runs
    # the same VectorStep methods, so the default limit of 8 would send later envs to eager.
    config = torch._dynamo.config
    config.recompile_limit = max(config.recompile_limit, 256)
    config.accumulated_recompile_limit = max(config.accumulated_recompile_limit, 4096)
    # A static graph per batch size: dynamic=True let one graph serve every num_envs, with
    # the same bits, but its steps were 30-51% slower on CPU (docs/pages/speed-torch.md,
    # scripts/bench_compile.py), and a warm cache recompiles a new size in seconds.
    compiled_fn = torch.compile(fn, dynamic=False, options=dict(INDUCTOR_OPTIONS))
    name = getattr(fn, "__qualname__", repr(fn))

    cold = [True]  # until the first call has compiled its graph (with CACHE_OPTIONS)

    def call(*args: Any) -> Any:
        try:
            if cold[0]:
                with torch._inductor.config.patch(CACHE_OPTIONS):
                    out = compiled_fn(*args)
                cold[0] = False
                return out
            return compiled_fn(*args)
        except TorchDynamoException as error:  # the compiler failed, not the step
            raise RuntimeError(
                f"torch.compile failed on {name} ({type(error).__name__}: {error}); "
                "pass compile=False to run the torch backend eagerly (slower)"
            ) from error

    return call


def compile_cache_dir() -> str:
    """Where torch's inductor keeps its on-disk compile cache (``TORCHINDUCTOR_CACHE_DIR``,
    by default a folder under the temp dir): a later process that compiles the same graph
    reads its kernels from there instead of generating and compiling them again.

    Returns:
        The folder's path, or a sentence saying where to look where this torch keeps it
        elsewhere.
    """
    try:  # a private module of torch: where it moves, say where to look instead
        from torch._inductor.runtime.cache_dir_utils import cache_dir
    except ImportError:
        return "torch's inductor cache, TORCHINDUCTOR_CACHE_DIR"
    return str(cache_dir())


# -- what a person waiting for a compile is told ---------------------------------------------
QUIET_VARIABLE = "BBGYM_QUIET"
"""The environment variable that silences bbgym's notices on stderr (``BBGYM_QUIET=1``):
the compile notice of a torch env's first step and the waits of the scripted agents and
``bbgym evaluate``. Python's logging (logger ``bbgym``) still gets the compile lines."""

PROGRESS_INTERVAL_S = 15.0
"""Seconds between the "still compiling" lines while a first step compiles."""

NOTICE_AFTER_S = 2.0
"""Seconds a wait under :func:`announced` runs before it is said on stderr."""

TYPICAL_COMPILE_S = {"cold": (45, 140), "warm": (5, 15)}
"""The range of seconds a first compiled step took on the 2-core CPU the project measures
on, with a cold and a warm compile cache, across the envs (``scripts/compile_times.py``,
its table on docs/pages/speed-torch.md): what the notice tells a user to expect. A faster
core takes less, a busy machine more."""

_ANNOUNCED: set[tuple[Any, ...]] = set()
"""The compiles this process has announced on stderr (one line each, not one per env)."""


def quiet() -> bool:
    """Whether bbgym's notices on stderr are off (:data:`QUIET_VARIABLE` set, not to 0).

    Returns:
        True where ``BBGYM_QUIET`` is set to anything but ``""`` or ``"0"``.
    """
    return os.environ.get(QUIET_VARIABLE, "") not in ("", "0")


def _logging_shows(log: logging.Logger) -> bool:
    """Whether an INFO record of ``log`` reaches a handler that prints it (the ``bbgym``
    command's, or a script's ``logging.basicConfig(level=logging.INFO)``)."""
    if not log.isEnabledFor(logging.INFO):
        return False
    current: logging.Logger | None = log
    while current is not None:
        if any(h.level <= logging.INFO for h in current.handlers):
            return True
        current = current.parent if current.propagate else None
    return False


def notice(message: str, log: logging.Logger | None = None) -> None:
    """Tell a person waiting what bbgym is doing: ``message`` goes to ``log`` at INFO
    (logger ``bbgym.backends`` by default) and, unless logging already shows it or
    ``BBGYM_QUIET=1``, to stderr as ``bbgym: <message>``.

    Args:
        message: one line, without the ``bbgym:`` prefix.
        log: the logger that also gets it.
    """
    log = logger if log is None else log
    log.info("%s", message)
    if not quiet() and not _logging_shows(log):
        print(f"bbgym: {message}", file=sys.stderr, flush=True)


@contextmanager
def _ticking(tick: Callable[[], None], every_s: float, once: bool = False) -> Iterator[Any]:
    """Call ``tick`` from a daemon thread every ``every_s`` seconds while the block runs
    (only the first time if ``once``); yields an event set once it has been called."""
    done, ticked = threading.Event(), threading.Event()

    def run() -> None:
        while not done.wait(every_s):
            ticked.set()
            tick()
            if once:
                return

    thread = threading.Thread(target=run, name="bbgym-notice", daemon=True)
    thread.start()
    try:
        yield ticked
    finally:
        done.set()
        thread.join()


@contextmanager
def announced(message: str, threshold_s: float | None = None) -> Iterator[None]:
    """A wait that may be long, said on stderr (:func:`notice`) only if it lasts over
    ``threshold_s``: ``message`` then, and ``... done in N s`` after it.

    Args:
        message: what the block does, e.g. ``"VMGAutopilot: computing the polar ..."``.
        threshold_s: seconds the block runs before anything is said
            (:data:`NOTICE_AFTER_S` by default).

    Yields:
        Nothing; the block runs while a thread waits for the threshold.
    """
    threshold = NOTICE_AFTER_S if threshold_s is None else threshold_s
    start = time.perf_counter()
    with _ticking(lambda: notice(f"{message}..."), threshold, once=True) as said:
        yield
    if said.is_set():
        notice(f"{message}: done in {time.perf_counter() - start:.1f} s")


def _expected_wait(cache: str) -> str:
    """The notice's estimate of a first compile: the typical cold and warm seconds
    (:data:`TYPICAL_COMPILE_S`) and whether the cache holds any graph yet."""
    try:
        with os.scandir(os.path.join(cache, "fxgraph")) as entries:
            empty = not any(entries)
    except OSError:
        empty = True
    state = "the cache is empty, so expect the cold time" if empty else "the cache has graphs"
    (cold_low, cold_high), (warm_low, warm_high) = TYPICAL_COMPILE_S.values()
    return (
        f"a first step takes {cold_low:.0f}-{cold_high:.0f} s with a cold compile cache and "
        f"{warm_low:.0f}-{warm_high:.0f} s with a warm one on a 2-core CPU ({state})"
    )


@contextmanager
def compile_logged(
    what: str,
    backend: Backend,
    batch: int,
    graph: str | None = None,
    interval_s: float | None = None,
) -> Iterator[None]:
    """Say that the block compiles ``what`` and, after it, how long that took and how many
    graphs Dynamo traced: a cold first step runs for a minute or more with no output of
    its own, which looks like a hang.

    The lines go to logger ``bbgym.backends`` (INFO) and, unless logging shows them or
    ``BBGYM_QUIET=1``, to stderr (:func:`notice`): the first line once per process for each
    (what, device, dtype, batch, graph), then ``still compiling ...`` every ``interval_s``
    (logger ``bbgym.backends.progress``) while the block runs, and ``compiled ... in N s``.

    Args:
        what: what compiles, e.g. ``"the <env id> step"``.
        backend: the torch backend compiling it.
        batch: the batch size the graph is compiled for.
        graph: how the step compiles, ``"parts"`` or ``"one"`` (``STEP_GRAPHS``).
        interval_s: seconds between progress lines (:data:`PROGRESS_INTERVAL_S`).

    Yields:
        Nothing; the block compiles while a thread says it is still compiling.
    """
    interval = PROGRESS_INTERVAL_S if interval_s is None else interval_s
    key = (backend.name, what, backend.device, backend.dtype, batch, graph)
    first = key not in _ANNOUNCED
    _ANNOUNCED.add(key)
    if backend.name == "jax":
        cache = jax_cache_dir()
        kind = "the step as one program"
        graph_count: Callable[[], int] = lambda: 0  # noqa: E731
        expected = _expected_jax_wait(cache)
    else:
        from torch._dynamo.utils import counters

        cache = compile_cache_dir()
        kind = {"one": "the step as one graph", "parts": "the step's parts"}.get(graph or "")
        graph_count = lambda: counters["stats"]["unique_graphs"]  # noqa: E731
        expected = _expected_wait(cache)
    start_line = (
        f"compiling {what} for {backend.name} ({backend.device}, {backend.dtype}, batch "
        f"{batch}){'' if kind is None else f' ({kind})'}: {expected}; later "
        f"calls and runs reuse the compile cache ({cache})"
    )
    progress_log = logging.getLogger(f"{__name__}.progress")
    if first:
        notice(start_line)
    else:  # this process announced it: a recompile here is quick, and said only if not
        logger.info("%s", start_line)
    graphs = graph_count()
    start = time.perf_counter()

    def progress() -> None:
        elapsed = time.perf_counter() - start
        notice(f"still compiling {what}: {elapsed:.0f} s so far", progress_log)

    with _ticking(progress, interval) as spoke:
        yield
    end_line = f"compiled {what} in {time.perf_counter() - start:.1f} s" + (
        "" if backend.name == "jax" else f" ({graph_count() - graphs} new graphs)"
    )
    if first or spoke.is_set():
        notice(end_line)
    else:
        logger.info("%s", end_line)


TYPICAL_JAX_COMPILE_S = {"cold": (3, 15), "warm": (0.5, 2)}
""":data:`TYPICAL_COMPILE_S` for the JAX backend (``scripts/compile_times.py``)."""

JAX_CACHE_VARIABLE = "BBGYM_JAX_CACHE"
"""The environment variable naming the folder of JAX's persistent compile cache that bbgym
sets where the user has set none (``0``: bbgym sets none)."""


def jax_cache_dir() -> str:
    """The folder of JAX's persistent compilation cache, which bbgym turns on at a JAX
    env's first step where the process has none (``jax_compilation_cache_dir`` unset):
    :data:`JAX_CACHE_VARIABLE`, else ``$XDG_CACHE_HOME/bbgym/jax`` (``~/.cache/bbgym/jax``).
    A later process that compiles the same step loads it from there in about a second.

    Returns:
        The folder in use, or a sentence saying the cache is off.
    """
    import jax

    current = jax.config.jax_compilation_cache_dir
    if current:
        return str(current)
    chosen = os.environ.get(JAX_CACHE_VARIABLE)
    if chosen == "0":
        return "none: BBGYM_JAX_CACHE=0 turned it off"
    if not chosen:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        chosen = os.path.join(base, "bbgym", "jax")
    jax.config.update("jax_compilation_cache_dir", chosen)
    return chosen


def _expected_jax_wait(cache: str) -> str:
    """:func:`_expected_wait` for JAX: the typical seconds, cold and warm."""
    (cold_low, cold_high), (warm_low, warm_high) = TYPICAL_JAX_COMPILE_S.values()
    empty = not os.path.isdir(cache) or not os.listdir(cache)
    state = "the cache is empty, so expect the cold time" if empty else "the cache has programs"
    return (
        f"a first step takes {cold_low:.0f}-{cold_high:.0f} s with a cold compile cache and "
        f"{warm_low:.1f}-{warm_high:.0f} s with a warm one on a 2-core CPU ({state})"
    )


# -- counter-based random numbers -----------------------------------------------------------
def _is_uint32(x: Any) -> bool:
    """Whether ``x`` holds its 32-bit words as uint32 (JAX), where arithmetic wraps modulo
    2^32 by itself, rather than in int64 (NumPy, torch), where it is masked."""
    return str(getattr(x, "dtype", "")) == "uint32"


def _low32(x: Any) -> Any:
    """``x mod 2^32``: a mask on int64, nothing on uint32 (which cannot hold more)."""
    return x if _is_uint32(x) else x & _MASK32


def _word(value: int, like: Any) -> Any:
    """The 32-bit constant ``value`` to combine with ``like``'s words: a ``np.uint32`` for
    uint32 words (a Python int over 2^31 would not fit JAX's default int), else the int."""
    return np.uint32(value) if _is_uint32(like) else value


def _mul32(x: Any, c: int) -> Any:
    """``x * c mod 2^32`` for ``0 <= x < 2^32``, in int64 without overflow (products stay
    below 2^49) or in uint32 wrapping, so the same bits come out of NumPy, torch (CPU,
    CUDA, compiled), JAX and any array-API namespace."""
    low, high = c & 0xFFFF, c >> 16
    return _low32(x * low + (((x & 0xFFFF) * high) & 0xFFFF) * 65536)


def hash32(x: Any) -> Any:
    """A 32-bit integer hash with good avalanche (Wellons' "lowbias32"), on int64 arrays
    holding values in ``[0, 2^32)`` or on uint32 arrays (the same bits).

    Args:
        x: An int64 array (NumPy, torch or any array-API namespace) of values in
            ``[0, 2^32)``, or a uint32 array (JAX without ``jax_enable_x64``).

    Returns:
        An array of ``x``'s shape and dtype, values in ``[0, 2^32)``.
    """
    x = x ^ (x >> 16)
    x = _mul32(x, 0x7FEB352D)
    x = x ^ (x >> 15)
    x = _mul32(x, 0x846CA68B)
    return x ^ (x >> 16)


def env_keys(seed: int, num_envs: int, xp: Any, device: Any = None) -> Any:
    """One 32-bit key per env from a seed: env ``i`` gets ``hash(seed + i)``.

    Args:
        seed: An int (taken modulo 2^32).
        num_envs: The number of envs.
        xp: The array namespace to return the keys in (``numpy`` or the torch namespace).
        device: Where a torch array goes (``"cpu"``, ``"cuda"``); ignored for NumPy.

    Returns:
        A ``(num_envs,)`` int64 array of keys in ``[0, 2^32)``.
    """
    base = (int(seed) & _MASK32) + np.arange(num_envs, dtype=np.int64)
    keys = hash32(hash32(base & _MASK32) ^ 0x5BD1E995)
    return keys if xp is np else xp.asarray(keys, device=device)


def _stream_base(key: Any, counter: Any, stream: int) -> Any:
    """The hash every draw of one (env, step, stream) starts from."""
    salt = _word((stream * 0x9E3779B1 + 1) & _MASK32, key)
    return hash32(hash32(key ^ _low32(counter)) ^ salt)


def uniforms(key: Any, counter: Any, stream: int, count: int, dtype: Any, xp: Any) -> list:
    """``count`` uniform draws in (0, 1) per env: ``[(batch,)] * count``, a pure function of
    the env's key, its step counter and the stream number: one 32-bit hash per draw
    (float64 draws carry 32 random bits, float32 draws 24, both strictly inside (0, 1)).

    Args:
        key: ``(batch,)`` int64 env keys (:func:`env_keys`).
        counter: ``(batch,)`` int64 step counters.
        stream: A small int that tells apart the draws of one step (initial state,
            step noise, ...).
        count: Draws per env (>= 1).
        dtype: ``xp.float64`` or ``xp.float32``.
        xp: The array namespace of ``key``.

    Returns:
        ``count`` arrays of shape ``(batch,)`` and dtype ``dtype``.
    """
    rows = _uniform_rows(key, counter, stream, count, dtype, xp)
    return [rows[k, ...] for k in range(count)]


def _uniform_rows(key: Any, counter: Any, stream: int, count: int, dtype: Any, xp: Any) -> Any:
    """:func:`uniforms` as one ``(count, batch)`` array. All of a stream's draws are one
    broadcast hash, so a compiled graph holds the hash once however many draws it takes
    (its compile time does not grow with them)."""
    return _uniform_rows_at(key, counter, stream, range(count), dtype, xp)


def _uniform_rows_at(
    key: Any, counter: Any, stream: int, places: range, dtype: Any, xp: Any
) -> Any:
    """The draws at ``places`` of a stream as one ``(len(places), batch)`` array: draw
    ``k`` of a stream is the same whichever others are drawn beside it."""
    count = len(places)
    base = _stream_base(key, counter, stream)
    # The salts as a constant table, not an arange times a constant: inductor turns an
    # arange into index arithmetic, which Triton does in int32, and 0x85EBCA77 does not
    # fit there (torch 2.11 on CUDA refused to compile the step; bits are the same).
    salts = [(k * 0x85EBCA77) & _MASK32 for k in range(places.start + 1, places.stop + 1)]
    if _is_uint32(base):  # JAX: a constant of the program (a traced array has no device)
        salt = xp.asarray(np.asarray(salts, dtype=np.uint32))
    else:
        salt = xp.asarray(salts, dtype=xp.int64, device=base.device)
    bits = hash32(xp.expand_dims(base, axis=0) ^ xp.reshape(salt, (count,) + (1,) * base.ndim))
    if dtype == xp.float32:
        return (xp.astype(bits >> 8, dtype) + 0.5) * (1.0 / 16777216.0)
    return (xp.astype(bits, dtype) + 0.5) * (1.0 / 4294967296.0)


def normals(key: Any, counter: Any, stream: int, count: int, dtype: Any, xp: Any) -> list:
    """``count`` standard normal draws per env (Box-Muller on :func:`uniforms`: draws
    ``2j, 2j + 1`` make normals ``2j, 2j + 1``).

    Args:
        key: ``(batch,)`` int64 env keys (:func:`env_keys`).
        counter: ``(batch,)`` int64 step counters.
        stream: A small int that tells apart the draws of one step.
        count: Draws per env (>= 0).
        dtype: ``xp.float64`` or ``xp.float32``.
        xp: The array namespace of ``key``.

    Returns:
        ``count`` arrays of shape ``(batch,)`` and dtype ``dtype`` (an empty list for 0).
    """
    if count == 0:
        return []
    u = _uniform_rows(key, counter, stream, 2 * ((count + 1) // 2), dtype, xp)
    radius = xp.sqrt(-2.0 * xp.log(u[0::2, ...]))
    angle = (2.0 * math.pi) * u[1::2, ...]
    cos, sin = radius * xp.cos(angle), radius * xp.sin(angle)
    out = []
    for j in range(cos.shape[0]):
        out += [cos[j, ...], sin[j, ...]]
    return out[:count]


def draw_at(
    key: Any, counter: Any, stream: int, place: int, dtype: Any, xp: Any, normal: bool = False
) -> Any:
    """Draw ``place`` of a stream, alone: uniform in (0, 1), the same value as
    ``uniforms(key, counter, stream, n, ...)[place]`` for any ``n > place``; or, with
    ``normal``, standard normal, the same as ``normals(...)[place]`` (Box-Muller on the
    uniform pair ``2j, 2j + 1`` of ``j = place // 2``).

    Args:
        key: each env's key (int64 array).
        counter: each env's counter (int64 array, the key's shape).
        stream: the stream number.
        place: the draw's place in the stream (0 first).
        dtype: the float dtype.
        xp: the array namespace.
        normal: a standard normal draw instead of a uniform one.

    Returns:
        An array of the key's shape.
    """
    if not normal:
        return _uniform_rows_at(key, counter, stream, range(place, place + 1), dtype, xp)[0, ...]
    pair = 2 * (place // 2)
    u = _uniform_rows_at(key, counter, stream, range(pair, pair + 2), dtype, xp)
    radius = xp.sqrt(-2.0 * xp.log(u[0, ...]))
    angle = (2.0 * math.pi) * u[1, ...]
    return radius * (xp.cos(angle) if place % 2 == 0 else xp.sin(angle))


def is_jax_array(x: Any) -> bool:
    """Whether ``x`` is a JAX array (without importing JAX where it is not).

    Args:
        x: Anything.

    Returns:
        True for a ``jax.Array`` (or a tracer of one).
    """
    return type(x).__module__.startswith("jax")


def to_numpy(x: Any) -> Any:
    """A torch tensor or a JAX array as a NumPy array; anything else unchanged.

    Args:
        x: A torch tensor or JAX array (on any device), or anything else.

    Returns:
        A NumPy array for a tensor (zero-copy on the CPU, copied to the host from a GPU)
        or a JAX array (a writable copy: JAX's own buffers are read-only), else ``x``.
    """
    if hasattr(x, "detach"):
        x = x.detach()
        return (x if x.device.type == "cpu" else x.cpu()).numpy()
    if is_jax_array(x):
        return np.array(x)
    return x
