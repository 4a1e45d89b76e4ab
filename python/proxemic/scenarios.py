"""Scenario files: the bundled ones by name, or any TOML file by path.

Scenario files are parsed and validated once, by the Rust core; Python receives the validated
description as a dict (defaults filled in, world polygons computed).
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path
from typing import Any

from proxemic import _core
from proxemic.errors import UnknownNameError


def envs_dir() -> Path:
    """Folder of the scenario files shipped inside the package."""
    return Path(str(resources.files("proxemic") / "data" / "envs"))


def available() -> list[str]:
    """Names of the bundled scenarios (file stems), sorted."""
    return sorted(p.stem for p in envs_dir().glob("*.toml"))


def resolve(scenario: str | Path) -> Path:
    """Path of a scenario given by bundled name (``"museum"``) or by file path.

    Raises:
        UnknownNameError: neither a bundled name nor an existing file.

    """
    text = str(scenario)
    candidate = envs_dir() / f"{text}.toml"
    if not text.endswith(".toml") and candidate.is_file():
        return candidate
    path = Path(text).expanduser()
    if path.is_file():
        return path
    raise UnknownNameError(
        f"unknown scenario {text!r}: expected a bundled name ({', '.join(available())}) or a path to a .toml file",
        field="scenario",
        expected=f"one of {available()} or an existing .toml file",
        found=text,
    )


def load(scenario: str | Path) -> tuple[_core.Scenario, dict[str, Any]]:
    """Parses and validates a scenario; returns the core object and its description dict."""
    core = _core.Scenario.from_file(str(resolve(scenario)))
    return core, json.loads(core.to_json())
