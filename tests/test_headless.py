"""On a machine without a display: ``human`` is refused with a typed error, everything else works.

Each case runs in a subprocess with ``DISPLAY`` unset or pointing at no server, because MuJoCo's
viewer ends the whole process when GLFW cannot start (the bug these tests keep away).
"""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

import proxemic


def _run(code: str, display: str | None) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    if display is not None:
        env["DISPLAY"] = display
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("display", [None, ":97"])
@pytest.mark.parametrize("front", ["gym", "parallel"])
def test_human_without_display_is_a_typed_error(display: str | None, front: str) -> None:
    make = (
        "gym.make('proxemic/Museum-v5', render_mode='human')"
        if front == "gym"
        else "proxemic.parallel_env('museum_multi', robots=2, render_mode='human')"
    )
    code = f"""
import gymnasium as gym, proxemic
try:
    {make}
except proxemic.InputError as e:
    assert e.field == 'render_mode', e.field
    print('TYPED', e)
"""
    result = _run(code, display)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "TYPED render_mode: expected a display for 'human'" in result.stdout
    assert "rgb_array" in result.stdout and "topdown" in result.stdout
    assert ("DISPLAY is unset" if display is None else f"DISPLAY={display!r} cannot be opened") in result.stdout


def test_check_env_with_the_render_check_passes_headless_on_every_env() -> None:
    code = f"""
import gymnasium as gym, proxemic
from gymnasium.utils.env_checker import check_env
for env_id in {sorted(proxemic.ENV_IDS)!r}:
    env = gym.make(env_id)
    assert 'human' not in env.metadata['render_modes'], env.metadata
    check_env(env.unwrapped)  # render check included: every declared mode is built and rendered
    env.close()
    print('OK', env_id)
"""
    result = _run(code, None)
    assert result.returncode == 0, result.stderr[-3000:]
    assert result.stdout.count("OK ") == len(proxemic.ENV_IDS)
