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
    # The rl extra may be installed (make test installs it): hide it from the example's process.
    hide = (
        "import runpy, sys; sys.modules['stable_baselines3'] = None; sys.modules['torch'] = None; "
        f"sys.argv = ['train_ppo.py', '--steps', '10']; runpy.run_path({str(ROOT / 'examples' / 'train_ppo.py')!r}, "
        "run_name='__main__')"
    )
    proc = subprocess.run([sys.executable, "-c", hide], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    assert "pip install '.[rl]'" in proc.stderr


def test_demo_runs_test_split_seeds_draws_every_episode_and_says_what_figures_mean(tmp_path, monkeypatch, capsys):
    from proxemic import splits
    from proxemic.viz import plots

    drawn: dict[str, int] = {}
    real = plots.plot_episodes

    def counting(scenario, episodes, path, **kw):
        drawn[Path(path).name] = len(episodes)
        return real(scenario, episodes, path, **kw)

    monkeypatch.setattr(plots, "plot_episodes", counting)
    argv = ["demo", "--scenario", "daza2021_path3", "--planner", "astar", "--planner", "social", "--episodes", "2"]
    assert cli.main([*argv, "--workers", "1", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    first = splits.TEST_EPISODE_SEEDS[0]
    assert f"seeds {first}-{first + 1}" in out and "the test split" in out
    assert drawn == {"trajectories_astar.png": 2, "trajectories_social.png": 2}
    assert "Drawn: every episode" in out
    assert "What the figures mean" in out and "path length ratio (x geodesic)" in out
    assert "mean over the successful episodes" in out and "personal-zone time, centres (%)" in out


def test_the_path_length_ratio_is_averaged_over_successful_episodes():
    # A collision or the time limit cuts the path short (here to 0.4 and 0.6 of the geodesic):
    # summary.md, the headline and the demo average L_ratio over the successes only.
    from proxemic import reference
    from proxemic.evaluation import summarise

    records = [
        {"planner": "astar", "outcome": "collision", "success": False, "collision": True, "path_length_ratio": 0.4},
        {"planner": "astar", "outcome": "timeout", "success": False, "collision": False, "path_length_ratio": 0.6},
        {"planner": "astar", "outcome": "success", "success": True, "collision": False, "path_length_ratio": 1.2},
        {"planner": "astar", "outcome": "success", "success": True, "collision": False, "path_length_ratio": 1.4},
    ]
    (row,) = summarise(records)
    assert row["path_length_ratio"] == pytest.approx(1.3) and row["path_length_ratio_n"] == 2
    (info,) = [m for m in reference.metric_registry() if m["key"] == "path_length_ratio"]
    assert info["over_successes"] and "successful episodes only" in info["definition"]


def test_demo_defaults_to_the_test_split():
    from proxemic import splits

    args = cli.build_parser().parse_args(["demo"])
    assert args.seed == splits.TEST_EPISODE_SEEDS[0]
    assert set(range(args.seed, args.seed + args.episodes)) <= set(splits.TEST_EPISODE_SEEDS)
    assert cli.seeds_split(range(0, 10)).startswith("the tuning split")
