"""The compiled module's type stubs (``_core.pyi``) describe it: the same names, the same parameters."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path
from typing import Any

from proxemic import _core

STUB = Path(_core.__file__).resolve().parent / "_core.pyi"


def _stub() -> dict[str, Any]:
    """Top-level names of the stub: classes as {method: FunctionDef}, functions, constants."""
    out: dict[str, Any] = {}
    for node in ast.parse(STUB.read_text()).body:
        if isinstance(node, ast.ClassDef):
            out[node.name] = {n.name: n for n in node.body if isinstance(n, ast.FunctionDef)}
        elif isinstance(node, ast.FunctionDef):
            out[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out[node.target.id] = node
    return out


def _stub_params(fn: ast.FunctionDef) -> list[str]:
    a = fn.args
    star = [a.vararg] if a.vararg else []
    double_star = [a.kwarg] if a.kwarg else []
    return [p.arg for p in (*a.posonlyargs, *a.args, *star, *a.kwonlyargs, *double_star)]


def _runtime_params(obj: Any) -> list[str] | None:
    """Parameter names from pyo3's text signature (None when the object has none)."""
    if getattr(obj, "__text_signature__", None) is None:
        return None
    return list(inspect.signature(obj).parameters)


def test_every_public_name_is_in_the_stub_and_nothing_else():
    stub = _stub()
    runtime = {k for k in vars(_core) if not k.startswith("_")}
    public_stub = {k for k in stub if not k.startswith("_")}
    assert runtime - public_stub == set(), "compiled but not in _core.pyi"
    assert public_stub - runtime == set(), "in _core.pyi but not compiled"


def test_methods_and_functions_have_the_stub_parameters():
    stub = _stub()
    problems = []
    for name in sorted(k for k in vars(_core) if not k.startswith("_")):
        obj, described = getattr(_core, name), stub.get(name)
        if inspect.isclass(obj) and isinstance(described, dict):
            methods = {k: v for k, v in vars(obj).items() if not k.startswith("_")}
            for m in sorted(set(methods) - set(described)):
                problems.append(f"{name}.{m}: not in the stub")
            for m in sorted(set(described) - set(methods) - {"__init__"}):
                problems.append(f"{name}.{m}: in the stub only")
            for m in sorted(set(methods) & set(described)):
                got = _runtime_params(methods[m])
                if got is not None and got != _stub_params(described[m]):
                    problems.append(f"{name}.{m}: compiled {got}, stub {_stub_params(described[m])}")
        elif isinstance(described, ast.FunctionDef):
            got = _runtime_params(obj)
            if got is not None and got != _stub_params(described):
                problems.append(f"{name}: compiled {got}, stub {_stub_params(described)}")
    assert problems == []


def test_records_describe_the_dicts_the_core_returns():
    """The TypedDicts of ``proxemic.records`` (the stub's return types) have the runtime keys."""
    import numpy as np

    from proxemic import records, scenarios

    core, _ = scenarios.load("museum")
    world = _core.World(core)
    world.reset(0, np.zeros(world.num_robots * world.stride), np.zeros(world.num_people * _core.PERSON_OUT))
    metrics = world.episode_metrics()[0]
    assert set(metrics) == set(records.EpisodeMetrics.__annotations__)
    assert set(world.social_layers(0)) == set(records.SocialLayers.__annotations__)
    perception = world.perception()
    assert set(perception) == records.Perception.__required_keys__ | records.Perception.__optional_keys__
    assert set(perception["individuals"][0]) == set(records.Individual.__annotations__)
    assert set(perception["accuracy"]) == set(records.DetectionAccuracy.__annotations__)
