"""Rendering (MuJoCo offscreen and the 2D top-down view), the demo command, and installation."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from proxemic.cli import main
from proxemic.env import ProxemicEnv


def test_rgb_array_renders_offscreen_from_both_cameras():
    for camera in ("top", "follow"):
        env = ProxemicEnv("museum", render_mode="rgb_array", width=160, height=120, camera=camera)
        env.reset(seed=0)
        frame = env.render()
        assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
        assert frame.std() > 5.0  # not a blank image
        env.close()


def test_topdown_render_shows_the_robot():
    env = ProxemicEnv("museum", render_mode="topdown", width=320, height=240)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (240, 320, 3)
    r = env.ws.topdown
    col, row = r.world_to_pixel(env.robot_pose()[None, :2])[0].astype(int)
    assert tuple(frame[row, col]) == tuple(r.robot_color(0))
    env.close()


def test_demo_writes_tables_and_plots(tmp_path, capsys):
    assert main(["demo", "--episodes", "1", "--workers", "1", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "| astar |" in text and "| social_astar |" in text
    for scenario in ("museum", "care_center"):
        assert (tmp_path / scenario / "summary.md").read_text().count("\n") == 4
        for planner in ("astar", "social_astar"):
            assert (tmp_path / scenario / f"trajectories_{planner}.png").stat().st_size > 10_000
    assert (tmp_path / "social_map_sousa2022_fig16.png").stat().st_size > 20_000


def test_cli_reports_unknown_scenario(capsys):
    assert main(["demo", "--scenario", "atlantis", "--episodes", "1"]) == 2
    assert "unknown scenario 'atlantis'" in capsys.readouterr().err


def test_gym_make_works_from_any_directory(tmp_path):
    """Scenario files and MJCF assets ship inside the package, not next to the working directory."""
    code = (
        "import gymnasium as gym, proxemic; env = gym.make('proxemic/Museum-v0'); "
        "obs, _ = env.reset(seed=0); print(obs['lidar'].shape)"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "(72,)"
    assert not Path(tmp_path / "envs").exists()
