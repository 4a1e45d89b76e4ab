"""proxemic eval: statistics, records, the same results on any number of processes, errors."""

from __future__ import annotations

import csv
import json
import math
import sys

import pyarrow.parquet as pq
import pytest

from proxemic.cli import main
from proxemic.evaluation import EvalConfig, mean_ci, run_eval, summarise, wilson
from proxemic.scenarios import load as load_scenario


def test_wilson_interval_known_values():
    # 8 successes out of 10: Wilson 95% interval (0.4902, 0.9433), computed by hand from the formula
    p, lo, hi = wilson(8, 10)
    assert p == 0.8
    assert abs(lo - 0.49016) < 1e-4 and abs(hi - 0.94333) < 1e-4
    p, lo, hi = wilson(0, 5)
    assert p == 0.0 and lo == 0.0 and abs(hi - 0.43448) < 1e-4


def test_mean_ci_uses_student_t():
    mean, half, n = mean_ci([1.0, 2.0, 3.0, None, float("nan")])
    assert n == 3 and mean == 2.0
    assert abs(half - 4.303 * 1.0 / math.sqrt(3)) < 1e-12
    assert math.isnan(mean_ci([5.0])[1])


def test_summary_rows():
    recs = [
        {"planner": "a", "success": True, "path_length": 2.0},
        {"planner": "a", "success": False, "path_length": 4.0},
        {"planner": "b", "success": True, "path_length": 1.0},
    ]
    rows = summarise(recs)
    assert [r["planner"] for r in rows] == ["a", "b"]
    assert rows[0]["success"] == 0.5 and rows[0]["path_length"] == 3.0
    assert rows[1]["episodes"] == 1


def test_eval_writes_records_and_is_the_same_on_one_or_two_processes(tmp_path):
    runs = {}
    for workers in (1, 2):
        out = tmp_path / f"w{workers}"
        cfg = EvalConfig(scenario="museum", planners=["astar"], episodes=3, seed=5, out=out, workers=workers)
        run_eval(cfg, progress=False)
        with (out / "episodes.csv").open() as fh:
            runs[workers] = list(csv.DictReader(fh))
        table = pq.read_table(out / "episodes.parquet")
        assert table.num_rows == 3
        assert (out / "summary.md").read_text().startswith("| planner |")
        assert (out / "metrics.png").exists() and (out / "trajectories_astar.png").exists()
        assert (out / "trajectories_social_map.png").exists()
        # every metric is a column: the papers' ones, and one per person / per object space
        header = list(runs[workers][0])
        for col in (
            "l_ratio",
            "smooth_rad",
            "smooth_rad2",
            "psi_intimate",
            "psi_objects_active",
            "psi_objects_any",
            "ospace_pct",
            "d_t",
            "tau",
            "chc",
        ):
            assert col in header
        people = len(load_scenario("museum")[1]["persons"])
        assert sum(c.startswith("d_min_") for c in header) == people
        assert any(c.startswith("psi_object_active_") for c in header)
        assert any(c.startswith("psi_object_any_") for c in header)
        # metrics.json describes exactly the columns of the records, from the core's metric registry
        described = json.loads((out / "metrics.json").read_text())["columns"]
        assert set(described) == set(header)
        for col in header:
            assert described[col].get("definition") or described[col].get("description"), col
    assert runs[1] == runs[2]
    assert [r["seed"] for r in runs[1]] == ["5", "6", "7"]


def test_cli_errors_exit_non_zero(tmp_path, capsys):
    assert main(["eval", "--planner", "teleport", "--episodes", "1", "--out", str(tmp_path)]) == 2
    assert 'planner: expected one of ["astar"' in (err := capsys.readouterr().err) and 'got "teleport"' in err
    assert main(["eval", "--scenario", "atlantis", "--episodes", "1", "--out", str(tmp_path)]) == 2
    blocked = tmp_path / "file"
    blocked.write_text("not a folder")
    assert main(["eval", "--episodes", "1", "--out", str(blocked / "sub")]) == 2
    assert "cannot be written" in capsys.readouterr().err


def test_ray_backend_without_ray_is_a_clear_error(tmp_path, monkeypatch):
    from proxemic.errors import MissingExtraError

    monkeypatch.setitem(sys.modules, "ray", None)  # import ray now fails as if not installed
    cfg = EvalConfig(scenario="museum", planners=["astar"], episodes=1, out=tmp_path, backend="ray")
    with pytest.raises(MissingExtraError, match=r"backend 'ray' needs the package 'ray'.*'proxemic\[ray\]'"):
        run_eval(cfg, progress=False)


def test_a_failing_episode_keeps_the_finished_records(tmp_path, monkeypatch, capsys):
    from proxemic.evaluation import episodes as evaluation

    real = evaluation.run_task

    def fails_on_seed_2(task, keep=False):
        if task[2] == 2:
            raise RuntimeError("simulated crash")
        return real(task, keep)

    monkeypatch.setattr(evaluation, "run_task", fails_on_seed_2)
    out = tmp_path / "e"
    assert main(["eval", "--episodes", "4", "--workers", "1", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "episode 3 ('museum', 'astar', 2) failed (RuntimeError: simulated crash)" in err
    assert "the 2 finished episodes are kept" in err and "Traceback" not in err
    with (out / "episodes.csv").open() as fh:
        assert [r["seed"] for r in csv.DictReader(fh)] == ["0", "1"]
    assert pq.read_table(out / "episodes.parquet").num_rows == 2


def _closed_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_ray_address_that_does_not_answer_is_a_clear_error(tmp_path, capsys):
    address = f"127.0.0.1:{_closed_port()}"
    args = ["--backend", "ray", "--ray-address", address, "--episodes", "1", "--out", str(tmp_path)]
    assert main(["eval", *args]) == 2
    err = capsys.readouterr().err
    assert f"ray_address: expected the address of a running Ray cluster (host:port), got {address}" in err
    assert "no Ray cluster answers there" in err and "Traceback" not in err
    assert main(["tune", "--trials", "1", *args]) == 2
    assert "no Ray cluster answers there" in capsys.readouterr().err


def test_ray_backend_gives_the_same_records_as_processes(tmp_path):
    pytest.importorskip("ray", reason="the ray backend needs ray (pip install 'proxemic[ray]'; make test installs it)")
    runs = {}
    for backend in ("process", "ray"):
        out = tmp_path / backend
        cfg = EvalConfig(scenario="museum", planners=["astar"], episodes=2, seed=4, out=out, workers=2, backend=backend)
        run_eval(cfg, progress=False)
        with (out / "episodes.csv").open() as fh:
            runs[backend] = list(csv.DictReader(fh))
    assert len(runs["ray"]) == 2
    assert runs["ray"] == runs["process"]


def test_an_interrupted_run_keeps_the_finished_records(tmp_path, monkeypatch, capsys):
    from proxemic.evaluation import episodes as evaluation

    real = evaluation.run_task

    def interrupted_on_seed_1(task, keep=False):
        if task[2] == 1:
            raise KeyboardInterrupt
        return real(task, keep)

    monkeypatch.setattr(evaluation, "run_task", interrupted_on_seed_1)
    out = tmp_path / "i"
    assert main(["eval", "--episodes", "3", "--workers", "1", "--out", str(out)]) == 130
    assert "interrupted; the episodes that finished are kept" in capsys.readouterr().err
    with (out / "episodes.csv").open() as fh:
        assert [r["seed"] for r in csv.DictReader(fh)] == ["0"]
    assert pq.read_table(out / "episodes.parquet").num_rows == 1


def test_a_multi_robot_scene_scores_every_robot(tmp_path, capsys):
    """care_center_multi has 3 robots: every robot of every episode is a record (``robot`` column),
    the summary is over all of them and says so, and robot 0's record is the single env's."""
    import numpy as np

    import proxemic
    from proxemic.env import ProxemicEnv, flatten_metrics
    from proxemic.evaluation import robots_note
    from proxemic.runner import run_episode

    result = proxemic.evaluate(scenario="care_center_multi", planners=["social"], episodes=2, seed=3)
    assert [(r["seed"], r["robot"]) for r in result.records] == [(s, k) for s in (3, 4) for k in range(3)]
    (row,) = result.summary
    assert (row["episodes"], row["robots"]) == (2, 3)
    assert row["success"] == sum(bool(r["success"]) for r in result.records) / 6
    assert "Every robot scored" in result.summary_markdown() and "2 x 3 robots" in result.summary_markdown()
    # every robot's episode ran to its end, and the robots' episodes differ
    assert all(r["outcome"] in ("success", "collision", "timeout") for r in result.records)
    assert len({r["path_length"] for r in result.records}) == 6
    # robot 0: what the single-robot env measures on the same seed
    env = ProxemicEnv("care_center_multi", autopilot=True, planner="social")
    rec = run_episode("care_center_multi", 4, env=env)
    single = {"reward": rec.total_reward, **flatten_metrics(rec.metrics, env.scenario)}
    env.close()
    robot0 = next(r for r in result.records if (r["seed"], r["robot"]) == (4, 0))
    for key, value in single.items():
        assert robot0[key] == value or (isinstance(value, float) and np.isnan(value) and np.isnan(robot0[key])), key
    # single-robot scenes: no note, one robot per episode
    assert robots_note([{"robots": 1}]) == ""
    # the CLI prints the note too
    out = tmp_path / "multi"
    args = ["eval", "--scenario", "care_center_multi", "--planner", "astar", "--episodes", "1", "--workers", "1"]
    assert main([*args, "--out", str(out)]) == 0
    assert "Every robot scored: the planner drives all 3 robots" in capsys.readouterr().out
    with (out / "episodes.csv").open() as fh:
        assert [r["robot"] for r in csv.DictReader(fh)] == ["0", "1", "2"]


def test_a_policy_on_a_multi_robot_scene_scores_robot_0_for_everyone():
    """A policy drives robot 0 only: with one, planners are scored on robot 0 too (like for like)."""
    import numpy as np

    import proxemic
    from proxemic.evaluation import EvalConfig, policy_robot_note
    from proxemic.policy import PolicyRef

    result = proxemic.evaluate(lambda obs: np.zeros(3), scenario="care_center_multi", planners=["astar"], episodes=1)
    assert [(r["planner"], r["robot"]) for r in result.records] == [("<lambda>", 0), ("astar", 0)]
    cfg = EvalConfig(scenario="care_center_multi", planners=["astar"], policies=[PolicyRef("p", "m:f")])
    assert policy_robot_note(cfg).startswith("Robot 0 scored only: the scene has 3 robots")
    assert policy_robot_note(EvalConfig(scenario="museum", planners=["astar"], policies=[PolicyRef("p", "m:f")])) == ""


def test_run_task_on_a_multi_robot_scene_keeps_robot_0s_episode_as_the_single_env_gives():
    """reproduce uses run_task(keep=True): robot 0's trajectory, people and path are unchanged."""
    import numpy as np

    from proxemic.env import ProxemicEnv
    from proxemic.evaluation import run_task
    from proxemic.runner import run_episode

    res = run_task(("daza2021_path3", "social", 2), keep=True)
    env = ProxemicEnv("daza2021_path3", autopilot=True, planner="social")
    rec = run_episode("daza2021_path3", 2, env=env)
    env.close()
    for ours, single in ((res.robot, rec.robot), (res.people, rec.people), (res.path, rec.path)):
        np.testing.assert_array_equal(ours, single)
    assert [o.record["robot"] for o in res.others] == [1]
