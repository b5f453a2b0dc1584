"""The one cache of device code. A factory of kernels or ``wp.func``s decorated with ``@cached``
runs once per content of its arguments (a chain by its digest, arrays by their bytes), and
``module_name`` names a Warp module by the same content, so equal mechanisms share compiled code
in a process and Warp's on-disk cache serves later processes."""

from __future__ import annotations

import functools
import hashlib
from typing import Any, Callable

import numpy as np

# Compiler flags for kernels whose inputs are checked finite and bounded: no NaN and no signed zero
# lets the compiler fold a constant's zero components (0 * x) and fuse multiply-adds across lines
FINITE_MATH = ("-fno-signed-zeros -menable-no-nans -ffp-contract=fast -Wno-unknown-warning-option"
               " -Wno-nan-infinity-disabled")  # Warp's headers name NaN, to no harm here
# multiply-adds fused across lines (one rounding where there were two), IEEE semantics otherwise
FUSED = "-ffp-contract=fast"
_BUILT: dict[tuple, Any] = {}


def _part(value) -> Any:
    """A hashable stand-in for an argument, equal for equal contents."""
    if hasattr(value, "digest") and callable(value.digest):
        return ("digest", value.digest())
    if isinstance(value, np.ndarray):
        data = np.ascontiguousarray(value)
        return ("array", data.dtype.str, data.shape, hashlib.sha256(data.tobytes()).hexdigest())
    if isinstance(value, (set, frozenset)):
        return ("set", tuple(sorted((_part(v) for v in value), key=repr)))
    if isinstance(value, (list, tuple, range)):
        return ("seq", tuple(_part(v) for v in value))
    if isinstance(value, type):
        return ("type", value.__module__, value.__qualname__)
    if isinstance(value, (np.integer, np.floating, np.bool_)):
        return value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    raise TypeError(f"no content key for a {type(value).__name__}")


def content_digest(*args) -> str:
    """A short hash of the arguments' content."""
    return hashlib.sha256(repr(_part(args)).encode()).hexdigest()[:16]


@functools.lru_cache(maxsize=1)
def _source_digest() -> str:
    """A hash of this package's source, its subpackages' included (``rod``): Warp's own module hash
    can miss a change inside a closure reached through ``wp.static`` (seen with the FK lanes), and
    would load the old compiled code."""
    from pathlib import Path

    h = hashlib.sha256()
    for path in sorted(Path(__file__).parent.rglob("*.py")):
        h.update(path.read_bytes())
    return h.hexdigest()[:8]


def module_name(prefix: str, *args) -> str:
    """The Warp module of a factory's kernels: ``rswarp_<prefix>_<content digest>``, the content
    being the arguments and the kernels' source."""
    return f"rswarp_{prefix}_{content_digest(_source_digest(), *args)}"


def finite_math(kernel):
    """``kernel`` (the only one of its module) compiled for the CPU with ``FINITE_MATH``; its host
    checks the inputs finite and the kernel bounds them before any product. A Warp without
    per-module CPU flags compiles it as it is, slower."""
    if "cpu_compiler_flags" in kernel.module.options:
        cpu_flags(kernel.module, FINITE_MATH)
    return kernel


# a module's functions inlined whole into its kernels: a call left out of line takes its struct and
# matrix arguments by value, a copy at each call (the rod's parameters, 1.7 kB; a lanes pose, 512
# bytes); the first compile takes longer
INLINE_ALL = "-mllvm=-inline-threshold=60000"


def cpu_flags(module, extra: str) -> None:
    """The module compiled for the CPU with ``extra`` after its flags (once: setting them again
    would reload it)."""
    import warp as wp

    flags = module.options.get("cpu_compiler_flags") or wp.config.cpu_compiler_flags or "-march=native"
    if not flags.endswith(extra):
        wp.set_module_options({"cpu_compiler_flags": f"{flags} {extra}"}, module=module)


def cached(factory: Callable) -> Callable:
    """``factory(*args)`` made once per content of ``args`` in this process."""

    @functools.wraps(factory)
    def get(*args):
        key = (factory.__module__, factory.__qualname__, _part(args))
        if key not in _BUILT:
            _BUILT[key] = factory(*args)
        return _BUILT[key]

    return get
