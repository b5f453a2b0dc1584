"""The map at the door kept true: docs/layout.md names every package and module of ``rswarp`` and
``kernels`` (one line each) and nothing that does not exist; the layers' imports point down only;
the house's size rules hold (modules of at most 500 lines, functions of at most 60, at most 16
parameters)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LAYOUT = ROOT / "docs" / "layout.md"
TREES = ("rswarp", "kernels")
# Each top-level name of the package and its layer: an import may point at its own layer's
# package or below, never up. Device code (kernels) stands apart and imports nothing of rswarp.
LAYERS = {
    **dict.fromkeys(("errors", "transforms", "files", "config", "outputs", "findings", "launch", "kernels",
                     "examples"), 0),
    "rsxml": 1,
    **dict.fromkeys(("rapid", "options"), 2),
    "geometry": 3,
    "kinematics": 4,
    "sim": 5,
    "export": 6,
    "motion": 7,
    "report": 8,
    **dict.fromkeys(("cli", "cli_options", "__init__"), 9),
}


def modules() -> set[str]:
    """Every module file of the two trees, as a path from the repository's root."""
    return {p.relative_to(ROOT).as_posix() for tree in TREES for p in (ROOT / tree).rglob("*.py")
            if "__pycache__" not in p.parts}


def mapped() -> dict[str, str]:
    """What the map names: ``### folder/`` headings, each followed by ``- `module.py`: line``
    entries; path -> its line."""
    out, folder = {}, None
    for line in LAYOUT.read_text().splitlines():
        heading = re.match(r"^### `?([\w/]+/)`?\s*$", line)
        if heading:
            folder = heading.group(1)
            continue
        entry = re.match(r"^- `([\w/]+\.py)`:\s*(\S.*)$", line)
        if entry and folder is not None:
            out[folder + entry.group(1)] = entry.group(2)
    return out


def test_the_map_names_every_module_once_with_its_line_and_nothing_else():
    named, present = mapped(), modules()
    missing = sorted(m for m in present - set(named) if not m.endswith("/__init__.py"))
    assert not missing, f"docs/layout.md does not name: {missing}"
    extra = sorted(set(named) - present)
    assert not extra, f"docs/layout.md names modules that do not exist: {extra}"
    assert all(len(line) > 10 for line in named.values())


def test_every_package_has_its_overview_and_a_heading_in_the_map():
    text = LAYOUT.read_text()
    for tree in TREES:
        for init in (ROOT / tree).rglob("__init__.py"):
            folder = init.parent.relative_to(ROOT).as_posix() + "/"
            assert f"### `{folder}`" in text or f"### {folder}" in text, f"no heading for {folder}"
            assert ast.get_docstring(ast.parse(init.read_text())), f"{folder}__init__.py has no docstring"


def _imports(path: Path) -> list[tuple[str, int]]:
    """(the top-level name of rswarp imported, line) of every import in ``path``, inside functions too."""
    parts = path.relative_to(ROOT).with_suffix("").parts
    package = ["rswarp", *parts[:-1]] if parts[0] == "kernels" else list(parts[:-1])
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            target = base + (node.module.split(".") if node.module else [])
            if target == ["rswarp"]:  # from .. import files, config: each a top-level name
                out += [(alias.name, node.lineno) for alias in node.names]
            elif target[0] == "rswarp":
                out.append((target[1], node.lineno))
        elif isinstance(node, ast.Import):
            out += [(alias.name.split(".")[1], node.lineno) for alias in node.names
                    if alias.name.startswith("rswarp.")]
    return out


def _own(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return "kernels" if parts[0] == "kernels" else parts[1]


@pytest.mark.parametrize("path", sorted(modules()))
def test_no_import_climbs_a_layer(path):
    file = ROOT / path
    own = _own(file)
    assert own in LAYERS, f"{path}: '{own}' has no layer in this test (and in docs/layout.md)"
    for name, line in _imports(file):
        if own == "kernels":
            assert name == "kernels", f"{path}:{line}: kernels/ imports rswarp.{name}"
        elif name != own:
            assert name in LAYERS, f"{path}:{line}: rswarp.{name} has no layer"
            assert LAYERS[name] <= LAYERS[own], f"{path}:{line}: {own} (layer {LAYERS[own]}) imports {name} " \
                                                f"(layer {LAYERS[name]})"


@pytest.mark.parametrize("path", sorted(modules()))
def test_modules_and_functions_stay_small(path):
    source = (ROOT / path).read_text()
    assert source.count("\n") <= 500, f"{path}: {source.count(chr(10))} lines"
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = node.args
            count = len(a.args) + len(a.kwonlyargs) + len(a.posonlyargs)
            assert node.end_lineno - node.lineno + 1 <= 60, f"{path}:{node.lineno} {node.name} is over 60 lines"
            assert count <= 16, f"{path}:{node.lineno} {node.name} takes {count} parameters"


def test_every_package_is_installed():
    """pyproject's package list names every folder of the two trees (a non-editable install copies
    only those)."""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    for tree in TREES:
        for init in (ROOT / tree).rglob("__init__.py"):
            parts = init.parent.relative_to(ROOT).parts
            name = ".".join(("rswarp", *parts) if parts[0] == "kernels" else parts)
            assert name in listed, f"pyproject.toml's packages lack {name}"
