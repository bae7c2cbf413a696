"""The type stubs of the compiled module list exactly what it has, so that type checkers
and editors see the real API."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import beamflow
from beamflow import _native


def stub_names() -> dict:
    tree = ast.parse((Path(beamflow.__file__).parent / "_native.pyi").read_text())
    names: dict = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            names[node.name] = None
        elif isinstance(node, ast.ClassDef):
            names[node.name] = {
                n.name for n in node.body if isinstance(n, ast.FunctionDef) and not n.name.startswith("_")
            }
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = None
    return names


def test_stubs_match_the_compiled_module() -> None:
    stubs = stub_names()
    public = {n for n in dir(_native) if not n.startswith("_")} | {"__version__"}
    assert set(stubs) == public
    for name, methods in stubs.items():
        obj = getattr(_native, name)
        if inspect.isclass(obj):
            real = {n for n in vars(obj) if not n.startswith("_")}
            assert methods == real, (name, methods ^ real)


def test_the_package_is_typed() -> None:
    root = Path(beamflow.__file__).parent
    assert (root / "py.typed").exists()
    for f in root.glob("*.py"):
        tree = ast.parse(f.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and not node.name.startswith("__"):
                assert node.returns is not None, f"{f.name}: {node.name} has no return annotation"
