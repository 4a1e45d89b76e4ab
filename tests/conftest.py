"""Shared fixtures: scenario texts and env factories."""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco creates any GL context

import pytest

import proxemic  # noqa: F401  (registers the environments)

SMALL_ROOM = """
[scene]
name = "small_room"
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

[[object]]
name = "bench"
kind = "bench"
pose = [5, 6, 0]
size = [0.5, 2.0]

[[person]]
route = [[2, 2], [8, 2]]
speed = 1.0

[[robot]]
start = [1.5, 4, 0]
goal = [8.5, 4]

[episode]
max_time = 40
"""


@pytest.fixture
def small_room() -> str:
    """Scenario text of a 10 x 8 m room with a bench, one walker and a robot."""
    return SMALL_ROOM


@pytest.fixture
def write_scenario(tmp_path):
    """Writes scenario text to a file and returns its path."""

    def _write(text: str, name: str = "scenario.toml"):
        p = tmp_path / name
        p.write_text(text)
        return p

    return _write
