"""Bad inputs, table-driven: each gets a typed proxemic error (or exit code 2 with a one-line message
naming the field) and never kills the process.

Every case runs in its own subprocess, so a crash (a process exit, an abort, a Rust panic that
escapes) fails the case instead of the test session. A case is
``(id, code, error class, field)``: `code` runs after the preamble below and must raise an error of
`error class` (a name in :mod:`proxemic.errors`) whose ``field`` is `field`. CLI cases are
``(id, argv, field)`` and must exit with code 2, print one line on stderr, and name `field` there.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

PREAMBLE = """
import json, os, sys, tempfile, warnings
import numpy as np
import gymnasium as gym
import proxemic
from proxemic import _core, errors

def scen(text):
    f = tempfile.NamedTemporaryFile('w', suffix='.toml', delete=False)
    f.write(text)
    f.close()
    return f.name

ROOM = '''
[scene]
name = "room"
bounds = [0, 0, 10, 8]
[[wall]]
from = [0, 0]
to = [10, 0]
[[wall]]
from = [10, 0]
to = [10, 8]
[[wall]]
from = [10, 8]
to = [0, 8]
[[wall]]
from = [0, 8]
to = [0, 0]
'''
ROBOT = '''
[[robot]]
start = [1.5, 4, 0]
goal = [8.5, 4]
'''

def museum(**kw):
    env = gym.make("proxemic/Museum-v0", **kw)
    return env

def stepped(**kw):
    env = museum(**kw)
    env.reset(seed=0)
    return env

def multi(robots=2, reset=True):
    env = proxemic.parallel_env("museum_multi", robots=robots)
    if reset:
        env.reset(seed=0)
    return env

try:
    exec(compile(sys.argv[1], "<case>", "exec"))
except errors.ProxemicError as e:
    print(json.dumps({"class": type(e).__name__, "field": e.field, "message": str(e)}))
except BaseException as e:
    print(json.dumps({"class": "UNTYPED " + type(e).__name__, "field": None, "message": repr(e)}))
else:
    print(json.dumps({"class": "NO ERROR", "field": None, "message": ""}))
"""

S = "scen(ROOM + ROBOT + {extra!r})"

#: (id, code, error class, field)
API_CASES: list[tuple[str, str, str, str | None]] = [
    # --- the single-robot env
    ("env-step-before-reset", "museum().unwrapped.step(np.zeros(3))", "NeedsResetError", None),
    (
        "env-step-after-end",
        "env = stepped()\n"
        "while True:\n    *_, t, u, _ = env.step(np.ones(3))\n    if t or u: break\nenv.step(np.zeros(3))",
        "NeedsResetError",
        None,
    ),
    ("env-action-shape-1x3", "stepped().step(np.zeros((1, 3)))", "InputError", "action"),
    ("env-action-shape-2", "stepped().step(np.zeros(2))", "InputError", "action"),
    ("env-action-complex", "stepped().step(np.zeros(3, dtype=complex))", "InputError", "action"),
    ("env-action-bool", "stepped().step(np.array([True, False, True]))", "InputError", "action"),
    ("env-action-nan", "stepped().step(np.array([np.nan, 0, 0]))", "InputError", "action"),
    ("env-action-inf", "stepped().step(np.array([0, np.inf, 0]))", "InputError", "action"),
    ("env-action-string", "stepped().step('forward')", "InputError", "action"),
    ("env-action-none", "stepped().step(None)", "InputError", "action"),
    ("env-action-dict", "stepped().step({'vx': 1})", "InputError", "action"),
    ("env-seed-true", "museum().reset(seed=True)", "InputError", "seed"),
    ("env-seed-negative", "museum().reset(seed=-1)", "InputError", "seed"),
    ("env-seed-float", "museum().reset(seed=1.5)", "InputError", "seed"),
    ("env-seed-string", "museum().reset(seed='0')", "InputError", "seed"),
    ("env-reset-options", "museum().reset(seed=0, options={'goal': [1, 2]})", "InputError", "options"),
    ("env-width-zero", "museum(render_mode='rgb_array', width=0)", "InputError", "width"),
    ("env-height-negative", "museum(render_mode='topdown', height=-5)", "InputError", "height"),
    ("env-width-float", "museum(width=640.5)", "InputError", "width"),
    ("env-width-huge", "museum(width=100000)", "InputError", "width"),
    ("env-render-mode", "museum(render_mode='ascii')", "InputError", "render_mode"),
    ("env-camera", "museum(camera='side')", "InputError", "camera"),
    ("env-overlay", "museum(overlays=['heatmap'])", "InputError", "overlays"),
    # --- the parallel env
    ("par-step-before-reset", "multi(reset=False).step({})", "NeedsResetError", None),
    (
        "par-step-after-all-finished",
        "env = multi(2)\nfor _ in range(3000):\n    if not env.agents: break\n"
        "    env.step({a: np.ones(3) for a in env.agents})\nenv.step({})",
        "NeedsResetError",
        None,
    ),
    ("par-unknown-agent", "multi().step({'robot_9': np.zeros(3)})", "InputError", "actions"),
    ("par-missing-agent", "multi().step({'robot_0': np.zeros(3)})", "InputError", "actions"),
    (
        "par-action-bool",
        "multi().step({'robot_0': np.zeros(3), 'robot_1': np.array([True, True, False])})",
        "InputError",
        "actions['robot_1']",
    ),
    (
        "par-action-shape",
        "multi().step({'robot_0': np.zeros((1, 3)), 'robot_1': np.zeros(3)})",
        "InputError",
        "actions['robot_0']",
    ),
    ("par-seed-true", "multi(reset=False).reset(seed=True)", "InputError", "seed"),
    ("par-robots-zero", "proxemic.parallel_env('museum_multi', robots=0)", "InputError", "robots"),
    ("par-width-zero", "proxemic.parallel_env('museum_multi', robots=2, width=0)", "InputError", "width"),
]

#: (id, argv of ``python -m proxemic.cli``, the field the message names)
CLI_CASES: list[tuple[str, list[str], str]] = []


def run_case(code: str) -> dict[str, object]:
    result = subprocess.run(
        [sys.executable, "-c", PREAMBLE, textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, f"process died ({result.returncode}): {result.stderr[-2000:]}"
    lines = [line for line in result.stdout.splitlines() if line.startswith("{")]
    assert lines, f"no result line: {result.stdout[-1000:]} {result.stderr[-1000:]}"
    out: dict[str, object] = json.loads(lines[-1])
    return out


@pytest.mark.parametrize(("code", "cls", "field"), [c[1:] for c in API_CASES], ids=[c[0] for c in API_CASES])
def test_api_bad_input(code: str, cls: str, field: str | None) -> None:
    out = run_case(code)
    assert out["class"] == cls, out
    if field is not None:
        assert out["field"] == field, out
    assert out["message"], out


@pytest.mark.parametrize(("argv", "field"), [c[1:] for c in CLI_CASES], ids=[c[0] for c in CLI_CASES])
def test_cli_bad_input(argv: list[str], field: str) -> None:
    result = subprocess.run([sys.executable, "-m", "proxemic.cli", *argv], capture_output=True, text=True, timeout=600)
    assert result.returncode == 2, (result.returncode, result.stderr[-2000:])
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1, result.stderr
    assert field in lines[0], lines[0]


def test_the_table_is_large_and_ids_are_unique() -> None:
    ids = [c[0] for c in API_CASES] + [c[0] for c in CLI_CASES]
    assert len(ids) == len(set(ids))
