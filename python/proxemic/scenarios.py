"""Scenario files: the bundled ones by name or env id, or any TOML file by path.

Scenario files are parsed and validated once, by the Rust core; Python receives the validated
description as a dict (defaults filled in, world polygons computed).
"""

from __future__ import annotations

import difflib
import json
import os
import re
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from proxemic import _core
from proxemic.errors import ScenarioError, UnknownNameError, input_error

#: The elastic band's tunable gains (see ``Scenario.with_eband_gains``), in order.
EBAND_GAINS: tuple[str, ...] = tuple(_core.EBAND_GAINS)


def envs_dir() -> Path:
    """Folder of the scenario files shipped inside the package."""
    return Path(str(resources.files("proxemic") / "data" / "envs"))


def available() -> list[str]:
    """Names of the bundled scenarios (file stems), sorted."""
    return sorted(p.stem for p in envs_dir().glob("*.toml"))


def suggest(name: str, choices: Sequence[str]) -> str:
    """A ``" (did you mean 'x'?)"`` hint for a misspelt `name` among `choices`, or ``""``."""
    close = difflib.get_close_matches(name, list(choices), n=1, cutoff=0.6)
    if not close:  # names differing in case or separators ("CareCenter" for "care_center")
        folded = {c.lower().replace("_", "").replace("-", ""): c for c in choices}
        key = name.lower().replace("_", "").replace("-", "")
        close = [folded[k] for k in difflib.get_close_matches(key, list(folded), n=1, cutoff=0.75)]
    return f" (did you mean {close[0]!r}?)" if close else ""


def resolve(scenario: str | Path) -> Path:
    """Path of a scenario given by bundled name (``"museum"``), env id (``"proxemic/Museum-v5"``) or file path.

    Raises:
        ScenarioError: A path (a name ending in ``.toml`` or with a folder) to no file: "file
            not found: <path>".
        UnknownNameError: Neither a bundled name, an env id nor a file; the message suggests the
            closest name ("did you mean ...").
    """
    from proxemic.registration import ENV_IDS

    text = str(scenario)
    name = ENV_IDS.get(text, text)
    candidate = envs_dir() / f"{name}.toml"
    if not name.endswith(".toml") and candidate.is_file():
        return candidate
    path = Path(text).expanduser()
    if path.is_file():
        return path
    looks_like_id = text.startswith("proxemic/") or re.fullmatch(r"[\w.]+/[\w]+-v\d+", text) is not None
    if isinstance(scenario, Path) or text.endswith(".toml") or (("/" in text or os.sep in text) and not looks_like_id):
        raise ScenarioError(
            f"file not found: {text}" + (" (a directory, not a scenario file)" if path.is_dir() else ""),
            file=text,
            field="scenario",
            expected="an existing scenario .toml file",
            found=text,
        )
    names = available()
    hint = suggest(text, [*names, *ENV_IDS])
    raise UnknownNameError(
        f"unknown scenario {text!r}{hint}: expected a bundled name ({', '.join(names)}), "
        "an env id (proxemic/Museum-v5, see `proxemic scenes`) or a path to a .toml file",
        field="scenario",
        expected=f"one of {names}, an env id or an existing .toml file",
        found=text,
    )


DRIVES: tuple[str, ...] = ("holonomic", "differential")
"""The robots' drive names (the core's ``Drive::NAMES``): the ``drive=`` keyword's values."""


def check_planner(name: str) -> None:
    """Raises :class:`ScenarioError` for a planner name that is not one of ``PLANNERS``, with a suggestion."""
    if name not in _core.PLANNERS:
        raise ScenarioError(
            f"planner: expected one of {json.dumps(list(_core.PLANNERS))}, got {json.dumps(name)}"
            f"{suggest(name, _core.PLANNERS)}",
            field="planner",
            expected=f"one of {list(_core.PLANNERS)}",
            found=name,
        )


#: Prefix of a generated scene's name: ``generated/<seed>`` or ``generated/<seed>?key=value&...``.
GENERATED_PREFIX = "generated/"

#: Prefix of a Francis et al. 2023 archetype's scene:
#: ``francis2023/<archetype>[?seed=N&max_time=T&drive=D]`` (see :mod:`proxemic.francis2023`).
FRANCIS2023_PREFIX = "francis2023/"

#: Prefix of a CrowdNav protocol scene: ``crowdnav/<family>[?humans=N&visible=B&seed=S&drive=D]``
#: (see :mod:`proxemic.crowdnav`).
CROWDNAV_PREFIX = "crowdnav/"

#: Parameters of :func:`generate` (and of a ``generated/<seed>?...`` name), in the core's order.
GENERATE_PARAMS: tuple[str, ...] = tuple(_core.GENERATE_PARAMS)


#: The generator parameters whose values are names, and what they expect.
_NAMED = {
    "reaction": "a reaction name (ignore, aware, yield, curious, cautious)",
    "drive": "a drive name (holonomic or differential)",
}


def generated_name(seed: int, **params: float | str) -> str:
    """The scenario name ``generated/<seed>?key=value&...`` of a generated scene.

    Raises:
        InputError: `seed` not a non-negative integer, a parameter value not a number (for
            ``reaction`` and ``drive``, not a string; an unknown name is the core's ScenarioError).
        UnknownNameError: a parameter name not in ``GENERATE_PARAMS``.
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise input_error("seed", "a non-negative integer", seed)
    pairs = []
    for key, value in params.items():
        if key not in GENERATE_PARAMS:
            raise UnknownNameError(
                f"unknown generator parameter {key!r}: expected one of {list(GENERATE_PARAMS)}",
                field=key,
                expected=f"one of {list(GENERATE_PARAMS)}",
                found=key,
            )
        if key in _NAMED:
            if not isinstance(value, str):
                raise input_error(key, _NAMED[key], value)
            pairs.append(f"{key}={value}")
            continue
        pairs.append(
            f"{key}={_number(value, key):g}"
            if key not in ("robots", "objects_per_room", "encounters")
            else f"{key}={value}"
        )
    query = "?" + "&".join(pairs) if pairs else ""
    return f"{GENERATED_PREFIX}{int(seed)}{query}"


def generate(seed: int, **params: float | str) -> _core.Scenario:
    """A generated scene (a seeded floor plan with furniture, people and robots) as a scenario.

    Same seed and parameters, same scene. Parameters (defaults and ranges in ``docs/generated.md`` and the
    core's ``GenParams``): ``width`` (m, 24, [12, 60]), ``height`` (m, 16, [10, 40]),
    ``corridor_width`` (m, 3, [2.4, 6]), ``door_width`` (m, 1.8, [1.4, 3]), ``density`` (people per
    100 m^2, 1.5, [0, 6]), ``group_share`` (0.3), ``walker_share`` (0.4), ``seated_share`` (0.2),
    ``objects_per_room`` (3, [0, 8]), ``robots`` (1, [1, 8]), ``max_time`` (s, 180, [30, 3600]),
    ``encounters`` (0, [0, 1]: a conversation group placed on each robot's shortest way),
    ``reaction`` (the people's reaction to robots, default ``aware``; ``docs/people.md``),
    ``drive`` (every robot's drive, ``holonomic`` by default or ``differential``; ``docs/scenarios.md``).
    The same scene is ``gym.make("proxemic/Generated-v5", scenario=generated_name(seed, ...))``.

    Raises:
        ScenarioError: a parameter out of its range, naming it.
        UnknownNameError: an unknown parameter name.
        InputError: a seed or value of the wrong type.
    """
    core, _text = _core.generate(generated_name(seed, **params))
    return core


def generate_toml(seed: int, **params: float | str) -> str:
    """The scenario file text of :func:`generate`'s scene (loads back as the same scenario)."""
    return _core.generate(generated_name(seed, **params))[1]


def load(
    scenario: str | Path | _core.Scenario,
    *,
    planner: str | None = None,
    eband: Mapping[str, float] | None = None,
    goal: Sequence[float] | None = None,
    drive: str | None = None,
    subgoal: float | None = None,
) -> tuple[_core.Scenario, dict[str, Any]]:
    """Parses and validates a scenario; returns the core object and its description dict.

    Planner and gain names and values are validated by the core: an unknown one raises
    :class:`~proxemic.errors.ScenarioError` naming it, as it would in the file.

    Args:
        scenario: Bundled name, env id (``"proxemic/Museum-v5"``) or path of a scenario file, a generated scene's name
            (``generated/<seed>`` or ``generated/<seed>?key=value&...``, see :func:`generate`), a
            Francis et al. 2023 archetype's scene (``francis2023/<archetype>[?seed=N&max_time=T&drive=D]``,
            see :mod:`proxemic.francis2023`), a CrowdNav protocol scene
            (``crowdnav/<family>[?humans=N&visible=B&seed=S&drive=D]``, see :mod:`proxemic.crowdnav`), or an
            already validated scenario.
        planner: If given, every robot uses this built-in planner (one of ``PLANNERS``) instead of the file's.
        eband: If given, every robot's elastic-band gains (``contraction_gain``,
            ``repulsion_gain``, ``social_gain``; dimensionless, in [0, 100]) are replaced by these.
        goal: If given, the first robot's goal (x, y in metres) instead of the file's.
        drive: If given, every robot's drive (``"holonomic"`` or ``"differential"``) instead of the
            scenario's. It overrides a ``drive=`` key of a generated scene's name.
        subgoal: If given, the ``[sensors] subgoal`` look-ahead (metres, in [0, 10]; 0 leaves the
            ``subgoal`` observation key out) instead of the scenario's.
    """
    if drive is not None and (not isinstance(drive, str) or drive not in DRIVES):
        raise input_error("drive", f"one of {list(DRIVES)}", drive)
    if isinstance(scenario, _core.Scenario):
        core = scenario
    elif str(scenario).startswith((GENERATED_PREFIX, FRANCIS2023_PREFIX, CROWDNAV_PREFIX)):
        core, _text = _core.generate(str(scenario))
    else:
        core = _core.Scenario.from_file(str(resolve(scenario)))
    if planner is not None:
        check_planner(planner)
        core = core.with_planner(planner)
    if drive is not None:
        core = core.with_drive(drive)
    if eband:
        if not isinstance(eband, Mapping):
            raise input_error("eband", "a mapping of gain names to numbers", eband)
        core = core.with_eband_gains(**{k: _number(v, f"eband.{k}") for k, v in eband.items()})
    if goal is not None:
        core = core.with_goal(_point(goal, "goal"))
    if subgoal is not None:
        core = core.with_subgoal(_number(subgoal, "subgoal"))
    return core, json.loads(core.to_json())


def _number(value: object, field: str) -> float:
    """`value` as a float, or an :class:`InputError` naming `field`."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise input_error(field, "a number", value)
    return float(value)


def _point(value: object, field: str) -> tuple[float, float]:
    """`value` as a point (x, y) of two numbers, or an :class:`InputError` naming `field`."""
    try:
        xs = list(value)  # type: ignore[call-overload]
    except TypeError:
        raise input_error(field, "a point (x, y) of two numbers in metres", value) from None
    if len(xs) != 2 or isinstance(value, str):
        raise input_error(field, "a point (x, y) of two numbers in metres", value)
    return (_number(xs[0], field), _number(xs[1], field))
