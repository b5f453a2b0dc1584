"""The physical limit a benchmark prints beside its rate: what a copy of the same bytes runs at on
this machine (the memory's limit), and the floating-point operations of one item, counted in the
C++ Warp generated for the kernel (no hardware counters here: the machine is a VM). And
``held_gc``, the quiet a timed window runs in.

The count walks the kernel's generated function: each ``var = wp::op(...)`` costs what ``op``
costs on its operands' types (a vec3 sum 3, a 3x3 times 3x3 product 45, a dot of vec3 5, a square
root or a division 1 each), a call of a generated function costs that function's count, and both
arms of a branch are counted (an upper bound where code branches); a loop's body counts once; a
native snippet costs what ``NATIVE_FLOPS`` says. It
is a count of the code, not of the machine; for straight-line kernels (the FK, the arm's IK) it is
the work of an item."""

from __future__ import annotations

import contextlib
import gc
import re
import statistics
import time
from pathlib import Path

import numpy as np

_FUNC = re.compile(r"^static [^\n(]*?\b(\w+)\(\n(.*?)^\}", re.S | re.M)
_DECL = re.compile(r"^\s+(?:const )?(wp::[\w:<>, ]+?|bool|float|double|int)\*? (var_\w+)(?: =|;)", re.M)
_STMT = re.compile(r"^\s+(var_\w+) = (wp::)?(\w+)\((.*)\);\s*$", re.M)
_ARG = re.compile(r"^\s+(wp::[\w:<>, ]+?) (var_\w+)[,)]?\s*$", re.M)
_ELEMENTWISE = {"add", "sub", "neg", "div", "cw_mul", "cw_div"}
_ONE = {"sqrt", "sin", "cos", "atan2", "acos", "exp", "log", "floor", "round", "pow"}
# native snippets, whose C++ the count cannot read: ``trig.atan2_lanes`` is eight lanes of the
# scalar ``trig`` atan2, which this count makes 48 (a kernel of one such atan2 counted so)
NATIVE_FLOPS = {"atan2_lanes": 8 * 48}


def _size(ctype: str) -> tuple[int, int]:
    """(rows, columns) of a generated C++ type: a scalar (1, 1), a vec_t<n> (n, 1), a mat_t<r, c>;
    (0, 0) for an integer or a truth value (no floating-point work)."""
    if not re.search(r"float|half|double", ctype):
        return (0, 0)
    m = re.search(r"(vec|mat|quat)_t<(\d+)(?:, (\d+))?", ctype)
    if m is None:
        return (4, 1) if "quat" in ctype else (1, 1)
    return (int(m.group(2)), int(m.group(3)) if m.group(3) and m.group(1) == "mat" else 1)


def _cost(op: str, out: tuple[int, int], args: list[tuple[int, int]]) -> int:
    n = out[0] * out[1]
    if op in _ELEMENTWISE:
        return n
    if op in _ONE:
        return n
    if op == "mul":
        if len(args) == 2 and args[0][1] > 1 and args[1] != (1, 1):  # a matrix times a matrix or vector
            return n * (2 * args[0][1] - 1)
        return n
    if op == "dot":
        return 2 * args[0][0] * args[0][1] - 1 if args else 0
    if op == "cross":
        return 9
    if op == "length":
        return 2 * args[0][0] if args else 0
    if op == "determinant":
        return 14
    return 0


def kernel_flops(module_dir: Path, kernel_key: str) -> int:
    """The floating-point operations of one run of the kernel named ``kernel_key`` (its mangled
    name's start) in the module's generated C++ (``module_dir`` of Warp's kernel cache)."""
    source = next(Path(module_dir).glob("*.cpp")).read_text()
    bodies = {name: body for name, body in _FUNC.findall(source) if not name.startswith("adj_")}
    memo: dict[str, int] = {}

    def count(name: str) -> int:
        if name in memo:
            return memo[name]
        native = next((c for k, c in NATIVE_FLOPS.items() if re.fullmatch(rf"{k}_\d+", name)), None)
        if native is not None:
            return native
        memo[name] = 0  # recursion guard
        body = bodies[name]
        head = source[source.find(name + "(\n"):source.find(name + "(\n") + 2000].split("{", 1)[0]
        types = {v: _size(t) for t, v in _ARG.findall(head)}
        types.update({v: _size(t) for t, v in _DECL.findall(body)})
        total = 0
        for out, ns, op, args in _STMT.findall(body):
            if ns:
                operands = [types.get(a.strip(), (1, 1)) for a in args.split(",") if a.strip().startswith("var_")]
                if types.get(out, (1, 1)) != (0, 0) or op in ("dot", "length"):
                    total += _cost(op, types.get(out, (1, 1)), operands)
            elif op in bodies:
                total += count(op)
        for call in re.findall(r"^\s+(\w+_\d+)\(", body, re.M):  # calls whose value is not kept
            if call in bodies:
                total += count(call)
        memo[name] = total
        return total

    entry = next(name for name in bodies if name.startswith(kernel_key) and name.endswith("_cpu_kernel_forward"))
    return count(entry)


def module_dir(kernel) -> Path:
    """Where Warp's cache holds the kernel's compiled module (its generated C++ beside it)."""
    import warp as wp

    module = kernel.module
    exec_ = module.execs.get((None, "cpu")) or next(iter(module.execs.values()), None) if hasattr(module, "execs") \
        else None
    name = f"wp_{module.name}_{module.get_module_hash().hex()[:7]}" if exec_ is None else None
    root = Path(wp.config.kernel_cache_dir)
    if name is not None and (root / name).exists():
        return root / name
    matches = sorted(root.glob(f"wp_{module.name}_*"), key=lambda p: p.stat().st_mtime)
    return matches[-1]


@contextlib.contextmanager
def held_gc():
    """Python's garbage collector held off while a timing runs, as ``timeit`` does, for ours and
    every peer alike: what an earlier case left (a replicated Newton model's millions of objects)
    is otherwise collected inside the next timing."""
    gc.collect()
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def best_time(fn, repeats: int = 7, warm: bool = True) -> float:
    """The best of ``repeats`` timed runs of ``fn`` (after an untimed one with ``warm``: Warp compiles
    on the first call), the collector held off (``held_gc``): on a shared machine the least
    disturbed run is the one that measures the code."""
    if warm:
        fn()
    times = []
    with held_gc():
        for _ in range(repeats):
            t = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t)
    return min(times)


def alternated(runs: dict, rounds: int) -> dict:
    """Each of ``runs`` (name: a call) called once a round, in turn, for ``rounds`` rounds; per
    name, what its calls returned, in order. A noisy spell of a shared machine then meets ours
    and the peers alike; callers keep each one's best."""
    out = {name: [] for name in runs}
    for _ in range(rounds):
        for name, run in runs.items():
            out[name].append(run())
    return out


def copy_rate(bytes_per_item: int, items: int) -> float:
    """Items a second that a copy of ``items`` x ``bytes_per_item`` bytes between two buffers allows
    on one thread (the median of five copies after one that touches the pages)."""
    a = np.ones(max(bytes_per_item * items // 4, 1), np.float32)
    b = np.empty_like(a)
    np.copyto(b, a)
    times = []
    for _ in range(5):
        t = time.perf_counter()
        np.copyto(b, a)
        times.append(time.perf_counter() - t)
    return items / statistics.median(times)


def limit_line(what: str, rate: float, bytes_per_item: int, items: int, flops: float | None) -> str:
    """One line: the rate beside the copy of the same bytes, and the arithmetic it does a second."""
    copy = copy_rate(bytes_per_item, items)
    line = (f"the limit, {what}: {bytes_per_item} bytes an item in and out, a copy of the same bytes runs "
            f"{copy:,.0f}/s (ours on one thread at {rate / copy:.1%} of it)")
    if flops:
        line += f"; {flops:,.0f} floating-point operations an item (counted in the generated code), " \
                f"{rate * flops / 1e9:.2f} GFLOP/s on one thread"
    return line
