"""What a newcomer meets first: eval's output folders, the PPO example without its extra, the demo."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from proxemic import cli

ROOT = Path(__file__).resolve().parent.parent


def test_eval_without_out_writes_a_fresh_folder_each_run(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = ["eval", "--scenario", "daza2021_path3", "--planner", "astar", "--episodes", "1", "--workers", "1"]
    assert cli.main(argv) == 0
    assert cli.main(argv) == 0
    runs = sorted((tmp_path / "out" / "eval").iterdir())
    assert len(runs) == 2, runs
    assert all((r / "episodes.csv").is_file() for r in runs)
    assert "out/eval/<date>-<time>" in cli.build_parser()._subparsers._group_actions[0].choices["eval"].format_help()


def test_eval_into_a_given_folder_removes_the_old_videos(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    old = tmp_path / "run" / "videos" / "social_seed7.mp4"
    old.parent.mkdir(parents=True)
    old.write_bytes(b"an earlier run's video")
    argv = ["eval", "--scenario", "daza2021_path3", "--planner", "astar", "--episodes", "1", "--workers", "1"]
    assert cli.main([*argv, "--out", "run"]) == 0
    assert not old.exists()


def test_ppo_example_without_its_extra_names_it():
    pytest.importorskip("proxemic")
    try:
        import stable_baselines3  # noqa: F401

        pytest.skip("the rl extra is installed")
    except ImportError:
        pass
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "train_ppo.py"), "--steps", "10"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    assert "pip install '.[rl]'" in proc.stderr
