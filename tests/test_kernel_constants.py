"""Warp 1.19 makes ``wp.float64(NAME)`` of a module constant the constant's own variable, so a
dynamic loop that updates a variable started so changes every later ``NAME`` of the function: the
rod's clearance bound read the loop's least box distance where it meant "none", and each cable
after the first started its bend radii from the last cable's (its first segment's curvature, and
so its fatigue, were another hose's). ``kernels.values.fresh`` starts such a variable as its own."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import warp as wp
from rods import rod, run

from rswarp.kernels.values import fresh

KERNELS = Path(__file__).resolve().parents[1] / "kernels"
BIG = 1.0e30
F64 = wp.float64


def _static_range(node: ast.AST) -> bool:
    """A ``range`` of constant bounds, which Warp unrolls (no loop variable is carried)."""
    return isinstance(node, ast.Call) and getattr(node.func, "id", None) == "range" and all(
        isinstance(a, ast.Constant) or (isinstance(a, ast.Call) and getattr(a.func, "attr", None) == "static")
        for a in node.args)


def _started_from_constants(fn: ast.FunctionDef) -> dict[str, int]:
    """Names a function assigns straight from a constructor of one name it neither takes nor
    assigns (a module constant, or a factory's closure constant): ``x = F64(BIG)``."""
    own = {a.arg for a in fn.args.args} | {n.id for n in ast.walk(fn) if isinstance(n, ast.Name)
                                           and isinstance(n.ctx, ast.Store)}
    out = {}
    for node in ast.walk(fn):
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call) and len(node.value.args) == 1:
            arg = node.value.args[0]
            if isinstance(arg, ast.Name) and arg.id not in own:
                for target in node.targets:
                    if isinstance(target, ast.Name):
                        out.setdefault(target.id, node.lineno)
    return out


def _carried_from_constants(path: Path) -> list[str]:
    """``file:line`` of each variable started from a module constant's constructor and then updated
    in a dynamic loop (``for`` over a range of run-time bounds, or ``while``)."""
    found = []
    for fn in ast.walk(ast.parse(path.read_text())):
        if not isinstance(fn, ast.FunctionDef):
            continue
        started = _started_from_constants(fn)
        for loop in ast.walk(fn):
            if not (isinstance(loop, ast.While) or (isinstance(loop, ast.For) and not _static_range(loop.iter))):
                continue
            updated = {n.id for n in ast.walk(loop) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Store)}
            found += [f"{path.name}:{started[name]} {fn.name}: {name}" for name in updated & set(started)
                      if started[name] < loop.lineno]
    return sorted(set(found))


def test_no_kernel_carries_a_loop_variable_started_from_a_constant():
    files = sorted(KERNELS.rglob("*.py"))
    assert len(files) > 20
    assert [hit for path in files for hit in _carried_from_constants(path)] == []


def test_the_rule_finds_the_pattern_it_names(tmp_path):
    """The check above is not vacuous: the rod's clearance as it was is flagged."""
    source = tmp_path / "k.py"
    source.write_text("def f(a):\n    nearest = F64(BIG)\n    for k in range(a.shape[0]):\n"
                      "        nearest = wp.min(nearest, a[k])\n    return F64(BIG)\n")
    assert _carried_from_constants(source) == ["k.py:2 f: nearest"]


@wp.func
def _least_then_none(a: wp.array(dtype=F64)) -> F64:
    nearest = fresh(F64(BIG))
    for k in range(a.shape[0]):
        nearest = wp.min(nearest, a[k])
    none = F64(BIG)
    return none + F64(0.0) * nearest


@wp.kernel
def _least_kernel(a: wp.array(dtype=F64), out: wp.array(dtype=F64)):
    out[0] = _least_then_none(a)


def test_a_fresh_start_leaves_the_constant_as_it_is():
    a = wp.array([3.0, 1.0, 2.0], dtype=F64, device="cpu")
    out = wp.zeros(1, dtype=F64, device="cpu")
    wp.launch(_least_kernel, 1, inputs=[a, out], device="cpu")
    assert out.numpy()[0] == BIG  # without ``fresh``: 1.0, the loop's least


def test_each_cable_starts_its_bend_radii_from_its_own_joints():
    """catenary.rsxml: the wire sags into a catenary, the hose beside it hangs straight from the
    arm. Its first segment is as straight as the rest (it read the wire's last curvature, 0.62/m)."""
    _, solver, state = rod("catenary")
    run(solver, state, 1.0)
    wire, hose = solver.curvatures(state)
    assert wire[0, -1] > 0.3  # 1/m: the wire's end is bent
    assert np.all(hose[0] < 1e-3)
