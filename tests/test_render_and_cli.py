"""Rendering (MuJoCo offscreen and the 2D top-down view), the demo command, and installation."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from proxemic.cli import DEMO_PLANNERS, main
from proxemic.env import ProxemicEnv
from proxemic.errors import InputError


def test_rgb_array_renders_offscreen_from_both_cameras():
    for camera in ("top", "follow"):
        env = ProxemicEnv("museum", render_mode="rgb_array", width=160, height=120, camera=camera)
        env.reset(seed=0)
        frame = env.render()
        assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
        assert frame.std() > 5.0  # not a blank image
        env.close()


def test_topdown_render_shows_the_robot():
    # 640 x 480: the robot's disc (0.24 m) is some 4 pixels across the 36 x 25 m museum
    env = ProxemicEnv("museum", render_mode="topdown", width=640, height=480)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (480, 640, 3)
    r = env.ws.topdown
    col, row = r.world_to_pixel(env.robot_pose()[None, :2])[0].astype(int)
    # the robot's colour fills its disc around the centre (the white heading tick starts at the
    # centre, so the centre pixel itself may be part of the tick, depending on the pose)
    disc = frame[row - 2 : row + 3, col - 2 : col + 3]
    assert (disc == np.asarray(r.robot_color(0), np.uint8)).all(axis=-1).sum() >= 5
    env.close()


def test_topdown_overlays_are_switchable_and_leave_the_episode_unchanged():
    every = ("zones", "groups", "object_spaces", "path")
    drawn = ProxemicEnv("care_center", render_mode="topdown", autopilot=True, planner="social_astar", overlays=every)
    silent = ProxemicEnv("care_center", autopilot=True, planner="social_astar")
    frames = []
    for env in (drawn, silent):
        env.reset(seed=3)
    for _ in range(15):
        a = drawn.step(np.zeros(3))
        b = silent.step(np.zeros(3))
        frames.append(drawn.render())
        for key in a[0]:
            np.testing.assert_array_equal(a[0][key], b[0][key])
    bare = drawn.render_topdown(overlays=())
    assert drawn.overlays == every  # a per-call choice does not change the env's
    assert np.any(frames[-1] != bare)
    assert not np.array_equal(frames[0], frames[-1])
    with pytest.raises(InputError, match="overlays"):
        drawn.set_overlays(["zones", "halo"])
    drawn.close()
    silent.close()


def test_demo_writes_tables_and_plots(tmp_path, capsys):
    assert main(["demo", "--episodes", "1", "--workers", "1", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert DEMO_PLANNERS == ("astar", "astar_orca", "astar_stop", "social_astar", "social")
    header = next(line for line in text.splitlines() if line.split() == list(DEMO_PLANNERS))
    assert header.startswith(" ")  # the terminal's headline: a line per metric, a column per planner
    assert "success (%)" in text and "time to goal (s)" in text
    for scenario in ("museum", "care_center"):
        # the headline table (header, separator, one row per planner), then a verdict per pair, then all metrics
        summary = (tmp_path / scenario / "summary.md").read_text()
        assert summary.split("\n\n")[0].count("\n") == 1 + len(DEMO_PLANNERS)
        pairs = len(DEMO_PLANNERS) * (len(DEMO_PLANNERS) - 1) // 2
        assert summary.count("\n- ") == pairs and "social vs astar" in summary and "social vs astar_orca" in summary
        all_metrics = summary.split("## All metrics\n\n")[1]
        assert all_metrics.count("\n") == 2 + len(DEMO_PLANNERS)
        assert (tmp_path / scenario / "trajectories_social_map.png").stat().st_size > 10_000
        for planner in DEMO_PLANNERS:
            assert (tmp_path / scenario / f"trajectories_{planner}.png").stat().st_size > 10_000
    assert (tmp_path / "social_map_sousa2022_fig16.png").stat().st_size > 20_000


def test_cli_reports_unknown_scenario(capsys):
    assert main(["demo", "--scenario", "atlantis", "--episodes", "1"]) == 2
    assert "unknown scenario 'atlantis'" in capsys.readouterr().err


def test_gym_make_works_from_any_directory(tmp_path):
    """Scenario files and MJCF assets ship inside the package, not next to the working directory."""
    code = (
        "import gymnasium as gym, proxemic; env = gym.make('proxemic/Museum-v5'); "
        "obs, _ = env.reset(seed=0); print(obs['lidar'].shape)"
    )
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "(72,)"
    assert not Path(tmp_path / "envs").exists()
